#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/CMakeLists.txt, clang++-14, ASan + UBSan) into BUILD_DIR
# and runs each for SECONDS from a generated seed corpus, two targets at a time. Fails when any
# target finds a crash, sanitizer report, leak, timeout or out-of-memory; the reproducer is kept
# under BUILD_DIR/artifacts/<target>/ and its path printed.
#
#   tests/fuzz/build_and_smoke.sh BUILD_DIR SECONDS [TARGET...]
#
# Exit 77 (skipped) when clang++-14 or libFuzzer is missing, unless CI=true (then exit 1).
set -uo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 BUILD_DIR SECONDS [TARGET...]" >&2
  exit 2
fi
build_dir=$1
seconds=$2
shift 2
here=$(cd "$(dirname "$0")" && pwd)
all_targets=(fuzz_ply fuzz_npy fuzz_safetensors fuzz_nerf_cameras fuzz_png fuzz_checkpoint)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all_targets[@]}")

missing=()
command -v clang++-14 >/dev/null || missing+=("clang++-14 (apt-get install clang-14)")
ls /usr/lib/llvm-14/lib/clang/14*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1 ||
  ls /usr/lib/llvm-14/lib/clang/14*/lib/linux/libclang_rt.fuzzer-*.a >/dev/null 2>&1 ||
  missing+=("libFuzzer (apt-get install libclang-rt-14-dev libfuzzer-14-dev)")
command -v python3 >/dev/null || missing+=("python3")
command -v cmake >/dev/null || missing+=("cmake")
if [ ${#missing[@]} -gt 0 ]; then
  if [ "${CI:-}" = "true" ]; then
    echo "[fuzz] FAIL: missing in CI: ${missing[*]}" >&2
    exit 1
  fi
  echo "[fuzz] skipped: missing ${missing[*]}" >&2
  exit 77
fi

start=$(date +%s)
mkdir -p "$build_dir"
build_dir=$(cd "$build_dir" && pwd)
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
[ -f "$build_dir/CMakeCache.txt" ] && generator=()
echo "[fuzz] configuring and building in $build_dir" >&2
cmake -S "$here" -B "$build_dir" "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++-14 \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo >"$build_dir/configure.log" 2>&1 ||
  { cat "$build_dir/configure.log" >&2; echo "[fuzz] FAIL: configure" >&2; exit 1; }
cmake --build "$build_dir" --parallel "${S4D_FUZZ_JOBS:-2}" >"$build_dir/build.log" 2>&1 ||
  { tail -50 "$build_dir/build.log" >&2; echo "[fuzz] FAIL: build" >&2; exit 1; }

python3 "$here/make_seeds.py" "$build_dir/seeds" || { echo "[fuzz] FAIL: seed generation" >&2; exit 1; }

# One target: corpus (grows between runs) seeded from seeds/, artifacts/ for reproducers, a log.
run_one() {
  local t=$1 exe="$build_dir/$1"
  mkdir -p "$build_dir/corpus/$t" "$build_dir/artifacts/$t"
  if [ ! -x "$exe" ]; then
    echo "[fuzz] $t: not built (see $build_dir/configure.log)" >"$build_dir/$t.log"
    return 1
  fi
  # Leaks count (ASan's default); a hang over 10 s or 2 GB of memory is a finding.
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$exe" "$build_dir/corpus/$t" "$build_dir/seeds/$t" \
    -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -max_len=65536 \
    -artifact_prefix="$build_dir/artifacts/$t/" -print_final_stats=1 >"$build_dir/$t.log" 2>&1
}

status=0
declare -A rc
for ((i = 0; i < ${#targets[@]}; i += 2)); do
  pids=()
  for t in "${targets[@]:i:2}"; do
    echo "[fuzz] $t: ${seconds}s" >&2
    run_one "$t" &
    pids+=("$t:$!")
  done
  for p in "${pids[@]}"; do
    wait "${p#*:}"
    rc[${p%%:*}]=$?
  done
done

for t in "${targets[@]}"; do
  log="$build_dir/$t.log"
  summary=$(grep -E "^#[0-9]+.*cov:" "$log" | tail -1 | sed -E "s/^#[0-9]+[[:space:]]+[A-Z]+[[:space:]]+//")
  execs=$(grep -E "stat::average_exec_per_sec" "$log" | awk '{print $2}')
  if [ "${rc[$t]}" -eq 0 ]; then
    echo "[fuzz] $t: ok, ${execs:-?} exec/s, ${summary:-no summary}" >&2
  else
    status=1
    echo "[fuzz] $t: FAILED (exit ${rc[$t]}); log $log" >&2
    grep -E "^==[0-9]+==ERROR|SUMMARY:|runtime error|Test unit written to|ALARM|out-of-memory" "$log" | head -20 >&2
    for a in "$build_dir/artifacts/$t"/*; do
      [ -f "$a" ] && echo "[fuzz]   reproducer: $a  (rerun: $build_dir/$t $a)" >&2
    done
    # The sanitizer's stack, for the CI log.
    sed -n '/^==[0-9]*==ERROR\|runtime error/,/^SUMMARY/p' "$log" | head -60 >&2
  fi
done
echo "[fuzz] wall time $(($(date +%s) - start))s" >&2
exit $status

#!/usr/bin/env bash
# The sanitizer job: builds style4d and the unit tests with AddressSanitizer and UBSan
# (-DS4D_SANITIZE=ON; clang 14 at -O0, or the system compiler at -O1) into BUILD_DIR, then runs
# the unit tests (ctest -L unit) and the bad-input corpus (tests/corpus) against that build. Any
# sanitizer report is fatal to its process, so it fails the test or the corpus case that caused it.
#
#   tests/sanitize/build_and_run.sh BUILD_DIR
set -uo pipefail
[ $# -eq 1 ] || { echo "usage: $0 BUILD_DIR" >&2; exit 2; }
build_dir=$1
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
start=$(date +%s)
# Mesa's lavapipe keeps allocations until exit that LeakSanitizer would report as leaks of ours:
# leaks are the fuzz targets' job (tests/fuzz, readers only); here ASan checks memory errors.
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=0:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# ASan intercepts dlopen, and the lookup then uses the interceptor's RUNPATH, not the program's: the
# video plugin (libs4d_video.so, beside the programs) is found through the library path instead.
export LD_LIBRARY_PATH="$1${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

# clang 14 at -O0 when it is there (tools/run-tests.sh installs it): the build is the job's cost, and
# one of the heaviest files (tools/style4d/bench_run.cpp) compiled with ASan + UBSan in 29 s of CPU
# with GCC 12 at -O1, 15 s at -O0 and 8 s with clang 14 at -O0 (2026-11-29, 2 CPU cores, user time);
# the unit tests run in seconds either way.
compiler=$(command -v clang++-14 || command -v c++)
optimize=$([ "$(basename "$compiler")" = clang++-14 ] && echo -O0 || echo -O1)
# A tree configured with another compiler is configured afresh (CMake cannot switch one in place).
if [ -f "$build_dir/CMakeCache.txt" ] && ! grep -q "^CMAKE_CXX_COMPILER:[A-Z]*=$compiler\$" "$build_dir/CMakeCache.txt"; then
  rm -rf "$build_dir"
fi
cmake -S "$source_dir" -B "$build_dir" -G Ninja -DCMAKE_CXX_COMPILER="$compiler" -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_CXX_FLAGS_DEBUG="$optimize -g1" -DS4D_SANITIZE=ON -DS4D_BUILD_VIEWER=OFF -DS4D_BUILD_TESTS=ON \
  > "$build_dir.configure.log" 2>&1 ||
  { cat "$build_dir.configure.log"; echo "[sanitize] FAIL: configure"; exit 1; }
# The unit-labelled tests that are programs of this tree (some run a script instead).
mapfile -t unit_tests < <(comm -12 <(ctest --test-dir "$build_dir" -N -L unit | sed -n 's/^ *Test *#[0-9]*: //p' | sort) \
  <(ninja -C "$build_dir" -t targets all | sed -n 's|^\(.*/\)\{0,1\}\([A-Za-z0-9_]*\): CXX_EXECUTABLE_LINKER.*|\2|p' | sort))
[ ${#unit_tests[@]} -gt 0 ] || { echo "[sanitize] FAIL: no unit tests found"; exit 1; }
echo "[sanitize] building style4d, its video plugin and ${#unit_tests[@]} unit tests with ASan + UBSan ($(basename "$compiler") $optimize)"
cmake --build "$build_dir" --target style4d s4d_video "${unit_tests[@]}" -j "$(nproc)" > "$build_dir.build.log" 2>&1 ||
  { tail -40 "$build_dir.build.log"; echo "[sanitize] FAIL: build"; exit 1; }
echo "[sanitize] built in $(( $(date +%s) - start )) s"
status=0
ctest --test-dir "$build_dir" -R "^($(IFS='|'; echo "${unit_tests[*]}"))\$" --output-on-failure --parallel "$(nproc)" \
  --timeout 600 || status=1
python3 "$source_dir/tests/corpus/run_corpus.py" --exe "$build_dir/style4d" --timeout 240 || status=1
echo "[sanitize] $([ $status -eq 0 ] && echo passed || echo FAILED) in $(( $(date +%s) - start )) s"
exit $status

#!/usr/bin/env bash
# The GPU check (docs/gpu.md): one call that runs everything a GPU user needs figures for and writes
# OUT/gpu-check.json and OUT/gpu-check.md with the device, the driver and every figure, read from the
# programs' own JSON outputs (train.json, stylize.json, demo.json, report.json, the benches' lines).
#   1. the GPU test executables with the validation layer on (S4D_VALIDATION=1);
#   2. the demo;
#   3. a GPU-sized workload: synth --dnerf --object at 800x800, trained with --preset default to the
#      end, stylized and benched;
#   4. the viewer's frame loop at 1352x1014: 100,000 Gaussians, and the demo's trained scene on an orbit;
#   5. the rasterizer and deformation-field benches.
# Every step has a time cap, and the whole check a budget (8 minutes less a margin): a step that
# reaches its cap is stopped (train with SIGINT, so it checkpoints) and recorded as cut short.
# --small runs the same steps at tiny sizes, for lavapipe in CI (tests/release); its figures mean
# nothing. BIN holds style4d and the s4d_bench_* programs, BIN/tests the test executables: a build
# folder (the default in a checkout), or the bin/ of a release made with tools/package.sh --checks
# (the default when the script runs from one).
# --budget S sets the whole check's budget in seconds (default 450 full, 900 small).
# Usage: tools/gpu-check.sh OUT [--small] [--bin BIN] [--budget S] [--metric-weights DIR]
set -uo pipefail
usage() { echo "usage: tools/gpu-check.sh OUT [--small] [--bin BIN] [--budget S] [--metric-weights DIR]" >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
# In a release made with --checks the programs are in bin/, in a checkout in build/.
out="" small=0 bin=$root/build weights="" budget=""
[ -x "$root/bin/style4d" ] && bin=$root/bin
while [ $# -gt 0 ]; do
  case "$1" in
    --small) small=1; shift ;;
    --bin) [ $# -ge 2 ] || usage; bin=$2; shift 2 ;;
    --metric-weights) [ $# -ge 2 ] || usage; weights=$2; shift 2 ;;
    --budget) [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] || { echo "tools/gpu-check.sh: --budget needs whole seconds" >&2; usage; }
      budget=$2; shift 2 ;;
    -*) echo "tools/gpu-check.sh: unknown option '$1'" >&2; usage ;;
    *) [ -z "$out" ] || usage; out=$1; shift ;;
  esac
done
[ -n "$out" ] || usage
bin=$(realpath "$bin")
for p in style4d s4d_bench_splat s4d_bench_viewer s4d_bench_deform; do
  [ -x "$bin/$p" ] || { echo "tools/gpu-check.sh: --bin $bin has no $p (build it, or use a release made with --checks)" >&2; exit 2; }
done
if [ -e "$out" ] && [ -n "$(ls -A "$out")" ]; then echo "tools/gpu-check.sh: OUT $out is not empty" >&2; exit 2; fi
mkdir -p "$out/logs"
out=$(realpath "$out")
command -v python3 >/dev/null || { echo "tools/gpu-check.sh: python3 is needed to write the report" >&2; exit 2; }

# A release made with --checks carries the validation layer.
[ -d "$root/share/vulkan/explicit_layer.d" ] && export VK_LAYER_PATH=$root/share/vulkan/explicit_layer.d

# Sizes and caps (seconds). Full: what docs/gpu.md's goals are about; the caps add up to more than
# the budget, which then cuts the last steps short rather than overrun 8 minutes.
# --small is for checking that every step still runs, on a CPU: its caps are loose (x3) so that a
# loaded CI machine does not cut a step short.
cap_scale=1
if [ "$small" = 1 ]; then
  budget=${budget:-900} cap_scale=3
  tests_filter='^test_gpu_engine$'
  demo_args=(--keys 4096 --iters 10 --fine-iters 4 --style-iters 4 --mlp-iters 2 --spiral-frames 2)
  synth_args=(--dnerf --object --size 48x48 --frames 4)
  train_args=(--preset default --iters 100 --fine-iters 4)  # fewer static steps leave only the background
  stylize_args=(--iters 4 --mlp-iters 2 --spiral-frames 2)
  viewer_size=160x120 viewer_gaussians=2000 orbit=4 repeats=1
  splat_args=(--sizes 64x64:500 --repeats 1)
  deform_args=(--preset fast --gaussians 2000 --repeats 1 --check 200)
else
  budget=${budget:-450}
  tests_filter='^test_gpu_'
  demo_args=()
  synth_args=(--dnerf --object --size 800x800)
  train_args=(--preset default)
  stylize_args=()
  viewer_size=1352x1014 viewer_gaussians=100000 orbit=60 repeats=5
  splat_args=(--repeats 5)
  deform_args=(--preset default --gaussians 100000 --repeats 5)
fi
start=$(date +%s)
printf 'step\tstatus\tseconds\tcap_s\texit\n' > "$out/steps.tsv"

# step NAME CAP SIGNAL COMMAND...: runs COMMAND with at most CAP seconds (less when the budget is
# nearly spent); its output goes to logs/NAME.log. Status: ok, failed, cut short, or not run (budget).
step() {
  local name=$1 cap=$(($2 * cap_scale)) signal=$3; shift 3
  local left=$((budget - ($(date +%s) - start)))
  [ "$left" -lt "$cap" ] && cap=$left
  if [ "$cap" -le 0 ]; then
    printf '%s\tnot run (the budget was spent)\t0\t0\t\n' "$name" >> "$out/steps.tsv"; return 1
  fi
  local t0 rc status
  t0=$(date +%s%N)
  timeout -s "$signal" -k 10 "$cap" "$@" > "$out/logs/$name.log" 2>&1
  rc=$?
  # timeout says 124 when it had to stop the step (train then exits 130, having checkpointed).
  case $rc in 0) status=ok ;; 124|130) status="cut short" ;; *) status=failed ;; esac
  local ms=$((($(date +%s%N) - t0) / 1000000))
  printf '%s\t%s\t%d.%03d\t%s\t%s\n' "$name" "$status" $((ms / 1000)) $((ms % 1000)) "$cap" "$rc" >> "$out/steps.tsv"
  [ "$status" = ok ]
}

s4d=$bin/style4d
step devices 30 TERM "$s4d" devices --json
cp "$out/logs/devices.log" "$out/devices.json"

# 1. GPU test executables, one after the other, validation on.
gpu_tests='failed=0
for t in "$1"/tests/*; do
  [ -f "$t" ] && [ -x "$t" ] && [[ $(basename "$t") =~ $2 ]] || continue
  echo "== $(basename "$t")"
  S4D_VALIDATION=1 "$t" || { echo "FAILED: $(basename "$t")"; failed=1; }
done
exit $failed'
step gpu_tests 120 TERM bash -c "$gpu_tests" gpu_tests "$bin" "$tests_filter"

# 2. The demo. --small cannot shrink its stage 3 (every frame of the built-in scene), so there it
# has an unscaled minute and may be cut short.
if [ "$small" = 1 ]; then demo_cap=$((60 / cap_scale)); else demo_cap=120; fi
step demo "$demo_cap" TERM "$s4d" demo --out "$out/demo" "${demo_args[@]}"

# 3. The GPU-sized workload.
if step synth 60 TERM "$s4d" synth --out "$out/object" "${synth_args[@]}"; then
  step train 300 INT "$s4d" train --data "$out/object" --out "$out/object_run" "${train_args[@]}" &&
    step make_style 30 TERM "$s4d" make-style --out "$out/builtin.png" &&
    step stylize 90 TERM "$s4d" stylize --run "$out/object_run" --style "$out/builtin.png" "${stylize_args[@]}" &&
    step bench 90 TERM "$s4d" bench --run "$out/object_run" --style builtin --out "$out/object_bench" \
      ${weights:+--metric-weights "$weights"}
fi

# 4. The viewer's frame loop.
step viewer 60 TERM "$bin/s4d_bench_viewer" --sizes "$viewer_size:$viewer_gaussians" --repeats "$repeats"
# The built-in scene as the demo trained it; the workload's object when the demo did not finish.
orbit_run=$out/demo/run
[ -f "$out/demo/demo.json" ] || orbit_run=$out/object_run
echo "$orbit_run" > "$out/orbit_run.txt"
step viewer_orbit 60 TERM "$bin/s4d_bench_viewer" --run "$orbit_run" --size "$viewer_size" --orbit "$orbit" --repeats 1

# 5. The benches.
step bench_splat 60 TERM "$bin/s4d_bench_splat" "${splat_args[@]}"
step bench_deform 60 TERM "$bin/s4d_bench_deform" "${deform_args[@]}"

python3 "$root/tools/gpu_check_report.py" "$out" "$([ "$small" = 1 ] && echo small || echo full)" "$budget"

#!/usr/bin/env bash
# The speed/accuracy trade of 4DGS training on one scene (the built-in one, or DATA): one knob at a time around the
# `fast` preset (Gaussian budget, resolution, SH degree fixed at 0, 1 or 2 where the preset chooses
# it from the data, HexPlane resolution, deformation MLP width, iterations), each point trained to the end and scored on the held-out camera over all times.
# Writes OUT/points.jsonl (one JSON line per point: seconds, peak device memory, test PSNR/SSIM) and,
# through s4d_pareto_report, OUT/pareto.md, pareto.json and the plots pareto_seconds.png and
# pareto_device_peak_mib.png. Finished points are kept, so an interrupted sweep continues.
#
# Usage: bench/pareto_sweep.sh [OUT_DIR]
#   DATA=DIR sweeps that dataset instead of the built-in scene (any layout `train` reads), e.g. a
#   monocular object from `style4d synth --dnerf --motion squash --rgba --random-init 20000`. The
#   half-resolution point is rescored at full resolution on a rig capture's camera 0, and left out
#   elsewhere. NO_STYLE=1 leaves out the style model's points.
#   ITERS / FINE_ITERS (default 900 / 1500, the fast preset's) set the base point's run length;
#   smaller values give a quick sweep of the same shape. REPORT_ONLY=1 writes the reports from the
#   points finished so far and trains nothing. Wall-clock times: run it on a quiet machine
#   (on two lavapipe cores each full-length point takes about 20 minutes).
set -euo pipefail
out="${1:-out/pareto_sweep}"
build="${S4D_BUILD_DIR:-build}"
exe="$build/style4d"
iters="${ITERS:-900}"
fine="${FINE_ITERS:-1500}"
mkdir -p "$out"
data="${DATA:-$out/data}"
[ -n "${DATA:-}" ] || [ -f "$data/poses_bounds.npy" ] || "$exe" synth --out "$data" > "$out/synth.log" 2>&1

# A run trained below the data's resolution is scored like the others: its test camera rendered at
# the full resolution (a copy of the run with downscale 1) against the captured frames, through
# Style4D-Bench (psnr; content_ssim of the captured frames against the render is the test SSIM).
# Prints {"test_psnr": ..., "test_ssim": ...}.
full_resolution_scores() {
  local run=$1 work="$out/full_resolution/$(basename "$1")"
  rm -rf "$work"
  mkdir -p "$work"
  cp -r "$run" "$work/run"
  python3 - "$work/run/run.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
j["settings"]["downscale"] = 1
json.dump(j, open(sys.argv[1], "w"), indent=2)
PY
  "$exe" render --run "$work/run" --path test --out "$work/test" > "$work/render.log" 2>&1
  "$exe" bench --frames "$data/cam00" --original "$work/test/cam00" --ground-truth "$data/cam00" \
    --style-image "${STYLE:-assets/styles/builtin.png}" --out "$work/bench" > "$work/bench.log" 2>&1
  python3 -c 'import json, sys; r = json.load(open(sys.argv[1]))["results"][0]
print(json.dumps({"test_psnr": r["psnr"], "test_ssim": r["content_ssim"]}))' "$work/bench/report.json"
}

# point LABEL [train options...]
point() {
  local label=$1
  shift
  local run="$out/runs/$label"
  if [ ! -f "$run/train.json" ] || ! grep -q '"complete": true' "$run/train.json"; then
    [ -z "${REPORT_ONLY:-}" ] || return 0
    rm -rf "$run"
    mkdir -p "$out/runs"
    echo "[sweep] $label: style4d train $*" >&2
    "$exe" train --data "$data" --run "$run" --preset fast --iters "$iters" --fine-iters "$fine" "$@" > "$out/runs/$label.log" 2>&1
  fi
  local full="{}"
  if [ -d "$data/cam00" ] && python3 -c 'import json, sys; sys.exit(json.load(open(sys.argv[1]))["settings"]["downscale"] == 1)' "$run/run.json"; then
    full=$(full_resolution_scores "$run")
  fi
  python3 - "$run/train.json" "$label" "$*" "$full" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
s = j["settings"]
point = {"label": sys.argv[2], "options": sys.argv[3], "seconds": j["seconds"],
         "device_peak_mib": j["device_peak_mib"], "test_psnr": j["test_psnr"], "test_ssim": j["test_ssim"],
         "num_gaussians": j["num_gaussians"], "static_test_psnr": j["static"]["test_psnr"],
         "iterations": s["iterations"], "fine_iterations": s["fine_iterations"], "device": j["device"]}
full = json.loads(sys.argv[4])
if full:  # trained below full resolution: keep its own-resolution scores aside
    point.update({"test_psnr_own_resolution": point["test_psnr"], "test_ssim_own_resolution": point["test_ssim"], **full})
print(json.dumps(point))
PY
}

# style_point LABEL [stylize options...]: stages 3-4 on the base run with the demo's stage-4 length.
style_point() {
  local label=$1
  shift
  local dir="$out/runs/base/style/$label"
  if [ ! -f "$dir/stylize.json" ]; then
    [ -z "${REPORT_ONLY:-}" ] || return 0
    echo "[sweep] $label: style4d stylize $*" >&2
    "$exe" stylize --run "$out/runs/base" --style "$style" --name "$label" "$@" > "$out/runs/style_$label.log" 2>&1
  fi
  python3 - "$dir/stylize.json" "$label" "$*" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
w = j["warp_error"]
print(json.dumps({"label": sys.argv[2], "options": sys.argv[3], "seconds": j["stage4"]["seconds"],
                  "device_peak_mib": j["device_peak_mib"], "test_psnr": j["stage4"]["test_psnr_vs_stylized"],
                  "test_ssim": j["stage4"]["test_ssim_vs_stylized"],
                  "warp_error": w["spiral_exact_flow"]["styled_render"], "warp_error_2d": w["spiral_exact_flow"]["stylized_2d"],
                  "warp_error_dis": w["spiral_styled_render"], "warp_error_dis_2d": w["spiral_stylized_2d"],
                  "method": j["method"], "iterations": j["settings"]["iterations"],
                  "mlp_iterations": j["settings"]["mlp_iterations"], "device": j["device"]}))
PY
}

# The style model: no MLP (colours and opacities only) against the paper's 2-4-4-4 MLP per Gaussian,
# at the demo's stage-4 length and twice it. Quality is the held-out camera's PSNR against its
# stylized frames; the warp errors are the spiral render's and the 2D stylizer's on the same spiral,
# under the renderer's exact flow (lower is steadier; the DIS-flow ones are kept as *_dis).
style="${STYLE:-assets/styles/builtin.png}"
if [ -z "${NO_STYLE:-}" ]; then
point base > /dev/null
{
  style_point colors --method colors --iters 500
  style_point full --method full --iters 500 --mlp-iters 60
  style_point full_x2 --method full --iters 1000 --mlp-iters 120
} > "$out/style_points.jsonl"
"$build/s4d_pareto_report" "$out/style_points.jsonl" "$out/style"
fi

# Cheapest first, so that a sweep cut short still has the most points.
{
  point base
  # Scored at full resolution on a rig's camera 0 only: elsewhere its own-resolution PSNR would
  # not be comparable with the others', so the point is left out.
  [ ! -d "$data/cam00" ] || point half_res --set downscale=2
  base_iters=$iters base_fine=$fine
  iters=$((base_iters / 2)) fine=$((base_fine / 2)); point iters_half
  iters=$base_iters fine=$base_fine
  point budget_5k --budget 5000
  point mlp_16 --set field_width=16
  point sh0 --sh-degree 0
  point sh1 --sh-degree 1
  point planes_16 --set 'field_resolution=[16,16,16,8]'
  point sh2 --sh-degree 2
  point planes_64 --set 'field_resolution=[64,64,64,16]'
  point budget_30k --budget 30000
  iters=$((base_iters * 2)) fine=$((base_fine * 2)); point iters_double
} > "$out/points.jsonl"
"$build/s4d_pareto_report" "$out/points.jsonl" "$out"

#!/usr/bin/env bash
# The speed/accuracy trade of 4DGS training on the built-in scene: one knob at a time around the
# `fast` preset (Gaussian budget, resolution, SH degree, HexPlane resolution, deformation MLP width,
# iterations), each point trained to the end and scored on the held-out camera over all times.
# Writes OUT/points.jsonl (one JSON line per point: seconds, peak device memory, test PSNR/SSIM) and,
# through s4d_pareto_report, OUT/pareto.md, pareto.json and the plots pareto_seconds.png and
# pareto_device_peak_mib.png. Finished points are kept, so an interrupted sweep continues.
#
# Usage: bench/pareto_sweep.sh [OUT_DIR]
#   ITERS / FINE_ITERS (default 900 / 1500, the fast preset's) set the base point's run length;
#   smaller values give a quick sweep of the same shape. Wall-clock times: run it on a quiet machine
#   (on two lavapipe cores each full-length point takes about 20 minutes).
set -euo pipefail
out="${1:-out/pareto_sweep}"
build="${S4D_BUILD_DIR:-build}"
exe="$build/style4d"
iters="${ITERS:-900}"
fine="${FINE_ITERS:-1500}"
mkdir -p "$out"
[ -f "$out/data/poses_bounds.npy" ] || "$exe" synth --out "$out/data" > "$out/synth.log" 2>&1

# point LABEL [train options...]
point() {
  local label=$1
  shift
  local run="$out/runs/$label"
  if [ ! -f "$run/train.json" ] || ! grep -q '"complete": true' "$run/train.json"; then
    rm -rf "$run"
    mkdir -p "$out/runs"
    echo "[sweep] $label: style4d train $*" >&2
    "$exe" train --data "$out/data" --out "$run" --preset fast --iters "$iters" --fine-iters "$fine" "$@" > "$out/runs/$label.log" 2>&1
  fi
  python3 - "$run/train.json" "$label" "$*" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
s = j["settings"]
print(json.dumps({"label": sys.argv[2], "options": sys.argv[3], "seconds": j["seconds"],
                  "device_peak_mib": j["device_peak_mib"], "test_psnr": j["test_psnr"], "test_ssim": j["test_ssim"],
                  "num_gaussians": j["num_gaussians"], "static_test_psnr": j["static"]["test_psnr"],
                  "iterations": s["iterations"], "fine_iterations": s["fine_iterations"], "device": j["device"]}))
PY
}

{
  point base
  point budget_5k --budget 5000
  point budget_30k --budget 30000
  point half_res --set downscale=2
  point sh0 --sh-degree 0
  point sh2 --sh-degree 2
  point planes_16 --set 'field_resolution=[16,16,16,8]'
  point planes_64 --set 'field_resolution=[64,64,64,16]'
  point mlp_16 --set field_width=16
  base_iters=$iters base_fine=$fine
  iters=$((base_iters / 2)) fine=$((base_fine / 2)); point iters_half
  iters=$((base_iters * 2)) fine=$((base_fine * 2)); point iters_double
} > "$out/points.jsonl"
"$build/s4d_pareto_report" "$out/points.jsonl" "$out"

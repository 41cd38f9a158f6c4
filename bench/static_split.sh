#!/usr/bin/env bash
# What "deform only what moves" saves and costs: trains the built-in scene twice with the same
# settings, once with the motion split (still Gaussians off the field; the preset's --static-motion,
# or MOTION=X) and once without (--static-motion 0), and prints one JSON line per run (test PSNR,
# seconds, Gaussians that still use the field, field evaluations). The built-in scene's wall and floor are a large static
# background. Wall-clock seconds: run it on a quiet machine.
#
# Usage: bench/static_split.sh [OUT_DIR] [extra style4d train options...]
#   e.g. bench/static_split.sh out/split --preset fast
set -euo pipefail
out="${1:-out/static_split}"
shift || true
exe="${S4D_BUILD_DIR:-build}/style4d"
mkdir -p "$out"
[ -f "$out/data/poses_bounds.npy" ] || "$exe" synth --out "$out/data"
for arm in split no_split; do
  run="$out/run_$arm"
  case $arm in
    split) motion=(${MOTION:+--static-motion "$MOTION"}) ;;
    no_split) motion=(--static-motion 0) ;;
  esac
  [ -f "$run/train.json" ] || "$exe" train --data "$out/data" --out "$run" "${motion[@]}" "$@"
  python3 - "$run/train.json" "$arm" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
s = j["settings"]
print(json.dumps({"bench": "static_split", "arm": sys.argv[2], "static_motion": s["static_motion"], "device": j["device"],
                  "test_psnr": j["test_psnr"], "static_stage_psnr": j["static"]["test_psnr"], "seconds": j["seconds"],
                  "num_gaussians": j["num_gaussians"], "moving_gaussians": j["moving_gaussians"],
                  "deform_evaluations": j["deform_evaluations"],
                  "deform_evaluations_unmasked": j["deform_evaluations_unmasked"]}))
PY
done

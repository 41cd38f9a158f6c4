#!/usr/bin/env bash
# Stage 4's two settings (`stylize --style-setting tuned|paper`) on one trained run at equal training
# time: tuned first, then a short paper probe to measure its seconds per step, then paper for as many
# steps as fit tuned's training seconds. Writes OUT/style_settings.{json,md} (test PSNR and SSIM
# against the stylized frames, the warp errors of stylize.json, seconds, steps) and
# OUT/contact_sheet.png (tuned's contact sheet above paper's). Finished styles are kept: run it
# again to continue or to rewrite the tables.
#
# Usage: bench/style_settings.sh RUN OUT [--style IMG] [--tuned-iters N] [--tuned-mlp-iters M]
#                                [--paper-iters N] [--probe-iters N] [--spiral-frames N]
#   e.g. bench/style_settings.sh out/demo/run out/style_settings --tuned-iters 500 --tuned-mlp-iters 60
# RUN is a trained run (style4d train); its styles are named settings_tuned, settings_paper and
# settings_paper_probe. --paper-iters skips the probe.
set -euo pipefail
[ $# -ge 2 ] || { sed -n '2,14p' "$0" >&2; exit 2; }
run="$1" out="$2"
shift 2
root="$(cd "$(dirname "$0")/.." && pwd)"
style="$root/assets/styles/builtin.png" tuned_iters=500 tuned_mlp=60 paper_iters="" probe_iters=20 spiral=""
while [ $# -gt 0 ]; do
  case "$1" in
    --style) style="$2"; shift 2 ;;
    --tuned-iters) tuned_iters="$2"; shift 2 ;;
    --tuned-mlp-iters) tuned_mlp="$2"; shift 2 ;;
    --paper-iters) paper_iters="$2"; shift 2 ;;
    --probe-iters) probe_iters="$2"; shift 2 ;;
    --spiral-frames) spiral="$2"; shift 2 ;;
    *) echo "style_settings.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
exe="${S4D_EXE:-$root/${S4D_BUILD_DIR:-build}/style4d}"
[ -x "$exe" ] || { echo "style_settings.sh: $exe not built (tools/setup.sh style4d)" >&2; exit 2; }
mkdir -p "$out"
spiral_args=(${spiral:+--spiral-frames "$spiral"})

# stylize NAME ARGS...: one style of the run unless its stylize.json exists.
stylize() {
  local name="$1"
  shift
  if [ -e "$run/style/$name/stylize.json" ]; then echo "[style_settings] $name: done before, kept" >&2; return; fi
  echo "[style_settings] $name: stylize $*" >&2
  "$exe" stylize --run "$run" --style "$style" --name "$name" "$@"
}
# Training seconds of a finished style: its loss.csv's last row (the closing test left out).
train_seconds() { tail -n 1 "$run/style/$1/loss.csv" | cut -d, -f3; }
last_row() { tail -n 1 "$run/style/$1/loss.csv" | cut -d, -f1; }

stylize settings_tuned --style-setting tuned --iters "$tuned_iters" --mlp-iters "$tuned_mlp" "${spiral_args[@]}"
budget="$(train_seconds settings_tuned)"
if [ -z "$paper_iters" ]; then
  stylize settings_paper_probe --style-setting paper --iters "$probe_iters" --spiral-frames 2
  paper_iters="$(awk -v b="$budget" -v s="$(train_seconds settings_paper_probe)" -v n="$(last_row settings_paper_probe)" \
    'BEGIN { k = int(b * n / s); if (k < 10) k = 10; print k }')"
  echo "[style_settings] tuned trained ${budget} s; paper gets $paper_iters steps" >&2
fi
stylize settings_paper --style-setting paper --iters "$paper_iters" "${spiral_args[@]}"

python3 - "$run" "$out" <<'PY'
import json, sys, pathlib
run, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
rows = []
for setting in ("tuned", "paper"):
    d = run / "style" / f"settings_{setting}"
    s = json.load(open(d / "stylize.json"))
    last = open(d / "loss.csv").read().strip().splitlines()[-1].split(",")
    w, cfg = s["warp_error"], s["settings"]
    rows.append({"setting": setting, "iterations": cfg["iterations"], "mlp_iterations": cfg["mlp_iterations"],
                 "batch": cfg["batch"], "mlp_lr": cfg["mlp_lr"], "mlp_lr_final": cfg["mlp_lr_final"],
                 "mlp_init": cfg["mlp_init"], "train_seconds": float(last[2]), "final_loss": float(last[1]),
                 "test_psnr_vs_stylized": s["stage4"]["test_psnr_vs_stylized"],
                 "test_ssim_vs_stylized": s["stage4"]["test_ssim_vs_stylized"],
                 "warp_spiral_exact_flow": w["spiral_exact_flow"]["styled_render"],
                 "warp_spiral_dis": w["spiral_styled_render"], "warp_test_camera": (w["test_camera"] or {}).get("styled_render"),
                 "warp_stylized_frames_2d": w["stylized_frames_2d"], "device": s["device"],
                 "contact_sheet": str(d / "contact_sheet.png")})
json.dump({"run": str(run), "rows": rows}, open(out / "style_settings.json", "w"), indent=2)
def cell(v):
    return f"{v:.4f}" if isinstance(v, float) else "-"  # no test camera sequence (D-NeRF's test views)
md = ["| setting | steps (MLP steps) | views/step | MLP lr | train s | test PSNR vs stylized (dB) | SSIM | "
      "warp, spiral exact flow | warp, spiral DIS | warp, test camera |", "|---|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    lr = f"{r['mlp_lr']:g}" + (f" -> {r['mlp_lr_final']:g}" if r["mlp_lr_final"] else "")
    md.append(f"| {r['setting']} | {r['iterations']} ({r['mlp_iterations']}) | {r['batch']} | {lr} | {r['train_seconds']:.0f} | "
              f"{r['test_psnr_vs_stylized']:.2f} | {r['test_ssim_vs_stylized']:.3f} | {r['warp_spiral_exact_flow']:.4f} | "
              f"{r['warp_spiral_dis']:.4f} | {cell(r['warp_test_camera'])} |")
(out / "style_settings.md").write_text("\n".join(md) + "\n")
print("\n".join(md))
try:
    from PIL import Image
    sheets = [Image.open(r["contact_sheet"]).convert("RGB") for r in rows]
    w = max(s.width for s in sheets)
    both = Image.new("RGB", (w, sum(s.height for s in sheets)), (255, 255, 255))
    y = 0
    for s in sheets:
        both.paste(s, (0, y))
        y += s.height
    both.save(out / "contact_sheet.png")
except ImportError:
    print("style_settings.sh: no PIL; the two contact sheets stay in the styles' folders", file=sys.stderr)
PY

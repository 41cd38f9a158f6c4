#!/usr/bin/env bash
# A user's own capture end to end: check-data, train (stages 1-2), stylize (stages 3-4) and
# Style4D-Bench, at a chosen downscale, with the wall time and the peak resident memory of every
# stage (GNU time) next to the usual reports. Finished stages are kept: run it again to continue.
#
# Usage: bench/real_data.sh DATA OUT [--downscale N] [--frames N|A:B] [--preset P] [--style IMG]
#                           [--stage-4-iters N] [-- extra style4d train options...]
#   e.g. bench/real_data.sh ~/data/dnerf/lego out/lego --downscale 2
#        bench/real_data.sh ~/data/neu3d/coffee_martini out/coffee --downscale 4 --frames 60
# Writes OUT/check.txt, OUT/run/ (train.json, ...), OUT/run/style/NAME/stylize.json,
# OUT/bench/report.{json,md}, OUT/stages.json (seconds and peak RSS per stage) and OUT/summary.md.
set -euo pipefail
[ $# -ge 2 ] || { sed -n '2,12p' "$0" >&2; exit 2; }
data="$1" out="$2"
shift 2
root="$(cd "$(dirname "$0")/.." && pwd)"
downscale=1 frames="" preset=fast style="$root/assets/styles/builtin.png" stage4_iters=1500
while [ $# -gt 0 ]; do
  case "$1" in
    --downscale) downscale="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --preset) preset="$2"; shift 2 ;;
    --style) style="$2"; shift 2 ;;
    --stage-4-iters) stage4_iters="$2"; shift 2 ;;
    --) shift; break ;;
    *) echo "real_data.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
exe="${S4D_EXE:-$root/${S4D_BUILD_DIR:-build}/style4d}"
[ -x "$exe" ] || { echo "real_data.sh: $exe not built (tools/setup.sh style4d)" >&2; exit 2; }
command -v /usr/bin/time >/dev/null || { echo "real_data.sh: /usr/bin/time missing (apt-get install time)" >&2; exit 2; }
mkdir -p "$out"
style_name="$(basename "${style%.*}")"
stages="$out/stages.jsonl"

# Runs one stage under GNU time unless its marker file exists; appends {stage, seconds, peak_rss_mib}.
stage() {
  local name="$1" marker="$2"
  shift 2
  if [ -e "$marker" ]; then echo "[real_data] $name: done before, kept" >&2; return; fi
  echo "[real_data] $name: $*" >&2
  /usr/bin/time -f '%e %M' -o "$out/$name.time" "$@"
  read -r seconds rss_kib < "$out/$name.time"
  awk -v n="$name" -v s="$seconds" -v k="$rss_kib" 'BEGIN { printf "{\"stage\": \"%s\", \"seconds\": %s, \"peak_rss_mib\": %.1f}\n", n, s, k / 1024 }' >> "$stages"
}

frame_args=(${frames:+--frames "$frames"})
"$exe" check-data --data "$data" --downscale "$downscale" --json "$out/check.json" | tee "$out/check.txt" || {
  echo "real_data.sh: check-data found errors (listed above); fix them first" >&2; exit 1; }
stage train "$out/run/train.json" "$exe" train --data "$data" --out "$out/run" --preset "$preset" \
  --downscale "$downscale" "${frame_args[@]}" --skip-check "$@"
stage stylize "$out/run/style/$style_name/stylize.json" "$exe" stylize --run "$out/run" --style "$style" \
  --iters "$stage4_iters" --mlp-iters $((stage4_iters / 5))  # the MLPs in the last fifth, as the default 1500 / 300
stage bench "$out/bench/report.json" "$exe" bench --run "$out/run" --style "$style_name" --out "$out/bench"

python3 - "$out" "$style_name" <<'PY'
import json, sys, pathlib
out, style = pathlib.Path(sys.argv[1]), sys.argv[2]
stages = [json.loads(l) for l in open(out / "stages.jsonl")]
train = json.load(open(out / "run" / "train.json"))
stylize = json.load(open(out / "run" / "style" / style / "stylize.json"))
check = json.load(open(out / "check.json"))
summary = {"data": train["data"], "dataset": train.get("dataset"), "device": train["device"],
           "test_psnr": train["test_psnr"], "test_ssim": train["test_ssim"], "num_gaussians": train["num_gaussians"],
           "stages": stages, "check": check.get("summary", check)}
json.dump(summary, open(out / "stages.json", "w"), indent=2)
rows = "\n".join(f"| {s['stage']} | {s['seconds']:.0f} | {s['peak_rss_mib']:.0f} |" for s in stages)
d = train.get("dataset", {})
open(out / "summary.md", "w").write(
    f"# {train['data']}\n\nlayout {d.get('layout')}, capture {d.get('recipe', {}).get('capture')}, "
    f"background {d.get('background', {}).get('source')}, init {d.get('init', {}).get('method')} "
    f"({d.get('init', {}).get('points')} points), device {train['device']}\n\n"
    f"test PSNR {train['test_psnr']:.2f} dB, SSIM {train['test_ssim']:.3f}, {train['num_gaussians']} Gaussians\n\n"
    f"| stage | seconds | peak RSS (MiB) |\n|---|---|---|\n{rows}\n\n"
    f"Style4D-Bench: {out / 'bench' / 'report.md'}\n")
print(open(out / "summary.md").read())
PY

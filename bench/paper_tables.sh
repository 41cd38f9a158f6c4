#!/usr/bin/env bash
# The Style4D paper's tables from one command, on one scene: the stylization comparison (4DGS(AdaIN),
# 4DGS(AdaAttN), Style4D with the weight-free patch stylizer and with HGST, and the ablations "no
# MLPs" (--method colors) and "from scratch" (--method scratch)), scored by `style4d bench` on the
# run, and "Style Gaussians vs 4DGS on the original frames" (stage 4 trained on the content frames
# themselves, --strength 0, against the 4DGS run's own test PSNR). A method whose weights are not
# there is a row "skipped: no weights at PATH", not a failure. Finished steps are kept: run it again
# to continue or to rewrite the tables.
#
# Usage: bench/paper_tables.sh OUT [--data DIR | --run RUN] [--style IMG] [--adain-weights DIR]
#                              [--adaattn-weights DIR] [--hgst-weights DIR] [--metric-weights DIR]
#                              [--iters N] [--mlp-iters N] [--scratch-iters N] [--spiral-frames N]
#                              [--style-size N]
#                              [-- extra style4d train options...]
#   e.g. bench/paper_tables.sh out/tables --adain-weights ~/w/adain --hgst-weights ~/w/hgst
# Without --data or --run it trains the built-in scene (style4d synth) with the fast preset in
# OUT/run. Weights default to weights/adain, weights/adaattn and weights/hgst in the repository.
# --iters and --mlp-iters set stage 4 (default 1500 and 300); --scratch-iters the stage-1 length of
# the methods that retrain 4DGS (default: the run's own schedule).
# Writes OUT/paper_tables.json, OUT/paper_tables.md, OUT/bench/ (style4d bench's report) and
# OUT/logs/.
set -euo pipefail
[ $# -ge 1 ] || { sed -n '2,21p' "$0" >&2; exit 2; }
out="$1"
shift
root="$(cd "$(dirname "$0")/.." && pwd)"
data="" run="" style="$root/assets/styles/builtin.png" metric_weights="" iters=1500 mlp_iters=300 scratch_iters="" spiral="" style_size=512
adain="$root/weights/adain" adaattn="$root/weights/adaattn" hgst="$root/weights/hgst"
while [ $# -gt 0 ]; do
  case "$1" in
    --data) data="$2"; shift 2 ;;
    --run) run="$2"; shift 2 ;;
    --style) style="$2"; shift 2 ;;
    --adain-weights) adain="$2"; shift 2 ;;
    --adaattn-weights) adaattn="$2"; shift 2 ;;
    --hgst-weights) hgst="$2"; shift 2 ;;
    --metric-weights) metric_weights="$2"; shift 2 ;;
    --iters) iters="$2"; shift 2 ;;
    --mlp-iters) mlp_iters="$2"; shift 2 ;;
    --scratch-iters) scratch_iters="$2"; shift 2 ;;
    --spiral-frames) spiral="$2"; shift 2 ;;
    --style-size) style_size="$2"; shift 2 ;;
    --) shift; break ;;
    *) echo "paper_tables.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
exe="${S4D_EXE:-$root/${S4D_BUILD_DIR:-build}/style4d}"
[ -x "$exe" ] || { echo "paper_tables.sh: $exe not built (tools/setup.sh style4d)" >&2; exit 2; }
mkdir -p "$out/logs"
status="$out/status.tsv"
: > "$status"

# The run: given, trained from --data, or trained on the built-in scene.
if [ -z "$run" ]; then
  run="$out/run"
  if [ ! -e "$run/train.json" ]; then
    if [ -z "$data" ]; then
      data="$out/data"
      [ -e "$data/poses_bounds.npy" ] || "$exe" synth --out "$data" > "$out/logs/synth.log" 2>&1
    fi
    echo "[paper_tables] train: $data -> $run" >&2
    "$exe" train --data "$data" --out "$run" --preset fast "$@" > "$out/logs/train.log" 2>&1 || {
      echo "paper_tables.sh: training failed, see $out/logs/train.log" >&2; exit 1; }
  fi
fi
[ -e "$run/train.json" ] || { echo "paper_tables.sh: $run is not a trained run (no train.json)" >&2; exit 1; }

# The first weight file of FILES... missing from DIR, or nothing when all are there.
missing_weights() {
  local dir="$1"
  shift
  for f in "$@"; do [ -f "$dir/$f.safetensors" ] || { echo "$dir/$f.safetensors"; return; }; done
}

# method NAME LABEL WEIGHTS_DIR "FILES" STYLIZE_ARGS...: one row of the comparison; WEIGHTS_DIR "" for
# the weight-free stylizer. Appends "name<TAB>label<TAB>status<TAB>log" to status.tsv.
method() {
  local name="$1" label="$2" weights="$3" files="$4"
  shift 4
  local log="$out/logs/$name.log" state="ok" args=("$@")
  if [ -n "$weights" ]; then
    local lacking
    lacking="$(missing_weights "$weights" $files)"
    if [ -n "$lacking" ]; then
      state="skipped: no weights at $lacking"
    else
      args+=(--weights "$weights" --style-size "$style_size")
    fi
  fi
  # Stage 4's length, or a retraining's (method scratch takes no stage-4 options).
  if [[ " ${args[*]} " == *" --method scratch "* ]]; then
    [ -z "$scratch_iters" ] || args+=(--iters "$scratch_iters")
  else
    args+=(--iters "$iters" --mlp-iters "$mlp_iters")
  fi
  if [ "$state" = ok ] && [ ! -e "$run/style/$name/stylize.json" ]; then
    echo "[paper_tables] $name: stylize ${args[*]}" >&2
    "$exe" stylize --run "$run" --style "$style" --name "$name" ${spiral:+--spiral-frames "$spiral"} "${args[@]}" \
      > "$log" 2>&1 || state="failed: see $log"
  fi
  echo "[paper_tables] $name: $state" >&2
  printf '%s\t%s\t%s\t%s\n' "$name" "$label" "$state" "$log" >> "$status"
}

method 4dgs_adain "4DGS(AdaIN)" "$adain" "vgg_normalised decoder" --stylizer adain --method scratch
method 4dgs_adaattn "4DGS(AdaAttN)" "$adaattn" "vgg_normalised net_adaattn_3 net_transformer net_decoder" \
  --stylizer adaattn --method scratch
method style4d_patch "Style4D (patch stylizer)" "" "" --stylizer patch --method full
method style4d_hgst "Style4D (HGST)" "$hgst" "vgg_normalised decoder mcc_module" --stylizer hgst --method full
method ablation_no_mlp "ablation: no MLPs (patch)" "" "" --stylizer patch --method colors
method ablation_scratch "ablation: from scratch (patch)" "" "" --stylizer patch --method scratch
# Reconstruction: stage 4 on the content frames (strength 0 gives them back) against the 4DGS run.
method recon_style_gaussians "Style Gaussians on the original frames" "" "" --stylizer patch --strength 0 --method full

# style4d bench on the run with every finished method.
styles=()
while read -r name; do styles+=(--style "$name"); done < <(awk -F'\t' '$3 == "ok" && $1 != "recon_style_gaussians" { print $1 }' "$status")
if [ ${#styles[@]} -gt 0 ]; then
  echo "[paper_tables] bench: ${styles[*]}" >&2
  "$exe" bench --run "$run" "${styles[@]}" --out "$out/bench" ${spiral:+--spiral-frames "$spiral"} \
    ${metric_weights:+--metric-weights "$metric_weights"} > "$out/logs/bench.log" 2>&1 || {
    echo "paper_tables.sh: bench failed, see $out/logs/bench.log" >&2; exit 1; }
fi

python3 - "$run" "$out" <<'PY'
import json, sys, pathlib
run, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
rows = [dict(zip(("name", "label", "status", "log"), l.rstrip("\n").split("\t"))) for l in open(out / "status.tsv")]
bench = {}
if (out / "bench" / "report.json").exists():
    bench = {r["method"]: r for r in json.load(open(out / "bench" / "report.json"))["results"]}
# METRICS.md's keys in the paper's column order: imaging, aesthetic, consistency, style, content.
keys = ["uiqm", "clipiqa_plus", "musiq", "qalign", "musiq_paq2piq", "dists", "warp_loss", "dino_score", "ckdn",
        "style_lpips", "content_ssim", "content_lpips", "style_loss_gram"]
train = json.load(open(run / "train.json"))
table, recon = [], None
for r in rows:
    d = run / "style" / r["name"]
    if r["status"] == "ok":
        s = json.load(open(d / "stylize.json"))
        r["stylizer"], r["method"] = s["stylizer"], s["method"]
        r["test_psnr_vs_stylized"] = s["stage4"]["test_psnr_vs_stylized"]
        r["warp_spiral_exact_flow"] = s["warp_error"]["spiral_exact_flow"]["styled_render"]
        r["stage4_seconds"] = s["stage4"]["seconds"]
        if r["name"] in bench:
            r["bench"] = {k: bench[r["name"]].get(k) for k in keys}
    if r["name"] == "recon_style_gaussians":
        recon = r
    else:
        table.append(r)
recon_table = {"4dgs_test_psnr": train["test_psnr"], "4dgs_test_ssim": train["test_ssim"], "style_gaussians": recon}
json.dump({"run": str(run), "device": train["device"], "comparison": table, "reconstruction": recon_table},
          open(out / "paper_tables.json", "w"), indent=2)

def cell(v):
    if isinstance(v, (int, float)):
        return f"{v:.4g}"
    return "n/a"  # {"unavailable": why}: report.json says why
md = [f"# Style4D paper tables on {run}", "", "## Stylization comparison (style4d bench; n/a: unavailable, see bench/report.json)", "",
      "| method | status | " + " | ".join(keys) + " | stage-4 test PSNR vs stylized |",
      "|---|---|" + "---|" * (len(keys) + 1)]
for r in table:
    b = r.get("bench", {})
    md.append(f"| {r['label']} | {r['status']} | " + " | ".join(cell(b.get(k)) for k in keys) +
              f" | {cell(r.get('test_psnr_vs_stylized'))} |")
md += ["", "## Style Gaussians vs 4DGS on the original frames (test PSNR, dB)", "",
       "| 4DGS | Style Gaussians | difference |", "|---|---|---|"]
if recon and recon["status"] == "ok":
    sg = recon["test_psnr_vs_stylized"]
    md.append(f"| {train['test_psnr']:.2f} | {sg:.2f} | {sg - train['test_psnr']:+.2f} |")
else:
    md.append(f"| {train['test_psnr']:.2f} | {recon['status'] if recon else 'not run'} | |")
(out / "paper_tables.md").write_text("\n".join(md) + "\n")
print("\n".join(md))
PY

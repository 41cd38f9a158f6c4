#!/usr/bin/env bash
# How each stage's cost grows with pixels, Gaussians, cameras and frames, so a user can predict a
# full scene: seconds per iteration of static training, 4DGS fine training, stage-4 colour steps and
# stage-4 MLP steps, milliseconds per rendered frame, and each command's peak device memory, over a
# one-at-a-time grid around a base point (the built-in scene at 160x120, 10 cameras, 30 frames, an
# 8000-Gaussian budget). Prints one JSON line per point, then the fitted growth: the exponent b of
# cost = a * x^b for each stage and variable (log-log least squares), as JSON lines and a table.
#
# Usage: bench/stage_scaling.sh [OUT_DIR]    (about half an hour on two lavapipe cores; a quiet
# machine, since every number is a wall-clock time)
set -euo pipefail
out="${1:-out/stage_scaling}"
exe="${S4D_BUILD_DIR:-build}/style4d"
style="$(dirname "$0")/../assets/styles/builtin.png"
mkdir -p "$out"

# point NAME SIZE CAMS FRAMES BUDGET
point() {
  local name=$1 size=$2 cams=$3 frames=$4 budget=$5 dir="$out/$1"
  [ -f "$dir/point.json" ] && { cat "$dir/point.json"; return; }
  rm -rf "$dir" && mkdir -p "$dir"
  "$exe" synth --out "$dir/data" --size "$size" --cams "$cams" --frames "$frames" > "$dir/synth.log" 2>&1
  # Densify every 10 iterations with no gradient threshold: the budget is reached by iteration 50,
  # and the iterations after densification (150-200, fine 40-80) are timed at that count. No
  # motion split: the fine steps are timed with the field over every Gaussian, since the
  # moving share depends on the scene.
  "$exe" train --data "$dir/data" --out "$dir/run" --preset fast --iters 200 --fine-iters 80 --static-max-time 0 \
    --set densify_from=20 --set densify_every=10 --set grad_threshold=0 --set budget="$budget" \
    --set fine_densify_until=40 --static-motion 0 > "$dir/train.log" 2>&1
  "$exe" stylize --run "$dir/run" --style "$style" --name s --iters 40 --mlp-iters 20 --spiral-frames 4 > "$dir/stylize.log" 2>&1
  local t0 t1
  t0=$(date +%s.%N)
  "$exe" render --run "$dir/run" --path spiral --frames 60 --out "$dir/render" > "$dir/render.log" 2>&1
  t1=$(date +%s.%N)
  python3 - "$dir" "$name" "$size" "$cams" "$frames" "$budget" "$t0" "$t1" > "$dir/point.json" <<'PY'
import csv, json, sys
d, name, size, cams, frames, budget, t0, t1 = sys.argv[1:]
w, h = (int(v) for v in size.split("x"))

def rate(rows, lo, hi):
    """Seconds per iteration between iterations lo and hi (rows: (iteration, seconds))."""
    a = max(r for r in rows if r[0] <= lo)
    b = max(r for r in rows if r[0] <= hi)
    return (b[1] - a[1]) / (b[0] - a[0])

train = json.load(open(f"{d}/run/train.json"))
rows = list(csv.DictReader(open(f"{d}/run/loss.csv")))
static = [(int(r["iteration"]), float(r["seconds"])) for r in rows if r["stage"] == "static"]
fine = [(int(r["iteration"]), float(r["seconds"])) for r in rows if r["stage"] == "fine"]
style = json.load(open(f"{d}/run/style/s/stylize.json"))
srows = [(int(r["iteration"]), float(r["seconds"])) for r in csv.DictReader(open(f"{d}/run/style/s/loss.csv"))]
print(json.dumps({"bench": "stage_scaling", "point": name, "device": train["device"], "pixels": w * h, "width": w,
                  "height": h, "cams": int(cams), "frames": int(frames), "gaussians": train["num_gaussians"],
                  "static_s_per_it": rate(static, 150, 200), "fine_s_per_it": rate(fine, 40, 80),
                  "style_colour_s_per_it": rate(srows, 10, 20), "style_mlp_s_per_it": rate(srows, 30, 40),
                  "render_ms_per_frame": (float(t1) - float(t0)) * 1000 / 60,
                  "train_device_peak_mib": train["device_peak_mib"], "stylize_device_peak_mib": style["device_peak_mib"]}))
PY
  cat "$dir/point.json"
}

{
  point base 160x120 10 30 8000
  point px_small 80x60 10 30 8000
  point px_large 320x240 10 30 8000
  point g_small 160x120 10 30 4000
  point g_large 160x120 10 30 16000
  point cams_few 160x120 5 30 8000
  point cams_many 160x120 20 30 8000
  point frames_few 160x120 10 15 8000
  point frames_many 160x120 10 60 8000
} | tee "$out/points.jsonl"

python3 - "$out/points.jsonl" <<'PY' | tee "$out/growth.jsonl"
import json, math, sys
pts = [json.loads(l) for l in open(sys.argv[1])]
costs = ["static_s_per_it", "fine_s_per_it", "style_colour_s_per_it", "style_mlp_s_per_it", "render_ms_per_frame",
         "train_device_peak_mib", "stylize_device_peak_mib"]
groups = {"pixels": ("base", "px_small", "px_large"), "gaussians": ("base", "g_small", "g_large"),
          "cams": ("base", "cams_few", "cams_many"), "frames": ("base", "frames_few", "frames_many")}
by = {p["point"]: p for p in pts}
table = []
for var, names in groups.items():
    xs = [math.log(by[n][var]) for n in names]
    for c in costs:
        ys = [math.log(by[n][c]) for n in names]
        mx, my = sum(xs) / 3, sum(ys) / 3
        b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
        a = math.exp(my - b * mx)
        print(json.dumps({"bench": "stage_scaling_fit", "variable": var, "cost": c, "exponent": b, "coefficient": a}))
        table.append((var, c, b))
print("| cost | " + " | ".join(f"x {v}" for v in groups) + " |", file=sys.stderr)
print("|---" * (len(groups) + 1) + "|", file=sys.stderr)
for c in costs:
    print(f"| {c} | " + " | ".join(f"{b:.2f}" for v, cc, b in table if cc == c) + " |", file=sys.stderr)
PY

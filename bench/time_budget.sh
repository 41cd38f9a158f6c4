#!/usr/bin/env bash
# train --time-budget against fixed lengths, on one scene: the fast preset at three run lengths
# (a quarter, half and all of its 900 + 1500 steps; their times and PSNRs trace the iteration
# front), then a budgeted run given each fixed run's measured time. Reports per budget the time
# taken (the goal: within 10 %) and the PSNR against the front at that time (the goal: within 0.5 dB),
# in OUT/time_budget.md and OUT/points.jsonl. Finished runs are kept, so it continues where it stopped.
#
# Usage: bench/time_budget.sh DATA OUT [TRAIN OPTIONS...]   e.g. bench/time_budget.sh d out/tb --downscale 2
# Wall-clock times: run it on a quiet machine.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: bench/time_budget.sh DATA OUT [TRAIN OPTIONS...]" >&2; exit 2; }
data=$1 out=$2
shift 2
exe="${S4D_BUILD_DIR:-build}/style4d"
mkdir -p "$out"
train() {  # NAME ARGS...: trains OUT/NAME unless finished; appends its point
  local name=$1
  shift
  if [ ! -f "$out/$name/train.json" ] || ! grep -q '"complete": true' "$out/$name/train.json"; then
    rm -rf "${out:?}/$name"
    "$exe" train --data "$data" --run "$out/$name" --preset fast "$@" > "$out/$name.log" 2>&1 || [ $? -eq 3 ]
  fi
}
for f in 4 2 1; do train "fixed_$f" --iters $((900 / f)) --fine-iters $((1500 / f)) "$@"; done
for f in 4 2 1; do
  seconds=$(python3 -c "import json; print(round(json.load(open('$out/fixed_$f/train.json'))['seconds']))")
  train "budget_$f" --time-budget "${seconds}s" "$@"
done
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
def load(name):
    j = json.load(open(os.path.join(out, name, "train.json")))
    return {"name": name, "seconds": j["seconds"], "test_psnr": j["test_psnr"], "gaussians": j["num_gaussians"],
            "iterations": j["settings"]["iterations"], "fine_iterations": j["settings"]["fine_iterations"],
            "given": (j.get("time_budget") or {}).get("given_seconds")}
fixed = sorted((load(f"fixed_{f}") for f in (4, 2, 1)), key=lambda p: p["seconds"])
budget = [load(f"budget_{f}") for f in (4, 2, 1)]
def front(t):  # the best fixed-length PSNR reached by time t, linear between the fixed points
    best = None
    for a, b in zip(fixed, fixed[1:]):
        if a["seconds"] <= t <= b["seconds"]:
            best = a["test_psnr"] + (b["test_psnr"] - a["test_psnr"]) * (t - a["seconds"]) / (b["seconds"] - a["seconds"])
    if t >= fixed[-1]["seconds"]: best = fixed[-1]["test_psnr"]
    if t <= fixed[0]["seconds"]: best = fixed[0]["test_psnr"]
    return best
with open(os.path.join(out, "points.jsonl"), "w") as f:
    for p in fixed + budget: f.write(json.dumps(p) + "\n")
rows = ["| run | steps (static + 4DGS) | Gaussians | seconds | test PSNR (dB) | time vs budget | PSNR vs front |",
        "|---|---|---:|---:|---:|---:|---:|"]
for p in fixed:
    rows.append(f"| {p['name']} | {p['iterations']} + {p['fine_iterations']} | {p['gaussians']} | {p['seconds']:.0f} | {p['test_psnr']:.2f} | | |")
for p in budget:
    rows.append(f"| {p['name']} ({p['given']:.0f} s) | {p['iterations']} + {p['fine_iterations']} | {p['gaussians']} | {p['seconds']:.0f} | "
                f"{p['test_psnr']:.2f} | {100 * (p['seconds'] / p['given'] - 1):+.1f} % | {p['test_psnr'] - front(p['seconds']):+.2f} dB |")
open(os.path.join(out, "time_budget.md"), "w").write("\n".join(rows) + "\n")
print("\n".join(rows))
PY

#!/usr/bin/env bash
# tools/gpu-check.sh --small on lavapipe, so the GPU check cannot rot between lent GPUs: every step
# runs, and each figure in gpu-check.json is the value in the output it comes from. A second run with
# a 4-second budget records its steps as cut short or not run, and its missing figures as null.
# Usage: test_gpu_check_small.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if ! "$src/tools/gpu-check.sh" "$work/full" --small --bin "$build"; then
  echo "FAIL: gpu-check.sh --small failed:"; cat "$work/full/steps.tsv"
  for f in "$work"/full/logs/*.log; do echo "== $f"; tail -20 "$f"; done
  exit 1
fi
"$src/tools/gpu-check.sh" "$work/cut" --small --bin "$build" --budget 4 || true

python3 - "$work/full" "$work/cut" <<'PY'
import json, os, sys
full, cut = sys.argv[1], sys.argv[2]
def load(*p):
    with open(os.path.join(*p)) as f:
        return json.load(f)
def lines(path, bench):
    with open(path) as f:
        return [json.loads(l) for l in f if l.startswith("{") and json.loads(l).get("bench") == bench]
errors = []
def check(ok, what):
    if not ok:
        errors.append(what)
r = load(full, "gpu-check.json")
steps = {s["step"]: s for s in r["steps"]}
for name in ["devices", "gpu_tests", "synth", "train", "make_style", "stylize", "bench", "viewer",
             "viewer_orbit", "bench_splat", "bench_deform"]:
    check(steps.get(name, {}).get("status") == "ok", f"step {name}: {steps.get(name)}")
# The demo has a minute at --small (its stage 3 is full size): done, or stopped at its cap.
check(steps["demo"]["status"] in ("ok", "cut short"), f"demo: {steps['demo']}")
chosen = [d for d in load(full, "devices.json") if d["chosen"]][0]
check(r["device"]["name"] == chosen["name"], "device name")
f = r["figures"]
demo = load(full, "demo", "demo.json") if steps["demo"]["status"] == "ok" else None
train = load(full, "object_run", "train.json")
stylize = load(full, "object_run", "style", "builtin", "stylize.json")
check(f["demo_seconds"] == (demo["seconds"] if demo else None), "demo_seconds")
check(f["train_default_seconds"] == train["seconds"], "train seconds")
check(f["train_default_test_psnr"] == train["test_psnr"], "train PSNR")
check(train["settings"]["preset"] == "default", "the workload trains --preset default")
sm = train["stage_ms"]
check(abs(f["train_step_ms"] - sm["step_ms"] / sm["iterations"]) < 1e-9, "step ms")
check(f["stage4_seconds"] == stylize["stage4"]["seconds"], "stage 4 seconds")
viewer = lines(os.path.join(full, "logs", "viewer.log"), "viewer_frame")[0]
check(f["viewer_fps"] == viewer["fps_p50"] and f["viewer_size"] == "160x120", "viewer fps")
check(len(r["bench_splat"]) > 0 and len(r["bench_deform"]) > 0, "bench lines")
md = open(os.path.join(full, "gpu-check.md")).read()
check(chosen["name"] in md and "| train | ok |" in md, "markdown table")
c = load(cut, "gpu-check.json")
statuses = [s["status"] for s in c["steps"]]
# The step running when the budget ran out is stopped, the later ones never start: ok steps, at most
# one cut short, then steps not run. A fast machine may finish a step just as the budget runs out, so
# that none is cut short; then the steps that ran used the budget (to the whole second the script counts).
done = [s for s in c["steps"] if s["status"] in ("ok", "cut short")]
rest = statuses[len(done):]
check(all(s == "ok" for s in statuses[:len(done) - 1]), f"only the last step that ran is cut short: {statuses}")
check(len(rest) > 0 and all(s == "not run (the budget was spent)" for s in rest),
      f"the steps after the budget ran out are not run: {statuses}")
if "cut short" not in statuses:
    check(sum(float(s["seconds"]) for s in done) >= 4 - 1, f"no step cut short, yet the budget was not spent: {c['steps']}")
check(c["figures"]["demo_seconds"] is None and c["figures"]["train_default_seconds"] is None, "cut run leaves figures null")
for e in errors:
    print("FAIL:", e)
sys.exit(1 if errors else 0)
PY
echo "gpu-check --small: $(awk -F'\t' 'NR > 1 { s += $3 } END { print s }' "$work/full/steps.tsv") s of steps"

#!/usr/bin/env bash
# Soak: a long training run on the built-in scene with its memory sampled throughout, to show that
# nothing grows with the iteration count. Samples every few seconds the process's resident memory
# (on lavapipe the "device" memory is host memory, so it is inside this too) and the device memory
# its buffers hold (the progress line's device_mib), writes soak.csv, soak.svg (both against the
# iteration) and soak.json with each stage's growth after its Gaussian count last changed
# (densification over). Further arguments go to `style4d train` (e.g. --set densify_until=200).
#
# Usage: bench/soak.sh [OUT_DIR] [STATIC_ITERS] [FINE_ITERS] [WxH] [TRAIN_OPTION...]
#   default 10000 + 10000 = 20,000 iterations of the built-in scene at its 160x120 (hours on two
#   lavapipe cores; minutes on a GPU)
set -euo pipefail
out="${1:-out/soak}"
static_iters="${2:-10000}"
fine_iters="${3:-10000}"
size="${4:-160x120}"
shift $(( $# < 4 ? $# : 4 ))
exe="${S4D_BUILD_DIR:-build}/style4d"
here=$(cd "$(dirname "$0")" && pwd)
[ ! -e "$out/run" ] || { echo "soak: $out/run exists; choose another OUT_DIR" >&2; exit 1; }
mkdir -p "$out"
[ -d "$out/data" ] || "$exe" synth --out "$out/data" --size "$size" > "$out/synth.log" 2>&1
# Densification stops at the preset's point in each stage; no checkpoints in between to keep the
# samples about training, a test every 1000 iterations as a long run would have.
"$exe" train --data "$out/data" --out "$out/run" --preset fast --iters "$static_iters" --fine-iters "$fine_iters" \
  --checkpoint-every 100000 --set test_every=1000 "$@" > "$out/train.log" 2>&1 &
pid=$!
echo "seconds,stage,iteration,rss_mib,device_mib,gaussians" > "$out/soak.csv"
start=$(date +%s)
while kill -0 $pid 2>/dev/null; do
  sleep 5
  rss_kib=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
  [ -n "$rss_kib" ] || break
  # The newest progress line (from the log's end only: the log grows with the run): "[stage] ITER/TOTAL ... gaussians=N device_mib=M ..."
  line=$(tail -c 4096 "$out/train.log" | tr '\r' '\n' | grep -E '^\[(static|fine)\] [0-9]+/' | tail -1 || true)
  [ -n "$line" ] || continue
  stage=$(sed -E 's/^\[([a-z]+)\].*/\1/' <<< "$line")
  iter=$(sed -E 's/^\[[a-z]+\] ([0-9]+)\/.*/\1/' <<< "$line")
  device=$(grep -oE 'device_mib=[0-9.e+]+' <<< "$line" | cut -d= -f2 || true)
  gaussians=$(grep -oE 'gaussians=[0-9]+' <<< "$line" | cut -d= -f2 || true)
  [ -n "$device" ] && [ -n "$gaussians" ] || continue  # a stage's closing line carries its results instead
  echo "$(( $(date +%s) - start )),$stage,$iter,$(awk -v k="$rss_kib" 'BEGIN {printf "%.1f", k / 1024}'),$device,$gaussians" >> "$out/soak.csv"
done
wait $pid || { tail -5 "$out/train.log"; echo "soak: training failed" >&2; exit 1; }
python3 "$here/soak_plot.py" "$out/soak.csv" "$out/soak.svg" "$out/soak.json"
cat "$out/soak.json"

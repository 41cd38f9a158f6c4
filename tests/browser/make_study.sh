#!/usr/bin/env bash
# A small study from the built-in scene and style, through the real commands: synth, train,
# stylize (Part 1's methods: stage 4 "full" and "colors"), bench --run; stylize-frames at two
# strengths on one camera and bench's frames mode (Part 2); then study plan. Tiny sizes: about a
# minute on 2 cores with lavapipe.
# Usage: make_study.sh STYLE4D OUT [PARTICIPANTS]   (OUT/study is the study; reused when present)
set -euo pipefail
style4d=$1
out=$2
participants=${3:-24}
here=$(cd "$(dirname "$0")" && pwd)
style=$here/../../assets/styles/builtin.png
if [ -f "$out/study/study.json" ]; then exit 0; fi
rm -rf "$out"
mkdir -p "$out"
log=$out/make_study.log
run() { echo "+ style4d $*" >>"$log"; "$style4d" "$@" >>"$log" 2>&1 || { echo "make_study.sh: style4d $1 failed:" >&2; tail -20 "$log" >&2; exit 1; }; }
run synth --out "$out/data" --cams 3 --frames 6 --size 48x36
run train --data "$out/data" --out "$out/run" --preset fast --iters 30 --fine-iters 30
run stylize --run "$out/run" --style "$style" --name full --iters 30 --mlp-iters 10 --spiral-frames 12
run stylize --run "$out/run" --style "$style" --name colors --method colors --iters 30 --mlp-iters 10 --spiral-frames 12
run bench --run "$out/run" --style full --style colors --spiral-frames 12 --out "$out/bench_4d"
cam=$(ls -d "$out/data"/cam00* | head -1)
run stylize-frames --in "$cam" --style "$style" --out "$out/frames/patch" --strength 1
run stylize-frames --in "$cam" --style "$style" --out "$out/frames/patch_half" --strength 0.5
run bench --frames "$out/frames/patch" --name patch --frames "$out/frames/patch_half" --name patch_half \
  --original "$cam" --style-image "$style" --scene synth --out "$out/bench_video"
run study plan --bench "$out/bench_4d" --bench "$out/bench_video" --out "$out/study" --participants "$participants" --seed 1 --fps 8

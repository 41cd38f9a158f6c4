#!/bin/bash
# The windowed viewer while the mouse orbits the camera: `style4d view RUN` at 640x480 under Xvfb
# while xdotool holds the left button and drags, until the viewer has presented FRAMES frames.
# Prints the viewer's summary line (frames presented, frames rasterized, their mean scale and mean
# time from render to pixels on screen). Needs xvfb-run and xdotool (apt-get install xvfb xdotool).
#
#   xvfb-run -a -s "-screen 0 800x600x24" bench/viewer_drag.sh STYLE4D RUN BUDGET_MS FRAMES
set -euo pipefail
[ $# -eq 4 ] || { echo "usage: xvfb-run -a bench/viewer_drag.sh STYLE4D RUN BUDGET_MS FRAMES" >&2; exit 2; }
out=$(mktemp -d)
"$1" view "$2" --size 640x480 --exit-after "$4" --frame-budget-ms "$3" --out-dir "$out" > "$out/view.log" 2>&1 &
viewer=$!
window=$(xdotool search --sync --name "style4d view")
xdotool mousemove --window "$window" 320 240 mousedown 1
while kill -0 "$viewer" 2> /dev/null; do xdotool mousemove_relative -- 4 0 || true; sleep 0.01; done
xdotool mouseup 1 || true
wait "$viewer" || { cat "$out/view.log" >&2; exit 1; }
tail -1 "$out/view.log"
rm -rf "$out"

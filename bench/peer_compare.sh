#!/usr/bin/env bash
# Like for like against a peer, the pure-PyTorch rasterizer hbb1/torch-splatting: both draw
# the same scene files (s4d_bench_splat --write-peer-scene) from camera 0, forward + backward to
# every parameter, in alternating rounds of the same run, so the machine's load falls on both.
#
#   bench/peer_compare.sh PEER_CHECKOUT [OUT_DIR] [ROUNDS] [REPEATS] [CONFIGS]
#
# PEER_CHECKOUT is a clone of hbb1/torch-splatting (not part of this project, nothing is
# downloaded). CONFIGS is a space-separated list of GAUSSIANS:WxH (default the issue's two sizes).
# Writes OUT_DIR/peer_compare.jsonl (every run's JSON line) and OUT_DIR/peer_compare.md (the table
# of medians over the rounds and the ratio peer / project). PYTHON picks the interpreter (with
# torch); PEER_THREADS sets the peer's torch threads (0 keeps torch's default).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
peer=${1:?usage: bench/peer_compare.sh PEER_CHECKOUT [OUT_DIR] [ROUNDS] [REPEATS] [CONFIGS]}
out=${2:-out/peer_compare}
rounds=${3:-2}
repeats=${4:-5}
configs=${5:-"1000:128x128 10000:256x256"}
python=${PYTHON:-python3}
bench=${S4D_BENCH_SPLAT:-$here/build/s4d_bench_splat}
[ -x "$bench" ] || { echo "peer_compare: $bench: not built (cmake --build build --target s4d_bench_splat)" >&2; exit 1; }
[ -f "$peer/gaussian_splatting/gauss_render.py" ] || { echo "peer_compare: $peer: not a checkout of hbb1/torch-splatting (no gaussian_splatting/gauss_render.py)" >&2; exit 1; }
mkdir -p "$out"
log=$out/peer_compare.jsonl
: > "$log"; : > "$out/project_stderr.log"
for config in $configs; do
  gaussians=${config%%:*} size=${config#*:}
  scene=$out/scene_${gaussians}_${size}
  "$bench" --write-peer-scene "$scene" --gaussians "$gaussians" --size "$size" > /dev/null
  for round in $(seq 1 "$rounds"); do
    echo "[peer_compare] $gaussians Gaussians, $size, round $round of $rounds" >&2
    "$bench" --ply "$scene/points.ply" --cameras "$scene/transforms.json" --camera 0 --repeats "$repeats" --only fwdbwd 2>> "$out/project_stderr.log" \
      | grep '"bench":"splat_raster"' | sed "s/^{/{\"side\":\"project\",\"round\":$round,/" >> "$log"
    "$python" "$here/bench/peer_torch_splatting.py" --peer "$peer" --scene "$scene" --repeats "$repeats" \
      --threads "${PEER_THREADS:-0}" | grep '"pass": "fwdbwd"' | sed "s/^{/{\"side\":\"peer\",\"round\":$round,/" >> "$log"
  done
done
"$python" - "$log" "$out/peer_compare.md" <<'EOF'
import json, statistics, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
table = ["| image | Gaussians | tile instances | peer fwd+bwd ms | project fwd+bwd ms | peer / project |",
         "|---|---|---|---|---|---|"]
keys = sorted({(r["n_gaussians"], r["width"], r["height"]) for r in rows})
for n, w, h in keys:
    side = lambda s: [r for r in rows if r["side"] == s and (r["n_gaussians"], r["width"], r["height"]) == (n, w, h)]
    peer = statistics.median(r["ms_wall_p50"] for r in side("peer"))
    ours = statistics.median(r["ms_wall_p50"] for r in side("project"))
    instances = side("project")[0]["instances"]
    table.append(f"| {w}x{h} | {n:,} | {instances:,} | {peer:.1f} | {ours:.1f} | {peer / ours:.1f}x |")
open(sys.argv[2], "w").write("\n".join(table) + "\n")
print("\n".join(table))
EOF

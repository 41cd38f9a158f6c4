// A stand-in for tools/pyiqa_bridge.py that the bridge tests write: plain python3, no pyiqa, no
// third-party modules. It decodes the request's 8-bit PNG frames itself (zlib + the five PNG row
// filters) and answers with numbers a test can recompute: per-frame keys get the frame's mean value
// in [0, 1], pair keys (dists, dino_score) the mean |f_i+1 - f_i|, ckdn the frame's mean minus the
// style image's. MODE in the environment variable S4D_STAND_IN_MODE changes its behaviour:
// "crash" (prints to stderr, exits 3), "error" (musiq reports an error), "seq_error" (ckdn fails on
// sequence seq0 only), "short" (one value too few for clipiqa_plus), "garbage" (writes invalid JSON).
#pragma once

namespace s4d::test {

inline const char* kBridgeStandIn = R"py(
import json, os, struct, sys, zlib

def png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, w, h, ctype = 8, b"", 0, 0, 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and ctype in (2, 6), (path, depth, ctype)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    bpp = 3 if ctype == 2 else 4
    raw, stride, rows, prev = zlib.decompress(idat), w * bpp, [], bytearray(w * bpp)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], (prev[i - bpp] if i >= bpp else 0)
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return [line[i] / 255.0 for line in rows for i in range(stride) if i % bpp < 3]

def mean(v): return sum(v) / len(v)

mode = os.environ.get("S4D_STAND_IN_MODE", "")
if mode == "crash":
    sys.stderr.write("stand-in: boom\n")
    sys.exit(3)
req = json.load(open(sys.argv[1]))
assert req["protocol"] == "s4d-pyiqa-bridge/1"
out = {"protocol": req["protocol"], "results": {}, "errors": {}, "versions": {"stand_in": "1"}}
for seq in req["sequences"]:
    frames = [png(f) for f in seq["frames"]]
    res = out["results"].setdefault(seq["id"], {})
    for key in seq["metrics"]:
        if key in ("dists", "dino_score"):
            res[key] = [mean([abs(x - y) for x, y in zip(frames[i + 1], frames[i])]) for i in range(len(frames) - 1)]
        elif key == "ckdn":
            style = mean(png(seq["style_image"]))
            res[key] = [mean(f) - style for f in frames]
        else:
            res[key] = [mean(f) for f in frames]
if mode == "error":
    out["errors"]["musiq"] = "no MUSIQ weights here"
if mode == "seq_error":
    out["results"]["seq0"]["ckdn"] = {"error": "frame 2 is unreadable"}
if mode == "short":
    for res in out["results"].values(): res["clipiqa_plus"] = res["clipiqa_plus"][:-1]
with open(req["output"], "w") as f:
    f.write("{not json" if mode == "garbage" else json.dumps(out))
)py";

}  // namespace s4d::test

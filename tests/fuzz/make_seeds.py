#!/usr/bin/env python3
"""Writes the fuzz seed corpus: a few tiny valid files per reader into OUT/<target>/ (python3 standard
library only; nothing binary is committed).

    make_seeds.py OUT
"""
import json
import os
import struct
import sys
import zlib


def ply(n, degree):
    rest = 3 * ((degree + 1) ** 2 - 1)
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"]
    names += ["f_rest_%d" % j for j in range(rest)]
    names += ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    head = "ply\nformat binary_little_endian 1.0\ncomment seed\nelement vertex %d\n" % n
    head += "".join("property float %s\n" % p for p in names) + "end_header\n"
    body = b"".join(struct.pack("<%df" % len(names), *[0.1 * (i + k) for k in range(len(names))]) for i in range(n))
    return head.encode() + body


def ply_extra():
    # Doubles, shuffled order, an extra element with a list property before 'vertex'.
    names = ["rot_0", "rot_1", "rot_2", "rot_3", "x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity",
             "scale_0", "scale_1", "scale_2", "extra"]
    head = "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
    head += "element vertex 1\n" + "".join("property double %s\n" % p for p in names) + "end_header\n"
    return head.encode() + struct.pack("<B3i", 3, 0, 1, 2) + struct.pack("<%dd" % len(names), *range(len(names)))


def npy(descr, shape, values, version=1):
    header = "{'descr': '%s', 'fortran_order': False, 'shape': %s, }" % (descr, repr(tuple(shape)))
    size_len = 2 if version == 1 else 4
    total = 6 + 2 + size_len + len(header) + 1
    header += " " * ((64 - total % 64) % 64) + "\n"
    size = struct.pack("<H" if version == 1 else "<I", len(header))
    fmt = {"f8": "d", "f4": "f"}[descr[1:]]
    return b"\x93NUMPY" + bytes([version, 0]) + size + header.encode() + struct.pack("<%d%s" % (len(values), fmt), *values)


def safetensors():
    f32 = struct.pack("<6f", 1, 2, 3, 4, 5, 6)
    f16 = struct.pack("<2e", 0.5, -2.0)
    bf16 = struct.pack("<2H", 0x3F80, 0xC000)
    header = {
        "__metadata__": {"format": "pt"},
        "w": {"dtype": "F32", "shape": [2, 3], "data_offsets": [0, 24]},
        "h": {"dtype": "F16", "shape": [2], "data_offsets": [24, 28]},
        "b": {"dtype": "BF16", "shape": [2], "data_offsets": [28, 32]},
        "i": {"dtype": "I64", "shape": [], "data_offsets": [32, 40]},
    }
    text = json.dumps(header).encode()
    text += b" " * ((8 - len(text) % 8) % 8)
    return struct.pack("<Q", len(text)) + text + f32 + f16 + bf16 + struct.pack("<q", 7)


def nerf(per_frame):
    ident = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 2], [0, 0, 0, 1]]
    if per_frame:
        frames = [{"file_path": "./train/r_%03d" % i, "transform_matrix": ident, "fl_x": 10, "fl_y": 11,
                   "cx": 4, "cy": 3, "w": 8, "h": 6, "time": i / 2} for i in range(3)]
        return json.dumps({"frames": frames}).encode()
    frames = [{"file_path": "./test/r_%03d" % i, "rotation": 0.1, "time": i / 2, "transform_matrix": ident}
              for i in range(2)]
    return json.dumps({"camera_angle_x": 0.69, "frames": frames}).encode()


def png_chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def png(width, height, depth, color, row_bytes, extra=b""):
    raw = b"".join(b"\x00" + bytes((x * 37 + y * 11) & 0xFF for x in range(row_bytes)) for y in range(height))
    return (b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, depth, color, 0, 0, 0))
            + extra + png_chunk(b"IDAT", zlib.compress(raw)) + png_chunk(b"IEND", b""))


def fnv1a64(data):
    h = 14695981039346656037
    for b in data:
        h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h


def checkpoint(version, n=1, extra=True):
    widths = {"means": 3, "log_scales": 3, "quats": 4, "opacity_logits": 1, "sh": 3}
    arrays = []
    for a in ["means", "log_scales", "quats", "opacity_logits", "sh"]:
        arrays.append((a, n * widths[a]))
    for a in ["means", "log_scales", "quats", "opacity_logits", "sh"]:
        arrays.append((a + ".adam_m", n * widths[a]))
        arrays.append((a + ".adam_v", n * widths[a]))
    arrays += [("grad_accum", n), ("grad_count", n), ("max_radius", n)]
    if extra:
        arrays.append(("deform.weights", 2))
    listed, body = [], b""
    for name, floats in arrays:
        data = struct.pack("<%df" % floats, *[0.25 * k for k in range(floats)])
        listed.append({"name": name, "floats": floats, "fnv1a64": "%016x" % fnv1a64(data)})
        body += data
    header = json.dumps({"meta": {"iteration": 3, "stage": "coarse"}, "sh_degree": 0, "count": n,
                         "arrays": listed}, separators=(",", ":")).encode()
    if version == 1:
        return b"S4DCKPT1" + struct.pack("<Q", len(header)) + header + body
    return b"S4DCKPT2" + struct.pack("<QQ", len(header), fnv1a64(header)) + header + body


def main():
    out = sys.argv[1]
    seeds = {
        "fuzz_ply": {"deg0.ply": ply(2, 0), "deg1.ply": ply(1, 1), "extra.ply": ply_extra()},
        "fuzz_npy": {"f8.npy": npy("<f8", [2, 3], [1, 2, 3, 4, 5, 6]), "f4.npy": npy("<f4", [4], [1, 2, 3, 4]),
                     "v2.npy": npy("<f8", [1, 17], list(range(17)), version=2)},
        "fuzz_safetensors": {"mixed.safetensors": safetensors()},
        "fuzz_nerf_cameras": {"dnerf.json": nerf(False), "ngp.json": nerf(True)},
        "fuzz_png": {"rgb8.png": png(3, 2, 8, 2, 9), "gray16.png": png(2, 2, 16, 0, 4),
                     "pal.png": png(2, 2, 8, 3, 2, png_chunk(b"PLTE", bytes(range(12 * 3))[:3 * 4] * 1)
                                    + png_chunk(b"tRNS", b"\x80\xff")),
                     "ga.png": png(2, 1, 8, 4, 4), "rgba16.png": png(1, 1, 16, 6, 8)},
        "fuzz_checkpoint": {"v1.ckpt": checkpoint(1), "v2.ckpt": checkpoint(2, extra=False)},
    }
    for target, files in seeds.items():
        os.makedirs(os.path.join(out, target), exist_ok=True)
        for name, data in files.items():
            with open(os.path.join(out, target, name), "wb") as f:
                f.write(data)


if __name__ == "__main__":
    main()

"""The corpus's building blocks (make_corpus.py): the case list and its recorder, writers of the
damaged files (PNG, npy, safetensors, PLY, NeRF cameras) and editors of checkpoints and JSON.
python3 standard library only."""
import json
import os
import shutil
import struct
import zlib

CASES = []


def case(name, reader, cmd, expect, build=None, exit=1, untouched=(), known_failure=None):
    c = {"name": name, "reader": reader, "cmd": cmd, "exit": exit, "expect": expect, "untouched": list(untouched)}
    if known_failure:
        c["known_failure"] = known_failure
    CASES.append((c, build))


# ---------------------------------------------------------------------------------------------
# Writers of small valid or damaged files.

def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def read(path):
    with open(path, "rb") as f:
        return f.read()


def png_chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)


def png(w, h, color_type=2, depth=8, ihdr_w=None, ihdr_h=None):
    channels = {0: 1, 2: 3, 4: 2, 6: 4}[color_type]
    row = bytes([0]) + bytes((x * 7) % 256 for x in range(w * channels * depth // 8))
    raw = row * h
    ihdr = struct.pack(">IIBBBBB", ihdr_w if ihdr_w is not None else w, ihdr_h if ihdr_h is not None else h,
                       depth, color_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) + png_chunk(b"IDAT", zlib.compress(raw)) +
            png_chunk(b"IEND", b""))


def npy(shape, descr="<f8", values=None, fortran=False, magic=b"\x93NUMPY", header_extra=""):
    count = 1
    for s in shape:
        count *= s
    fmt = {"<f8": "<d", "<f4": "<f", "<i4": "<i", ">f8": ">d"}[descr]
    values = values if values is not None else [0.5] * count
    body = b"".join(struct.pack(fmt, v) for v in values)
    shape_text = "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
    header = "{'descr': '%s', 'fortran_order': %s, 'shape': %s, %s}" % (descr, "True" if fortran else "False",
                                                                        shape_text, header_extra)
    header += " " * ((64 - (len(header) + 11) % 64) % 64) + "\n"
    return magic + b"\x01\x00" + struct.pack("<H", len(header)) + header.encode() + body


def safetensors(tensors, header_patch=None, data_extra=b"", header_len=None):
    """tensors: list of (name, dtype, shape, values as float list)."""
    header, data = {}, b""
    for name, dtype, shape, values in tensors:
        fmt = {"F32": "<f", "F16": "<e", "I64": "<q"}[dtype]
        body = b"".join(struct.pack(fmt, v) for v in values)
        header[name] = {"dtype": dtype, "shape": shape, "data_offsets": [len(data), len(data) + len(body)]}
        data += body
    if header_patch:
        header_patch(header)
    text = json.dumps(header).encode() if not isinstance(header, bytes) else header
    return struct.pack("<Q", header_len if header_len is not None else len(text)) + text + data + data_extra


def ply(props, rows, fmt="binary_little_endian", count=None, extra_header="", body_cut=None):
    header = "ply\nformat %s 1.0\n%selement vertex %d\n" % (fmt, extra_header, len(rows) if count is None else count)
    header += "".join("property float %s\n" % p for p in props) + "end_header\n"
    if fmt == "ascii":
        body = "".join(" ".join(repr(v) for v in r) + "\n" for r in rows).encode()
    else:
        body = b"".join(struct.pack("<%df" % len(r), *r) for r in rows)
    if body_cut is not None:
        body = body[:body_cut]
    return header.encode() + body


GAUSS_PROPS = (["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1",
                "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"])


def gauss_row(i, **over):
    r = dict(x=0.1 * i, y=0.0, z=0.0, nx=0, ny=0, nz=0, f_dc_0=0.5, f_dc_1=0.5, f_dc_2=0.5, opacity=0.0,
             scale_0=-3.0, scale_1=-3.0, scale_2=-3.0, rot_0=1.0, rot_1=0.0, rot_2=0.0, rot_3=0.0)
    r.update(over)
    return [r[p] for p in GAUSS_PROPS]


def gauss_ply(n=8, props=GAUSS_PROPS, **kw):
    bad = kw.pop("bad", {})
    rows = [[gauss_row(i, **(bad if i == n - 1 else {}))[GAUSS_PROPS.index(p)] for p in props] for i in range(n)]
    return ply(props, rows, **kw)


def cameras_json(frames=None, **top):
    c = {"camera_angle_x": 0.8, "w": 32, "h": 24,
         "frames": frames if frames is not None else
         [{"file_path": "./f0", "transform_matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 3], [0, 0, 0, 1]]}]}
    c.update(top)
    return json.dumps(c, indent=1)


def copytree(src, dst):
    shutil.copytree(src, dst, symlinks=False)


def flip_bit(path, at, bit=0x10):
    b = bytearray(read(path))
    b[at if at >= 0 else len(b) + at] ^= bit
    write(path, bytes(b))


def truncate(path, keep):
    b = read(path)
    write(path, b[:keep if keep >= 0 else len(b) + keep])


def fnv1a64(data):
    h = 0xcbf29ce484222325
    for byte in data:
        h = ((h ^ byte) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return h


def edit_checkpoint(path, fn):
    """Edits an S4DCKPT2 checkpoint (magic, u64 header length, u64 header FNV-1a, JSON header, the
    arrays' floats in header order) through fn(header, {name: bytearray}) and signs it again."""
    b = read(path)
    assert b[:8] == b"S4DCKPT2"
    (n,) = struct.unpack("<Q", b[8:16])
    header = json.loads(b[24:24 + n])
    arrays, at = {}, 24 + n
    for a in header["arrays"]:
        arrays[a["name"]] = bytearray(b[at:at + 4 * a["floats"]])
        at += 4 * a["floats"]
    old = {k: bytes(v) for k, v in arrays.items()}
    fn(header, arrays)
    for a in header["arrays"]:
        if a["name"] in arrays and bytes(arrays[a["name"]]) != old.get(a["name"]):
            a["fnv1a64"] = "%016x" % fnv1a64(arrays[a["name"]])
    text = json.dumps(header).encode()
    body = b"".join(bytes(arrays[a["name"]]) for a in header["arrays"] if a["name"] in arrays)
    write(path, b"S4DCKPT2" + struct.pack("<QQ", len(text), fnv1a64(text)) + text + body)


def edit_json(path, fn):
    with open(path) as f:
        j = json.load(f)
    fn(j)
    write(path, json.dumps(j, indent=2))


# ---------------------------------------------------------------------------------------------

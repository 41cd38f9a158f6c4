#!/usr/bin/env python3
"""The bad-input corpus: writes every case's damaged inputs into OUT/<case>/ and the case list into
OUT/cases.json (python3 standard library only; nothing binary is committed).

    make_corpus.py --exe build/style4d --out DIR      build the corpus (about 5 s)
    make_corpus.py --list FILE                       write the case list alone (tests/corpus/cases.json)

Valid bases are made once with the program itself (OUT/_base: a 32x24 DyNeRF and D-NeRF scene, a
20-iteration static run, its PLY, a style image) and copied into each case before it is damaged.

Each case: name, reader, cmd (placeholders {EXE}: the program, {CASE}: the case folder, {BASE}:
OUT/_base), exit (the expected exit code), expect (a regex the one "style4d CMD: error: ..." line
on stderr must match: the file and the field), untouched (files under {CASE} that must be
byte-identical afterwards) and, for a case the program fails today, known_failure (why; the runner
skips it).
"""
import argparse
import json
import os
import shutil
import struct
import subprocess
import sys

from corpus_builders import (CASES, GAUSS_PROPS, case, cameras_json, copytree, edit_checkpoint, edit_json,  # noqa: F401
                             flip_bit, fnv1a64, gauss_ply, gauss_row, npy, ply, png, png_chunk, read, safetensors,
                             truncate, write)

# The cases. Each builder gets (case folder, base folder).

RENDER_PLY = "{EXE} render --ply {CASE}/g.ply --cameras {CASE}/transforms.json --out {CASE}/out"


def ply_case(name, data, expect, exit=1):
    def build(d, base):
        write(d + "/g.ply", data)
        write(d + "/transforms.json", cameras_json())
    case(name, "ply", RENDER_PLY, expect, build, exit, untouched=["g.ply"])


def define_ply():
    ply_case("ply_empty_file", b"", r"g\.ply: not a PLY file")
    ply_case("ply_no_magic", b"plx\nformat ascii 1.0\nend_header\n", r"g\.ply: not a PLY file")
    ply_case("ply_header_truncated", b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n",
             r"g\.ply: truncated header")
    ply_case("ply_unknown_format", gauss_ply(fmt="binary_middle_endian"), r"g\.ply: header line 2 .*unknown format")
    ply_case("ply_count_not_integer", b"ply\nformat binary_little_endian 1.0\nelement vertex -4\nend_header\n",
             r"g\.ply: header line 3 .*count '-4'")
    ply_case("ply_unknown_property_type", b"ply\nformat binary_little_endian 1.0\nelement vertex 1\n"
             b"property float128 x\nend_header\n", r"g\.ply: header line 4 .*unknown type 'float128'")
    ply_case("ply_property_twice", b"ply\nformat binary_little_endian 1.0\nelement vertex 1\n"
             b"property float x\nproperty float x\nend_header\n", r"g\.ply: .*property 'x' declared twice")
    ply_case("ply_binary_truncated_body", gauss_ply(8, body_cut=8 * 17 * 4 - 10), r"g\.ply: truncated")
    ply_case("ply_binary_count_lies_high", gauss_ply(8, count=1000), r"g\.ply: truncated")
    ply_case("ply_binary_count_lies_low", gauss_ply(8, count=3), r"g\.ply: 340 bytes follow the 3 vertices the header declares")
    ply_case("ply_missing_opacity", gauss_ply(8, props=[p for p in GAUSS_PROPS if p != "opacity"]),
             r"g\.ply: missing property 'opacity'")
    ply_case("ply_missing_rotation", gauss_ply(8, props=[p for p in GAUSS_PROPS if p != "rot_3"]),
             r"g\.ply: missing property 'rot_3'")
    ply_case("ply_binary_nan_position", gauss_ply(8, bad={"x": float("nan")}),
             r"g\.ply: vertex 7 property 'x' is not finite")
    ply_case("ply_binary_inf_scale", gauss_ply(8, bad={"scale_1": float("inf")}),
             r"g\.ply: vertex 7 property 'scale_1' is not finite")
    # ASCII PLYs are refused by format before their body is read (3DGS files are binary).
    ascii = r"g\.ply: format ascii is not supported"
    ply_case("ply_ascii_nan_opacity", gauss_ply(8, fmt="ascii", bad={"opacity": float("nan")}), ascii)
    ply_case("ply_ascii_truncated", gauss_ply(8, fmt="ascii", body_cut=200), ascii)
    ply_case("ply_ascii_count_lies_high", gauss_ply(8, fmt="ascii", count=20), ascii)
    ply_case("ply_ascii_not_a_number", ply(GAUSS_PROPS, [gauss_row(0)], fmt="ascii")[:-4] + b"abc\n", ascii)
    ply_case("ply_zero_rotation", gauss_ply(8, bad={"rot_0": 0.0}), r"g\.ply: vertex 7 .*rot")

    # A real PLY from export-ply, damaged.
    def real(name, damage, expect):
        def build(d, base):
            shutil.copy(base + "/g.ply", d + "/g.ply")
            damage(d + "/g.ply")
            write(d + "/transforms.json", cameras_json())
        case(name, "ply", RENDER_PLY, expect, build, 1, untouched=["g.ply"])
    real("ply_export_truncated_half", lambda p: truncate(p, len(read(p)) // 2), r"g\.ply: truncated")
    real("ply_export_nan_first_vertex", lambda p: write(p, read(p).replace(b"end_header\n", b"end_header\n\x00\x00\xc0\x7f", 1)[:-4]),
         r"g\.ply: vertex 0 property 'x' is not finite")


def cams_case(name, text, expect, size=None):
    def build(d, base):
        shutil.copy(base + "/g.ply", d + "/g.ply")
        write(d + "/transforms.json", text)
    cmd = RENDER_PLY + (" --size " + size if size else "")
    case(name, "nerf_cameras", cmd, expect, build, 1, untouched=["transforms.json"])


def define_cameras():
    m = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 3], [0, 0, 0, 1]]
    cams_case("cameras_not_json", "{\"frames\": [", r"transforms\.json: malformed JSON")
    cams_case("cameras_top_level_array", "[]", r"transforms\.json: expected a JSON object")
    cams_case("cameras_no_frames", json.dumps({"camera_angle_x": 0.8}), r"transforms\.json: missing 'frames'")
    cams_case("cameras_frames_empty", cameras_json(frames=[]), r"transforms\.json: 'frames' is empty")
    cams_case("cameras_no_focal", json.dumps({"w": 32, "h": 24, "frames": [{"file_path": "a", "transform_matrix": m}]}),
              r"transforms\.json: frames\[0\]: no focal length")
    cams_case("cameras_angle_out_of_range", cameras_json(camera_angle_x=4.0), r"transforms\.json: camera_angle_x")
    cams_case("cameras_no_size", json.dumps({"camera_angle_x": 0.8, "frames": [{"file_path": "a", "transform_matrix": m}]}),
              r"transforms\.json: frames\[0\]: no image size")
    cams_case("cameras_matrix_3x4", cameras_json(frames=[{"file_path": "a", "transform_matrix": m[:3]}]),
              r"transforms\.json: frames\[0\]\.transform_matrix: expected 4x4")
    cams_case("cameras_matrix_not_rotation",
              cameras_json(frames=[{"file_path": "a", "transform_matrix": [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 3], [0, 0, 0, 1]]}]),
              r"transforms\.json: frames\[0\]\.transform_matrix: the 3x3 part is not a rotation")
    cams_case("cameras_matrix_string", cameras_json(frames=[{"file_path": "a", "transform_matrix": "eye"}]),
              r"transforms\.json: frames\[0\]\.transform_matrix: expected 4x4")
    cams_case("cameras_no_file_path", cameras_json(frames=[{"transform_matrix": m}]),
              r"transforms\.json: frames\[0\]: missing 'file_path'")
    cams_case("cameras_time_out_of_range", cameras_json(frames=[{"file_path": "a", "time": 1.5, "transform_matrix": m}]),
              r"transforms\.json: frames\[0\]\.time: expected a time in \[0, 1\]")
    cams_case("cameras_w_negative", cameras_json(w=-32), r"transforms\.json: w: expected a positive integer")


def dataset_case(name, reader, build, expect, exit=2, untouched=()):
    case(name, reader, "{EXE} check-data --data {CASE}/data", expect, build, exit, untouched)


def with_data(damage, src="data"):
    def build(d, base):
        copytree(base + "/" + src, d + "/data")
        damage(d + "/data")
    return build


def define_npy():
    P = "data/poses_bounds.npy"
    dataset_case("npy_zero_bytes", "npy", with_data(lambda r: write(r + "/poses_bounds.npy", b"")),
                 r"poses_bounds\.npy: not a NumPy \.npy file", untouched=[P])
    dataset_case("npy_bad_magic", "npy", with_data(lambda r: write(r + "/poses_bounds.npy", npy((3, 17), magic=b"\x93NUMPX"))),
                 r"poses_bounds\.npy: not a NumPy \.npy file", untouched=[P])
    dataset_case("npy_truncated_header", "npy", with_data(lambda r: truncate(r + "/poses_bounds.npy", 40)),
                 r"poses_bounds\.npy: truncated header", untouched=[P])
    dataset_case("npy_truncated_data", "npy", with_data(lambda r: truncate(r + "/poses_bounds.npy", -9)),
                 r"poses_bounds\.npy: truncated: shape", untouched=[P])
    dataset_case("npy_dtype_int", "npy", with_data(lambda r: write(r + "/poses_bounds.npy", npy((3, 17), "<i4", [1] * 51))),
                 r"poses_bounds\.npy: dtype '<i4' is not supported", untouched=[P])
    dataset_case("npy_dtype_big_endian", "npy", with_data(lambda r: write(r + "/poses_bounds.npy", npy((3, 17), ">f8"))),
                 r"poses_bounds\.npy: dtype '>f8' is not supported", untouched=[P])
    dataset_case("npy_fortran_order", "npy", with_data(lambda r: write(r + "/poses_bounds.npy", npy((3, 17), fortran=True))),
                 r"poses_bounds\.npy: Fortran-ordered", untouched=[P])
    dataset_case("npy_shape_3x15", "npy", with_data(lambda r: write(r + "/poses_bounds.npy", npy((3, 15)))),
                 r"poses_bounds\.npy: shape must be \(N, 17\)", untouched=[P])
    dataset_case("npy_shape_1d", "npy", with_data(lambda r: write(r + "/poses_bounds.npy", npy((51,)))),
                 r"poses_bounds\.npy: shape must be \(N, 17\)", untouched=[P])
    dataset_case("npy_header_only", "npy",
                 with_data(lambda r: write(r + "/poses_bounds.npy", read(r + "/poses_bounds.npy")[:128] + b"")),
                 r"poses_bounds\.npy: truncated: shape \(3, 17\) needs 408 bytes of data, 0 present", untouched=[P])

    def nan_pose(r):
        b = bytearray(read(r + "/poses_bounds.npy"))
        b[128 + 8 * 3:128 + 8 * 4] = struct.pack("<d", float("nan"))
        write(r + "/poses_bounds.npy", bytes(b))
    dataset_case("npy_nan_pose", "npy", with_data(nan_pose), r"poses_bounds\.npy: row 0 \(cam00\): non-finite value at column 3",
                 untouched=[P])


def define_dnerf():
    T = "data/transforms_train.json"

    def tj(fn, which="transforms_train.json"):
        return with_data(lambda r: edit_json(r + "/" + which, fn), "dnerf")
    dataset_case("dnerf_train_json_not_json", "dnerf",
                 with_data(lambda r: write(r + "/transforms_train.json", "{ nope"), "dnerf"),
                 r"transforms_train\.json: malformed JSON", untouched=[T])
    dataset_case("dnerf_missing_test_json", "dnerf",
                 with_data(lambda r: os.remove(r + "/transforms_test.json"), "dnerf"),
                 r"transforms_test\.json: missing")
    dataset_case("dnerf_frame_without_time", "dnerf", tj(lambda j: j["frames"][0].pop("time")),
                 r"transforms_train\.json: frames\[0\]\.time: missing \(D-NeRF needs a time per frame\)", untouched=[T])
    dataset_case("dnerf_time_negative", "dnerf", tj(lambda j: j["frames"][1].__setitem__("time", -0.5)),
                 r"transforms_train\.json: frames\[1\]\.time: expected a time in \[0, 1\]", untouched=[T])
    dataset_case("dnerf_file_path_outside", "dnerf",
                 tj(lambda j: j["frames"][0].__setitem__("file_path", "../../etc/passwd")),
                 r"transforms_train\.json: frames\[0\]\.file_path: .* is not inside the dataset folder", untouched=[T])
    dataset_case("dnerf_image_missing", "dnerf", tj(lambda j: j["frames"][0].__setitem__("file_path", "./train/nothing")),
                 r"transforms_train\.json: frames\[0\]\.file_path: image .* does not exist", untouched=[T])
    dataset_case("dnerf_nan_literal", "dnerf",
                 with_data(lambda r: write(r + "/transforms_train.json",
                                           read(r + "/transforms_train.json").decode().replace("[", "[NaN, ", 3)), "dnerf"),
                 r"transforms_train\.json: malformed JSON: parse error at line \d+", untouched=[T])
    dataset_case("dnerf_focal_string", "dnerf", tj(lambda j: j.__setitem__("camera_angle_x", "wide")),
                 r"transforms_train\.json: camera_angle_x: expected a number", untouched=[T])


def define_hypernerf():
    def hn(dataset=None, extra=None):
        def build(d, base):
            r = d + "/data"
            os.makedirs(r)
            if dataset is not None:
                write(r + "/dataset.json", dataset)
            for k, v in (extra or {}).items():
                write(r + "/" + k, v)
        return build
    dataset_case("hypernerf_dataset_not_json", "hypernerf", hn("[1, 2"), r"dataset\.json: not valid JSON: .*line 1, column 6")
    dataset_case("hypernerf_ids_missing", "hypernerf", hn(json.dumps({"count": 0})), r"dataset\.json: ids: missing")
    dataset_case("hypernerf_ids_empty", "hypernerf",
                 hn(json.dumps({"count": 0, "num_exemplars": 0, "ids": [], "train_ids": [], "val_ids": []}),
                    {"scene.json": json.dumps({"scale": 1, "center": [0, 0, 0], "near": 0.1, "far": 5}),
                     "metadata.json": "{}"}),
                 r"dataset\.json: ids: empty")
    dataset_case("hypernerf_scene_missing", "hypernerf",
                 hn(json.dumps({"count": 1, "num_exemplars": 1, "ids": ["a"], "train_ids": ["a"], "val_ids": []})),
                 r"scene\.json: missing \(a HyperNeRF dataset needs it\)")


def define_colmap():
    def cm(files):
        def build(d, base):
            for k, v in files.items():
                write(d + "/data/sparse/0/" + k, v)
            os.makedirs(d + "/data/images", exist_ok=True)
        return build
    dataset_case("colmap_no_model_files", "colmap", cm({"readme.txt": "empty"}), r"sparse/0/cameras\.bin: missing, and so is cameras\.txt")
    dataset_case("colmap_cameras_bin_truncated", "colmap",
                 cm({"cameras.bin": struct.pack("<Q", 5) + b"\x01\x00", "images.bin": struct.pack("<Q", 0),
                     "points3D.bin": struct.pack("<Q", 0)}),
                 r"cameras\.bin: camera count: 5 records need at least 48 bytes each but only 2 bytes follow")
    dataset_case("colmap_cameras_bad_model", "colmap",
                 cm({"cameras.bin": struct.pack("<QIiQQddd", 1, 1, 99, 32, 24, 1.0, 1.0, 1.0), "images.bin": struct.pack("<Q", 0),
                     "points3D.bin": struct.pack("<Q", 0)}),
                 r"cameras\.bin: .*model_id 99")
    dataset_case("colmap_cameras_txt_garbage", "colmap",
                 cm({"cameras.txt": "1 PINHOLE 32 24 banana\n", "images.txt": "", "points3D.txt": ""}),
                 r"cameras\.txt: line 1: camera 1: params: PINHOLE has 4, got 1")


def define_images():
    F = "frames"

    def fr(damage):
        def build(d, base):
            copytree(base + "/data/cam00", d + "/frames")
            damage(d + "/frames")
        return build
    sf = "{EXE} stylize-frames --in {CASE}/frames --style-image {CASE}/style.png --out {CASE}/out"

    def style_case(name, data, expect, known=None):
        def build(d, base):
            copytree(base + "/data/cam00", d + "/frames")
            write(d + "/style.png", data)
        case(name, "png", sf, expect, build, 1, untouched=["style.png"], known_failure=known)
    # The style image is read through OpenCV, which does not say why it failed; a file that starts as
    # a PNG is named with the PNG reader's reason. Frames go through the PNG reader alone.
    unreadable = r"style\.png: not a readable image"
    style_case("png_style_zero_bytes", b"", unreadable)
    style_case("png_style_not_png", b"GIF89a" + b"\x00" * 40, unreadable)
    style_case("png_style_truncated", png(32, 32)[:60], r"style\.png: corrupt PNG: truncated")
    style_case("png_style_huge_header", png(32, 32, ihdr_w=1 << 30, ihdr_h=1 << 30), r"style\.png: corrupt PNG: Invalid IHDR")
    style_case("png_style_bad_crc", png(32, 32)[:29] + b"\x00\x00\x00\x00" + png(32, 32)[33:], r"style\.png: corrupt PNG: IHDR: CRC error")

    def frame_case(name, damage, expect, cmd=sf, exit=1):
        def build(d, base):
            copytree(base + "/data/cam00", d + "/frames")
            shutil.copy(base + "/style.png", d + "/style.png")
            damage(d + "/frames")
        case(name, "png", cmd, expect, build, exit, untouched=["frames/0000.png", "frames/0001.png", "frames/0002.png"])
    frame_case("png_frame_truncated", lambda r: truncate(r + "/0001.png", 100), r"frames/0001\.png: corrupt PNG: truncated")
    frame_case("png_frame_zero_bytes", lambda r: write(r + "/0001.png", b""), r"frames/0001\.png: not a PNG file")
    frame_case("png_frame_16bit_other_size", lambda r: write(r + "/0002.png", png(16, 12, 2, 16)),
               r"frames/0002\.png: 16x12, but the first frame is 32x24")
    frame_case("png_frame_gray_other_size", lambda r: write(r + "/0002.png", png(20, 10, 0)),
               r"frames/0002\.png: 20x10, but the first frame is 32x24")
    frame_case("png_frame_alpha_other_size", lambda r: write(r + "/0002.png", png(10, 10, 6)),
               r"frames/0002\.png: 10x10, but the first frame is 32x24")
    bench = "{EXE} bench --stylized {CASE}/frames --original {BASE}/data/cam00 --style-image {BASE}/style.png --out {CASE}/out"
    frame_case("png_bench_frame_truncated", lambda r: truncate(r + "/0000.png", 50),
               r"frames/0000\.png: corrupt PNG: truncated", bench)
    # Grey and 16-bit frames are read (data::FrameReader); one of another size is refused.
    frame_case("png_bench_frame_16bit_gray_other_size", lambda r: write(r + "/0001.png", png(16, 12, 0, 16)),
               r"frames/0001\.png: 16x12, but the first frame is 32x24", bench)
    frame_case("png_bench_frame_huge_header", lambda r: write(r + "/0000.png", png(4, 4, ihdr_w=100000, ihdr_h=100000)),
               r"frames/0000\.png: ", bench)
    # A dataset's frames: check-data lists each problem as one "error: FILE: field: message" line on
    # stdout and exits 1 ("report": the runner reads those lines instead of the fatal one).
    def frame_report(name, damage, expect):
        dataset_case(name, "png", with_data(damage), expect, exit=1, untouched=["data/cam01/0001.png"])
        CASES[-1][0]["report"] = True
    frame_report("png_dataset_frame_truncated", lambda r: truncate(r + "/cam01/0001.png", 120),
                 r"cam01/0001\.png: pixels: cannot be decoded .*corrupt PNG: truncated")
    frame_report("png_dataset_frame_wrong_size", lambda r: write(r + "/cam01/0001.png", png(16, 12)),
                 r"cam01/0001\.png: size: is 16x12 but the view's camera .* is 32x24")
    frame_report("png_dataset_frame_zero_bytes", lambda r: write(r + "/cam01/0001.png", b""),
                 r"cam01/0001\.png: file: not a PNG file")


def define_safetensors():
    W = "weights/vgg_normalised.safetensors"
    sty = "{EXE} stylize-frames --in {BASE}/data/cam00 --style-image {BASE}/style.png --out {CASE}/out --stylizer adain --weights {CASE}/weights"

    def st(name, data, expect, known=None):
        def build(d, base):
            write(d + "/" + W, data)
            write(d + "/weights/decoder.safetensors", safetensors([("x", "F32", [1], [1.0])]))
        case(name, "safetensors", sty, expect, build, 1, untouched=[W], known_failure=known)
    st("safetensors_zero_bytes", b"", r"vgg_normalised\.safetensors: truncated")
    st("safetensors_header_len_huge", safetensors([("a", "F32", [1], [1.0])], header_len=1 << 40),
       r"vgg_normalised\.safetensors: bad header: its length")
    st("safetensors_header_len_past_end", safetensors([("a", "F32", [1], [1.0])], header_len=5000),
       r"vgg_normalised\.safetensors: truncated: the header is 5000 bytes")
    st("safetensors_header_not_json", struct.pack("<Q", 6) + b"{nope}", r"vgg_normalised\.safetensors: bad header: not JSON")
    st("safetensors_header_array", struct.pack("<Q", 2) + b"[]", r"vgg_normalised\.safetensors: bad header: not a JSON object")
    st("safetensors_unknown_dtype",
       safetensors([("a", "F32", [1], [1.0])], header_patch=lambda h: h["a"].__setitem__("dtype", "F128")),
       r"vgg_normalised\.safetensors: bad header: tensor 'a' has an unknown dtype \"F128\"")
    st("safetensors_offsets_reversed",
       safetensors([("a", "F32", [2], [1.0, 2.0])], header_patch=lambda h: h["a"].__setitem__("data_offsets", [8, 0])),
       r"vgg_normalised\.safetensors: bad header: tensor 'a' has data_offsets \[8, 0\]")
    st("safetensors_offsets_past_end",
       safetensors([("a", "F32", [2], [1.0, 2.0])], header_patch=lambda h: h["a"].__setitem__("data_offsets", [0, 800])),
       r"vgg_normalised\.safetensors: bad header: tensor 'a' has data_offsets \[0, 800\]")
    st("safetensors_shape_negative",
       safetensors([("a", "F32", [1], [1.0])], header_patch=lambda h: h["a"].__setitem__("shape", [-1])),
       r"vgg_normalised\.safetensors: bad header: tensor 'a' has a shape that is not")
    st("safetensors_no_dtype",
       safetensors([("a", "F32", [1], [1.0])], header_patch=lambda h: h["a"].pop("dtype")),
       r"vgg_normalised\.safetensors: bad header: tensor 'a' needs dtype")
    st("safetensors_missing_tensor", safetensors([("a", "F32", [1], [1.0])]),
       r"vgg_normalised\.safetensors: no tensor '0\.weight'")
    FIRST = "0.weight"  # vgg_normalised's first convolution (1x1, 3 -> 3)
    st("safetensors_wrong_shape", safetensors([(FIRST, "F32", [3, 3, 1, 2], [0.0] * 18), ("0.bias", "F32", [3], [0.0] * 3)]),
       r"vgg_normalised\.safetensors: tensor '0\.weight' has shape")
    st("safetensors_int_dtype", safetensors([(FIRST, "I64", [3, 3, 1, 1], [0] * 9), ("0.bias", "F32", [3], [0.0] * 3)]),
       r"vgg_normalised\.safetensors: tensor '0\.weight' is I64")
    st("safetensors_nan_weight",
       safetensors([(FIRST, "F32", [3, 3, 1, 1], [0.0] * 8 + [float("nan")]), ("0.bias", "F32", [3], [0.0] * 3)]),
       r"vgg_normalised\.safetensors: tensor '0\.weight' holds a non-finite value")
    bench = ("{EXE} bench --stylized {BASE}/data/cam00 --original {BASE}/data/cam00 --style-image {BASE}/style.png "
             "--out {CASE}/out --metric-weights {CASE}/weights")

    def mw(name, data, expect):
        def build(d, base):
            write(d + "/weights/vgg16.safetensors", data)
            write(d + "/weights/lpips_vgg.safetensors", safetensors([("x", "F32", [1], [1.0])]))
        case(name, "safetensors", bench, expect, build, 1, untouched=["weights/vgg16.safetensors"])
    mw("safetensors_metric_weights_truncated", safetensors([("a", "F32", [4], [1.0] * 4)])[:-3],
       r"vgg16\.safetensors: truncated: tensor 'a' ends at data byte 16, the file holds 13")


RESUME = "{EXE} train --resume {CASE}/run"
RUN_FILES = ["run/run.json", "run/train.json", "run/geometry/gaussians.ply", "run/checkpoint/state.s4dckpt",
             "run/checkpoint/state.prev.s4dckpt"]


def stopped(run):
    """The base run as a run stopped before its end leaves it (train.json says complete: false): a
    finished run is never trained again, so continuing only reads checkpoints of a stopped one."""
    edit_json(run + "/train.json", lambda j: j.__setitem__("complete", False))


def run_case(name, reader, damage, expect, cmd=RESUME, exit=1, untouched=None, known=None):
    def build(d, base):
        copytree(base + "/run", d + "/run")
        if cmd == RESUME:
            stopped(d + "/run")
        damage(d + "/run")
    u = [f for f in (RUN_FILES if untouched is None else untouched)]
    case(name, reader, cmd, expect, build, exit, u, known)


def define_checkpoint():
    C, P = "/checkpoint/state.s4dckpt", "/checkpoint/state.prev.s4dckpt"

    def both(fn):
        def damage(r):
            fn(r + C)
            fn(r + P)
        return damage

    def only(fn):
        def damage(r):
            fn(r + C)
            os.remove(r + P)
        return damage
    kept = [f for f in RUN_FILES if not f.endswith("prev.s4dckpt")]
    run_case("ckpt_truncated_both", "checkpoint", both(lambda p: truncate(p, len(read(p)) // 2)),
             r"state\.s4dckpt: truncated in array '[^']+'; the previous checkpoint is unusable too: "
             r".*state\.prev\.s4dckpt: truncated in array")
    run_case("ckpt_zero_bytes_no_prev", "checkpoint", only(lambda p: write(p, b"")),
             r"state\.s4dckpt: not a style4d checkpoint \(and there is no previous checkpoint", untouched=kept)
    run_case("ckpt_bad_magic_no_prev", "checkpoint", only(lambda p: flip_bit(p, 0)),
             r"state\.s4dckpt: not a style4d checkpoint", untouched=kept)
    run_case("ckpt_header_bit_flipped", "checkpoint", only(lambda p: flip_bit(p, 40)),
             r"state\.s4dckpt: header: checksum mismatch", untouched=kept)
    run_case("ckpt_array_bit_flipped", "checkpoint", only(lambda p: flip_bit(p, len(read(p)) // 2)),
             r"state\.s4dckpt: array '[^']+': checksum mismatch", untouched=kept)
    run_case("ckpt_trailing_bytes", "checkpoint", only(lambda p: write(p, read(p) + b"\x00" * 16)),
             r"state\.s4dckpt: 16 unexpected bytes after the arrays", untouched=kept)
    run_case("ckpt_header_length_lies", "checkpoint",
             only(lambda p: write(p, read(p)[:8] + struct.pack("<Q", 1 << 40) + read(p)[16:])),
             r"state\.s4dckpt: truncated header", untouched=kept)
    run_case("ckpt_both_missing_with_results", "checkpoint",
             lambda r: (os.remove(r + C), os.remove(r + P)),
             r"state\.s4dckpt: missing, and so is .*state\.prev\.s4dckpt", untouched=RUN_FILES[:3])

    def nan_array(p):
        # Replace the last float of the file (an array's value) by NaN and fix nothing else: the
        # array's checksum then fails first, which is the honest answer for a file edited by hand.
        b = bytearray(read(p))
        b[-4:] = struct.pack("<f", float("nan"))
        write(p, bytes(b))
    run_case("ckpt_nan_value_unsigned", "checkpoint", only(nan_array),
             r"state\.s4dckpt: array 'max_radius': checksum mismatch", untouched=kept)

    def nan_signed(p):
        # NaN in the first mean, with the array's and the header's checksums made to match: only
        # the finiteness check can catch it.
        edit_checkpoint(p, lambda h, arrays: arrays["means"].__setitem__(slice(0, 4), struct.pack("<f", float("nan"))))
    run_case("ckpt_nan_value_signed", "checkpoint", only(nan_signed),
             r"state\.s4dckpt: array 'means' holds a non-finite value at 0", untouched=kept)
    run_case("ckpt_count_lies", "checkpoint", only(lambda p: edit_checkpoint(p, lambda h, a: h.__setitem__("count", h["count"] + 1))),
             r"state\.s4dckpt: array 'means' holds \d+ floats, expected \d+ for \d+ Gaussians", untouched=kept)
    run_case("ckpt_sh_degree_lies", "checkpoint", only(lambda p: edit_checkpoint(p, lambda h, a: h.__setitem__("sh_degree", 7))),
             r"state\.s4dckpt: sh_degree 7 is not 0\.\.3", untouched=kept)
    # Found by fuzz_checkpoint (tests/fuzz): an array listed with 0 floats once reached memcpy with a null pointer.
    def empty_array(h, arrays):
        arrays["opacity_logits.adam_m"][:] = b""
        next(a for a in h["arrays"] if a["name"] == "opacity_logits.adam_m")["floats"] = 0
    run_case("ckpt_array_empty", "checkpoint", only(lambda p: edit_checkpoint(p, empty_array)),
             r"state\.s4dckpt: array 'opacity_logits\.adam_m' holds 0 floats, expected \d+", untouched=kept)
    run_case("ckpt_array_renamed", "checkpoint",
             only(lambda p: edit_checkpoint(p, lambda h, a: h["arrays"][0].__setitem__("name", "positions"))),
             r"state\.s4dckpt: array 0 is 'positions', expected 'means'", untouched=kept)


def define_run_json():
    R = "run/run.json"

    def rj(fn):
        return lambda r: edit_json(r + "/run.json", fn)
    run_case("runjson_not_json", "run_json", lambda r: write(r + "/run.json", "{\"settings\": "),
             r"run/run\.json: .*parse error at line 1, column 14")
    run_case("runjson_missing", "run_json", lambda r: os.remove(r + "/run.json"), r"run/run\.json: missing; .* is not a training run",
             untouched=RUN_FILES[1:])
    run_case("runjson_settings_missing", "run_json", rj(lambda j: j.pop("settings")),
             r"run/run\.json: field 'settings' \(the training settings\) is missing")
    run_case("runjson_iterations_string", "run_json", rj(lambda j: j["settings"].__setitem__("iterations", "many")),
             r"run/run\.json: field 'iterations' = \"many\": expected a whole number")
    run_case("runjson_sh_degree_9", "run_json", rj(lambda j: j["settings"].__setitem__("sh_degree", 9)),
             r"run/run\.json: field 'sh_degree' = 9: must be 0\.\.3")
    run_case("runjson_unknown_setting", "run_json", rj(lambda j: j["settings"].__setitem__("warp_speed", 9)),
             r"run/run\.json: field 'warp_speed': not a training setting")
    run_case("runjson_data_folder_gone", "run_json", rj(lambda j: j.__setitem__("data", "/nonexistent/s4d-corpus")),
             r"/nonexistent/s4d-corpus: not a directory")
    run_case("runjson_stage_bogus", "run_json", rj(lambda j: j.__setitem__("stage", "bogus")), r"run/run\.json: field 'stage' = \"bogus\"")
    rr = "{EXE} render --run {CASE}/run --path test --out {CASE}/out"
    run_case("render_run_json_not_json", "run_json", lambda r: write(r + "/run.json", "nope"),
             r"run/run\.json: .*parse error at line 1, column 2", rr)
    run_case("render_run_gaussians_truncated", "run_json",
             lambda r: truncate(r + "/geometry/gaussians.ply", len(read(r + "/geometry/gaussians.ply")) // 3),
             r"geometry/gaussians\.ply: truncated: header says 4002 vertices", rr)
    run_case("render_run_gaussians_missing", "run_json", lambda r: os.remove(r + "/geometry/gaussians.ply"),
             r"run is an incomplete run: .*geometry/gaussians\.ply: missing", rr, untouched=["run/run.json", "run/train.json"])
    run_case("render_run_sh_degree_9", "run_json", rj(lambda j: j["settings"].__setitem__("sh_degree", 9)),
             r"run/run\.json: field 'sh_degree' = 9: must be 0\.\.3", rr)
    run_case("render_run_checkpoint_gone_ply_nan", "run_json",
             lambda r: write(r + "/geometry/gaussians.ply", read(r + "/geometry/gaussians.ply").replace(
                 b"end_header\n", b"end_header\n\x00\x00\xc0\x7f", 1)[:-4]),
             r"geometry/gaussians\.ply: vertex 0 property 'x' is not finite", rr)


def cli_case(name, cmd, expect, exit=2, build=None, untouched=()):
    case(name, "command_line", cmd, expect, build, exit, untouched)


def define_command_lines():
    cli_case("cli_synth_bad_size", "{EXE} synth --out {CASE}/o --size 32by24", r"--size: expected WxH \(for example 160x120\), got '32by24'")
    cli_case("cli_synth_cams_text", "{EXE} synth --out {CASE}/o --cams ten", r"--cams: expected an integer, got 'ten'")
    cli_case("cli_synth_unknown_option", "{EXE} synth --out {CASE}/o --colour red", r"unknown option --colour")
    cli_case("cli_train_no_data", "{EXE} train --run {CASE}/run", r"--run .*run: no run to continue there \(no run\.json\); "
             r"a new run needs --data DIR")
    cli_case("cli_train_iters_negative", "{EXE} train --data {BASE}/data --run {CASE}/run --iters -5", r"--iters: expected a non-negative integer, got '-5'")
    cli_case("cli_train_bad_preset", "{EXE} train --data {BASE}/data --run {CASE}/run --preset turbo", r"--preset: unknown preset 'turbo'")
    cli_case("cli_train_set_unknown_key", "{EXE} train --data {BASE}/data --run {CASE}/run --set warp=1", r"--set: expected KEY=VALUE .*got 'warp=1'")
    cli_case("cli_train_out_exists", "{EXE} train --data {BASE}/data --run {CASE}/run --iters 5",
             r"run already exists and is not empty", 1, lambda d, b: copytree(b + "/run", d + "/run"), RUN_FILES)
    cli_case("cli_train_resume_changes_iters", "{EXE} train --run {CASE}/run --iters 50",
             r"--iters cannot change a run being continued", 2, lambda d, b: copytree(b + "/run", d + "/run"), RUN_FILES)
    cli_case("cli_render_no_out", "{EXE} render --run {BASE}/run --path test", r"missing required option --out")
    cli_case("cli_render_bad_path", "{EXE} render --run {BASE}/run --path sideways --out {CASE}/o", r"--path: expected test, spiral, train:CAM .*got 'sideways'")
    cli_case("cli_render_alpha_out_of_range", "{EXE} render --run {BASE}/run --path test --mix original --alpha 2 --out {CASE}/o",
             r"--alpha: expected a number in \[0, 1\], got '2'")
    cli_case("cli_export_ply_time_out_of_range", "{EXE} export-ply --run {BASE}/run --time 3 --out {CASE}/o.ply", r"--time: expected a value in \[0, 1\]")
    cli_case("cli_stylize_no_style", "{EXE} stylize --run {BASE}/run", r"missing required option --style-image")
    cli_case("cli_stylize_bad_method", "{EXE} stylize --run {BASE}/run --style-image {BASE}/style.png --method best",
             r"method 'best' is not full, colors or scratch")
    cli_case("cli_stylize_frames_bad_stylizer",
             "{EXE} stylize-frames --in {BASE}/data/cam00 --style-image {BASE}/style.png --out {CASE}/o --stylizer magic",
             r"unknown stylizer 'magic'")
    cli_case("cli_make_style_small", "{EXE} make-style --out {CASE}/s.png --size 4", r"--size: 4 is below 32")
    cli_case("cli_bench_no_out", "{EXE} bench --stylized {BASE}/data/cam00 --original {BASE}/data/cam00", r"missing required option --out")
    cli_case("cli_bench_bad_uiqm",
             "{EXE} bench --stylized {BASE}/data/cam00 --original {BASE}/data/cam00 --style-image {BASE}/style.png --out {CASE}/o "
             "--uiqm c", r"--uiqm: expected one of a, b, got 'c'")
    cli_case("cli_view_no_run", "{EXE} view", r"missing required option --run")
    cli_case("cli_view_bad_camera", "{EXE} view --run {BASE}/run --screenshot {CASE}/s.png --camera 99",
             r"--camera 99: the run's dataset has cameras 0\.\.2")
    cli_case("cli_check_data_downscale_zero", "{EXE} check-data --data {BASE}/data --downscale 0", r"--downscale: must be at least 1")
    cli_case("cli_sweep_unknown_verb", "{EXE} sweep fly", r"sweep fly: expected SWEEP")
    cli_case("cli_demo_unknown_option", "{EXE} demo --fast", r"unknown option --fast")
    cli_case("cli_devices_extra_argument", "{EXE} devices now", r"now")
    cli_case("cli_check_data_two_dirs", "{EXE} check-data --data {BASE}/data {BASE}/dnerf", r"check-data: error: ", 2)
    cli_case("cli_export_ply_no_run", "{EXE} export-ply --time 0 --out {CASE}/o.ply", r"missing required option --run")
    cli_case("cli_render_ply_without_cameras", "{EXE} render --ply {BASE}/g.ply --out {CASE}/o", r"--cameras")
    cli_case("cli_sweep_plan_missing_spec", "{EXE} sweep plan {CASE}/nospec.json --out {CASE}/sw", r"nospec\.json", 1)
    cli_case("cli_unknown_command", "{EXE} trian", r"unknown command 'trian'", 2)
    cli_case("cli_export_ply_onto_checkpoint",
             "{EXE} export-ply --run {CASE}/run --time 0 --out {CASE}/run/checkpoint/state.s4dckpt",
             r"--out: .*checkpoint/state\.s4dckpt is one of .*run's own files", 2,
             lambda d, b: copytree(b + "/run", d + "/run"), RUN_FILES)
    cli_case("cli_view_screenshot_into_eval", "{EXE} view --run {CASE}/run --screenshot {CASE}/run/eval/shot.png",
             r"--screenshot: .*eval/shot\.png is one of .*run's own files", 2,
             lambda d, b: copytree(b + "/run", d + "/run"), RUN_FILES)

    # Unwritable and full output folders: a path under a regular file, a file-size limit (ulimit -f,
    # reported as a write error like a full disk, not a signal). The real full disk is cli_disk_full.
    def a_file(d, b):
        write(d + "/file", "not a folder\n")
    cli_case("cli_synth_out_under_file", "{EXE} synth --out {CASE}/file/o --cams 2 --frame-count 2 --size 32x24",
             r"Not a directory.*file/o", 1, a_file)
    cli_case("cli_train_out_under_file", "{EXE} train --data {BASE}/data --run {CASE}/file/run --iters 5",
             r"Not a directory.*file/run", 1, a_file)
    cli_case("cli_render_out_under_file", "{EXE} render --run {BASE}/run --path test --out {CASE}/file/o",
             r"Not a directory.*file/o", 1, a_file)
    cli_case("cli_export_ply_out_under_file", "{EXE} export-ply --run {BASE}/run --time 0 --out {CASE}/file/o.ply",
             r"cannot write .*file/o\.ply: open: Not a directory", 1, a_file)
    cli_case("cli_check_data_json_under_file", "{EXE} check-data --data {BASE}/data --json {CASE}/file/c.json",
             r"cannot write .*file/c\.json: open: Not a directory", 1, a_file)
    cli_case("cli_train_file_size_limit", "ulimit -f 16; {EXE} train --data {BASE}/data --run {CASE}/run --iters 5 --preset fast",
             r"run: the file size limit \(ulimit -f\) is [0-9.]+ [KM]B, a checkpoint of [0-9]+ Gaussians", 1)
    cli_case("cli_train_resume_file_size_limit", "ulimit -f 16; {EXE} train --run {CASE}/run",
             r"run: the file size limit \(ulimit -f\) is [0-9.]+ [KM]B, a checkpoint of [0-9]+ Gaussians", 1,
             lambda d, b: (copytree(b + "/run", d + "/run"), stopped(d + "/run")), RUN_FILES)
    cli_case("cli_export_ply_file_size_limit", "ulimit -f 1; {EXE} export-ply --run {BASE}/run --time 0 --out {CASE}/o.ply",
             r"cannot write .*o\.ply: write: File too large", 1)


DEFINE = [define_ply, define_cameras, define_npy, define_dnerf, define_hypernerf, define_colmap, define_images,
          define_safetensors, define_checkpoint, define_run_json, define_command_lines]


def make_bases(exe, base):
    def run(*args):
        subprocess.run([exe] + list(args), check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.makedirs(base)
    run("synth", "--out", base + "/data", "--size", "32x24", "--cams", "3", "--frame-count", "3")
    run("synth", "--out", base + "/dnerf", "--size", "32x24", "--cams", "3", "--frame-count", "3", "--dnerf")
    run("train", "--data", base + "/data", "--run", base + "/run", "--iters", "20", "--fine-iters", "0", "--preset", "fast")
    run("export-ply", "--run", base + "/run", "--time", "0", "--out", base + "/g.ply")
    run("make-style", "--out", base + "/style.png", "--size", "32")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", help="the style4d program")
    ap.add_argument("--out", help="the corpus folder to create (must not exist)")
    ap.add_argument("--list", help="only write the case list as JSON to this file")
    a = ap.parse_args()
    for define in DEFINE:
        define()
    names = [c["name"] for c, _ in CASES]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        sys.exit("make_corpus.py: repeated case names: " + ", ".join(sorted(dup)))
    listing = json.dumps({"cases": [c for c, _ in CASES]}, indent=1) + "\n"
    if a.list:
        write(a.list, listing)
        return
    if not a.exe or not a.out:
        ap.error("--exe and --out are required (or --list FILE)")
    if os.path.exists(a.out):
        sys.exit("make_corpus.py: " + a.out + " exists")
    out = os.path.abspath(a.out)
    base = out + "/_base"
    make_bases(os.path.abspath(a.exe), base)
    for c, build in CASES:
        d = out + "/" + c["name"]
        os.makedirs(d)
        if build:
            build(d, base)
    write(out + "/cases.json", listing)


if __name__ == "__main__":
    main()

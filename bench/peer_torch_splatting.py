#!/usr/bin/env python3
"""Times the pure-PyTorch rasterizer hbb1/torch-splatting (the peer) on a scene written by
`s4d_bench_splat --write-peer-scene DIR`, so both programs draw the same Gaussians from the same camera.

The peer is not part of this project: pass a checkout of it with --peer (nothing is downloaded).
Its renderer hard-codes the 'cuda' device; this harness reads its sources, maps that device name
to --device (cpu by default) and imports them, changing nothing else. Its module imports einops
without using it in the renderer; where einops is not installed (Debian has no package), an empty
stand-in module lets the import pass and fails loudly if anything calls it.

One JSON line per pass: forward, and forward + backward (the sum of the rendered image
back-propagated to every Gaussian parameter: means, scales, rotations, opacities, SH), the median
wall time of --repeats runs after a warm-up.
"""
import argparse
import json
import math
import os
import statistics
import sys
import time
import types

import numpy as np
import torch


def fail(message):
    sys.exit(f"peer_torch_splatting: {message}")


def import_peer(peer_dir, device):
    """Imports gaussian_splatting.gauss_render and utils.camera_utils from the checkout, with the
    device name mapped. Returns (GaussRenderer, Camera)."""
    package_dir = os.path.join(peer_dir, "gaussian_splatting")
    files = {
        "gaussian_splatting.utils.sh_utils": os.path.join(package_dir, "utils", "sh_utils.py"),
        "gaussian_splatting.utils.camera_utils": os.path.join(package_dir, "utils", "camera_utils.py"),
        "gaussian_splatting.gauss_render": os.path.join(package_dir, "gauss_render.py"),
    }
    for name, path in files.items():
        if not os.path.isfile(path):
            fail(f"{path}: missing (--peer must be a checkout of hbb1/torch-splatting)")
    try:
        import einops  # noqa: F401
    except ImportError:
        stand_in = types.ModuleType("einops")

        def reduce(*args, **kwargs):
            raise RuntimeError("einops is not installed: the peer called einops.reduce")

        stand_in.reduce = reduce
        sys.modules["einops"] = stand_in
    for package in ("gaussian_splatting", "gaussian_splatting.utils"):
        module = types.ModuleType(package)
        module.__path__ = []
        sys.modules[package] = module
    for name, path in files.items():
        with open(path, encoding="utf-8") as f:
            source = f.read()
        source = source.replace("'cuda'", repr(device)).replace('"cuda"', repr(device))
        module = types.ModuleType(name)
        module.__file__ = path
        module.__package__ = name.rpartition(".")[0]
        sys.modules[name] = module
        exec(compile(source, path, "exec"), module.__dict__)
    return (sys.modules["gaussian_splatting.gauss_render"].GaussRenderer,
            sys.modules["gaussian_splatting.utils.camera_utils"].Camera)


def read_ply(path):
    """A binary little-endian 3DGS PLY of float properties -> dict name -> float32 array."""
    with open(path, "rb") as f:
        names, count = [], None
        while True:
            line = f.readline()
            if not line:
                fail(f"{path}: header: no end_header")
            line = line.decode("ascii", "replace").strip()
            if line.startswith("format") and line != "format binary_little_endian 1.0":
                fail(f"{path}: format: only binary_little_endian 1.0 is read, not '{line}'")
            if line.startswith("element vertex"):
                count = int(line.split()[2])
            elif line.startswith("property"):
                kind, name = line.split()[1:3]
                if kind != "float":
                    fail(f"{path}: property {name}: type {kind}, only float is read")
                names.append(name)
            elif line == "end_header":
                break
        data = np.frombuffer(f.read(), dtype="<f4")
    if count is None or data.size != count * len(names):
        fail(f"{path}: vertex data: {data.size} floats for {count} vertices of {len(names)} properties")
    table = data.reshape(count, len(names))
    return {name: table[:, i] for i, name in enumerate(names)}


class PeerScene:
    """The attributes the peer's renderer reads from its GaussModel, as leaf tensors."""

    def __init__(self, ply, device):
        def leaf(array):
            return torch.tensor(np.ascontiguousarray(array), dtype=torch.float32, device=device, requires_grad=True)

        rest = sorted((n for n in ply if n.startswith("f_rest_")), key=lambda n: int(n[7:]))
        if len(rest) != 45:
            fail(f"scene PLY: f_rest_*: {len(rest)} properties, SH degree 3 needs 45")
        count = ply["x"].shape[0]
        dc = np.stack([ply[f"f_dc_{c}"] for c in range(3)], axis=1)[:, None, :]
        # 3DGS stores the rest channel-major: f_rest[c * 15 + k] is coefficient k + 1 of channel c.
        higher = np.stack([ply[n] for n in rest], axis=1).reshape(count, 3, 15).transpose(0, 2, 1)
        self.xyz = leaf(np.stack([ply["x"], ply["y"], ply["z"]], axis=1))
        self.log_scales = leaf(np.stack([ply[f"scale_{i}"] for i in range(3)], axis=1))
        self.quats = leaf(np.stack([ply[f"rot_{i}"] for i in range(4)], axis=1))
        self.opacity_logits = leaf(ply["opacity"][:, None])
        self.features = leaf(np.concatenate([dc, higher], axis=1))
        self.count = count

    @property
    def get_xyz(self):
        return self.xyz

    @property
    def get_scaling(self):
        return torch.exp(self.log_scales)

    @property
    def get_rotation(self):
        return torch.nn.functional.normalize(self.quats, dim=-1)

    @property
    def get_opacity(self):
        return torch.sigmoid(self.opacity_logits)

    @property
    def get_features(self):
        return self.features

    def leaves(self):
        return [self.xyz, self.log_scales, self.quats, self.opacity_logits, self.features]


def peer_camera(Camera, transforms_path, index, device):
    with open(transforms_path, encoding="utf-8") as f:
        frames = json.load(f).get("frames")
    if not frames or not 0 <= index < len(frames):
        fail(f"{transforms_path}: frames: no camera {index}")
    frame = frames[index]
    for key in ("fl_x", "fl_y", "w", "h", "transform_matrix"):
        if key not in frame:
            fail(f"{transforms_path}: frames[{index}].{key}: missing")
    if abs(frame.get("cx", frame["w"] / 2) - frame["w"] / 2) > 1e-6 or abs(frame.get("cy", frame["h"] / 2) - frame["h"] / 2) > 1e-6:
        fail(f"{transforms_path}: frames[{index}].cx/cy: the peer assumes a centred principal point")
    c2w = torch.tensor(frame["transform_matrix"], dtype=torch.float32)
    c2w[:3, 1:3] *= -1  # NeRF's OpenGL camera axes -> the peer's OpenCV axes (y down, z forward)
    intrinsic = torch.eye(4)
    intrinsic[0, 0], intrinsic[1, 1] = frame["fl_x"], frame["fl_y"]
    return Camera(width=frame["w"], height=frame["h"], intrinsic=intrinsic, c2w=c2w.to(device))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--peer", required=True, help="a checkout of hbb1/torch-splatting")
    parser.add_argument("--scene", required=True, help="a folder from s4d_bench_splat --write-peer-scene")
    parser.add_argument("--camera", type=int, default=0)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--threads", type=int, default=0, help="torch threads; 0 keeps torch's default")
    args = parser.parse_args()
    if args.repeats < 1:
        fail(f"--repeats: {args.repeats}, must be at least 1")
    if args.threads > 0:
        torch.set_num_threads(args.threads)
    GaussRenderer, Camera = import_peer(args.peer, args.device)
    scene = PeerScene(read_ply(os.path.join(args.scene, "points.ply")), args.device)
    camera = peer_camera(Camera, os.path.join(args.scene, "transforms.json"), args.camera, args.device)
    renderer = GaussRenderer(active_sh_degree=3, white_bkgd=False)

    def forward():
        return renderer(camera=camera, pc=scene)["render"]

    def forward_backward():
        for leaf in scene.leaves():
            leaf.grad = None
        image = forward()
        image.sum().backward()
        return image

    image = forward_backward()  # warm-up; also the coverage check below
    coverage = float((image.detach() > 0).any(dim=-1).float().mean())
    if not all(leaf.grad is not None and math.isfinite(float(leaf.grad.abs().sum())) for leaf in scene.leaves()):
        fail("the peer's backward left a parameter without a finite gradient")
    for name, run in (("fwd", forward), ("fwdbwd", forward_backward)):
        times = []
        for _ in range(args.repeats):
            start = time.perf_counter()
            run()
            if args.device.startswith("cuda"):
                torch.cuda.synchronize()  # the work queued on the device counts
            times.append((time.perf_counter() - start) * 1000.0)
        print(json.dumps({"bench": "peer_torch_splatting", "pass": name, "n_gaussians": scene.count,
                          "width": camera.image_width, "height": camera.image_height, "camera": args.camera,
                          "ms_wall_p50": statistics.median(times), "ms_wall_min": min(times),
                          "ms_wall_max": max(times), "repeats": args.repeats, "threads": torch.get_num_threads(),
                          "covered_pixels": coverage, "device": args.device}), flush=True)


if __name__ == "__main__":
    main()

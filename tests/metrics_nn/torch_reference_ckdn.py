#!/usr/bin/env python3
"""Native CKDN against a PyTorch reference (ctest metrics_torch_reference_ckdn).

    torch_reference_ckdn.py STYLE4D CONVERT_WEIGHTS_PY WORK_DIR CALIBRATION_PUBLISHED

The reference is pyiqa's CKDN assembled from torchvision's ResNet-50 modules (reference_nets.Ckdn:
conv1, maxpool, layer1 per branch, layer2 on the difference, the MLP) with random weights and random
BatchNorm running statistics (so the loader's folding is checked), saved as pyiqa's checkpoint and
converted by tools/convert_weights.py ckdn. Its preprocessing is pyiqa's CKDN._default_preprocess
with torchvision's own functions: resize of the shorter side to 329 (x bicubic with antialiasing,
y nearest), center_crop(288), ImageNet mean/std; float64 throughout. `style4d bench` scores frames
larger than 329 (bicubic shrinking) against a smaller style image (nearest enlarging), and the
published-calibration program scores small pairs (bicubic enlarging); both must match the reference.
Exit 77 (skipped) without torch.
"""
import json
import os
import shutil
import subprocess
import sys

import torch_or_skip  # noqa: F401  (exits 77 without torch, outside CI)
from reference_nets import Ckdn
from torch_reference import calibration_scores, noise_image, randomise, run, write_calibration_pairs
import torch
import torch.nn as nn
import torchvision
import torchvision.transforms.functional as TF
from torchvision.transforms import InterpolationMode

IMAGENET_MEAN, IMAGENET_STD = [0.485, 0.456, 0.406], [0.229, 0.224, 0.225]


def randomise_ckdn(model, gen):
    """torch_reference.randomise; the last layer small so the sigmoid stays off its flat ends."""
    randomise(model, gen)
    model.net.fc_[6].weight.data *= 0.05
    return model


def score(model, x, y, antialias=True, swap=False):
    """pyiqa's ckdn(x, y) on [1, 3, H, W] float64 images in [0, 1]."""
    if swap:
        x, y = y, x
    x = TF.center_crop(TF.resize(x, 329, InterpolationMode.BICUBIC, antialias=antialias), 288)
    y = TF.center_crop(TF.resize(y, 329, InterpolationMode.NEAREST), 288)
    mean = torch.tensor(IMAGENET_MEAN, dtype=x.dtype).view(1, 3, 1, 1)
    std = torch.tensor(IMAGENET_STD, dtype=x.dtype).view(1, 3, 1, 1)
    return float(model.net((x - mean) / std, (y - mean) / std))


def main():
    style4d, converter, work, calibration = sys.argv[1:5]
    shutil.rmtree(work, ignore_errors=True)
    gen = torch.Generator().manual_seed(22)
    torch.manual_seed(22)  # module constructors draw from the global generator: every run the same

    image = lambda w, h: noise_image(w, h, gen)

    as_input = lambda u8: (u8.double() / 255).unsqueeze(0)
    model = randomise_ckdn(Ckdn(), gen)
    sys.path.insert(0, os.path.dirname(os.path.abspath(converter)))
    import convert_weights
    pth, weights = os.path.join(work, "CKDN_model_best.pth"), os.path.join(work, "weights")
    os.makedirs(work)
    torch.save(model.state_dict(), pth)
    if convert_weights.main(["convert_weights.py", "ckdn", pth, weights]) != 0:
        sys.exit("FAILED: convert_weights.py ckdn %s" % pth)
    model.double().eval()

    # Frames 345x340: shrunk to 333x329, cropped at (20, 22), round(20.5) and round(22.5) half to even.
    # The style image 170x150: enlarged to 372x329 by nearest, cropped at (20, 42).
    frames_dir = os.path.join(work, "frames")
    os.makedirs(frames_dir)
    frames = [image(345, 340) for _ in range(2)]
    for t, f in enumerate(frames):
        torchvision.io.write_png(f, os.path.join(frames_dir, "%03d.png" % t))
    style = image(170, 150)
    torchvision.io.write_png(style, os.path.join(work, "style.png"))
    out = os.path.join(work, "bench")
    run([style4d, "bench", "--frames", frames_dir, "--original", frames_dir, "--style-image", os.path.join(work, "style.png"),
         "--out", out, "--metric-weights", weights])
    with open(os.path.join(out, "report.json")) as f:
        report = json.load(f)
    got = report["results"][0]["per_frame"].get("ckdn")
    with torch.no_grad():
        expected = [score(model, as_input(f), as_input(style)) for f in frames]
        wrong = {"no antialiasing": score(model, as_input(frames[0]), as_input(style), antialias=False),
                 "frame and style image swapped": score(model, as_input(frames[0]), as_input(style), swap=True)}
    # Float32 on lavapipe (Mesa 22.3.6) against float64 torch, 34 convolutions deep: measured worst
    # 4.5e-7 (the bench frames; the calibration pairs 3.7e-7).
    tolerance = 4e-6
    failed = got is None or len(got) != len(expected)
    worst = float("inf") if failed else max(abs(v - r) / r for v, r in zip(got, expected))
    failed |= not worst <= tolerance
    print("%s bench ckdn worst relative difference %.2e (tolerance %.1e); native %s, reference %s" %
          ("FAIL" if failed else "ok  ", worst, tolerance, got, ["%.9g" % r for r in expected]))
    info = report.get("metrics_info", {}).get("ckdn", {})
    ok = "native CKDN" in info.get("impl", "")
    failed |= not ok
    print("%s report says how ckdn was computed: %s" % ("ok  " if ok else "FAIL", info.get("impl")))
    for what, alternative in wrong.items():
        apart = abs(alternative - expected[0]) / expected[0]
        ok = apart > 100 * tolerance
        failed |= not ok
        print("%s %s would differ by %.2e relative" % ("ok  " if ok else "FAIL", what, apart))

    # The calibration program on pairs smaller than the crop (bicubic enlarging), in pyiqa's layout.
    calib = os.path.join(work, "calibration")
    pairs = {name: (image(37, 31), image(37, 31)) for name in ("I03", "I04", "I06", "I08", "I19")}
    write_calibration_pairs(calib, pairs)
    with torch.no_grad():
        reference = [score(model, as_input(d), as_input(r)) for d, r in pairs.values()]
    code, scores, output = calibration_scores(calibration, weights, calib)
    values = scores.get("ckdn", [])
    worst = max((abs(v - r) / r for v, r in zip(values, reference)), default=float("inf"))
    # Random weights cannot meet the published values, so the program must run and report failure.
    ok = code == 1 and len(values) == len(reference) and worst <= tolerance
    failed |= not ok
    print("%s calibration_published ckdn on random weights: exit %d, worst relative difference %.2e\n%s" %
          ("ok  " if ok else "FAIL", code, worst, output.strip()))
    if failed:
        sys.exit("native CKDN differs from the reference; the files are in %s" % work)
    shutil.rmtree(work)


if __name__ == "__main__":
    main()

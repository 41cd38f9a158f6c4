#!/usr/bin/env python3
"""The native learned metrics against PyTorch references (ctest metrics_torch_reference).

    torch_reference.py STYLE4D CONVERT_WEIGHTS_PY WORK_DIR CALIBRATION_PUBLISHED

Builds the backbones from torchvision's own modules (make_layers of cfgs "D"/"E", AlexNet().features)
and AdaIN's vgg_normalised as net.py declares it, with random weights; writes each as the published
checkpoint would be (torch.save of the state dict, LPIPS's heads in the legacy format), converts them
with tools/convert_weights.py, and runs `style4d bench --metric-weights` on PNG frames of odd sizes.
The heads are written here from the papers' definitions (LPIPS v0.1, DISTS, the Gram loss), in
float64, and compared with report.json's per-frame values. The same weights drive the published-
calibration program (calibration_published.cpp) over BMP pairs in pyiqa's layout, so its run path is
checked here too. Exit 77 (skipped) without torch.
"""
import json
import os
import shutil
import struct
import subprocess
import sys

import torch_or_skip  # noqa: F401  (exits 77 without torch, outside CI)
from reference_nets import adain_vgg
import torch
import torch.nn as nn
import torch.nn.functional as F
import torchvision
from torchvision.models.vgg import cfgs, make_layers

# Frames of odd sizes (AlexNet needs >= 31; VGG16's maps go 37x31, 18x15, 9x7, 4x3, 2x1) and a
# style image twice as large, which style_lpips shrinks to the frame (an exact 2x2 box average).
W, H = 37, 31
IMAGENET_MEAN, IMAGENET_STD = [0.485, 0.456, 0.406], [0.229, 0.224, 0.225]
LPIPS_SHIFT, LPIPS_SCALE = [-0.030, -0.088, -0.188], [0.458, 0.448, 0.450]


def randomise(module, gen, other=None):
    """He-scaled convolution and linear weights keep activations O(1) through 16 layers; nonzero
    biases so they are read; BatchNorm affine parameters and running statistics away from the
    identity. Any other module goes to `other(m)`, in the same walk, so the random stream is one."""
    for m in module.modules():
        if isinstance(m, (nn.Conv2d, nn.Linear)):
            m.weight.data = torch.randn(m.weight.shape, generator=gen) * (2.0 / m.weight[0].numel()) ** 0.5
            if m.bias is not None:
                m.bias.data = torch.rand(m.bias.shape, generator=gen) * 0.2 - 0.1
        elif isinstance(m, nn.BatchNorm2d):
            c = m.num_features
            m.weight.data = torch.rand(c, generator=gen) + 0.5
            m.bias.data = torch.rand(c, generator=gen) * 0.4 - 0.2
            m.running_mean = torch.rand(c, generator=gen) * 0.4 - 0.2
            m.running_var = torch.rand(c, generator=gen) * 1.5 + 0.5
        elif other is not None:
            other(m)
    return module


class Features(nn.Module):
    """torchvision's VGG/AlexNet state-dict layout: "features.<i>"."""

    def __init__(self, features):
        super().__init__()
        self.features = features




def taps(features, x, indices):
    """Outputs of the modules at `indices` (the ReLUs of the published taps)."""
    out = []
    for i, m in enumerate(features):
        x = m(x)
        if i in indices:
            out.append(x.clone())
        if len(out) == len(indices):
            return out
    raise AssertionError("tap past the end of the network")


def imagenet(x):
    """torchvision's ImageNet normalisation of a [0, 1] image."""
    mean = torch.tensor(IMAGENET_MEAN, dtype=x.dtype).view(1, 3, 1, 1)
    return (x - mean) / torch.tensor(IMAGENET_STD, dtype=x.dtype).view(1, 3, 1, 1)


class NetLinLayer(nn.Module):
    """LPIPS's head of one tap: Dropout, then a 1x1 convolution to one channel without bias."""

    def __init__(self, channels, gen):
        super().__init__()
        self.model = nn.Sequential(nn.Dropout(), nn.Conv2d(channels, 1, 1, bias=False))
        self.model[1].weight.data = torch.rand((1, channels, 1, 1), generator=gen) * 0.1  # LPIPS's are >= 0


class LpipsHeads(nn.Module):
    """The heads lin0 .. lin4, named as in LPIPS's weights/v0.1/*.pth."""

    def __init__(self, widths, gen):
        super().__init__()
        for l, c in enumerate(widths):
            setattr(self, "lin%d" % l, NetLinLayer(c, gen))

    def convs(self):
        return [getattr(self, "lin%d" % l).model[1] for l in range(5)]


class L2Pool(nn.Module):
    """DISTS's L2 pooling: sqrt(depthwise conv(x^2, hanning(5)[1:-1] outer product / sum, stride 2, pad 1) + 1e-12)."""

    def forward(self, x):
        a = torch.tensor([0.5, 1.0, 0.5], dtype=x.dtype)
        g = (a[:, None] * a[None, :]) / 4.0
        out = F.conv2d(x * x, g.expand(x.shape[1], 1, 3, 3), stride=2, padding=1, groups=x.shape[1])
        return (out + 1e-12).sqrt()


def lpips(net, lins, a, b, signed):
    """LPIPS v0.1 (Zhang et al. 2018): scaling layer, unit-normalised taps, 1x1 heads, spatial mean, sum."""
    shift = torch.tensor(LPIPS_SHIFT, dtype=a.dtype).view(1, 3, 1, 1)
    scale = torch.tensor(LPIPS_SCALE, dtype=a.dtype).view(1, 3, 1, 1)
    prep = lambda x: ((2 * x - 1 if signed else x) - shift) / scale
    total = 0.0
    for fa, fb, lin in zip(net(prep(a)), net(prep(b)), lins):
        na = fa / (fa.pow(2).sum(1, keepdim=True).sqrt() + 1e-10)
        nb = fb / (fb.pow(2).sum(1, keepdim=True).sqrt() + 1e-10)
        total += lin((na - nb) ** 2).mean().item()
    return total


def dists(features, alpha, beta, x, y):
    """DISTS (Ding et al. 2020): stage 0 the image, then relu1_2 .. relu5_3 of VGG16 with L2 pooling."""
    l2 = nn.Sequential(*[L2Pool() if isinstance(m, nn.MaxPool2d) else m for m in features])
    fx = [x] + taps(l2, imagenet(x), [3, 8, 15, 22, 29])
    fy = [y] + taps(l2, imagenet(y), [3, 8, 15, 22, 29])
    w = alpha.sum() + beta.sum()
    a, b, k, s = alpha.flatten() / w, beta.flatten() / w, 0, 0.0
    for p, q in zip(fx, fy):
        c = p.shape[1]
        mx, my = p.mean([2, 3]).flatten(), q.mean([2, 3]).flatten()
        vx, vy = p.var([2, 3], unbiased=False).flatten(), q.var([2, 3], unbiased=False).flatten()
        cov = (p * q).mean([2, 3]).flatten() - mx * my
        s1 = (2 * mx * my + 1e-6) / (mx ** 2 + my ** 2 + 1e-6)
        s2 = (2 * cov + 1e-6) / (vx + vy + 1e-6)
        s += float((a[k:k + c] * s1).sum() + (b[k:k + c] * s2).sum())
        k += c
    return 1 - s


def gram_loss(fa, fb):
    """sum over layers of the mean squared difference of F F^T / (C H W)."""
    def gram(f):
        c = f.shape[1]
        m = f.reshape(c, -1)
        return m @ m.t() / m.numel()
    return sum(float(((gram(a) - gram(b)) ** 2).mean()) for a, b in zip(fa, fb))


def noise_image(w, h, gen):
    """A [3, h, w] uint8 frame: RGB noise over a gradient, so channels differ (a swapped colour order shows)."""
    ramp = torch.linspace(0, 1, w).view(1, 1, w).expand(3, h, w) * torch.tensor([0.8, 0.3, 0.5]).view(3, 1, 1)
    return ((0.5 * ramp + 0.5 * torch.rand((3, h, w), generator=gen)) * 255).round().to(torch.uint8)


def write_bmp(path, u8):
    """A 24-bit BMP (bottom-up BGR rows padded to 4 bytes) of a [3, H, W] uint8 tensor."""
    c, h, w = u8.shape
    pad = (4 - 3 * w % 4) % 4
    rows = b"".join(bytes(u8[[2, 1, 0], y].permute(1, 0).flatten().tolist()) + b"\0" * pad for y in range(h - 1, -1, -1))
    header = b"BM" + struct.pack("<IHHI", 54 + len(rows), 0, 0, 54)
    info = struct.pack("<IiiHHIIiiII", 40, w, h, 1, 24, 0, len(rows), 2835, 2835, 0, 0)
    with open(path, "wb") as f:
        f.write(header + info + rows)


def write_calibration_pairs(folder, pairs):
    """{name: (distorted, reference)} uint8 images as pyiqa's ResultsCalibra: dist_dir/NAME.bmp, ref_dir/NAME.bmp."""
    for sub in ("dist_dir", "ref_dir"):
        os.makedirs(os.path.join(folder, sub))
    for name, (dist, ref) in pairs.items():
        write_bmp(os.path.join(folder, "dist_dir", name + ".bmp"), dist)
        write_bmp(os.path.join(folder, "ref_dir", name + ".bmp"), ref)


def calibration_scores(program, weights, images):
    """calibration_published on our images and random weights: its per-image scores (it must run, and
    fail the published values, which random weights cannot meet)."""
    env = dict(os.environ, S4D_METRIC_WEIGHTS=weights, S4D_CALIBRATION_DIR=images)
    p = subprocess.run([program], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
    scores = {}
    for line in p.stdout.splitlines():
        if line.endswith(" FAILED") or line.endswith(" ok"):
            metric, image = line.split(":")[0].split()
            scores.setdefault(metric, []).append(float(line.split(":")[1].split(",")[0]))
    return p.returncode, scores, p.stdout


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        sys.exit("FAILED: %s\n%s" % (" ".join(cmd), p.stdout))
    return p.stdout


def main():
    style4d, converter, work, calibration = sys.argv[1:5]
    shutil.rmtree(work, ignore_errors=True)
    gen = torch.Generator().manual_seed(2024)
    torch.manual_seed(2024)  # module constructors draw from the global generator: every run the same
    image = lambda w, h: noise_image(w, h, gen)
    dirs = {d: os.path.join(work, d) for d in ("stylised", "original")}
    frames = {}
    for d, path in dirs.items():
        os.makedirs(path)
        frames[d] = [image(W, H) for _ in range(3)]
        for t, f in enumerate(frames[d]):
            torchvision.io.write_png(f, os.path.join(path, "%03d.png" % t))
    # The style image: coarser and warmer than the frames, so its Gram matrices differ clearly.
    style = (image(W // 2 + 1, H // 2 + 1).repeat_interleave(4, 1).repeat_interleave(4, 2)[:, :2 * H, :2 * W].float()
             * torch.tensor([1.0, 0.6, 0.3]).view(3, 1, 1)).round().to(torch.uint8)
    torchvision.io.write_png(style, os.path.join(work, "style.png"))
    as_input = lambda u8: (u8.double() / 255).unsqueeze(0)

    # Networks as published, random weights, saved as their checkpoints and converted.
    vgg16 = randomise(Features(make_layers(cfgs["D"])), gen)
    vgg19 = randomise(Features(make_layers(cfgs["E"])), gen)
    alex = randomise(Features(torchvision.models.AlexNet().features), gen)
    adain = randomise(adain_vgg(), gen)
    heads = {"lpips_vgg": LpipsHeads([64, 128, 256, 512, 512], gen), "lpips_alex": LpipsHeads([64, 192, 384, 256, 256], gen)}
    n = 3 + 64 + 128 + 256 + 512 + 512
    alpha, beta = torch.rand((1, n, 1, 1), generator=gen) * 0.02 + 0.01, torch.rand((1, n, 1, 1), generator=gen) * 0.02
    checkpoints = [("a", "vgg16", vgg16.state_dict()), ("a", "lpips_vgg", heads["lpips_vgg"].state_dict()),
                   ("a", "dists", {"alpha": alpha, "beta": beta}), ("a", "vgg_normalised", adain.state_dict()),
                   ("b", "alexnet", alex.state_dict()), ("b", "lpips_alex", heads["lpips_alex"].state_dict()),
                   ("b", "vgg19", vgg19.state_dict())]
    # The converter's main() in this process: a new interpreter per file would import torch again
    # (~2 s each); test_convert_weights.py runs it as a program.
    sys.path.insert(0, os.path.dirname(os.path.abspath(converter)))
    import convert_weights
    for folder, kind, state in checkpoints:
        pth = os.path.join(work, kind + ".pth")
        # LPIPS's released heads and DISTS's weights.pt use torch's legacy (non-zip) format.
        torch.save(state, pth, _use_new_zipfile_serialization=kind not in ("lpips_alex", "dists"))
        if convert_weights.main(["convert_weights.py", kind, pth, os.path.join(work, "weights_" + folder)]) != 0:
            sys.exit("FAILED: convert_weights.py %s %s" % (kind, pth))
    for m in (vgg16, vgg19, alex, adain, heads["lpips_vgg"], heads["lpips_alex"]):
        m.double().eval()

    def bench(folder, extra):
        out = os.path.join(work, "bench_" + folder)
        run([style4d, "bench", "--frames", dirs["stylised"], "--original", dirs["original"], "--style-image",
             os.path.join(work, "style.png"), "--out", out, "--metric-weights", os.path.join(work, "weights_" + folder)] + extra)
        with open(os.path.join(out, "report.json")) as f:
            return json.load(f)["results"][0]["per_frame"]

    s = [as_input(f) for f in frames["stylised"]]
    o = [as_input(f) for f in frames["original"]]
    st = as_input(style)
    st_small = F.avg_pool2d(st, 2)  # OpenCV INTER_AREA at an exact factor 2
    vgg_taps = lambda x: taps(vgg16.features, x, [3, 8, 15, 22, 29])
    alex_taps = lambda x: taps(alex.features, x, [1, 4, 7, 9, 11])
    lins = lambda kind: heads[kind].convs()
    with torch.no_grad():
        expected = {
            "a": {"content_lpips": [lpips(vgg_taps, lins("lpips_vgg"), a, b, True) for a, b in zip(s, o)],
                  "style_lpips": [lpips(vgg_taps, lins("lpips_vgg"), a, st_small, True) for a in s],
                  "dists": [dists(vgg16.features, alpha.double(), beta.double(), s[t + 1], s[t]) for t in range(2)],
                  "style_loss_gram": [gram_loss(taps(adain, a, [3, 10, 17, 30, 43]), taps(adain, st, [3, 10, 17, 30, 43]))
                                      for a in s]},
            "b": {"content_lpips": [lpips(alex_taps, lins("lpips_alex"), a, b, False) for a, b in zip(s, o)],
                  "style_lpips": [lpips(alex_taps, lins("lpips_alex"), a, st_small, False) for a in s],
                  "style_loss_gram": [gram_loss(taps(vgg19.features, imagenet(a), [1, 6, 11, 20, 29]),
                                                taps(vgg19.features, imagenet(st), [1, 6, 11, 20, 29])) for a in s]}}
    got = {"a": bench("a", []),
           "b": bench("b", ["--lpips-net", "alex", "--lpips-input", "3dgs", "--gram-vgg", "torchvision"])}
    # Float32 GPU networks (lavapipe) against float64 torch: worst relative differences measured over
    # two image sets (Mesa 22.3.6): lpips 4.9e-7, dists 2.4e-6 (1 - a sum near 1 cancels), Gram 3.0e-6.
    tolerance = {"content_lpips": 5e-6, "style_lpips": 5e-6, "dists": 2.5e-5, "style_loss_gram": 3e-5}
    failed = False
    for folder in ("a", "b"):
        for key, ref in expected[folder].items():
            values = got[folder].get(key)
            if values is None or len(values) != len(ref):
                print("FAIL run %s %s: native gave %s, the reference %d values" % (folder, key, values, len(ref)))
                failed = True
                continue
            worst = max(abs(v - r) / abs(r) for v, r in zip(values, ref))
            failed |= not worst <= tolerance[key]
            print("%s run %s %-16s worst relative difference %.2e (tolerance %.1e); reference %s" %
                  ("ok  " if worst <= tolerance[key] else "FAIL", folder, key, worst, tolerance[key], ["%.6g" % r for r in ref]))
    # The comparison can tell the conventions apart: swapped colour channels and the other LPIPS input
    # convention move the first frame's value far past the tolerance (measured: by more than 1e-2).
    with torch.no_grad():
        wrong = {"BGR frames (content_lpips, run a)": (lpips(vgg_taps, lins("lpips_vgg"), s[0].flip(1), o[0].flip(1), True),
                                                       got["a"]["content_lpips"][0]),
                 "2x - 1 input (content_lpips, run b)": (lpips(alex_taps, lins("lpips_alex"), s[0], o[0], True),
                                                        got["b"]["content_lpips"][0])}
    for what, (alternative, native) in wrong.items():
        apart = abs(alternative - native) / abs(native)
        ok = apart > 100 * tolerance["content_lpips"]
        failed |= not ok
        print("%s %s would differ by %.2e relative" % ("ok  " if ok else "FAIL", what, apart))
    # The published-calibration program's run path (its own test can only skip here): random pairs as
    # pyiqa's ResultsCalibra BMPs, scored with DISTS (weights a) and LPIPS-AlexNet, 2x - 1 (weights b).
    calib = os.path.join(work, "calibration")
    pairs = {name: (image(W, H), image(W, H)) for name in ("I03", "I04", "I06", "I08", "I19")}
    write_calibration_pairs(calib, pairs)
    with torch.no_grad():
        calibration_expected = {
            ("a", "dists"): [dists(vgg16.features, alpha.double(), beta.double(), as_input(d), as_input(r))
                             for d, r in pairs.values()],
            ("b", "lpips_alex"): [lpips(alex_taps, lins("lpips_alex"), as_input(d), as_input(r), True) for d, r in pairs.values()]}
    for (folder, metric), ref in calibration_expected.items():
        code, scores, output = calibration_scores(calibration, os.path.join(work, "weights_" + folder), calib)
        values = scores.get(metric, [])
        worst = max((abs(v - r) / abs(r) for v, r in zip(values, ref)), default=float("inf"))
        ok = code == 1 and len(values) == len(ref) and worst <= tolerance[metric if metric == "dists" else "content_lpips"]
        failed |= not ok
        print("%s calibration_published %s on random weights: exit %d, worst relative difference %.2e\n%s" %
              ("ok  " if ok else "FAIL", metric, code, worst, output.strip()))
    if failed:
        sys.exit("the native metrics differ from the references; the files are in %s" % work)
    shutil.rmtree(work)  # about 450 MB of checkpoints and weights


if __name__ == "__main__":
    main()

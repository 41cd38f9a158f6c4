#!/usr/bin/env python3
"""MCCNet's training loss and its decoder/MCC gradients (ctest train_mcc_loss_reference) against a
PyTorch reference.

    mcc_loss_reference.py MCC_LOSS_GRADS CONVERT_WEIGHTS_PY WORK_DIR

The reference is written here from ALGORITHMS.md 4.2 (normalised VGG-19 with reflection padding and
ceil-mode pooling, the mirrored decoder, the MCC module) and MCCNet's net.py loss terms (content on
normalised relu4_1/relu5_1, mean/std style on relu1_1..relu5_1, or HGST's levels from ALGORITHMS.md
4.5: content on relu3_1..relu5_1, style on relu5_1, relu2_1..relu5_1; identity 1 on images, identity 2 on
all five levels, the noise loss MSE(Ics_N, Ics) with neither side detached, the L1 TV sum of Ics,
HGST's self-similarity "Iins" on relu5_1 written literally: 3x3 average pool, D = v v^T / |V|^2, the
larger of the mean row and column minima of 1 - D, averaged over channels; CCPL from CCPL's net.py
and HGST's variant from ALGORITHMS.md 4.5: difference vectors of anchors and their 8 neighbours,
projection heads Linear(C, C)-ReLU-Linear(C, C/4), L2 normalisation + 1e-7, PatchNCE as the
cross-entropy of [positive, masked negatives] / 0.07 with target 0; the anchors (and HGST's jitter)
are drawn here and passed to the native side), in float64 with autograd. Random weights (He-uniform, so activations survive the
ReLU stacks; g's bias in [1, 2] keeps MCC's sum(G) away from 0) at shrunk widths are saved with the
nn.Sequential / MCC_Module state-dict names the hgst stylizer reads; content 64x56 and style 56x48
(relu5_1 4x4 and 4x3 by ceil-mode pooling). Compared: the four loss terms and the total, and every
decoder/MCC weight and bias gradient, for both level sets (MCCNet's with the original CCPL, HGST's
with its jittered LCL), then for the self-similarity, TV, noise and both CCPL variants alone, and the
CCPL heads' gradients where CCPL trains them. Exit 77 (skipped) without torch.
"""
import copy
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "metrics_nn"))
import torch_or_skip  # noqa: F401,E402  (exits 77 without torch, outside CI)
import torch  # noqa: E402
import torch.nn as nn  # noqa: E402

WIDTHS = [4, 6, 8, 12, 10]
WEIGHTS = {"content": 3.0, "style": 18.0, "identity1": 70.0, "identity2": 1.0, "noise": 3000.0, "tv": 1e-4, "selfsim": 1.0,
           "ccpl": 4.0}  # HGST's
# CCPL's variants: levels, anchors per level, HGST's jitter, heads trained (their gradients compared).
CCPL = {"original": ([2, 3, 4], 8, False, True), "hgst": ([3, 4], 16, True, False)}
TAU = 0.07


def conv(cin, cout, k):
    c = nn.Conv2d(cin, cout, k)
    bound = (6.0 / (cin * k * k)) ** 0.5
    nn.init.uniform_(c.weight, -bound, bound)
    nn.init.uniform_(c.bias, -0.1, 0.1)
    return c


def vgg_normalised(w):
    """The layer list of AdaIN's vgg_normalised.pth up to relu5_1 (indices 0..43)."""
    pad, relu = nn.ReflectionPad2d(1), nn.ReLU()
    pool = nn.MaxPool2d(2, 2, 0, ceil_mode=True)
    layers = [conv(3, 3, 1), pad, conv(3, w[0], 3), relu, pad, conv(w[0], w[0], 3), relu, pool,
              pad, conv(w[0], w[1], 3), relu, pad, conv(w[1], w[1], 3), relu, pool,
              pad, conv(w[1], w[2], 3), relu]
    for _ in range(3):
        layers += [pad, conv(w[2], w[2], 3), relu]
    layers += [pool, pad, conv(w[2], w[3], 3), relu]
    for _ in range(3):
        layers += [pad, conv(w[3], w[3], 3), relu]
    layers += [pool, pad, conv(w[3], w[4], 3), relu]
    return nn.Sequential(*layers)


def decoder(w):
    pad, relu, up = nn.ReflectionPad2d(1), nn.ReLU(), nn.Upsample(scale_factor=2, mode="nearest")
    layers = [pad, conv(w[3], w[2], 3), relu, up]
    for _ in range(3):
        layers += [pad, conv(w[2], w[2], 3), relu]
    layers += [pad, conv(w[2], w[1], 3), relu, up, pad, conv(w[1], w[1], 3), relu, pad, conv(w[1], w[0], 3), relu, up,
               pad, conv(w[0], w[0], 3), relu, pad, conv(w[0], 3, 3)]
    return nn.Sequential(*layers)


def mean_std(f, eps=1e-5):
    c = f.shape[0]
    v = f.reshape(c, -1)
    return v.mean(1), (v.var(1, unbiased=True) + eps).sqrt()


def normal(f):
    mu, sigma = mean_std(f)
    return (f - mu[:, None, None]) / sigma[:, None, None]


class MccNet(nn.Module):
    """MCCNet's MCC (ALGORITHMS.md 4.2); h is defined and unused, as in the original."""

    def __init__(self, c):
        super().__init__()
        self.f, self.g, self.h, self.out_conv = conv(c, c, 1), conv(c, c, 1), conv(c, c, 1), conv(c, c, 1)
        self.fc = nn.Linear(c, c)
        nn.init.uniform_(self.g.bias, 1.0, 2.0)

    def forward(self, fc, fs):
        c_hat = self.f(normal(fc)[None])[0]
        g_hat = self.g(normal(fs)[None])[0].flatten(1)
        a = (g_hat * g_hat).sum(1) / g_hat.sum(1)
        w = self.fc(a)
        return fc + self.out_conv((c_hat * w[:, None, None])[None])[0]


class MccModule(nn.Module):
    def __init__(self, c):
        super().__init__()
        self.MCCN = MccNet(c)


def encode_levels(vgg, x):
    ends = [4, 11, 18, 31, 44]
    feats, start, y = [], 0, x[None]
    for e in ends:
        y = vgg[start:e](y)
        feats.append(y[0])
        start = e
    return feats


def mse(a, b):
    return ((a - b) ** 2).mean()


LEVELS = {"mccnet": ([4, 5], [1, 2, 3, 4, 5]), "hgst": ([3, 4, 5], [5, 2, 3, 4, 5])}


def losses(vgg, dec, mcc, content, style, content_noise, levels, weights, heads, samples):
    content_levels, style_levels = LEVELS[levels]
    fc, fs = encode_levels(vgg, content), encode_levels(vgg, style)
    ics = dec(mcc.MCCN(fc[3], fs[3])[None])[0]
    ics_n = dec(mcc.MCCN(encode_levels(vgg, content_noise)[3], fs[3])[None])[0]
    fi = encode_levels(vgg, ics)
    out = {"content": sum(mse(normal(fi[l - 1]), normal(fc[l - 1])) for l in content_levels)}
    style_loss = 0
    for l in style_levels:
        (mi, si), (ms, ss) = mean_std(fi[l - 1]), mean_std(fs[l - 1])
        style_loss = style_loss + mse(mi, ms) + mse(si, ss)
    out["style"] = style_loss
    icc = dec(mcc.MCCN(fc[3], fc[3])[None])[0]
    iss = dec(mcc.MCCN(fs[3], fs[3])[None])[0]
    out["identity1"] = mse(icc, content) + mse(iss, style)
    fcc, fss = encode_levels(vgg, icc), encode_levels(vgg, iss)
    out["identity2"] = sum(mse(fcc[l], fc[l]) + mse(fss[l], fs[l]) for l in range(5))
    out["noise"] = mse(ics_n, ics)
    out["tv"] = (ics[:, :, :-1] - ics[:, :, 1:]).abs().sum() + (ics[:, :-1, :] - ics[:, 1:, :]).abs().sum()
    pooled = nn.functional.avg_pool2d(fi[4][None], 3, 1)[0].flatten(1)
    d = pooled[:, :, None] * pooled[:, None, :] / (pooled ** 2).sum()
    cos = 1 - d
    out["selfsim"] = torch.maximum(cos.min(2).values.mean(1), cos.min(1).values.mean(1)).mean()
    out["ccpl"] = sum(ccpl_level(fi[l - 1], fc[l - 1], *samples[l], heads[str(l)]) for l in samples)
    out["total"] = sum(weights[k] * out[k] for k in weights)
    return out


def draw_samples(h, w, anchors, jitter, gen):
    """Distinct interior anchors and their 8 neighbours in row-major order of the 3x3 window, flat
    indices; with jitter each offset moves by -1, 0 or +1, then all are clamped to the plane."""
    picks = torch.randperm((h - 2) * (w - 2), generator=gen)[:anchors]
    centre = (1 + picks // (w - 2)) * w + 1 + picks % (w - 2)
    offsets = torch.tensor([-w - 1, -w, -w + 1, -1, 1, w - 1, w, w + 1])
    shift = torch.randint(-1, 2, (anchors, 8), generator=gen) if jitter else torch.zeros(anchors, 8, dtype=torch.long)
    neighbour = (centre[:, None] + offsets[None, :] + shift).clamp(0, h * w - 1)
    return centre[:, None].expand(anchors, 8).reshape(-1), neighbour.reshape(-1)


def ccpl_level(fq, fk, anchor, neighbour, head):
    c = fq.shape[0]
    q, k = fq.reshape(c, -1), fk.reshape(c, -1)
    zs = []
    for f in (q, k):
        proj = head((f[:, anchor] - f[:, neighbour]).t())  # [S, C / 4]
        zs.append(proj / (proj.pow(2).sum(1, keepdim=True).sqrt() + 1e-7))
    zq, zk = zs
    positive = (zq * zk).sum(1, keepdim=True)
    negative = zq @ zk.t()
    negative = negative.masked_fill(torch.eye(negative.shape[0], dtype=torch.bool), float("-inf"))
    logits = torch.cat([positive, negative], 1) / TAU
    return nn.functional.cross_entropy(logits, torch.zeros(logits.shape[0], dtype=torch.long))


def smooth_image(h, w, seed):
    g = torch.Generator().manual_seed(seed)
    coarse = torch.rand(1, 3, h // 4, w // 4, generator=g, dtype=torch.float64)
    fine = torch.rand(1, 3, h, w, generator=g, dtype=torch.float64)
    up = nn.functional.interpolate(coarse, size=(h, w), mode="bilinear", align_corners=False)
    return (0.8 * up + 0.2 * fine)[0]


def compare(exe, work, write_safetensors, vgg, dec, mcc, heads, images, levels, weights, variant, seed):
    """Runs the native loss at `levels` with CCPL's `variant` (samples drawn from `seed`) and returns
    what differs from the reference."""
    failures = []
    ccpl_levels, anchors, jitter, train_heads = CCPL[variant]
    gen = torch.Generator().manual_seed(seed)
    samples = {}
    for l in ccpl_levels:
        h, w = images[0].shape[1] >> (l - 1), images[0].shape[2] >> (l - 1)
        samples[l] = draw_samples(h, w, anchors, jitter, gen)
    tensors = {"content": images[0].float(), "style": images[1].float(), "content_noise": images[2].float()}
    for l, (a, n) in samples.items():
        tensors["ccpl.%d.anchor" % l], tensors["ccpl.%d.neighbour" % l] = a.float(), n.float()
    write_safetensors(os.path.join(work, "inputs.safetensors"), tensors, {})
    ref, grads = reference(vgg, dec, mcc, heads, images, levels, weights, samples, train_heads)
    # CCPL's neighbour differences of features cancel: PyTorch itself in float32 is this far from
    # float64 (relative to each tensor's largest value, or the floor below); measured 2.6e-3 for
    # HGST's CCPL alone, 1.3e-3 for CCPL's, 7.8e-4 for MCCNet's loss with CCPL, under 7e-5 without CCPL.
    modules32 = [copy.deepcopy(m).float() for m in (vgg, dec, mcc, heads)]
    _, grads32 = reference(*modules32, [t.float() for t in images], levels, weights, samples, train_heads)
    floor = 1e-3 * max(float(g.abs().max()) for g in grads.values())
    float32_error = max(float((grads32[k].double() - g).abs().max()) / max(float(g.abs().max()), floor) for k, g in grads.items())
    levels_arg = ",".join(str(l) for l in ccpl_levels)
    run = subprocess.run([exe, work] + [str(w) for w in WIDTHS] + [str(weights[k]) for k in WEIGHTS] +
                         [levels, levels_arg, "1" if train_heads else "0"], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit("FAILED: mcc_loss_grads exited %d: %s" % (run.returncode, run.stderr))
    got = json.loads(run.stdout)
    for k in ("content", "style", "identity1", "identity2", "noise", "tv", "selfsim", "ccpl", "total"):
        r, g = float(ref[k]), got["loss"][k]
        rel = abs(g - r) / abs(r)
        print("%s/%s loss %-9s native %.8g reference %.8g rel %.2e" % (levels, variant, k, g, r, rel))
        # Float32 networks against float64: measured worst 2.2e-6 (6.9e-5 when relu5_1 had 15 values).
        if rel > 1e-4:
            failures.append("%s loss %s" % (levels, k))
    worst = 0.0
    # Each tensor's error relative to its largest reference value, or to a thousandth of the largest
    # of all where a term is blind to it (TV's gradient w.r.t. the last bias is exactly 0).
    for name, ref_grad in grads.items():
        if name not in got["grads"]:
            failures.append("%s missing gradient %s" % (levels, name))
            continue
        g = torch.tensor(got["grads"][name], dtype=torch.float64)
        r = ref_grad.flatten()
        rel = float((g - r).abs().max()) / max(float(r.abs().max()), floor)
        worst = max(worst, rel)
        print("%s/%s grad %-24s %6d values, max |ref| %.3e, max rel error %.2e" % (levels, variant, name, r.numel(), float(r.abs().max()), rel))
        # Float32 forward and backward through ~45 layers against float64: measured worst 2.6e-5
        # without CCPL; with it, within twice PyTorch's own float32 error (measured at most 0.99x of it).
        if rel > max(5e-4, 2 * float32_error):
            failures.append("%s gradient %s" % (levels, name))
    print("%s/%s: worst gradient error %.2e over %d tensors (PyTorch float32: %.2e)" % (levels, variant, worst, len(grads), float32_error))
    return failures


def reference(vgg, dec, mcc, heads, images, levels, weights, samples, train_heads):
    """The reference loss terms and the gradients the native side prints, by name."""
    for m in (dec, mcc, heads):
        m.zero_grad(set_to_none=True)
    for p in heads.parameters():
        p.requires_grad_(train_heads)
    for p in vgg.parameters():
        p.requires_grad_(False)
    ref = losses(vgg, dec, mcc, *images, levels, weights, heads, samples)
    ref["total"].backward()
    grads = {"decoder." + k: p.grad for k, p in dec.named_parameters()}
    grads.update({k: p.grad for k, p in mcc.named_parameters() if not k.startswith("MCCN.h.")})
    if train_heads:
        grads.update({"ccpl_heads.%s" % k: p.grad for k, p in heads.named_parameters() if int(k[0]) in samples})
    return ref, grads


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__)
    exe, converter, work = argv[1], argv[2], argv[3]
    sys.path.insert(0, os.path.dirname(os.path.abspath(converter)))
    import convert_weights
    os.makedirs(work, exist_ok=True)
    torch.manual_seed(7)
    vgg, dec, mcc = vgg_normalised(WIDTHS), decoder(WIDTHS), MccModule(WIDTHS[3])
    # One CCPL head per level 2..4 at PyTorch's default init, as CCPL's mlp list.
    heads = nn.ModuleDict({str(l): nn.Sequential(nn.Linear(WIDTHS[l - 1], WIDTHS[l - 1]), nn.ReLU(),
                                                 nn.Linear(WIDTHS[l - 1], WIDTHS[l - 1] // 4)) for l in (2, 3, 4)})
    content, style = smooth_image(64, 56, 1), smooth_image(56, 48, 2)
    content_noise = content + 0.015 * torch.randn(content.shape, generator=torch.Generator().manual_seed(3), dtype=torch.float64)
    write_safetensors = convert_weights.write_safetensors
    for name, module in (("vgg", vgg), ("decoder", dec), ("mcc", mcc)):
        state = {k: v.detach().float() for k, v in module.state_dict().items()}
        write_safetensors(os.path.join(work, name + ".safetensors"), state, {})
    write_safetensors(os.path.join(work, "heads.safetensors"),
                      {"ccpl_heads." + k: v.detach().float() for k, v in heads.state_dict().items()}, {})
    # The reference starts from the float32 values the native side reads, in float64.
    for module in (vgg, dec, mcc, heads):
        module.double()
        for p in module.parameters():
            p.data = p.data.float().double()
    content, style, content_noise = (t.float().double() for t in (content, style, content_noise))
    for p in vgg.parameters():
        p.requires_grad_(False)
    failures = []
    images = (content, style, content_noise)
    # MCCNet's levels with the original CCPL at its weight 5 (the ccpl set), HGST's with LCL (full).
    failures += compare(exe, work, write_safetensors, vgg, dec, mcc, heads, images, "mccnet", dict(WEIGHTS, ccpl=5.0), "original", 11)
    failures += compare(exe, work, write_safetensors, vgg, dec, mcc, heads, images, "hgst", WEIGHTS, "hgst", 12)
    # The small terms' gradients alone, where the others cannot hide an error in them.
    for term, variant in (("selfsim", "hgst"), ("tv", "hgst"), ("noise", "hgst"), ("ccpl", "hgst"), ("ccpl", "original")):
        alone = {k: (WEIGHTS[k] if k == term else 0.0) for k in WEIGHTS}
        failures += compare(exe, work, write_safetensors, vgg, dec, mcc, heads, images, "hgst", alone, variant, 13)
    if failures:
        sys.exit("FAILED: " + ", ".join(failures))
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/env python3
"""tools/convert_weights.py on random-weight checkpoints torch writes (ctest convert_weights).

    test_convert_weights.py CONVERT_WEIGHTS_PY WORK_DIR

The names come from torchvision's own modules (make_layers of cfgs "D"/"E", AlexNet().features) and
from the published layouts of LPIPS's heads, DISTS's weights.pt, AdaIN's vgg_normalised.pth and
pyiqa's LPIPS/DISTS/CKDN/MUSIQ files (backbone under net.slice<s>.<i> / stage<s>.<i>, buffers beside it). Each
converted file is read back here and must hold exactly the expected tensors, bit for bit; the sha256
printed must be the input's; wrong shapes, missing, unknown and non-finite tensors and a file that is
not a checkpoint must fail naming the file and the tensor. Exit 77 (skipped) without torch.
"""
import contextlib
import hashlib
import io
import json
import os
import shutil
import struct
import subprocess
import sys

import torch_or_skip  # noqa: F401  (exits 77 without torch, outside CI)
from reference_musiq import Musiq
from reference_nets import Ckdn, ClipModel, adain_vgg, dino_state_dict
from torch_reference_clipiqa import tokenize
import torch
import torch.nn as nn
import torchvision
from torchvision.models.vgg import cfgs, make_layers
from torchvision.models.vision_transformer import VisionTransformer

FAILURES = []


def check(ok, what):
    print("%s %s" % ("ok  " if ok else "FAIL", what))
    if not ok:
        FAILURES.append(what)


def read_safetensors(path):
    """{name: float32 tensor} of a safetensors file, read independently of the converter."""
    with open(path, "rb") as f:
        data = f.read()
    n = struct.unpack("<Q", data[:8])[0]
    header = json.loads(data[8:8 + n])
    out = {}
    for name, e in header.items():
        if name == "__metadata__":
            continue
        assert e["dtype"] == "F32", (path, name, e["dtype"])
        begin, end = e["data_offsets"]
        out[name] = torch.frombuffer(bytearray(data[8 + n + begin:8 + n + end]), dtype=torch.float32).reshape(e["shape"])
    return out, header.get("__metadata__", {})


def features_only(state):
    return {k: v for k, v in state.items() if k.startswith("features.")}


def main():
    converter, work = sys.argv[1:3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    torch.manual_seed(5)

    # The first conversion runs the script as users do; the others call its main() in this process
    # (each new interpreter would import torch again, ~2 s).
    sys.path.insert(0, os.path.dirname(os.path.abspath(converter)))
    import convert_weights

    def run_converter(kind, path, out):
        stdout, stderr = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            code = convert_weights.main(["convert_weights.py", kind, path, out])
        return subprocess.CompletedProcess([], code, stdout.getvalue(), stderr.getvalue())

    def convert(kind, state, legacy=False, name=None):
        path = os.path.join(work, name or kind + ".pth")
        torch.save(state, path, _use_new_zipfile_serialization=not legacy)
        out = os.path.join(work, "out_" + os.path.basename(path))
        if kind == "vgg16" and name is None:
            return subprocess.run([sys.executable, converter, kind, path, out], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                  text=True), path, out
        return run_converter(kind, path, out), path, out

    def same(path, expected, what):
        got, meta = read_safetensors(path)
        ok = sorted(got) == sorted(expected) and all(torch.equal(got[k], expected[k].float()) for k in expected)
        check(ok, "%s: %d tensors, names, shapes and values as the checkpoint's" % (what, len(expected)))
        return meta

    class Holder(nn.Module):
        def __init__(self, features):
            super().__init__()
            self.features = features

    vgg16 = Holder(make_layers(cfgs["D"])).state_dict()
    # torchvision's files also hold the classifier, which the bench never reads.
    vgg16_published = dict(vgg16, **{"classifier.0.weight": torch.randn(8, 4), "classifier.0.bias": torch.randn(8)})
    p, pth, out = convert("vgg16", vgg16_published)
    check(p.returncode == 0, "vgg16 converts (%s)" % p.stderr.strip())
    with open(pth, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    check(("sha256 %s  %s" % (digest, pth)) in p.stdout, "the input's sha256 is printed")
    meta = same(os.path.join(out, "vgg16.safetensors"), vgg16, "vgg16 (classifier dropped)")
    check(meta.get("source_sha256") == digest, "the sha256 is recorded in the file's metadata")

    vgg19 = Holder(make_layers(cfgs["E"])).state_dict()
    p, _, out = convert("vgg19", vgg19)
    same(os.path.join(out, "vgg19.safetensors"), vgg19, "vgg19")
    alex = features_only(torchvision.models.AlexNet().state_dict())
    p, _, out = convert("alexnet", alex)
    same(os.path.join(out, "alexnet.safetensors"), alex, "alexnet")

    # LPIPS's released heads: legacy torch.save format, NetLinLayer = Dropout + bias-free 1x1 conv.
    heads = {"lin%d.model.1.weight" % l: torch.rand(1, c, 1, 1) for l, c in enumerate([64, 128, 256, 512, 512])}
    p, _, out = convert("lpips_vgg", heads, legacy=True)
    same(os.path.join(out, "lpips_vgg.safetensors"), heads, "lpips_vgg heads (legacy format)")
    check(not os.path.exists(os.path.join(out, "vgg16.safetensors")), "richzhang's heads alone give no backbone file")

    # pyiqa's LPIPS file: the module's whole state, the backbone split into slices that keep features' indices.
    slices = [range(0, 4), range(4, 9), range(9, 16), range(16, 23), range(23, 30)]
    pyiqa_lpips = dict(heads, **{"scaling_layer.shift": torch.tensor([-.030, -.088, -.188]).view(1, 3, 1, 1),
                                 "scaling_layer.scale": torch.tensor([.458, .448, .450]).view(1, 3, 1, 1)})
    for s, r in enumerate(slices, 1):
        for k, v in vgg16.items():
            i = int(k.split(".")[1])
            if i in r:
                pyiqa_lpips["net.slice%d.%d.%s" % (s, i, k.split(".")[2])] = v
    p, _, out = convert("lpips_vgg", {"params": pyiqa_lpips}, name="LPIPS_v0.1_vgg-pyiqa.pth")
    check(p.returncode == 0, "pyiqa's LPIPS file converts (%s)" % p.stderr.strip())
    same(os.path.join(out, "lpips_vgg.safetensors"), heads, "pyiqa LPIPS heads")
    same(os.path.join(out, "vgg16.safetensors"), vgg16, "pyiqa LPIPS backbone as torchvision's features.<i>")

    # DISTS: weights.pt (legacy) and pyiqa's file with the VGG16 in stages and the L2 pools' filters.
    ab = {"alpha": torch.rand(1, 1475, 1, 1), "beta": torch.rand(1, 1475, 1, 1)}
    p, _, out = convert("dists", ab, legacy=True)
    same(os.path.join(out, "dists.safetensors"), ab, "dists alpha/beta (legacy format)")
    stages = [range(0, 4), range(4, 9), range(9, 16), range(16, 23), range(23, 30)]
    pyiqa_dists = dict(ab, mean=torch.zeros(1, 3, 1, 1), std=torch.ones(1, 3, 1, 1))
    for s, r in enumerate(stages, 1):
        if s > 1:
            pyiqa_dists["stage%d.%d.filter" % (s, r[0])] = torch.ones(4, 1, 3, 3)
        for k, v in vgg16.items():
            i = int(k.split(".")[1])
            if i in r:
                pyiqa_dists["stage%d.%d.%s" % (s, i, k.split(".")[2])] = v
    p, _, out = convert("dists", {("module." + k): v for k, v in pyiqa_dists.items()}, name="DISTS_weights-pyiqa.pth")
    same(os.path.join(out, "dists.safetensors"), ab, "pyiqa DISTS alpha/beta (module. prefixes)")
    same(os.path.join(out, "vgg16.safetensors"), vgg16, "pyiqa DISTS backbone as torchvision's features.<i>")

    # AdaIN's vgg_normalised: nn.Sequential of 1x1 conv, then (ReflectionPad2d, Conv2d, ReLU) per layer
    # with ceil-mode max pools, up to relu5_4.
    adain = adain_vgg().state_dict()
    p, _, out = convert("vgg_normalised", adain)
    same(os.path.join(out, "vgg_normalised.safetensors"), adain, "AdaIN vgg_normalised")

    # DINO's dino_vitbase16_pretrain.pth: ViT-B/16 under vision_transformer.py's names (torchvision's
    # VisionTransformer renamed, reference_nets.dino_state_dict), a plain state dict of the backbone.
    dino = dino_state_dict(VisionTransformer(image_size=224, patch_size=16, num_layers=12, num_heads=12, hidden_dim=768,
                                             mlp_dim=3072))
    p, _, out = convert("dino_vitb16", dino, name="dino_vitbase16_pretrain.pth")
    check(p.returncode == 0 and "note:" not in p.stdout, "DINO ViT-B/16 converts without a note (%s)" % p.stderr.strip())
    same(os.path.join(out, "dino_vitb16.safetensors"), dino, "DINO ViT-B/16")
    small = dino_state_dict(VisionTransformer(image_size=32, patch_size=16, num_layers=2, num_heads=2, hidden_dim=128, mlp_dim=256))
    p, _, out = convert("dino_vitb16", small, name="dino_small.pth")
    check(p.returncode == 0 and "is not DINO ViT-B/16 (width 128, 2 blocks, patch 16)" in p.stdout,
          "a smaller DINO ViT converts with a note: " + p.stdout.strip().splitlines()[-1])

    # pyiqa's CKDN: the whole module's state (both stems, csp and the unused aux_csp and fc1_, BatchNorm
    # buffers with num_batches_tracked); the file keeps what the forward pass reads, BatchNorm unfolded.
    ckdn = Ckdn().state_dict()
    used = {k: v for k, v in ckdn.items()
            if not k.startswith(("net.aux_csp.", "net.fc1_.")) and not k.endswith("num_batches_tracked")}
    p, _, out = convert("ckdn", ckdn, name="CKDN_model_best-pyiqa.pth")
    check(p.returncode == 0, "pyiqa's CKDN file converts (%s)" % p.stderr.strip())
    same(os.path.join(out, "ckdn.safetensors"), used, "pyiqa CKDN without aux_csp, fc1_ and num_batches_tracked")

    # pyiqa's MUSIQ (reference_musiq.py keeps pyiqa's module names), at a reduced width and depth.
    musiq = Musiq(width=128, mlp=256, heads=2, layers=2).state_dict()
    p, _, out = convert("musiq_paq2piq", musiq, name="musiq_paq2piq_ckpt-pyiqa.pth")
    check(p.returncode == 0 and "is not pyiqa's MUSIQ configuration (width 128, 2 blocks, MLP 256" in p.stdout,
          "a reduced pyiqa MUSIQ converts with a note (%s)" % p.stderr.strip())
    same(os.path.join(out, "musiq_paq2piq.safetensors"), musiq, "pyiqa MUSIQ")

    # Errors: one line naming the file and the tensor, exit code 1, nothing written.
    bad_files = []

    def refused(kind, state, parts, what):
        bad_files.append(what)
        p, path, out = convert(kind, state, name="bad_%d.pth" % len(bad_files))
        line = p.stderr.strip()
        ok = p.returncode == 1 and all(x in line for x in [os.path.basename(path)] + parts) and not os.path.exists(out)
        check(ok, "%s is refused: %s" % (what, line))

    bad = dict(heads)
    bad["lin2.model.1.weight"] = torch.rand(1, 255, 1, 1)
    refused("lpips_vgg", bad, ["lin2.model.1.weight", "[1, 255, 1, 1]", "[1, 256, 1, 1]"], "a head of the wrong width")
    refused("lpips_alex", heads, ["lin1.model.1.weight", "[1, 128, 1, 1]", "[1, 192, 1, 1]"], "VGG heads as AlexNet's")
    refused("vgg19", vgg16, ["missing features.16.weight"], "a VGG16 as VGG19")  # VGG19's third block has 4 convolutions
    missing = {k: v for k, v in vgg16.items() if k != "features.28.bias"}
    refused("vgg16", missing, ["missing features.28.bias"], "a missing bias")
    refused("dists", dict(ab, gamma=torch.rand(3)), ["unexpected tensor 'gamma'"], "an unknown tensor")
    no_var = {k: v for k, v in ckdn.items() if k != "net.csp.0.downsample.1.running_var"}
    refused("ckdn", no_var, ["missing net.csp.0.downsample.1.running_var"], "a CKDN without a BatchNorm statistic")
    narrow = dict(ckdn, **{"net.fc_.0.weight": torch.rand(2048, 256)})
    refused("ckdn", narrow, ["net.fc_.0.weight", "[2048, 256]", "[2048, 512]"], "a CKDN MLP of the wrong width")
    refused("ckdn", vgg16, ["unexpected tensor 'features.0.weight'"], "a VGG16 as CKDN")
    refused("musiq", dict(musiq, **{"head.weight": torch.rand(10, 128), "head.bias": torch.rand(10)}),
            ["head.weight", "10-class head"], "MUSIQ-AVA's distribution head")
    refused("musiq", dict(musiq, **{"transformer_encoder.transformer.encoderblock_1.attention.qkv.weight": torch.rand(3)}),
            ["unexpected tensor 'transformer_encoder.transformer.encoderblock_1.attention.qkv.weight'"], "a fused MUSIQ qkv")
    refused("musiq", {k: v for k, v in musiq.items() if k != "block1.gn_proj.bias"}, ["missing block1.gn_proj.bias"],
            "a MUSIQ without its projection's GroupNorm bias")
    nan = dict(ab)
    nan["beta"] = ab["beta"].clone()
    nan["beta"][0, 7, 0, 0] = float("nan")
    refused("dists", nan, ["beta", "not finite"], "a NaN")
    bad_qkv = dict(small)
    bad_qkv["blocks.1.attn.qkv.weight"] = torch.zeros(3 * 128, 64)
    refused("dino_vitb16", bad_qkv, ["blocks.1.attn.qkv.weight", "[384, 64]", "[384, 128]"], "a DINO qkv of the wrong width")
    refused("dino_vitb16", dict(small, **{"head.last_layer.weight": torch.zeros(4, 128)}), ["unexpected tensor 'head.last_layer.weight'"],
            "DINO's training head (a full checkpoint, not the pretrain file)")
    refused("dino_vitb16", {k: v for k, v in small.items() if k != "blocks.1.mlp.fc2.bias"}, ["missing blocks.1.mlp.fc2.bias"],
            "a missing DINO bias")
    # A random file under a published name: its hash cannot be the publisher's. torchvision's downloader
    # checks the name's hash prefix, so the converter refuses it; pyiqa's does not, so it only notes it.
    p, path, out = convert("vgg16", vgg16_published, name="vgg16-397923af.pth")
    line = p.stderr.strip()
    check(p.returncode == 1 and "vgg16-397923af.pth: sha256 " in line and "published vgg16-397923af.pth has 397923af" in line
          and not os.path.exists(out), "a torchvision name with another file's hash is refused: " + line)
    p, path, out = convert("dists", ab, name="DISTS_weights-f5e65c96.pth")
    check(p.returncode == 0 and "note: DISTS_weights-f5e65c96.pth: sha256 " in p.stdout and "pyiqa does not check it" in p.stdout
          and os.path.exists(os.path.join(out, "dists.safetensors")), "a pyiqa name with another hash converts with a note")
    # CLIP-IQA+: OpenAI's RN50.pt is a TorchScript archive (here traced from reference_nets.ClipModel at a
    # small width) and pyiqa's prompts file a bare tensor. The file keeps the image tower's tensors bit
    # for bit, logit_scale, and the two prompt features; the text tower and the attention pool's
    # positional_embedding (unused: pos_embedding=False) are dropped.
    clip_model = ClipModel(width=8, blocks=[1, 2, 1, 1], embed=16, text_width=64, text_layers=2, vocab=64).eval()
    clip_pt, prompts = os.path.join(work, "clip_rn50_random.pt"), os.path.join(work, "CLIP-IQA+_learned_prompts.pth")
    torch.jit.save(torch.jit.trace(clip_model, torch.rand(1, 3, 64, 64)), clip_pt)
    ctx = torch.randn(2, 16, 64)
    torch.save(ctx, prompts)

    def convert_clip(clip_path, prompts_path, out, tokenizer=tokenize):
        stdout, stderr = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            code = convert_weights.main(["convert_weights.py", "clipiqa_plus", clip_path, prompts_path, out], tokenizer)
        return subprocess.CompletedProcess([], code, stdout.getvalue(), stderr.getvalue())

    out = os.path.join(work, "out_clipiqa")
    p = convert_clip(clip_pt, prompts, out)
    check(p.returncode == 0 and "is not CLIP RN50 (width 8, blocks [1, 2, 1, 1], 16 outputs)" in p.stdout,
          "a TorchScript CLIP archive and a prompts tensor convert, with a note on the width (%s)" % p.stderr.strip())
    got, _ = read_safetensors(os.path.join(out, "clipiqa_plus.safetensors"))
    visual = {k: v for k, v in clip_model.state_dict().items()
              if k.startswith("visual.") and "positional_embedding" not in k and not k.endswith("num_batches_tracked")}
    with torch.no_grad():
        features = clip_model.double().prompt_features(tokenize(["X " * 16 + "Good photo..", "X " * 16 + "Bad photo.."]),
                                                       ctx.double())
    clip_model.float()
    check(sorted(got) == sorted(list(visual) + ["logit_scale", "text_features"]) and
          all(torch.equal(got[k], v) for k, v in visual.items()) and float(got["logit_scale"]) == float(clip_model.logit_scale),
          "clipiqa_plus: the image tower (%d tensors) bit for bit and logit_scale; text tower and position embedding dropped"
          % len(visual))
    worst = float((got["text_features"].double() - features).abs().max() / features.abs().max())
    # The converter's functional text transformer against nn.MultiheadAttention's, both float64, stored
    # as float32: measured 3.6e-8 of the largest value.
    check(list(got["text_features"].shape) == [2, 16] and worst < 1e-7,
          "clipiqa_plus: the prompt features match the reference PromptLearner (%.1e of the largest value)" % worst)

    def clip_refused(state, parts, what, ctx_value=ctx, tokenizer=tokenize):
        bad_files.append(what)
        path, ctx_path = os.path.join(work, "bad_%d.pt" % len(bad_files)), os.path.join(work, "bad_%d_ctx.pth" % len(bad_files))
        torch.save(state, path)
        torch.save(ctx_value, ctx_path)
        p = convert_clip(path, ctx_path, os.path.join(work, "x_clip"), tokenizer)
        line = p.stderr.strip()
        check(p.returncode == 1 and all(x in line for x in parts) and not os.path.exists(os.path.join(work, "x_clip")),
              "%s is refused: %s" % (what, line))

    clip_state = clip_model.state_dict()
    clip_refused(dict(clip_state, **{"visual.attnpool.extra": torch.zeros(3)}), ["unexpected tensor 'visual.attnpool.extra'"],
                 "an unknown CLIP tensor")
    clip_refused({k: v for k, v in clip_state.items() if k != "visual.layer2.1.bn2.running_var"},
                 ["missing visual.layer2.1.bn2.running_var"], "a CLIP ResNet without a BatchNorm statistic")
    clip_refused({k: v for k, v in clip_state.items() if k != "transformer.resblocks.1.mlp.c_fc.bias"},
                 ["missing transformer.resblocks.1.mlp.c_fc.bias"], "a CLIP text tower without a bias")
    clip_refused(clip_state, ["learned context has shape [2, 8, 64]", "needs [2, 16, 64]"], "a learned context of 8 tokens",
                 ctx_value=torch.randn(2, 8, 64))
    clip_refused(dict(clip_state, **{"text_projection": torch.randn(64, 32)}), ["text_projection", "[64, 32]", "[64, 16]"],
                 "a text projection of another width than the image tower's")
    clip_refused(clip_state, ["needs OpenAI CLIP's tokenizer", "openai-clip"], "a conversion without the clip package",
                 tokenizer=convert_weights.openai_tokenize)
    with open(os.path.join(work, "not_a_checkpoint.pth"), "w") as f:
        f.write("hello")
    p = run_converter("vgg16", os.path.join(work, "not_a_checkpoint.pth"), os.path.join(work, "x"))
    check(p.returncode == 1 and "not_a_checkpoint.pth: not a PyTorch checkpoint" in p.stderr, "a text file is refused: " + p.stderr.strip())
    if FAILURES:
        sys.exit("%d check(s) failed; the files are in %s" % (len(FAILURES), work))
    shutil.rmtree(work)  # about 770 MB of checkpoints and conversions


if __name__ == "__main__":
    main()

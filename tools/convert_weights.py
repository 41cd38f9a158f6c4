#!/usr/bin/env python3
"""Published metric checkpoints -> the safetensors files `style4d bench --metric-weights DIR` reads.

    python3 tools/convert_weights.py KIND CHECKPOINT DIR
    python3 tools/convert_weights.py clipiqa_plus RN50.pt CLIP-IQA+_learned_prompts-603f3273.pth DIR

KIND (docs/bench.md, "Learned metrics", has the table of files):
  vgg16, vgg19, alexnet  torchvision vgg16-397923af.pth, vgg19-dcbb9e9d.pth, alexnet-owt-7be5be79.pth
                         -> vgg16/vgg19/alexnet.safetensors ("features.<i>" only; the classifier is dropped)
  lpips_vgg, lpips_alex  LPIPS weights/v0.1/vgg.pth, alex.pth ("lin<l>.model.1.weight"), or pyiqa's
                         LPIPS_v0.1_vgg-a78928a0.pth / LPIPS_v0.1_alex-df73285e.pth, whose backbone
                         ("net.slice<s>.<i>") also becomes vgg16/alexnet.safetensors
  dists                  DISTS_pytorch/weights.pt ("alpha", "beta"), or pyiqa's DISTS_weights-f5e65c96.pth,
                         whose VGG16 ("stage<s>.<i>") also becomes vgg16.safetensors
  vgg_normalised         AdaIN's vgg_normalised.pth (nn.Sequential names "0", "2", ...)
  dino_vitb16            DINO's dino_vitbase16_pretrain.pth (vision_transformer.py names: cls_token,
                         pos_embed, patch_embed.proj, blocks.<i>.norm1/attn.qkv/attn.proj/norm2/mlp.fc1/
                         mlp.fc2, norm) -> dino_vitb16.safetensors; width, depth, patch and grid are read
                         from the shapes (ViT-B/16: 768, 12, 16, 14) and every tensor checked against them
  ckdn                   pyiqa's CKDN_model_best-38b27dc6.pth (pyiqa's CKDN module: "net.qse_1.weight", ...)
                         -> ckdn.safetensors with the tensors its forward pass reads (the branch stems
                         qse_*/dte_*, csp, fc_; aux_csp, fc1_ and num_batches_tracked are dropped)
  musiq, musiq_paq2piq   pyiqa's musiq_koniq_ckpt-e95806b9.pth / musiq_paq2piq_ckpt-364c0c84.pth (pyiqa's MUSIQ
                         module: conv_root, gn_root, block1.*, embedding, transformer_encoder.*, head)
                         -> musiq.safetensors / musiq_paq2piq.safetensors; width, depth, MLP, position grid
                         and scales read from the shapes (pyiqa: 384, 14, 1152, 10, 3), one output class
                         (the AVA checkpoint's 10-class head is refused)
  clipiqa_plus           OpenAI CLIP's RN50.pt (a TorchScript archive or a state dict) and pyiqa's
                         CLIP-IQA+_learned_prompts-603f3273.pth (the CoOp context, [2, 16, 512])
                         -> clipiqa_plus.safetensors: the image tower "visual.*" as CLIP names it (the
                         attention pool's positional_embedding dropped: pyiqa runs without it),
                         "logit_scale" and "text_features" [2, embed] (good, bad): pyiqa's
                         PromptLearner output, computed here in float64 through CLIP's text
                         transformer from RN50.pt's text weights (which are then dropped). The prompt
                         tokens come from OpenAI CLIP's tokenizer (the `clip` module of the
                         openai-clip package that pyiqa imports).
Every tensor's name and shape is checked against the network's definition; the state-dict names are
kept, so the native loaders read the file as PyTorch would. Prints the input's sha256 and compares it
with the publisher's (tools/published_weights.py): a torchvision or CLIP file whose hash differs from
the one its name or address carries is refused. Needs torch to read .pth.
"""
import hashlib
import json
import os
import re
import struct
import sys

import published_weights

# torchvision's cfgs "D" (VGG16) and "E" (VGG19): channels of each 3x3 convolution, 0 for a max pool.
VGG_CFGS = {
    "vgg16": [64, 64, 0, 128, 128, 0, 256, 256, 256, 0, 512, 512, 512, 0, 512, 512, 512, 0],
    "vgg19": [64, 64, 0, 128, 128, 0, 256, 256, 256, 256, 0, 512, 512, 512, 512, 0, 512, 512, 512, 512, 0],
}
# Channels of the five LPIPS taps, per backbone.
LPIPS_WIDTHS = {"lpips_vgg": [64, 128, 256, 512, 512], "lpips_alex": [64, 192, 384, 256, 256]}
DISTS_CHANNELS = 3 + 64 + 128 + 256 + 512 + 512  # stage 0 (the image) and relu1_2 .. relu5_3


class ConvertError(Exception):
    pass


def conv(prefix, cout, cin, k):
    return {prefix + ".weight": [cout, cin, k, k], prefix + ".bias": [cout]}


def torchvision_vgg(depth):
    """features.<i>.weight/bias of every convolution, i the module index in `features`."""
    spec, index, cin = {}, 0, 3
    for v in VGG_CFGS[depth]:
        if v == 0:
            index += 1
            continue
        spec.update(conv("features.%d" % index, v, cin, 3))
        cin, index = v, index + 2
    return spec


def torchvision_alexnet():
    spec = {}
    for index, cout, cin, k in [(0, 64, 3, 11), (3, 192, 64, 5), (6, 384, 192, 3), (8, 256, 384, 3), (10, 256, 256, 3)]:
        spec.update(conv("features.%d" % index, cout, cin, k))
    return spec


def adain_vgg_normalised():
    """AdaIN net.py's `vgg`: a 1x1 convolution, then VGG19's 16 3x3 convolutions, each after a
    ReflectionPad2d and before a ReLU, with max pools after relu1_2, relu2_2, relu3_4, relu4_4."""
    spec = conv("0", 3, 3, 1)
    index, cin = 2, 3
    for v in VGG_CFGS["vgg19"][:-1]:
        if v == 0:
            index += 1
            continue
        spec.update(conv(str(index), v, cin, 3))
        cin, index = v, index + 3
    return spec


def dino_vit(path, t):
    """DINO vision_transformer.py's state dict, its dimensions taken from cls_token [1, 1, D],
    patch_embed.proj.weight [D, 3, P, P], pos_embed [1, 1 + g^2, D], the blocks.<i> present and
    blocks.0.mlp.fc1.weight [M, D]."""
    for name in ("cls_token", "pos_embed", "patch_embed.proj.weight", "blocks.0.mlp.fc1.weight"):
        if name not in t:
            raise ConvertError("%s: missing %s (DINO ViT)" % (path, name))
    d, p, m = t["cls_token"].shape[-1], t["patch_embed.proj.weight"].shape[-1], t["blocks.0.mlp.fc1.weight"].shape[0]
    g = int(round((t["pos_embed"].shape[1] - 1) ** 0.5))
    depth = 0
    while "blocks.%d.norm1.weight" % depth in t:
        depth += 1
    spec = {"cls_token": [1, 1, d], "pos_embed": [1, 1 + g * g, d], "norm.weight": [d], "norm.bias": [d],
            "patch_embed.proj.weight": [d, 3, p, p], "patch_embed.proj.bias": [d]}
    for i in range(depth):
        b = "blocks.%d." % i
        for name, shape in (("norm1", [d]), ("norm2", [d])):
            spec.update({b + name + ".weight": shape, b + name + ".bias": shape})
        for name, cout, cin in (("attn.qkv", 3 * d, d), ("attn.proj", d, d), ("mlp.fc1", m, d), ("mlp.fc2", d, m)):
            spec.update({b + name + ".weight": [cout, cin], b + name + ".bias": [cout]})
    out = check(path, t, spec, "DINO ViT (width %d, %d blocks, patch %d, grid %d, MLP %d)" % (d, depth, p, g, m))
    if (d, depth, p, g, m) != (768, 12, 16, 14, 3072):
        print("note: %s is not DINO ViT-B/16 (width %d, %d blocks, patch %d); VBench's subject consistency uses "
              "dino_vitbase16_pretrain.pth" % (path, d, depth, p))
    return out


def ckdn():
    """pyiqa archs/ckdn_arch.py's CKDN (module "net"): two ResNet-50 stems, Conv2d(3, 64, 7, bias=False)
    qse_1/dte_1 and torchvision's layer1 qse_2/dte_2 (3 Bottlenecks of width 64), layer2 csp (4 of
    width 128, the first with the downsample), the MLP fc_ = Linear(512, 2048), ReLU, Dropout,
    Linear(2048, 2048), ReLU, Dropout, Linear(2048, 1). Convolutions have no bias; each has a BatchNorm2d."""
    def bn(prefix, c):
        return {prefix + "." + p: [c] for p in ("weight", "bias", "running_mean", "running_var")}

    def layer(prefix, cin, planes, blocks):
        spec = {}
        for i in range(blocks):
            p, inp = "%s.%d" % (prefix, i), cin if i == 0 else 4 * planes
            for n, (cout, c, k) in enumerate([(planes, inp, 1), (planes, planes, 3), (4 * planes, planes, 1)], 1):
                spec["%s.conv%d.weight" % (p, n)] = [cout, c, k, k]
                spec.update(bn("%s.bn%d" % (p, n), cout))
            if i == 0:
                spec[p + ".downsample.0.weight"] = [4 * planes, inp, 1, 1]
                spec.update(bn(p + ".downsample.1", 4 * planes))
        return spec

    spec = {"net.qse_1.weight": [64, 3, 7, 7], "net.dte_1.weight": [64, 3, 7, 7]}
    spec.update(layer("net.qse_2", 64, 64, 3))
    spec.update(layer("net.dte_2", 64, 64, 3))
    spec.update(layer("net.csp", 256, 128, 4))
    for index, out, inp in [(0, 2048, 512), (3, 2048, 2048), (6, 1, 2048)]:
        spec.update({"net.fc_.%d.weight" % index: [out, inp], "net.fc_.%d.bias" % index: [out]})
    return spec


def clip_visual(t, path):
    """CLIP model.py's ModifiedResNet under "visual.": width w (conv3's outputs), block counts from
    the layers present, embed 32 w, the output dim from c_proj. Returns (spec, (w, blocks, out))."""
    for name in ("visual.conv3.weight", "visual.attnpool.c_proj.weight"):
        if name not in t:
            raise ConvertError("%s: missing %s (CLIP ResNet image tower)" % (path, name))
    w, out = t["visual.conv3.weight"].shape[0], t["visual.attnpool.c_proj.weight"].shape[0]
    blocks = [len({n.split(".")[2] for n in t if n.startswith("visual.layer%d." % l)}) for l in (1, 2, 3, 4)]

    def bn(prefix, c):
        return {prefix + "." + p: [c] for p in ("weight", "bias", "running_mean", "running_var")}

    spec = {}
    for i, (cout, cin) in enumerate([(w // 2, 3), (w // 2, w // 2), (w, w // 2)], 1):
        spec["visual.conv%d.weight" % i] = [cout, cin, 3, 3]
        spec.update(bn("visual.bn%d" % i, cout))
    cin = w
    for l, n in enumerate(blocks):
        planes = w << l
        for i in range(n):
            p, inp = "visual.layer%d.%d" % (l + 1, i), cin if i == 0 else 4 * planes
            for k, (co, ci, size) in enumerate([(planes, inp, 1), (planes, planes, 3), (4 * planes, planes, 1)], 1):
                spec["%s.conv%d.weight" % (p, k)] = [co, ci, size, size]
                spec.update(bn("%s.bn%d" % (p, k), co))
            if i == 0 and (l > 0 or inp != 4 * planes):
                spec[p + ".downsample.0.weight"] = [4 * planes, inp, 1, 1]
                spec.update(bn(p + ".downsample.1", 4 * planes))
        cin = 4 * planes
    e = 32 * w
    for name, rows in (("q_proj", e), ("k_proj", e), ("v_proj", e), ("c_proj", out)):
        spec.update({"visual.attnpool.%s.weight" % name: [rows, e], "visual.attnpool.%s.bias" % name: [rows]})
    return spec, (w, blocks, out)


def clip_text(t, path, out):
    """CLIP model.py's text tower: width from ln_final, context length from positional_embedding, the
    blocks present (heads of 64 channels), text_projection to the image tower's output dim."""
    for name in ("ln_final.weight", "positional_embedding", "token_embedding.weight"):
        if name not in t:
            raise ConvertError("%s: missing %s (CLIP's text tower, for the prompt features)" % (path, name))
    width, length = t["ln_final.weight"].shape[0], t["positional_embedding"].shape[0]
    spec = {"token_embedding.weight": [t["token_embedding.weight"].shape[0], width], "positional_embedding": [length, width],
            "ln_final.weight": [width], "ln_final.bias": [width], "text_projection": [width, out]}
    for i in range(len({n.split(".")[2] for n in t if n.startswith("transformer.resblocks.")})):
        b = "transformer.resblocks.%d." % i
        for name, shape in (("ln_1.weight", [width]), ("ln_1.bias", [width]), ("ln_2.weight", [width]), ("ln_2.bias", [width]),
                            ("attn.in_proj_weight", [3 * width, width]), ("attn.in_proj_bias", [3 * width]),
                            ("attn.out_proj.weight", [width, width]), ("attn.out_proj.bias", [width]),
                            ("mlp.c_fc.weight", [4 * width, width]), ("mlp.c_fc.bias", [4 * width]),
                            ("mlp.c_proj.weight", [width, 4 * width]), ("mlp.c_proj.bias", [width])):
            spec[b + name] = shape
    if length < 22 or width % 64 != 0:
        raise ConvertError("%s: a text tower of width %d and context %d cannot hold CLIP-IQA+'s prompts (needs 22 "
                           "tokens, 64-wide heads)" % (path, width, length))
    return spec


def clip_prompt_features(t, ctx, tokenize, path):
    """pyiqa's PromptLearner.forward in float64: the tokens of "X x16 Good photo.." / "... Bad photo..",
    their embeddings with the 16 "X" replaced by the learned context split around the first 3 class
    tokens ("good photo ." or "bad photo ."), CLIP's text transformer (pre-LayerNorm blocks, causal
    mask, QuickGELU), ln_final, the end-of-text token's row times text_projection."""
    import torch
    import torch.nn.functional as F
    n_ctx, width = 16, t["ln_final.weight"].shape[0]
    if ctx.dim() == 2:
        ctx = ctx.unsqueeze(0).expand(2, -1, -1)
    if list(ctx.shape) != [2, n_ctx, width]:
        raise ConvertError("%s: the learned context has shape %s, needs [2, %d, %d] (or [%d, %d])" %
                           (path, list(ctx.shape), n_ctx, width, n_ctx, width))
    prefix = " ".join(["X"] * n_ctx) + " "
    tokens = tokenize([prefix + "Good photo..", prefix + "Bad photo.."])
    d = {k: v.double() for k, v in t.items()}
    emb = d["token_embedding.weight"][tokens]
    half = n_ctx // 2
    x = torch.cat([emb[:, :1], ctx[:, :half].double(), emb[:, 1 + n_ctx:4 + n_ctx], ctx[:, half:].double(),
                   emb[:, 4 + n_ctx:]], dim=1) + d["positional_embedding"]
    length, heads = x.shape[1], width // 64
    mask = torch.full((length, length), float("-inf"), dtype=torch.float64).triu(1)
    layers = len({n.split(".")[2] for n in t if n.startswith("transformer.resblocks.")})
    for i in range(layers):
        b = "transformer.resblocks.%d." % i
        h = F.layer_norm(x, (width,), d[b + "ln_1.weight"], d[b + "ln_1.bias"])
        q, k, v = (h @ d[b + "attn.in_proj_weight"].T + d[b + "attn.in_proj_bias"]).split(width, dim=-1)
        split = lambda z: z.reshape(2, length, heads, width // heads).transpose(1, 2)
        scores = split(q) @ split(k).transpose(-1, -2) / (width // heads) ** 0.5 + mask
        a = (scores.softmax(-1) @ split(v)).transpose(1, 2).reshape(2, length, width)
        x = x + a @ d[b + "attn.out_proj.weight"].T + d[b + "attn.out_proj.bias"]
        h = F.layer_norm(x, (width,), d[b + "ln_2.weight"], d[b + "ln_2.bias"])
        h = h @ d[b + "mlp.c_fc.weight"].T + d[b + "mlp.c_fc.bias"]
        h = h * torch.sigmoid(1.702 * h)
        x = x + h @ d[b + "mlp.c_proj.weight"].T + d[b + "mlp.c_proj.bias"]
    x = F.layer_norm(x, (width,), d["ln_final.weight"], d["ln_final.bias"])
    return (x[torch.arange(2), tokens.argmax(dim=-1)] @ d["text_projection"]).float()


def openai_tokenize(texts):
    try:
        import clip
    except ImportError as e:
        raise ConvertError("clipiqa_plus needs OpenAI CLIP's tokenizer, the `clip` module pyiqa imports "
                           "(pip install openai-clip): %s" % e)
    return clip.tokenize(texts)


def load_clip(path):
    """RN50.pt as OpenAI publishes it (a TorchScript archive), or a plain state dict."""
    import torch
    try:
        state = {k: v for k, v in torch.jit.load(path, map_location="cpu").state_dict().items()}
    except Exception:
        return load_state_dict(path)
    return state


def clipiqa_plus(clip_path, prompts_path, tokenize=openai_tokenize):
    import torch
    t = load_clip(clip_path)
    refuse_unknown(clip_path, t, [r"visual\.(conv\d|bn\d)\..*", r"visual\.layer\d\.\d+\..*", r"visual\.attnpool\..*",
                                  r"transformer\.resblocks\.\d+\..*", r"token_embedding\.weight", r"positional_embedding",
                                  r"ln_final\.(weight|bias)", r"text_projection", r"logit_scale",
                                  r"input_resolution", r"context_length", r"vocab_size"], "clipiqa_plus (CLIP RN50.pt)")
    refuse_unknown(clip_path, {n: v for n, v in t.items() if n.startswith("visual.")},
                   [r"visual\.(conv\d\.weight|bn\d\.(weight|bias|running_mean|running_var|num_batches_tracked))",
                    r"visual\.layer\d\.\d+\.(conv\d\.weight|(bn\d|downsample\.1)\.(weight|bias|running_mean|running_var|"
                    r"num_batches_tracked)|downsample\.0\.weight)",
                    r"visual\.attnpool\.(positional_embedding|[qkvc]_proj\.(weight|bias))"], "clipiqa_plus (CLIP ResNet)")
    spec, (w, blocks, out) = clip_visual(t, clip_path)
    spec["logit_scale"] = []
    tensors = check(clip_path, t, spec, "CLIP ResNet (width %d, blocks %s, %d outputs)" % (w, blocks, out))
    if (w, blocks, out) != (64, [3, 4, 6, 3], 1024):
        print("note: %s is not CLIP RN50 (width %d, blocks %s, %d outputs); pyiqa's clipiqa+ uses RN50" %
              (clip_path, w, blocks, out))
    text = check(clip_path, t, clip_text(t, clip_path, out), "CLIP text transformer")
    try:
        ctx = torch.load(prompts_path, map_location="cpu")
    except Exception as e:
        raise ConvertError("%s: not a PyTorch file (%s: %s)" % (prompts_path, type(e).__name__, e))
    if not torch.is_tensor(ctx) or not ctx.is_floating_point():
        raise ConvertError("%s: holds a %s, not the learned context tensor" % (prompts_path, type(ctx).__name__))
    features = clip_prompt_features(text, ctx, tokenize, prompts_path)
    tensors["text_features"] = check(prompts_path, {"text_features": features}, {"text_features": [2, out]},
                                     "CLIP-IQA+ prompt features")["text_features"]
    return {"clipiqa_plus.safetensors": tensors}
def musiq(path, t):
    """pyiqa archs/musiq_arch.py's MUSIQ: the ResNet root (StdConv conv_root 7x7 and GroupNorm gn_root of
    width 64, block1 = one Bottleneck 64 -> 256 with conv1/2/3, conv_proj and their gn*), embedding =
    Linear(8 * 8 * 256, D), the transformer_encoder (hashed position_emb [1, g^2, D], scale_emb [S, D], cls,
    encoderblock_<i> with norm1, attention.query/key/value/out, norm2, mlp.fc1/fc2; encoder_norm) and head."""
    for name in ("embedding.weight", "transformer_encoder.posembed_input.position_emb",
                 "transformer_encoder.scaleembed_input.scale_emb", "head.weight"):
        if name not in t:
            raise ConvertError("%s: missing %s (pyiqa MUSIQ)" % (path, name))
    if t["head.weight"].shape[0] != 1:
        raise ConvertError("%s: head.weight has shape %s: a %d-class head (MUSIQ-AVA's distribution); only the "
                           "one-output KonIQ / PaQ-2-PiQ / SPAQ checkpoints are supported" %
                           (path, list(t["head.weight"].shape), t["head.weight"].shape[0]))
    d = t["embedding.weight"].shape[0]
    cells, scales = t["transformer_encoder.posembed_input.position_emb"].shape[1], t["transformer_encoder.scaleembed_input.scale_emb"].shape[0]
    block = "transformer_encoder.transformer.encoderblock_%d."
    depth = 0
    while (block % depth) + "norm1.weight" in t:
        depth += 1
    m = t[(block % 0) + "mlp.fc1.weight"].shape[0] if depth > 0 else 0
    spec = {"conv_root.weight": [64, 3, 7, 7], "embedding.weight": [d, 8 * 8 * 256], "embedding.bias": [d],
            "transformer_encoder.posembed_input.position_emb": [1, cells, d],
            "transformer_encoder.scaleembed_input.scale_emb": [scales, d], "transformer_encoder.cls": [1, 1, d],
            "transformer_encoder.encoder_norm.weight": [d], "transformer_encoder.encoder_norm.bias": [d],
            "head.weight": [1, d], "head.bias": [1]}
    for name, (cout, cin, k) in {"conv1": (64, 64, 1), "conv2": (64, 64, 3), "conv3": (256, 64, 1),
                                 "conv_proj": (256, 64, 1)}.items():
        spec["block1.%s.weight" % name] = [cout, cin, k, k]
    for name, c in {"gn_root": 64, "block1.gn1": 64, "block1.gn2": 64, "block1.gn3": 256, "block1.gn_proj": 256}.items():
        spec.update({name + ".weight": [c], name + ".bias": [c]})
    for i in range(depth):
        b = block % i
        for name in ("norm1", "norm2"):
            spec.update({b + name + ".weight": [d], b + name + ".bias": [d]})
        for name, cout, cin in (("attention.query", d, d), ("attention.key", d, d), ("attention.value", d, d),
                                ("attention.out", d, d), ("mlp.fc1", m, d), ("mlp.fc2", d, m)):
            spec.update({b + name + ".weight": [cout, cin], b + name + ".bias": [cout]})
    g = int(round(cells ** 0.5))
    out = check(path, t, spec, "pyiqa MUSIQ (width %d, %d blocks, MLP %d, %d positions, %d scales)" % (d, depth, m, cells, scales))
    if (d, depth, m, cells, scales) != (384, 14, 1152, 100, 3):
        print("note: %s is not pyiqa's MUSIQ configuration (width %d, %d blocks, MLP %d, %dx%d positions, %d scales; "
              "pyiqa: 384, 14, 1152, 10x10, 3)" % (path, d, depth, m, g, g, scales))
    return out


def lpips_heads(kind):
    return {"lin%d.model.1.weight" % l: [1, c, 1, 1] for l, c in enumerate(LPIPS_WIDTHS[kind])}


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def load_state_dict(path):
    try:
        import torch
    except ImportError as e:
        raise ConvertError("reading %s needs torch (Debian: apt-get install python3-torch): %s" % (path, e))
    try:
        state = torch.load(path, map_location="cpu")
    except Exception as e:
        raise ConvertError("%s: not a PyTorch checkpoint (%s: %s)" % (path, type(e).__name__, e))
    # pyiqa's and training scripts' wrappers around the state dict.
    for key in ("params", "state_dict"):
        if isinstance(state, dict) and key in state and isinstance(state[key], dict):
            state = state[key]
    if not isinstance(state, dict):
        raise ConvertError("%s: holds a %s, not a state dict" % (path, type(state).__name__))
    out = {}
    for name, value in state.items():
        if not torch.is_tensor(value):
            raise ConvertError("%s: entry '%s' is a %s, not a tensor" % (path, name, type(value).__name__))
        out[name[len("module."):] if name.startswith("module.") else name] = value
    return out


def check(path, tensors, spec, what):
    """The spec's tensors from `tensors` as float32, each present and of its shape."""
    import torch
    out = {}
    for name, shape in spec.items():
        if name not in tensors:
            raise ConvertError("%s: missing %s (%s)" % (path, name, what))
        t = tensors[name]
        if list(t.shape) != shape:
            raise ConvertError("%s: %s has shape %s, %s needs %s" % (path, name, list(t.shape), what, shape))
        if not t.is_floating_point():
            raise ConvertError("%s: %s is %s, not floating point" % (path, name, t.dtype))
        t = t.detach().to(torch.float32)
        if not bool(torch.isfinite(t).all()):
            raise ConvertError("%s: %s holds a value that is not finite" % (path, name))
        out[name] = t
    return out


def renamed(tensors, pattern, template):
    """The tensors whose names match `pattern`, renamed by `template` (pyiqa's module paths to
    torchvision's "features.<i>": pyiqa keeps features' module indices inside its slices)."""
    return {re.sub(pattern, template, n): t for n, t in tensors.items() if re.match(pattern, n)}


def refuse_unknown(path, tensors, known_patterns, kind):
    for name in tensors:
        if not any(re.fullmatch(p, name) for p in known_patterns):
            raise ConvertError("%s: unexpected tensor '%s' for %s (is this the right KIND?)" % (path, name, kind))


def write_safetensors(path, tensors, metadata):
    """The safetensors layout: u64 header length, JSON header (names, dtype, shape, byte offsets),
    then the raw little-endian float32 data; the header is padded with spaces to 8 bytes."""
    header, blobs, offset = {"__metadata__": metadata}, [], 0
    for name in sorted(tensors):
        data = tensors[name].contiguous().numpy().astype("<f4").tobytes()
        header[name] = {"dtype": "F32", "shape": list(tensors[name].shape), "data_offsets": [offset, offset + len(data)]}
        blobs.append(data)
        offset += len(data)
    text = json.dumps(header, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 8)
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(struct.pack("<Q", len(text)))
        f.write(text)
        for b in blobs:
            f.write(b)
    os.replace(tmp, path)


def convert(kind, path):
    """{output file name: {tensor name: float32 tensor}} for a checkpoint of `kind`."""
    t = load_state_dict(path)
    if kind in ("vgg16", "vgg19"):
        refuse_unknown(path, t, [r"features\.\d+\.(weight|bias)", r"classifier\..*"], kind)
        return {kind + ".safetensors": check(path, t, torchvision_vgg(kind), "torchvision " + kind)}
    if kind == "alexnet":
        refuse_unknown(path, t, [r"features\.\d+\.(weight|bias)", r"classifier\..*"], kind)
        return {"alexnet.safetensors": check(path, t, torchvision_alexnet(), "torchvision alexnet")}
    if kind == "vgg_normalised":
        refuse_unknown(path, t, [r"\d+\.(weight|bias)"], kind)
        return {"vgg_normalised.safetensors": check(path, t, adain_vgg_normalised(), "AdaIN vgg_normalised")}
    if kind in LPIPS_WIDTHS:
        refuse_unknown(path, t, [r"lin\d\.model\.1\.weight", r"net\.slice\d\.\d+\.(weight|bias)", r"scaling_layer\.(shift|scale)"],
                       kind)
        out = {kind + ".safetensors": check(path, t, lpips_heads(kind), "LPIPS v0.1 " + kind[6:] + " heads")}
        backbone = renamed(t, r"^net\.slice\d\.(\d+)\.", r"features.\1.")
        if backbone:  # pyiqa's file: the backbone too
            if kind == "lpips_vgg":
                out["vgg16.safetensors"] = check(path, backbone, torchvision_vgg("vgg16"), "LPIPS's VGG16 (net.slice*)")
            else:
                out["alexnet.safetensors"] = check(path, backbone, torchvision_alexnet(), "LPIPS's AlexNet (net.slice*)")
        return out
    if kind == "dists":
        # pyiqa's file also holds the L2 pools' fixed filters and the ImageNet mean/std buffers.
        refuse_unknown(path, t, [r"alpha", r"beta", r"stage\d\.\d+\.(weight|bias|filter)", r"mean", r"std"], kind)
        ab = {"alpha": [1, DISTS_CHANNELS, 1, 1], "beta": [1, DISTS_CHANNELS, 1, 1]}
        out = {"dists.safetensors": check(path, t, ab, "DISTS alpha/beta")}
        backbone = renamed(t, r"^stage\d\.(\d+)\.(weight|bias)$", r"features.\1.\2")
        if backbone:
            out["vgg16.safetensors"] = check(path, backbone, torchvision_vgg("vgg16"), "DISTS's VGG16 (stage*)")
        return out
    if kind == "dino_vitb16":
        # DINO's full training checkpoints hold student/teacher dicts with heads: the pretrain file is the backbone.
        refuse_unknown(path, t, [r"cls_token", r"pos_embed", r"patch_embed\.proj\.(weight|bias)", r"norm\.(weight|bias)",
                                 r"blocks\.\d+\.(norm1|norm2|attn\.qkv|attn\.proj|mlp\.fc1|mlp\.fc2)\.(weight|bias)"], kind)
        return {"dino_vitb16.safetensors": dino_vit(path, t)}
    if kind == "ckdn":
        refuse_unknown(path, t, [r"net\.(qse|dte)_1\.weight",
                                 r"net\.(qse_2|dte_2|csp|aux_csp)\.\d+\.(conv\d|bn\d|downsample\.[01])\."
                                 r"(weight|bias|running_mean|running_var|num_batches_tracked)",
                                 r"net\.(fc_|fc1_)\.[036]\.(weight|bias)"], kind)
        return {"ckdn.safetensors": check(path, t, ckdn(), "pyiqa CKDN")}
    if kind in ("musiq", "musiq_paq2piq"):
        refuse_unknown(path, t, [r"conv_root\.weight", r"gn_root\.(weight|bias)", r"block1\.(conv1|conv2|conv3|conv_proj)\.weight",
                                 r"block1\.(gn1|gn2|gn3|gn_proj)\.(weight|bias)", r"embedding\.(weight|bias)", r"head\.(weight|bias)",
                                 r"transformer_encoder\.(posembed_input\.position_emb|scaleembed_input\.scale_emb|cls)",
                                 r"transformer_encoder\.encoder_norm\.(weight|bias)",
                                 r"transformer_encoder\.transformer\.encoderblock_\d+\.(norm1|norm2|attention\.(query|key|value|out)|"
                                 r"mlp\.fc1|mlp\.fc2)\.(weight|bias)"], kind)
        return {kind + ".safetensors": musiq(path, t)}
    raise ConvertError("unknown KIND '%s' (vgg16, vgg19, alexnet, lpips_vgg, lpips_alex, dists, vgg_normalised, dino_vitb16, "
                       "ckdn, clipiqa_plus, musiq, musiq_paq2piq)" % kind)


def check_published(path, digest):
    """Prints the input's sha256; refuses a published file whose hash differs from its publisher's."""
    print("sha256 %s  %s" % (digest, path))
    note = published_weights.check(os.path.basename(path), digest)
    if note:
        print("note: " + note)


def main(argv, tokenize=openai_tokenize):
    if len(argv) == 2 and argv[1] in ("-h", "--help"):  # asked for: the usage on stdout, success
        sys.stdout.write(__doc__)
        return 0
    inputs = 3 if len(argv) > 1 and argv[1] == "clipiqa_plus" else 2
    if len(argv) != 2 + inputs:
        sys.stderr.write(__doc__)
        return 2
    kind, paths, out_dir = argv[1], argv[2:-1], argv[-1]
    path = paths[0]
    try:
        digest = sha256(path)
        check_published(path, digest)
        if kind == "clipiqa_plus":
            check_published(paths[1], sha256(paths[1]))
            files = clipiqa_plus(path, paths[1], tokenize)
        else:
            files = convert(kind, path)
        os.makedirs(out_dir, exist_ok=True)
        for name, tensors in files.items():
            target = os.path.join(out_dir, name)
            write_safetensors(target, tensors, {"format": "pt", "source": os.path.basename(path), "source_sha256": digest})
            print("wrote %s (%d tensors)" % (target, len(tensors)))
    except (ConvertError, published_weights.HashMismatch, OSError) as e:
        sys.stderr.write("convert_weights: %s\n" % e)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

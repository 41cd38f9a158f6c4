"""Networks the PyTorch tests build (torch_reference.py, dino_reference.py, test_convert_weights.py),
written from their authors' definitions."""
import torch.nn as nn
from torchvision.models.vgg import cfgs


def adain_vgg():
    """AdaIN net.py's `vgg` (vgg_normalised.pth), up to relu5_4."""
    layers, cin = [nn.Conv2d(3, 3, 1)], 3
    for v in cfgs["E"][:-1]:
        if v == "M":
            layers.append(nn.MaxPool2d(2, 2, 0, ceil_mode=True))
        else:
            layers += [nn.ReflectionPad2d(1), nn.Conv2d(cin, v, 3), nn.ReLU()]
            cin = v
    return nn.Sequential(*layers)


def dino_state_dict(vit):
    """torchvision's VisionTransformer under DINO vision_transformer.py's names (dino_vitbase16_pretrain.pth),
    the classification head dropped: nn.MultiheadAttention's in_proj rows are q, k, v as DINO's qkv."""
    out = {"cls_token": vit.class_token, "pos_embed": vit.encoder.pos_embedding,
           "patch_embed.proj.weight": vit.conv_proj.weight, "patch_embed.proj.bias": vit.conv_proj.bias,
           "norm.weight": vit.encoder.ln.weight, "norm.bias": vit.encoder.ln.bias}
    for i, layer in enumerate(vit.encoder.layers):
        b = "blocks.%d." % i
        pairs = {"norm1": layer.ln_1, "norm2": layer.ln_2, "attn.proj": layer.self_attention.out_proj,
                 "mlp.fc1": layer.mlp[0], "mlp.fc2": layer.mlp[3]}
        for name, m in pairs.items():
            out[b + name + ".weight"], out[b + name + ".bias"] = m.weight, m.bias
        out[b + "attn.qkv.weight"] = layer.self_attention.in_proj_weight
        out[b + "attn.qkv.bias"] = layer.self_attention.in_proj_bias
    return {k: v.detach().clone().float().contiguous() for k, v in out.items()}


class CkdnResNet(nn.Module):
    """CKDN's two-branch ResNet (Zheng et al. 2021; pyiqa archs/ckdn_arch.py's ResNet, module "net")
    assembled from torchvision's ResNet-50 modules: per branch conv1 (7x7 stride 2, no BN/ReLU after
    it in CKDN), ResNet's MaxPool2d(3, 2, 1) and layer1; the difference restored - reference through
    layer2 ("csp"), global average, MLP 512-2048-2048-1 with dropout, sigmoid. aux_csp and fc1_ exist
    in the published state dict but not in the forward pass."""

    def __init__(self):
        super().__init__()
        import torchvision
        restored, reference = torchvision.models.resnet50(), torchvision.models.resnet50()
        self.qse_1, self.qse_2, self.csp = restored.conv1, restored.layer1, restored.layer2
        self.dte_1, self.dte_2, self.aux_csp = reference.conv1, reference.layer1, reference.layer2
        self.maxpool, self.avgpool = restored.maxpool, nn.AdaptiveAvgPool2d(1)
        mlp = lambda: nn.Sequential(nn.Linear(512, 2048), nn.ReLU(True), nn.Dropout(), nn.Linear(2048, 2048), nn.ReLU(True),
                                    nn.Dropout(), nn.Linear(2048, 1))
        self.fc_, self.fc1_ = mlp(), mlp()

    def forward(self, x, y):
        import torch
        d = self.qse_2(self.maxpool(self.qse_1(x))) - self.dte_2(self.maxpool(self.dte_1(y)))
        return torch.sigmoid(self.fc_(torch.flatten(self.avgpool(self.csp(d)), 1)))


class Ckdn(nn.Module):
    """pyiqa's CKDN module, whose state dict (CKDN_model_best-38b27dc6.pth) names everything "net.*"."""

    def __init__(self):
        super().__init__()
        self.net = CkdnResNet()


class ClipBottleneck(nn.Module):
    """CLIP model.py's Bottleneck: 1x1, 3x3 (padding 1), 1x1 convolutions without bias, each with a
    BatchNorm; the stride is an AvgPool2d after the 3x3's ReLU, and the downsample path ("-1" the
    pooling, "0" the 1x1 convolution, "1" its BatchNorm) exists when the block strides or widens."""

    def __init__(self, cin, planes, stride):
        super().__init__()
        from collections import OrderedDict
        self.conv1, self.bn1 = nn.Conv2d(cin, planes, 1, bias=False), nn.BatchNorm2d(planes)
        self.conv2, self.bn2 = nn.Conv2d(planes, planes, 3, padding=1, bias=False), nn.BatchNorm2d(planes)
        self.avgpool = nn.AvgPool2d(stride) if stride > 1 else nn.Identity()
        self.conv3, self.bn3 = nn.Conv2d(planes, 4 * planes, 1, bias=False), nn.BatchNorm2d(4 * planes)
        self.relu = nn.ReLU()
        self.downsample = None
        if stride > 1 or cin != 4 * planes:
            self.downsample = nn.Sequential(OrderedDict([("-1", nn.AvgPool2d(stride)),
                                                         ("0", nn.Conv2d(cin, 4 * planes, 1, bias=False)),
                                                         ("1", nn.BatchNorm2d(4 * planes))]))

    def forward(self, x):
        out = self.relu(self.bn1(self.conv1(x)))
        out = self.avgpool(self.relu(self.bn2(self.conv2(out))))
        out = self.bn3(self.conv3(out))
        return self.relu(out + (x if self.downsample is None else self.downsample(x)))


class ClipAttentionPool(nn.Module):
    """CLIP's AttentionPool2d: tokens = [spatial mean, positions], multi-head attention of all tokens
    (PyTorch's multi_head_attention_forward with separate q/k/v projections), output token 0. With
    pos_embedding, pyiqa's variant: the stored embedding resized bicubically to the token count."""

    def __init__(self, grid, embed, heads, out):
        super().__init__()
        import torch
        self.positional_embedding = nn.Parameter(torch.randn(grid * grid + 1, embed) / embed ** 0.5)
        self.k_proj, self.q_proj, self.v_proj = nn.Linear(embed, embed), nn.Linear(embed, embed), nn.Linear(embed, embed)
        self.c_proj = nn.Linear(embed, out)
        self.heads = heads

    def forward(self, x, pos_embedding=False):
        import torch
        import torch.nn.functional as F
        x = x.flatten(2).permute(2, 0, 1)  # [HW, N, C]
        x = torch.cat([x.mean(dim=0, keepdim=True), x], dim=0)
        if pos_embedding:
            pos = F.interpolate(self.positional_embedding[None, None], size=(x.shape[0], x.shape[2]), mode="bicubic")[0, 0]
            x = x + pos[:, None, :].to(x.dtype)
        x, _ = F.multi_head_attention_forward(
            query=x, key=x, value=x, embed_dim_to_check=x.shape[-1], num_heads=self.heads,
            q_proj_weight=self.q_proj.weight, k_proj_weight=self.k_proj.weight, v_proj_weight=self.v_proj.weight,
            in_proj_weight=None, in_proj_bias=torch.cat([self.q_proj.bias, self.k_proj.bias, self.v_proj.bias]),
            bias_k=None, bias_v=None, add_zero_attn=False, dropout_p=0.0, out_proj_weight=self.c_proj.weight,
            out_proj_bias=self.c_proj.bias, use_separate_proj_weight=True, training=False, need_weights=False)
        return x[0]


class ClipResnet(nn.Module):
    """CLIP's ModifiedResNet: three 3x3 stem convolutions (the first stride 2) with BatchNorm and ReLU,
    AvgPool2d(2), four layers of ClipBottlenecks (widths w, 2w, 4w, 8w; strides 1, 2, 2, 2), the
    attention pool over 32 w channels with 32 w / 64 heads."""

    def __init__(self, width, blocks, out, grid=7):
        super().__init__()
        self.conv1, self.bn1 = nn.Conv2d(3, width // 2, 3, stride=2, padding=1, bias=False), nn.BatchNorm2d(width // 2)
        self.conv2, self.bn2 = nn.Conv2d(width // 2, width // 2, 3, padding=1, bias=False), nn.BatchNorm2d(width // 2)
        self.conv3, self.bn3 = nn.Conv2d(width // 2, width, 3, padding=1, bias=False), nn.BatchNorm2d(width)
        self.avgpool, self.relu = nn.AvgPool2d(2), nn.ReLU()
        cin = width
        for l, n in enumerate(blocks):
            planes = width << l
            layer = [ClipBottleneck(cin if i == 0 else 4 * planes, planes, (2 if l > 0 else 1) if i == 0 else 1)
                     for i in range(n)]
            setattr(self, "layer%d" % (l + 1), nn.Sequential(*layer))
            cin = 4 * planes
        self.attnpool = ClipAttentionPool(grid, 32 * width, 32 * width // 64, out)

    def forward(self, x, pos_embedding=False):
        for conv, bn in ((self.conv1, self.bn1), (self.conv2, self.bn2), (self.conv3, self.bn3)):
            x = self.relu(bn(conv(x)))
        x = self.avgpool(x)
        x = self.layer4(self.layer3(self.layer2(self.layer1(x))))
        return self.attnpool(x, pos_embedding)


class QuickGelu(nn.Module):
    def forward(self, x):
        import torch
        return x * torch.sigmoid(1.702 * x)


class ClipTextBlock(nn.Module):
    """CLIP's ResidualAttentionBlock: x += attn(ln_1(x)) with the causal mask, x += mlp(ln_2(x))."""

    def __init__(self, width):
        super().__init__()
        from collections import OrderedDict
        self.attn, self.ln_1, self.ln_2 = nn.MultiheadAttention(width, width // 64), nn.LayerNorm(width), nn.LayerNorm(width)
        self.mlp = nn.Sequential(OrderedDict([("c_fc", nn.Linear(width, 4 * width)), ("gelu", QuickGelu()),
                                              ("c_proj", nn.Linear(4 * width, width))]))

    def forward(self, x):  # [L, N, D]
        import torch
        h = self.ln_1(x)
        mask = torch.full((x.shape[0], x.shape[0]), float("-inf"), dtype=x.dtype).triu(1)
        x = x + self.attn(h, h, h, need_weights=False, attn_mask=mask)[0]
        return x + self.mlp(self.ln_2(x))


class ClipModel(nn.Module):
    """OpenAI CLIP (model.py) with the ResNet image tower, under its state-dict names (RN50.pt):
    visual.*, transformer.resblocks.*, token_embedding, positional_embedding, ln_final,
    text_projection, logit_scale."""

    def __init__(self, width, blocks, embed, text_width, text_layers, vocab, length=77):
        super().__init__()
        import math
        import torch
        self.visual = ClipResnet(width, blocks, embed)
        self.transformer = nn.Module()
        self.transformer.resblocks = nn.Sequential(*[ClipTextBlock(text_width) for _ in range(text_layers)])
        self.token_embedding = nn.Embedding(vocab, text_width)
        self.positional_embedding = nn.Parameter(torch.randn(length, text_width) * 0.01)
        self.ln_final = nn.LayerNorm(text_width)
        self.text_projection = nn.Parameter(torch.randn(text_width, embed) * text_width ** -0.5)
        self.logit_scale = nn.Parameter(torch.tensor(math.log(100.0)))

    def forward(self, image):
        """The image tower only: what torch.jit.trace records (with every parameter) for an archive
        laid out as OpenAI's RN50.pt."""
        return self.visual(image)

    def prompt_features(self, tokens, ctx):
        """pyiqa's PromptLearner.forward: the token embeddings with positions 1..16 replaced by the
        learned context, its halves around the first 3 class tokens; the text transformer; the
        end-of-text row (the largest token id) times text_projection."""
        import torch
        emb, n = self.token_embedding(tokens), ctx.shape[1]
        x = torch.cat([emb[:, :1], ctx[:, :n // 2], emb[:, 1 + n:4 + n], ctx[:, n // 2:], emb[:, 4 + n:]], dim=1)
        x = self.transformer.resblocks((x + self.positional_embedding).permute(1, 0, 2)).permute(1, 0, 2)
        x = self.ln_final(x)
        return x[torch.arange(x.shape[0]), tokens.argmax(dim=-1)] @ self.text_projection

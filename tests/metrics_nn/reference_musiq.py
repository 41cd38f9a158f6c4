"""MUSIQ written from the paper (Ke et al., ICCV 2021) and pyiqa's definitions (archs/musiq_arch.py,
data/multiscale_trans_util.py; METRICS.md 3), with pyiqa's module names so its state dict is the
checkpoint layout: the reference of torch_reference_musiq.py. Unlike the native code it keeps
pyiqa's padded tokens and their attention mask."""
import math

import torch
import torch.nn as nn
import torch.nn.functional as F


def same_pad(x, k, stride):
    """TF 'SAME' zero padding for a k x k window with `stride`: the total split floor before, ceil after."""
    h, w = x.shape[-2:]
    ph = max((math.ceil(h / stride) - 1) * stride + k - h, 0)
    pw = max((math.ceil(w / stride) - 1) * stride + k - w, 0)
    return F.pad(x, (pw // 2, pw - pw // 2, ph // 2, ph - ph // 2))


class StdConv(nn.Conv2d):
    """Weight-standardised convolution (Qiao et al.): (w - mean) / (unbiased std + 1e-5) per output channel."""

    def forward(self, x):
        w = self.weight
        w = (w - w.mean((1, 2, 3), keepdim=True)) / (w.std((1, 2, 3), keepdim=True) + 1e-5)
        return F.conv2d(same_pad(x, self.kernel_size[0], self.stride[0]), w, None, self.stride)


class Bottleneck(nn.Module):
    def __init__(self, cin, cout):
        super().__init__()
        self.conv1, self.gn1 = StdConv(cin, cin, 1, bias=False), nn.GroupNorm(32, cin, eps=1e-4)
        self.conv2, self.gn2 = StdConv(cin, cin, 3, bias=False), nn.GroupNorm(32, cin, eps=1e-4)
        self.conv3, self.gn3 = StdConv(cin, cout, 1, bias=False), nn.GroupNorm(32, cout, eps=1e-4)
        self.conv_proj, self.gn_proj = StdConv(cin, cout, 1, bias=False), nn.GroupNorm(32, cout, eps=1e-4)

    def forward(self, x):
        y = F.relu(self.gn1(self.conv1(x)))
        y = F.relu(self.gn2(self.conv2(y)))
        return F.relu(self.gn3(self.conv3(y)) + self.gn_proj(self.conv_proj(x)))


class Attention(nn.Module):
    def __init__(self, d, heads):
        super().__init__()
        self.heads = heads
        self.query, self.key, self.value, self.out = (nn.Linear(d, d) for _ in range(4))

    def forward(self, x, mask):
        b, n, d = x.shape
        split = lambda t: t.view(b, n, self.heads, d // self.heads).transpose(1, 2)
        q, k, v = split(self.query(x)), split(self.key(x)), split(self.value(x))
        scores = q @ k.transpose(-1, -2) / math.sqrt(d // self.heads)
        pair = mask.view(b, 1, n, 1) * mask.view(b, 1, 1, n)
        scores = scores.masked_fill(pair == 0, -1e3)
        return self.out((scores.softmax(-1) @ v).transpose(1, 2).reshape(b, n, d))


class Mlp(nn.Module):
    def __init__(self, d, m):
        super().__init__()
        self.fc1, self.fc2 = nn.Linear(d, m), nn.Linear(m, d)

    def forward(self, x):
        return self.fc2(F.gelu(self.fc1(x)))


class Block(nn.Module):
    def __init__(self, d, m, heads):
        super().__init__()
        self.norm1, self.norm2 = nn.LayerNorm(d, eps=1e-6), nn.LayerNorm(d, eps=1e-6)
        self.attention, self.mlp = Attention(d, heads), Mlp(d, m)

    def forward(self, x, mask):
        x = x + self.attention(self.norm1(x), mask)
        return x + self.mlp(self.norm2(x))


class PositionEmbs(nn.Module):
    def __init__(self, grid, d):
        super().__init__()
        self.position_emb = nn.Parameter(torch.zeros(1, grid * grid, d))


class ScaleEmbs(nn.Module):
    def __init__(self, scales, d):
        super().__init__()
        self.scale_emb = nn.Parameter(torch.zeros(scales, d))


class Encoder(nn.Module):
    def __init__(self, d, m, heads, layers, scales, grid):
        super().__init__()
        self.posembed_input, self.scaleembed_input = PositionEmbs(grid, d), ScaleEmbs(scales, d)
        self.cls = nn.Parameter(torch.zeros(1, 1, d))
        self.encoder_norm = nn.LayerNorm(d, eps=1e-6)
        self.transformer = nn.ModuleDict({"encoderblock_%d" % i: Block(d, m, heads) for i in range(layers)})

    def forward(self, x, position, scale, mask):
        x = x + self.posembed_input.position_emb[0][position] + self.scaleembed_input.scale_emb[scale]
        x = torch.cat([self.cls.expand(x.shape[0], 1, -1), x], dim=1)
        mask = torch.cat([torch.ones_like(mask[:, :1]), mask], dim=1)
        for block in self.transformer.values():
            x = block(x, mask)
        return self.encoder_norm(x)


class Musiq(nn.Module):
    """MUSIQ with one output (KonIQ, PaQ-2-PiQ): patches [b, n, 3 * 32 * 32] -> the score [b]."""

    def __init__(self, width=384, mlp=1152, heads=6, layers=14, scales=3, grid=10):
        super().__init__()
        self.conv_root = StdConv(3, 64, 7, 2, bias=False)
        self.gn_root = nn.GroupNorm(32, 64, eps=1e-6)
        self.block1 = Bottleneck(64, 256)
        self.embedding = nn.Linear(8 * 8 * 256, width)
        self.transformer_encoder = Encoder(width, mlp, heads, layers, scales, grid)
        self.head = nn.Linear(width, 1)

    def forward(self, patches, position, scale, mask):
        b, n, _ = patches.shape
        x = self.gn_root(self.conv_root(patches.reshape(b * n, 3, 32, 32)))
        x = F.max_pool2d(same_pad(F.relu(x), 3, 2), 3, 2)
        x = self.block1(x).permute(0, 2, 3, 1).reshape(b, n, -1)  # (row, column, channel), as TF
        x = self.transformer_encoder(self.embedding(x), position, scale, mask)
        return self.head(x[:, 0]).flatten()


def hashed_positions(grid, count_h, count_w):
    """Row-major grid positions: nearest rows / columns of the grid x grid table (F.interpolate nearest)."""
    table = torch.arange(grid, dtype=torch.float32).view(1, 1, grid)
    rows = F.interpolate(table, size=count_h, mode="nearest").flatten().long()
    cols = F.interpolate(table, size=count_w, mode="nearest").flatten().long()
    return (rows.view(-1, 1) * grid + cols.view(1, -1)).flatten()


def scale_patches(image, grid, scale, max_len, antialias=False):
    """One scale's patches [n, 3072], positions, scales and mask, padded to max_len (>= 0) with zeros."""
    h, w = image.shape[-2:]
    ch, cw = math.ceil(h / 32), math.ceil(w / 32)
    patches = F.unfold(same_pad(image, 32, 32), 32, stride=32)[0].t()
    position = hashed_positions(grid, ch, cw)
    scales, mask = torch.full_like(position, scale), torch.ones_like(position)
    if max_len >= 0:
        pad = max_len - patches.shape[0]
        patches = torch.cat([patches, patches.new_zeros(pad, patches.shape[1])])
        position, scales, mask = (torch.cat([t, t.new_zeros(pad)]) for t in (position, scales, mask))
    return patches, position, scales, mask


def multiscale_input(x, grid=10, longer=(224, 384), antialias=False, full=True):
    """pyiqa's eval preprocessing of x [1, 3, H, W] in [0, 1]: 2x - 1, the bicubic scales (padded to
    ceil(L / 32)^2 tokens), then the image itself; batched as [1, n, ...]."""
    x = (x - 0.5) * 2
    h, w = x.shape[-2:]
    parts = []
    for s, side in enumerate(sorted(longer)):
        ratio = side / max(h, w)
        resized = F.interpolate(x, size=(round(h * ratio), round(w * ratio)), mode="bicubic", align_corners=False,
                                antialias=antialias)
        parts.append(scale_patches(resized, grid, s, math.ceil(side / 32) ** 2))
    if full:
        parts.append(scale_patches(x, grid, len(longer), -1))
    return [torch.cat(p).unsqueeze(0) for p in zip(*parts)]

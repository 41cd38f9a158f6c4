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

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

"""Networks both PyTorch tests build (torch_reference.py, test_convert_weights.py), written from
their authors' definitions."""
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

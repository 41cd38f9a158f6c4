"""A torch.hub repository for the bridge's dino_score test (S4D_DINO_REPO): dino_vitb16 returns a
model whose "CLS feature" of an image batch [N, 3, H, W] is its per-channel mean, so the test can
recompute VBench's subject consistency from the frames' pixels. Needs torch."""
import torch

dependencies = ["torch"]


class ChannelMeans(torch.nn.Module):
    def forward(self, x):
        if x.dim() != 4 or x.shape[1] != 3 or min(x.shape[2:]) != 224:
            raise ValueError("fake dino: expected [N, 3, H, W] with a shorter side of 224, got %s" % list(x.shape))
        return x.mean(dim=(2, 3))


def dino_vitb16(**kwargs):
    return ChannelMeans()

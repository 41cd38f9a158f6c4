"""The published checkpoints tools/convert_weights.py reads, with what is known of their sha256.

torchvision's and OpenAI CLIP's downloaders verify a file against the hash in its address: torch.hub
checks that the sha256 starts with the hex digits after the last '-' of the file name (vgg16-397923af.pth),
CLIP's loader the full sha256 in the address's folder. A file under such a name whose digest differs
is not the published file (damaged or replaced), and the converter refuses it. pyiqa's release names
follow the same pattern, but pyiqa downloads without checking (download_url_to_file(hash_prefix=None)),
so there a difference is only reported. Files published without any hash are not listed.
"""

# file name -> (expected sha256 or its leading hex digits, publisher, verified by the publisher's downloader)
PUBLISHED = {
    "vgg16-397923af.pth": ("397923af", "torchvision", True),
    "vgg19-dcbb9e9d.pth": ("dcbb9e9d", "torchvision", True),
    "alexnet-owt-7be5be79.pth": ("7be5be79", "torchvision", True),
    "RN50.pt": ("afeb0e10f9e5a86da6080e35cf09123aca3b358a0c3e3b6c78a7b63bc04b6762", "OpenAI CLIP", True),
    "LPIPS_v0.1_vgg-a78928a0.pth": ("a78928a0", "pyiqa", False),
    "LPIPS_v0.1_alex-df73285e.pth": ("df73285e", "pyiqa", False),
    "DISTS_weights-f5e65c96.pth": ("f5e65c96", "pyiqa", False),
    "CKDN_model_best-38b27dc6.pth": ("38b27dc6", "pyiqa", False),
    "CLIP-IQA+_learned_prompts-603f3273.pth": ("603f3273", "pyiqa", False),
    "musiq_koniq_ckpt-e95806b9.pth": ("e95806b9", "pyiqa", False),
    "musiq_paq2piq_ckpt-364c0c84.pth": ("364c0c84", "pyiqa", False),
}


class HashMismatch(Exception):
    pass


def check(name, digest):
    """None when `name` is not a listed file or `digest` matches; a note for an unverified publisher's
    mismatch; raises HashMismatch for a verified one's."""
    if name not in PUBLISHED:
        return None
    expected, publisher, verified = PUBLISHED[name]
    if digest.startswith(expected):
        return None
    what = "%s: sha256 %s, but %s's published %s has %s%s" % (
        name, digest, publisher, name, expected, "" if len(expected) == 64 else "...")
    if verified:
        raise HashMismatch(what + " (its downloader checks this): a damaged or different file")
    return what + " (by its name; %s does not check it when downloading)" % publisher

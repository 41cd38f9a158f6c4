"""A fake pyiqa for the bridge tests (put tests/bench/fake_pyiqa on PYTHONPATH): plain python3, no torch.

It holds the bridge to pyiqa's documented interface and raises where real pyiqa would misbehave or
where the call would be a silent mistake:
  create_metric(metric_name, as_loss=False, device=None): a known name (AssertionError otherwise, as
    pyiqa), as_loss False (a loss keeps gradients and reduces the batch), device None, "cpu", "cuda"
    or "cuda:N", no other options;
  metric(target, ref=None, **kwargs): target and ref image file paths of 8-bit RGB(A) PNGs (pyiqa
    reads them as [0, 1] RGB); ref required by the full-reference metrics (dists, ckdn) and refused
    by the others (pyiqa would ignore it); dists's two images of one size; only qalign takes task_,
    "quality" or "aesthetic";
  .lower_better, .score_range, .metric_mode as pyiqa's DEFAULT_CONFIGS declare them.
Scores are computed from the pixels so a test can recompute them: clipiqa+ the mean value, musiq
100 x the red mean, musiq-paq2piq 100 x the green mean, qalign 1 + 4 x the blue mean, dists the mean
|target - ref|, ckdn 0.5 + (mean(target) - mean(ref)) / 2. The result has .item(), as pyiqa's tensor.
S4D_FAKE_PYIQA (comma-separated) injects failures: "absent" (importing fails, as without torch),
"no_weights=NAME" (create_metric fails, as a failed download), "unreadable=TEXT" (a call on a path
containing TEXT fails), "out_of_range=NAME" (NAME scores 10 over its range), "flip=NAME" (NAME's
lower_better is inverted).
"""
import os
import re
import struct
import zlib

_MODES = [m for m in os.environ.get("S4D_FAKE_PYIQA", "").split(",") if m]
if "absent" in _MODES:
    raise ImportError("No module named 'torch' (fake pyiqa, S4D_FAKE_PYIQA=absent)")

__version__ = "0.0-fake"

# name -> (metric_mode, lower_better, score_range), as pyiqa's default_model_configs.py.
_CONFIGS = {"clipiqa+": ("NR", False, "0, 1"), "musiq": ("NR", False, "~0, ~100"), "qalign": ("NR", False, "1, 5"),
            "musiq-paq2piq": ("NR", False, "~0, ~100"), "dists": ("FR", True, "0, 1"), "ckdn": ("FR", False, "0, 1")}


def _mode(key, name):
    return any(m == "%s=%s" % (key, name) for m in _MODES)


def _read_png(path):
    """[(r, g, b), ...] in [0, 1] and the size of an 8-bit RGB or RGBA PNG (zlib + the five row filters)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise OSError("fake pyiqa: %s is not a PNG" % path)
    pos, idat, w, h, ctype = 8, b"", 0, 0, 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            if depth != 8 or ctype not in (2, 6):
                raise OSError("fake pyiqa: %s is not 8-bit RGB(A)" % path)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    bpp = 3 if ctype == 2 else 4
    raw, stride, pixels, prev = zlib.decompress(idat), w * bpp, [], bytearray(w * bpp)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], (prev[i - bpp] if i >= bpp else 0)
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        pixels += [(line[x * bpp] / 255.0, line[x * bpp + 1] / 255.0, line[x * bpp + 2] / 255.0) for x in range(w)]
        prev = line
    return pixels, (h, w)


def _image(name, what, value):
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError("fake pyiqa %s: %s must be an image file path (pyiqa also takes N,3,H,W tensors in [0, 1]; "
                        "the bridge passes paths), got %s" %
                        (name, what, type(value).__name__))
    if any(m.startswith("unreadable=") and m[len("unreadable="):] in str(value) for m in _MODES):
        raise OSError("fake pyiqa %s: cannot read %s" % (name, value))
    return _read_png(value)


def _mean(pixels, channel=None):
    if channel is None:
        return sum(sum(p) for p in pixels) / (3 * len(pixels))
    return sum(p[channel] for p in pixels) / len(pixels)


class _Score:
    """What pyiqa returns for one image: a tensor of shape (1, 1); .item() is its value."""

    def __init__(self, value):
        self._value = value
        self.shape = (1, 1)

    def item(self):
        return self._value


class InferenceModel:
    def __init__(self, name):
        self.metric_name = name
        self.metric_mode, lower_better, self.score_range = _CONFIGS[name]
        self.lower_better = lower_better != _mode("flip", name)

    def __call__(self, target, ref=None, **kwargs):
        name = self.metric_name
        if name == "qalign":
            if set(kwargs) != {"task_"} or kwargs["task_"] not in ("quality", "aesthetic"):
                raise TypeError("fake pyiqa qalign: takes task_='quality' or 'aesthetic', got %r" % kwargs)
        elif kwargs:
            raise TypeError("fake pyiqa %s: unexpected keyword arguments %s" % (name, sorted(kwargs)))
        if self.metric_mode == "FR" and ref is None:
            raise AssertionError("Please specify reference image for Full Reference metric")
        if self.metric_mode == "NR" and ref is not None:
            raise TypeError("fake pyiqa %s: a no-reference metric got ref=%r (pyiqa would ignore it)" % (name, ref))
        x, size = _image(name, "target", target)
        if ref is not None:
            y, ref_size = _image(name, "ref", ref)
        if name == "dists":
            if ref_size != size:
                raise ValueError("fake pyiqa dists: target %s and ref %s differ in size" % (size, ref_size))
            value = sum(abs(a - b) for p, q in zip(x, y) for a, b in zip(p, q)) / (3 * len(x))
        elif name == "ckdn":
            value = 0.5 + (_mean(x) - _mean(y)) / 2
        else:
            value = {"clipiqa+": lambda: _mean(x), "musiq": lambda: 100 * _mean(x, 0),
                     "musiq-paq2piq": lambda: 100 * _mean(x, 1), "qalign": lambda: 1 + 4 * _mean(x, 2)}[name]()
        return _Score(value + (10.0 if _mode("out_of_range", name) else 0.0))


def create_metric(metric_name, as_loss=False, device=None, **kwargs):
    assert metric_name in _CONFIGS, f"Metric {metric_name} not implemented yet."
    if as_loss is not False:
        raise ValueError("fake pyiqa: as_loss=%r builds a loss (gradients, batch reduction), not a scorer" % (as_loss,))
    if device is not None and not (isinstance(device, str) and re.fullmatch(r"cpu|cuda(:\d+)?", device)):
        raise TypeError("fake pyiqa: device must be None, 'cpu', 'cuda' or 'cuda:N', got %r" % (device,))
    if kwargs:
        raise TypeError("fake pyiqa: create_metric got unexpected options %s" % sorted(kwargs))
    if _mode("no_weights", metric_name):
        raise RuntimeError("cannot download the weights of %s (fake pyiqa, S4D_FAKE_PYIQA)" % metric_name)
    return InferenceModel(metric_name)

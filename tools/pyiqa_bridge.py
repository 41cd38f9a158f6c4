#!/usr/bin/env python3
"""Style4D-Bench's pyiqa bridge (protocol s4d-pyiqa-bridge/1, docs/bench.md "The pyiqa bridge protocol").

Run by `style4d bench --python PY` as `PY pyiqa_bridge.py REQUEST.json`. Reads the request (metric
keys and PNG frame files per sequence), computes each metric through pyiqa's documented interface,
and writes the response JSON to the request's "output": per sequence and key, one value per frame
(clipiqa_plus, musiq, qalign, musiq_paq2piq, ckdn) or per consecutive pair (dists, dino_score).
pyiqa: metric = pyiqa.create_metric(name, device=..., as_loss=False); metric(target) for a no-reference
metric, metric(target, ref) for a full-reference one, target and ref image file paths (pyiqa reads
them as RGB in [0, 1]); metric.lower_better and metric.score_range describe the score. DINO (VBench's
subject consistency) comes through torch.hub. Each metric fails on its own: one that cannot be
created, whose direction is not Style4D-Bench's, or whose score leaves pyiqa's declared range is
reported under "errors"; a failure on one sequence as {"error": ...} in place of that sequence's list.
Needs: pip install pyiqa (PolyForm Noncommercial licence) torch torchvision.
S4D_BRIDGE_DEVICE (e.g. cpu, cuda:1) picks the device; unset, pyiqa picks (CUDA when available).
"""
import json
import os
import sys
import traceback

PROTOCOL = "s4d-pyiqa-bridge/1"
# Style4D-Bench key -> (pyiqa metric name, lower is better).
PYIQA = {"clipiqa_plus": ("clipiqa+", False), "musiq": ("musiq", False), "qalign": ("qalign", False),
         "musiq_paq2piq": ("musiq-paq2piq", False), "dists": ("dists", True), "ckdn": ("ckdn", False)}


class MetricError(Exception):
    pass


def hard_bounds(score_range):
    """pyiqa's score_range text ("0, 1", "~0, ~100"): the bounds not marked approximate ("~")."""
    if not isinstance(score_range, str) or "," not in score_range:
        return None, None
    bounds = []
    for part in score_range.split(",")[:2]:
        part = part.strip()
        bounds.append(None if not part or part.startswith("~") else float(part))
    return bounds[0], bounds[1]


def scorer(metric, name):
    """metric(...) -> a float, checked against the range pyiqa declares for it."""
    low, high = hard_bounds(getattr(metric, "score_range", None))

    def score(*args, **kwargs):
        value = float(metric(*args, **kwargs).item())
        if value != value or (low is not None and value < low - 1e-6) or (high is not None and value > high + 1e-6):
            raise MetricError("pyiqa %s gave %r, outside its declared range %s" % (name, value, metric.score_range))
        return value
    return score


def create(pyiqa, key, device):
    name, lower_better = PYIQA[key]
    metric = pyiqa.create_metric(name, device=device, as_loss=False)
    if bool(metric.lower_better) != lower_better:
        raise MetricError("pyiqa %s has lower_better=%s; Style4D-Bench's %s is %s-is-better" %
                          (name, metric.lower_better, key, "lower" if lower_better else "higher"))
    return metric


def values_for(key, score, seq):
    frames = seq["frames"]
    if key == "dists":  # DISTS(f_i+1, f_i): target the later frame, reference the earlier
        return [score(frames[i + 1], frames[i]) for i in range(len(frames) - 1)]
    if key == "ckdn":  # degraded-reference: the frame against the style image
        if not seq["style_image"]:
            raise ValueError("ckdn needs the style image")
        return [score(f, seq["style_image"]) for f in frames]
    if key == "qalign":  # Style4D-Bench's aesthetic dimension
        return [score(f, task_="aesthetic") for f in frames]
    return [score(f) for f in frames]


def dino_scores(frames, device):
    # VBench subject consistency: DINO ViT-B/16 CLS features of each frame (shorter side 224,
    # bilinear without antialias, ImageNet mean/std), s_i = (max(0, cos(f_i-1, f_i)) +
    # max(0, cos(f_0, f_i))) / 2 for i >= 1.
    import torch
    import torch.nn.functional as F
    import torchvision.transforms as T
    from torchvision.io import ImageReadMode, read_image
    device = device or ("cuda" if torch.cuda.is_available() else "cpu")
    repo = os.environ.get("S4D_DINO_REPO")
    model = (torch.hub.load(repo, "dino_vitb16", source="local") if repo
             else torch.hub.load("facebookresearch/dino:main", "dino_vitb16")).to(device).eval()
    resize = T.Resize(224, antialias=False)
    norm = T.Normalize((0.485, 0.456, 0.406), (0.229, 0.224, 0.225))
    feats = []
    with torch.no_grad():
        for f in frames:
            img = resize(read_image(f, mode=ImageReadMode.RGB))  # uint8, as VBench resizes before scaling
            x = norm(img.float() / 255.0).unsqueeze(0).to(device)
            feats.append(F.normalize(model(x), dim=-1))
    out = []
    for i in range(1, len(feats)):
        prev = max(0.0, F.cosine_similarity(feats[i - 1], feats[i]).item())
        first = max(0.0, F.cosine_similarity(feats[0], feats[i]).item())
        out.append((prev + first) / 2)
    return out


def why(e):
    return "%s: %s" % (type(e).__name__, e)


def main():
    with open(sys.argv[1]) as f:
        request = json.load(f)
    response = {"protocol": PROTOCOL, "results": {}, "errors": {}, "versions": {"python": sys.version.split()[0]}}
    device = os.environ.get("S4D_BRIDGE_DEVICE") or None
    pyiqa, no_pyiqa = None, None
    if any(k in PYIQA for k in request["metrics"]):
        try:
            import pyiqa
            response["versions"]["pyiqa"] = getattr(pyiqa, "__version__", "?")
        except Exception as e:  # each pyiqa metric says so; dino_score does not need pyiqa
            no_pyiqa = "cannot import pyiqa in %s (pip install pyiqa): %s" % (sys.executable, why(e))
    for key in request["metrics"]:
        if key == "dino_score":
            compute = lambda seq: dino_scores(seq["frames"], device)
        elif no_pyiqa:
            response["errors"][key] = no_pyiqa
            continue
        else:
            try:  # a metric that cannot be built fails for every sequence
                metric = create(pyiqa, key, device)
                response["versions"][key] = "pyiqa %s (lower_better %s, score range %s)" % (
                    PYIQA[key][0], metric.lower_better, getattr(metric, "score_range", "?"))
            except Exception as e:
                traceback.print_exc()
                response["errors"][key] = why(e)
                continue
            compute = lambda seq, score=scorer(metric, PYIQA[key][0]), key=key: values_for(key, score, seq)
        for seq in request["sequences"]:
            if key not in seq["metrics"]:
                continue
            try:  # a failure on one sequence is reported for that sequence only
                values = compute(seq)
            except MetricError as e:  # the metric itself is off, not this sequence
                response["errors"][key] = str(e)
                for done in response["results"].values():
                    done.pop(key, None)
                break
            except Exception as e:
                traceback.print_exc()
                values = {"error": why(e)}
            response["results"].setdefault(seq["id"], {})[key] = values
    with open(request["output"], "w") as out:
        json.dump(response, out)


if __name__ == "__main__":
    main()

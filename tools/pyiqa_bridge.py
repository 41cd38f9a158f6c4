#!/usr/bin/env python3
"""Style4D-Bench's pyiqa bridge (protocol s4d-pyiqa-bridge/1, docs/bench.md "The pyiqa bridge protocol").

Run by `style4d bench --python PY` as `PY pyiqa_bridge.py REQUEST.json`. Reads the request (metric
keys and PNG frame files per sequence), computes each metric with pyiqa (DINO through torch.hub),
and writes the response JSON to the request's "output": per sequence and key, one value per frame
(clipiqa_plus, musiq, qalign, musiq_paq2piq, ckdn) or per consecutive pair (dists, dino_score).
A metric that cannot be created is reported under "errors", a failure on one sequence as
{"error": ...} in place of that sequence's list; the others still run.
Needs: pip install pyiqa (PolyForm Noncommercial licence) torch torchvision.
"""
import json
import sys
import traceback

PROTOCOL = "s4d-pyiqa-bridge/1"
PYIQA_NAMES = {"clipiqa_plus": "clipiqa+", "musiq": "musiq", "qalign": "qalign",
               "musiq_paq2piq": "musiq-paq2piq", "dists": "dists", "ckdn": "ckdn"}


def as_floats(values):
    return [float(v) for v in values]


def per_frame(metric, frames, **kwargs):
    return as_floats(metric(f, **kwargs).item() for f in frames)


def dino_scores(frames, device):
    # VBench subject consistency: DINO ViT-B/16 CLS features of each frame (shorter side 224,
    # bilinear without antialias, ImageNet mean/std), s_i = (max(0, cos(f_i-1, f_i)) +
    # max(0, cos(f_0, f_i))) / 2 for i >= 1.
    import os
    import torch
    import torch.nn.functional as F
    import torchvision.transforms as T
    from torchvision.io import ImageReadMode, read_image
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


def main():
    request = json.load(open(sys.argv[1]))
    response = {"protocol": PROTOCOL, "results": {}, "errors": {}, "versions": {}}
    keys = request["metrics"]
    try:
        import pyiqa
        import torch
        response["versions"] = {"pyiqa": getattr(pyiqa, "__version__", "?"), "torch": torch.__version__}
        device = torch.device("cuda" if torch.cuda.is_available() else "cpu")
    except Exception as e:  # no pyiqa: every metric says so
        for k in keys:
            response["errors"][k] = "cannot import pyiqa/torch in %s: %s" % (sys.executable, e)
        keys = []
    for key in keys:
        try:  # a metric that cannot be built fails for every sequence
            metric = None if key == "dino_score" else pyiqa.create_metric(PYIQA_NAMES[key], device=device)
        except Exception as e:
            traceback.print_exc()
            response["errors"][key] = "%s: %s" % (type(e).__name__, e)
            continue
        for seq in request["sequences"]:
            if key not in seq["metrics"]:
                continue
            frames = seq["frames"]
            try:  # a failure on one sequence is reported for that sequence only
                if key == "dino_score":
                    values = dino_scores(frames, device)
                elif key == "dists":
                    values = as_floats(metric(frames[i + 1], frames[i]).item() for i in range(len(frames) - 1))
                elif key == "ckdn":
                    if not seq["style_image"]:
                        raise ValueError("ckdn needs the style image")
                    values = as_floats(metric(f, seq["style_image"]).item() for f in frames)
                elif key == "qalign":
                    values = per_frame(metric, frames, task_="aesthetic")
                else:
                    values = per_frame(metric, frames)
            except Exception as e:
                traceback.print_exc()
                values = {"error": "%s: %s" % (type(e).__name__, e)}
            response["results"].setdefault(seq["id"], {})[key] = values
    with open(request["output"], "w") as out:
        json.dump(response, out)


if __name__ == "__main__":
    main()

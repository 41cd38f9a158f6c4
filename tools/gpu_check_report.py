#!/usr/bin/env python3
"""Writes OUT/gpu-check.json and OUT/gpu-check.md from what tools/gpu-check.sh left in OUT: the step
table (steps.tsv) and the programs' own outputs. A figure whose step did not finish is null, and the
Markdown says which step it waits for; nothing here is measured or assumed by this script.
Usage: gpu_check_report.py OUT small|full BUDGET_S"""
import csv
import json
import os
import sys


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def json_lines(path):
    """The JSON objects a bench printed one a line on stdout (its log also holds stderr's table)."""
    lines = []
    try:
        with open(path) as f:
            for line in f:
                if line.startswith("{"):
                    try:
                        lines.append(json.loads(line))
                    except ValueError:
                        pass
    except OSError:
        pass
    return lines


def get(obj, *keys):
    for k in keys:
        if not isinstance(obj, dict) or k not in obj:
            return None
        obj = obj[k]
    return obj


def main():
    out, mode, budget = sys.argv[1], sys.argv[2], float(sys.argv[3])
    with open(os.path.join(out, "steps.tsv")) as f:
        steps = [dict(r) for r in csv.DictReader(f, delimiter="\t")]
    for s in steps:
        s["seconds"] = float(s["seconds"])
        s["cap_s"] = float(s["cap_s"]) if s["cap_s"] else 0.0
        s["log"] = f"logs/{s['step']}.log"
    status = {s["step"]: s["status"] for s in steps}
    devices = read_json(os.path.join(out, "devices.json")) or []
    device = next((d for d in devices if d.get("chosen")), {})
    demo = read_json(os.path.join(out, "demo", "demo.json"))
    train = read_json(os.path.join(out, "object_run", "train.json"))
    stylize = read_json(os.path.join(out, "object_run", "style", "builtin", "stylize.json"))
    bench = read_json(os.path.join(out, "object_bench", "report.json"))
    viewer = json_lines(os.path.join(out, "logs", "viewer.log"))
    orbit = json_lines(os.path.join(out, "logs", "viewer_orbit.log"))
    splat = json_lines(os.path.join(out, "logs", "bench_splat.log"))
    deform = json_lines(os.path.join(out, "logs", "bench_deform.log"))

    step_ms = get(train, "stage_ms", "step_ms")
    iterations = get(train, "stage_ms", "iterations")
    gaussians = get(train, "num_gaussians")
    frame = next((l for l in viewer if l.get("bench") == "viewer_frame"), {})
    orbit_full = next((l for l in orbit if l.get("bench") == "viewer_orbit_ratio"), {})
    figures = {
        "demo_seconds": get(demo, "seconds") if status.get("demo") == "ok" else None,
        "train_default_seconds": get(train, "seconds") if status.get("train") == "ok" else None,
        "train_default_test_psnr": get(train, "test_psnr") if status.get("train") == "ok" else None,
        "train_num_gaussians": gaussians,
        "train_step_ms": step_ms / iterations if step_ms and iterations else None,
        # Per Gaussian of the final cloud: densification grows it over the run, so this is a lower bound.
        "train_step_ns_per_gaussian": 1e6 * step_ms / iterations / gaussians if step_ms and iterations and gaussians else None,
        "stage4_seconds": get(stylize, "stage4", "seconds"),
        "bench_seconds": next((s["seconds"] for s in steps if s["step"] == "bench" and s["status"] == "ok"), None),
        "viewer_fps": frame.get("fps_p50"),
        "viewer_size": f"{frame['width']}x{frame['height']}" if frame else None,
        "viewer_gaussians": frame.get("n_gaussians"),
        "viewer_orbit_fps_full": orbit_full.get("fps_full"),
        "viewer_orbit_fps_adaptive": orbit_full.get("fps_adaptive"),
    }
    report = {
        "mode": mode,
        "budget_s": budget,
        "seconds": sum(s["seconds"] for s in steps),
        "device": {k: device.get(k) for k in ("name", "type", "driver", "driver_info", "api_version")},
        "steps": steps,
        "figures": figures,
        "demo_stages": get(demo, "stages"),
        "train_stage_ms": get(train, "stage_ms"),
        "bench_report": bench,
        "bench_splat": splat,
        "bench_deform": deform,
        "viewer": viewer + orbit,
    }
    with open(os.path.join(out, "gpu-check.json"), "w") as f:
        json.dump(report, f, indent=2)
        f.write("\n")

    def fmt(v, digits=2):
        return "not measured" if v is None else (f"{v:.{digits}f}" if isinstance(v, float) else str(v))

    md = [f"# GPU check ({mode})", "",
          f"Device: **{device.get('name')}** ({device.get('type')}), driver {device.get('driver')} {device.get('driver_info')}, "
          f"Vulkan {device.get('api_version')}. Budget {budget:.0f} s, steps took {report['seconds']:.0f} s.", "",
          "| step | status | seconds | cap (s) |", "|---|---|---:|---:|"]
    md += [f"| {s['step']} | {s['status']} | {s['seconds']:.1f} | {s['cap_s']:.0f} |" for s in steps]
    md += ["", "| figure | value |", "|---|---:|"]
    md += [f"| {k} | {fmt(v)} |" for k, v in figures.items()]
    md += ["", "Kernel benches (bench_splat, bench_deform) and every stage time are in gpu-check.json.", ""]
    with open(os.path.join(out, "gpu-check.md"), "w") as f:
        f.write("\n".join(md))
    failed = [s["step"] for s in steps if s["status"] == "failed"]
    print(f"gpu-check: {os.path.join(out, 'gpu-check.md')}; failed steps: {', '.join(failed) or 'none'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

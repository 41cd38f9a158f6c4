#!/usr/bin/env python3
"""Plots bench/soak.sh's samples (resident and device memory against the iteration, one panel per
stage) as an SVG, and writes as JSON each stage's growth once its Gaussian count last changed
(densification over): MiB per 1000 iterations by a least-squares line, and the range there.

    soak_plot.py soak.csv soak.svg soak.json
"""
import csv
import json
import sys


def slope(xs, ys):
    n = len(xs)
    if n < 2:
        return 0.0
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else 0.0


def main():
    csv_path, svg_path, json_path = sys.argv[1:4]
    rows = list(csv.DictReader(open(csv_path)))
    stages = [s for s in ("static", "fine") if any(r["stage"] == s for r in rows)]
    report, panels = {}, []
    for s in stages:
        stage_rows = [r for r in rows if r["stage"] == s]
        pts = [(int(r["iteration"]), float(r["rss_mib"]), float(r["device_mib"])) for r in stage_rows]
        last = max(p[0] for p in pts)
        # The steady part: from the first sample with the stage's final Gaussian count on.
        final = stage_rows[-1]["gaussians"]
        first = max((k for k, r in enumerate(stage_rows) if r["gaussians"] != final), default=-1) + 1
        steady = pts[first:]
        report[s] = {
            "samples": len(pts),
            "iterations": last,
            "gaussians": int(final),
            "steady_from_iteration": steady[0][0],
            "rss_mib_per_1000_iterations_steady": 1000 * slope([p[0] for p in steady], [p[1] for p in steady]),
            "device_mib_per_1000_iterations_steady": 1000 * slope([p[0] for p in steady], [p[2] for p in steady]),
            "rss_mib_range_steady": [min(p[1] for p in steady), max(p[1] for p in steady)],
            "device_mib_range_steady": [min(p[2] for p in steady), max(p[2] for p in steady)],
        }
        panels.append((s, pts))
    json.dump(report, open(json_path, "w"), indent=2)
    w, h, pad = 520, 300, 50
    top = max(max(p[1] for p in pts) for _, pts in panels) * 1.1
    svg = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">'
           % (w * len(panels), h)]
    for k, (s, pts) in enumerate(panels):
        x0, last = k * w, max(p[0] for p in pts)
        sx = lambda i: x0 + pad + (w - 2 * pad) * i / max(last, 1)
        sy = lambda v: h - pad - (h - 2 * pad) * v / top
        svg.append('<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="#888"/>' % (x0 + pad, pad, w - 2 * pad, h - 2 * pad))
        svg.append('<text x="%d" y="%d">%s stage: memory (MiB) against the iteration</text>' % (x0 + pad, pad - 20, s))
        svg.append('<text x="%d" y="%d">0</text><text x="%d" y="%d">%d</text>' % (x0 + pad, h - pad + 15, x0 + w - pad - 30, h - pad + 15, last))
        svg.append('<text x="%d" y="%d">%.0f</text>' % (x0 + 5, pad + 5, top))
        for col, colour, name in ((1, "#c33", "resident"), (2, "#36c", "device buffers")):
            path = " ".join("%.1f,%.1f" % (sx(p[0]), sy(p[col])) for p in pts)
            svg.append('<polyline fill="none" stroke="%s" stroke-width="1.5" points="%s"/>' % (colour, path))
            svg.append('<text x="%d" y="%d" fill="%s">%s</text>' % (x0 + pad + 10, pad + 18 * col, colour, name))
    svg.append("</svg>")
    open(svg_path, "w").write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main()

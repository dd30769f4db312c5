#!/usr/bin/env python3
"""Draws the charts of `caustica bench accuracy` and `caustica bench convergence`.

From results.csv (bench accuracy), two panels: caustics, relative L1 error of the caustic map against
the photon reference over the GPU time of the caustic pass, log-log, one curve per method and scene,
points labelled by photon grid; refraction, the same for the refraction passes against the
ray-traced reference. From convergence.csv (bench convergence), one panel: the error of each
method's accumulated map over the wall time since it started accumulating, log-log. Given both, the
convergence panel stands beside the other two.
Usage: plot_accuracy.py CSV [CSV] OUT.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt

COLOURS = plt.get_cmap("tab20").colors
STYLES = [("o", "-"), ("s", "--"), ("D", ":"), ("^", "-.")]


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def log_axes(axes, title, xlabel):
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_title(title)
    axes.set_xlabel(xlabel)
    axes.set_ylabel("relative L1 error against the reference")
    axes.grid(True, which="both", alpha=0.3)
    if axes.lines:
        axes.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2)


def speed_accuracy(rows, caustics, refraction):
    # One colour per method (20 before one repeats), one marker and line style per scene.
    methods = sorted({r["method"] for r in rows})
    scenes = sorted({r["scene"] for r in rows})
    curves = {}
    for row in rows:
        curves.setdefault((row["kind"], row["scene"], row["method"]), []).append(row)
    for (kind, scene, method), points in sorted(curves.items()):
        axes = caustics if kind == "caustics" else refraction
        points.sort(key=lambda r: float(r["method_ms"]))
        x = [max(float(r["method_ms"]), 1e-3) for r in points]
        y = [max(float(r["relative_l1"]), 1e-4) for r in points]
        marker, line = STYLES[scenes.index(scene) % len(STYLES)]
        axes.plot(x, y, marker=marker, linestyle=line, color=COLOURS[methods.index(method) % len(COLOURS)],
                  label=f"{method} ({scene})")
        if kind == "caustics":
            for r, px, py in zip(points, x, y):
                axes.annotate(f"{r['grid']}²", (px, py), textcoords="offset points", xytext=(4, 3), fontsize=7)
    log_axes(caustics, "caustics", "caustic pass GPU time (ms)")
    log_axes(refraction, "refraction", "refraction passes GPU time (ms)")


def convergence(rows, axes):
    methods = list(dict.fromkeys(r["method"] for r in rows))
    scenes = sorted({r["scene"] for r in rows})
    for scene in scenes:
        for method in methods:
            points = [r for r in rows if r["scene"] == scene and r["method"] == method]
            if not points:
                continue
            marker, line = STYLES[scenes.index(scene) % len(STYLES)]
            axes.plot([max(float(r["seconds"]), 1e-3) for r in points], [max(float(r["relative_l1"]), 1e-4) for r in points],
                      marker=marker, markersize=3, linestyle=line, color=COLOURS[methods.index(method) % len(COLOURS)],
                      label=f"{method} ({scene})")
    for limit in (0.10, 0.05):
        axes.axhline(limit, color="grey", linewidth=0.8, linestyle=":")
    log_axes(axes, "convergence while still", "wall time accumulating (s)")


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit("usage: plot_accuracy.py CSV [CSV] OUT.png")
    accuracy, converging = None, None
    for path in sys.argv[1:-1]:
        rows = read(path)
        if rows and "kind" in rows[0]:
            accuracy = rows
        elif rows and "seconds" in rows[0]:
            converging = rows
        else:
            sys.exit(f"{path}: neither bench accuracy's results.csv nor bench convergence's convergence.csv (or no rows)")
    panels = (2 if accuracy else 0) + (1 if converging else 0)
    ratios = ([3, 2] if accuracy else []) + ([2] if converging else [])
    # The legends go under the panels, where they cover no curve (a default run draws 18 caustic curves).
    fig, axes = plt.subplots(1, panels, figsize=(7.5 * panels, 9), gridspec_kw={"width_ratios": ratios}, squeeze=False)
    axes = list(axes[0])
    if accuracy:
        speed_accuracy(accuracy, axes[0], axes[1])
    if converging:
        convergence(converging, axes[-1])
    fig.tight_layout()
    fig.savefig(sys.argv[-1], dpi=110)


if __name__ == "__main__":
    main()

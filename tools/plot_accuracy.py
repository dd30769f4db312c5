#!/usr/bin/env python3
"""Draws speed_accuracy.png from the results.csv of `caustica bench accuracy`.

Left: caustics, relative L1 error of the caustic map against the photon reference over the GPU time
of the caustic pass, log-log, one curve per method and scene, points labelled by photon grid.
Right: refraction, the same for the refraction passes against the ray-traced reference.
Usage: plot_accuracy.py RESULTS.csv OUT.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_accuracy.py RESULTS.csv OUT.png")
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    # The legends go under the panels, where they cover no curve (a default run draws 18 caustic curves).
    fig, (caustics, refraction) = plt.subplots(1, 2, figsize=(15, 9), gridspec_kw={"width_ratios": [3, 2]})
    # One colour per method (20 before one repeats), one marker and line style per scene.
    methods = sorted({r["method"] for r in rows})
    scenes = sorted({r["scene"] for r in rows})
    colours = plt.get_cmap("tab20").colors
    styles = [("o", "-"), ("s", "--"), ("D", ":"), ("^", "-.")]
    curves = {}
    for row in rows:
        curves.setdefault((row["kind"], row["scene"], row["method"]), []).append(row)
    for (kind, scene, method), points in sorted(curves.items()):
        axes = caustics if kind == "caustics" else refraction
        points.sort(key=lambda r: float(r["method_ms"]))
        x = [max(float(r["method_ms"]), 1e-3) for r in points]
        y = [max(float(r["relative_l1"]), 1e-4) for r in points]
        marker, line = styles[scenes.index(scene) % len(styles)]
        axes.plot(x, y, marker=marker, linestyle=line, color=colours[methods.index(method) % len(colours)],
                  label=f"{method} ({scene})")
        if kind == "caustics":
            for r, px, py in zip(points, x, y):
                axes.annotate(f"{r['grid']}²", (px, py), textcoords="offset points", xytext=(4, 3), fontsize=7)
    for axes, title, xlabel in ((caustics, "caustics", "caustic pass GPU time (ms)"),
                                (refraction, "refraction", "refraction passes GPU time (ms)")):
        axes.set_xscale("log")
        axes.set_yscale("log")
        axes.set_title(title)
        axes.set_xlabel(xlabel)
        axes.set_ylabel("relative L1 error against the reference")
        axes.grid(True, which="both", alpha=0.3)
        if axes.lines:
            axes.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()

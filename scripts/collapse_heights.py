#!/usr/bin/env python3
"""The collapse heights of van Herwijnen et al. (2016) (data/published_psts/vanherwijnen2016/, 255
PSTs: dy, the slab's displacement behind the crack by PTV) against the weak layer's thickness, with
the fit weac uses, 4.70 (1 - exp(-h / 7.78 mm)) mm, and, where a scored study is given, the model's
predicted collapse heights (summary.json collapsed_layer_under_the_slab, via field_score.json).
Prints the measured heights and strains by thickness class; draws docs/figures/collapse_heights.png
(or OUT).

    scripts/collapse_heights.py [--study out/published] [--out FILE]
"""
import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from published_scenes import MISSING, tests
from scene_study import ROOT

CLASSES_MM = [(0, 10), (10, 20), (20, 40), (40, 100), (100, 400)]


def weac_fit_mm(thickness_mm):
    """The collapse height fitted to van Herwijnen et al. (2016) as weac uses it."""
    return 4.70 * (1 - np.exp(-thickness_mm / 7.78))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--study", help="a scored study folder (field_score.json) whose predictions to draw")
    parser.add_argument("--out", default=os.path.join(ROOT, "docs", "figures", "collapse_heights.png"))
    args = parser.parse_args()
    rows = [t for t in tests() if t["dy_cm"] != MISSING and t["weak_cm"] > 0]
    dy = np.array([10 * t["dy_cm"] for t in rows])
    h = np.array([10 * t["weak_cm"] for t in rows])
    print(f"{len(rows)} PSTs with dy and a weak-layer thickness")
    print("| weak layer [mm] | PSTs | dy median [quartiles] [mm] | dy / thickness, median |")
    print("|---|---|---|---|")
    for lo, hi in CLASSES_MM:
        m = (h >= lo) & (h < hi)
        q = np.percentile(dy[m], [25, 50, 75])
        print(f"| {lo}–{hi} | {m.sum()} | {q[1]:.2f} [{q[0]:.2f}, {q[2]:.2f}] | {np.median(dy[m] / h[m]):.3f} |")
    ratio = dy / weac_fit_mm(h)
    print(f"dy / weac's fit: median {np.median(ratio):.2f} [{np.percentile(ratio, 25):.2f}, {np.percentile(ratio, 75):.2f}]")

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ax.scatter(h, dy, s=10, color="0.55", label=f"van Herwijnen et al. (2016), {len(rows)} PSTs")
    grid = np.geomspace(h.min(), h.max(), 200)
    ax.plot(grid, weac_fit_mm(grid), "k-", label="4.70 (1 − exp(−h/7.78 mm)) mm (weac)")
    if args.study:
        import json
        cases = json.load(open(os.path.join(args.study, "field_score.json")))["cases"]
        pairs = [(c["test"], c["collapse_height_m"]) for c in cases if c.get("collapse_height_m")]
        thickness = {f"vh2016_{t['id']:03d}": 10 * t["weak_cm"] for t in rows}
        x = [thickness[name] for name, _ in pairs if name in thickness]
        y = [1000 * value for name, value in pairs if name in thickness]
        ax.scatter(x, y, s=28, color="C3", marker="D", label=f"this model ({len(x)} of them)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("weak-layer thickness h [mm]")
    ax.set_ylabel("collapse height dy [mm]")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.out, dpi=150)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Plot the failure points of an anticrack campaign.

Usage: scripts/plot_campaign.py DIR [--output FILE.png]

Reads DIR/campaign.h5 (the table /failure_points and the histories /tests/<id>/history) and writes
DIR/campaign.png with three panels: the yield points in Ritter et al.'s (2020) base-stress plane (sigma, tau),
the same in the invariant plane (p, q) of the Love-Weber stress (one marker per realization, colour
by loading angle), and the base stress paths of the first realization up to failure. The fit of
the cohesive Cam-Clay surface is `anticrack calibrate`'s job; this is the raw envelope.
"""
import argparse
import os
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
from atomic_output import save_figure  # noqa: E402 (scripts/atomic_output.py)


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory", help="campaign output directory (holds campaign.h5)")
    parser.add_argument("--output", help="PNG file (default DIR/campaign.png)")
    args = parser.parse_args()
    path = os.path.join(args.directory, "campaign.h5")
    if not os.path.exists(path):
        print(f"plot_campaign: {path} does not exist", file=sys.stderr)
        return 1
    with h5py.File(path, "r") as f:
        fp = {name: f["failure_points"][name][()] for name in f["failure_points"]}
        paths = {}
        for test, realization in zip(fp["test"], fp["realization"]):
            test = text(test)
            if realization == 0 and test in f["tests"] and "history" in f["tests"][test]:
                h = f["tests"][test]["history"]
                paths[test] = (h["base_normal_stress"][()], h["base_shear_stress"][()], h["step"][()])
        scene = text(f.attrs.get("scene_file", ""))

    angles = fp["loading_angle_deg"]
    colours = plt.cm.viridis((angles - angles.min()) / max(np.ptp(angles), 1e-12))
    markers = "osD^v<>p*h"
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    for ax, (x, y, xlabel, ylabel) in zip(axes[:2], [
            (fp["sigma"], fp["tau"], "base normal stress σ [kPa] (compression +)", "base shear stress τ [kPa]"),
            (fp["p"], fp["q"], "mean stress p [kPa] (compression +)", "von Mises stress q [kPa]")]):
        for k in range(len(x)):
            ax.scatter(x[k] / 1e3, y[k] / 1e3, color=colours[k],
                       marker=markers[int(fp["realization"][k]) % len(markers)], s=40, edgecolor="k", linewidth=0.4)
        ax.axhline(0, color="0.7", lw=0.6)
        ax.axvline(0, color="0.7", lw=0.6)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
    axes[0].set_title("yield points, base stresses (Ritter et al. 2020)")
    axes[1].set_title("yield points, invariants")
    ax = axes[2]
    for test, (sigma, tau, step) in paths.items():
        row = [text(t) for t in fp["test"]].index(test)
        last = np.searchsorted(step, fp["failure_step"][row], side="right")
        ax.plot(sigma[:last] / 1e3, tau[:last] / 1e3, color=colours[row], lw=1)
        ax.plot(sigma[last - 1] / 1e3, tau[last - 1] / 1e3, "o", color=colours[row], ms=4)
    ax.set_xlabel("σ [kPa]")
    ax.set_ylabel("τ [kPa]")
    ax.set_title("stress paths to failure (realization 0)")
    ax.grid(alpha=0.3)
    mappable = plt.cm.ScalarMappable(cmap="viridis", norm=plt.Normalize(angles.min(), angles.max()))
    fig.colorbar(mappable, ax=axes, label="loading angle ψ [deg]", shrink=0.85)
    fig.suptitle(f"{scene}: {len(angles)} tests (marker = realization)")
    output = args.output or os.path.join(args.directory, "campaign.png")
    save_figure(fig, output, dpi=120)
    print(f"wrote {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

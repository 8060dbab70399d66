#!/usr/bin/python3
"""Plot the time series of an anticrack run directory.

Usage: scripts/plot_history.py DIR [--output FILE.png]

Reads DIR/history.h5 (one dataset per column, with a `units` attribute) and DIR/summary.json (for
the title) and writes DIR/history.png: loading (wall stresses vs axial strain, or clump and base
stresses vs time), bonds, energies and the energy-balance error. Panels whose columns are missing
are skipped, so any anticrack history can be plotted.
"""
import argparse
import json
import os
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
from atomic_output import save_figure  # noqa: E402 (scripts/atomic_output.py)

PREFIXES = [(1e9, "G"), (1e6, "M"), (1e3, "k"), (1.0, ""), (1e-3, "m"), (1e-6, "µ"), (1e-9, "n"), (1e-12, "p")]


def scaled(columns, unit):
    """The columns (a list of arrays) divided by one SI prefix that brings their largest magnitude
    into [1, 1000), and the prefixed unit."""
    finite = np.abs(np.concatenate([c[np.isfinite(c)] for c in columns]))
    peak = finite.max() if finite.size else 0.0
    factor, prefix = next(((f, p) for f, p in PREFIXES if peak >= f), (1.0, ""))
    return [c / factor for c in columns], prefix + unit


def read_history(path):
    with h5py.File(path, "r") as f:
        return {name: (np.asarray(f[name][()], dtype=float), f[name].attrs.get("units", "-"))
                for name in f if isinstance(f[name], h5py.Dataset) and f[name].ndim == 1}


def loading_panel(ax, h, t, t_label):
    """Wall stresses vs axial strain (walls on both faces of an axis), else stresses vs time."""
    walls = sorted(n[5:-len("_normal_stress")] for n in h if n.startswith("wall_") and n.endswith("_normal_stress"))
    if walls:
        x, x_label = t, t_label
        for axis in "xyz":
            lo, hi = f"wall_{axis}-_position", f"wall_{axis}+_position"
            if lo in h and hi in h:
                length = h[hi][0] - h[lo][0]
                if np.ptp(length) > 0 and length[0] > 0:
                    x, x_label = 100 * (1 - length / length[0]), f"axial strain along {axis}, 1 - L/L0 [%]"
                    break
        stresses, unit = scaled([h[f"wall_{w}_normal_stress"][0] for w in walls], "Pa")
        for w, s in zip(walls, stresses):
            ax.plot(x, s, label=f"wall {w}")
        ax.set(xlabel=x_label, ylabel=f"compressive normal stress [{unit}]", title="Wall stresses")
        return True
    names = [n for n in ("clump_normal_stress", "clump_shear_stress", "base_normal_stress", "base_shear_stress")
             if n in h and np.nanmax(np.abs(h[n][0]), initial=0) > 0]  # e.g. no shear in pure tension
    if not names:
        return False
    stresses, unit = scaled([h[n][0] for n in names], "Pa")
    for n, s in zip(names, stresses):
        label = n.replace("_", " ").replace("clump", "clump (applied)").replace("base", "base (reaction)")
        ax.plot(t, s, "-" if n.startswith("clump") else "--", label=label)
    ax.set(xlabel=t_label, ylabel=f"stress [{unit}]", title="Clump load and base reactions")
    return True


def bonds_panel(ax, h, t, t_label):
    if "intact_bonds" not in h:
        return False
    for name, label in (("intact_bonds", "intact"), ("broken_bonds_tension", "broken in tension"),
                        ("broken_bonds_shear", "broken in shear")):
        if name in h:
            ax.plot(t, h[name][0], label=label)
    ax.set(xlabel=t_label, ylabel="number of bonds [-]", title="Parallel bonds")
    return True


def energy_panel(ax, h, t, t_label):
    curves = [("kinetic_energy", "kinetic"), ("elastic_energy_contacts", "elastic, contacts"),
              ("elastic_energy_bonds", "elastic, bonds"), ("gravity_potential_energy", "|gravity potential|"),
              ("dissipated_friction", "dissipated: friction"), ("dissipated_viscous", "dissipated: viscous"),
              ("dissipated_local_damping", "dissipated: local damping"),
              ("dissipated_bond_breakage", "dissipated: bond breakage"), ("external_work", "|external work|")]
    top = 0.0
    for name, label in curves:
        if name in h and np.nanmax(np.abs(h[name][0]), initial=0) > 0:
            style = "k--" if name == "external_work" else "-"
            ax.plot(t, np.abs(h[name][0]), style, label=label, lw=1.8 if name == "external_work" else 1.2)
            finite = np.abs(h[name][0][np.isfinite(h[name][0])])
            top = max(top, finite.max(initial=0))
    if top == 0:
        return False
    ax.set_yscale("log")
    # Round-off-sized values at the start would stretch the axis; the lowest decades hold the legend.
    ax.set_ylim(top * 1e-14, top * 10)
    ax.legend(fontsize=7, ncol=3, loc="lower center", framealpha=0.9)
    ax.set(xlabel=t_label, ylabel="energy [J] (log scale)", title="Energies")
    return True


def balance_panel(ax, h, t, t_label, initial_balance):
    if "energy_balance_error" not in h:
        return False
    (error,), unit = scaled([h["energy_balance_error"][0]], "J")
    ax.plot(t, error, color="C3")
    ax.axhline(0, color="0.6", lw=0.8)
    ax.set(xlabel=t_label, title="Energy balance: stored + dissipated − external work")
    ax.set_ylabel(f"balance error [{unit}]", color="C3")
    parts = [np.abs(h[n][0]) for n in ("external_work", "dissipated_energy", "gravity_potential_energy") if n in h]
    stored = sum(h[n][0] for n in ("kinetic_energy", "elastic_energy_contacts", "elastic_energy_bonds") if n in h)
    scale = np.maximum.reduce(parts + [np.abs(stored), np.full_like(t, abs(initial_balance))])
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.where(scale > 0, 100 * np.abs(h["energy_balance_error"][0]) / scale, 0.0)
    twin = ax.twinx()
    twin.plot(t, relative, color="C0", lw=0.9, ls=":")
    twin.set_ylabel("|error| / energy scale [%]", color="C0")
    return True


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory", help="run directory (anticrack run -o DIR)")
    parser.add_argument("--output", help="PNG to write (default: DIR/history.png)")
    args = parser.parse_args()
    history_file = os.path.join(args.directory, "history.h5")
    if not os.path.isfile(history_file):
        sys.exit(f"plot_history: {history_file} does not exist")
    h = read_history(history_file)
    if "time" not in h or h["time"][0].size == 0:
        sys.exit(f"plot_history: {history_file} has no rows")
    summary = {}
    try:
        with open(os.path.join(args.directory, "summary.json")) as f:
            summary = json.load(f)
    except (OSError, ValueError):
        pass
    (t,), t_unit = scaled([h["time"][0]], "s")
    t_label = f"time [{t_unit}]"

    fig, axes = plt.subplots(2, 2, figsize=(13, 8.5))
    panels = [loading_panel, bonds_panel, energy_panel, lambda ax, *a: balance_panel(
        ax, *a, summary.get("dem", {}).get("energies_J", {}).get("initial_balance") or 0.0)]
    used = 0  # panels without data draw nothing and leave their axes to the next one
    for panel in panels:
        used += panel(axes.flat[used], h, t, t_label)
    for k, ax in enumerate(axes.flat):
        ax.set_visible(k < used)
        if ax.get_legend() is None and ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
        ax.grid(alpha=0.3)

    scene = summary.get("scene", {}).get("file", args.directory)
    dem = summary.get("dem", {})
    title = f"{os.path.basename(scene)}: {summary.get('status', '?')}"
    if dem:
        title += (f", {dem.get('steps')} of {dem.get('steps_requested')} steps, {dem.get('particles')} particles, "
                  f"{dem.get('intact_bonds')}/{dem.get('bonds')} bonds intact")
    fig.suptitle(title)
    fig.tight_layout()
    output = args.output or os.path.join(args.directory, "history.png")
    save_figure(fig, output, dpi=110)
    print(f"plot_history: wrote {output}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Plot the results of a snowpack (FE) run directory.

Usage: scripts/plot_pst.py DIR [--output FILE.png]

A dynamic or quasi-static PST (DIR/series.h5): the saw and the crack tip against time (or saw
step), the touchdown front, and the energies with the balance error. An energy release rate run
(DIR/energy_release_rate.h5): G(a) of the FE model and of the beam on an elastic foundation, with
the fracture energy and the cut length where G reaches it. Writes DIR/pst.png (or --output).
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


def read(path):
    with h5py.File(path, "r") as f:
        return {name: np.asarray(f[name][()], dtype=float) for name in f}


def plot_series(series, results, axes):
    time = series.get("time")
    x = time * 1e3 if time is not None else np.arange(len(series["cut_length"]))
    xlabel = "time since the saw started [ms]" if time is not None else "saw step"
    top, bottom = axes
    top.plot(x, series["cut_length"], label="saw cut")
    top.plot(x, series["crack_tip"], label="crack tip")
    top.plot(x, series["touchdown_front"], ":", label="touchdown front")
    critical = results.get("critical_cut_length_m")
    if critical is not None:
        top.axhline(critical, color="grey", lw=0.8, ls="--", label=f"critical cut {critical:.3f} m")
    top.set_xlabel(xlabel)
    top.set_ylabel("distance from the cut end [m]")
    top.legend(loc="upper left", fontsize=8)
    names = [("external_work", "work of gravity"), ("elastic_energy", "elastic"), ("kinetic_energy", "kinetic"),
             ("dissipated_energy", "plastic dissipation"), ("viscous_energy", "viscous"),
             ("removed_by_saw", "removed by the saw")]
    for name, label in names:
        if name in series:
            bottom.plot(x, series[name], label=label)
    bottom.set_xlabel(xlabel)
    bottom.set_ylabel("energy per m of width [J/m]")
    bottom.legend(loc="upper left", fontsize=8)


def plot_release_rate(table, results, axis):
    axis.plot(table["midpoint_cut_length"], table["energy_release_rate"], "o-", ms=3, label="FE, -dPi/da")
    beam = table.get("energy_release_rate_beam")
    if beam is not None and np.all(np.isfinite(beam)):
        axis.plot(table["midpoint_cut_length"], beam, "--", label="beam on elastic foundation")
    g_c = results.get("fracture_energy_J_per_m2")
    if g_c is not None:
        axis.axhline(g_c, color="grey", lw=0.8, ls="--", label=f"G_c = {g_c} J/m²")
    a_c = results.get("critical_cut_length_m")
    if a_c is not None:
        axis.axvline(a_c, color="grey", lw=0.8, ls=":", label=f"a = {a_c:.3f} m")
    axis.set_xlabel("cut length a [m]")
    axis.set_ylabel("energy release rate G [J/m²]")
    axis.legend(fontsize=8)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory")
    parser.add_argument("--output")
    args = parser.parse_args()
    results = {}
    summary_path = os.path.join(args.directory, "summary.json")
    if os.path.exists(summary_path):
        with open(summary_path) as f:
            results = json.load(f).get("results", {})
    # A critical-cut search (PST/Saw = practice or bisection): the series of its shortest ending trial.
    series_path = os.path.join(args.directory, results.get("series_directory", ""), "series.h5")
    release_path = os.path.join(args.directory, "energy_release_rate.h5")
    if os.path.exists(series_path):
        figure, axes = plt.subplots(2, 1, figsize=(8, 8))
        plot_series(read(series_path), results, axes)
        title = f"{results.get('analysis', 'PST')}: outcome {results.get('outcome', '')}"
        if results.get("series_directory"):
            title += f" (the trial {results['series_directory']})"
        speed = results.get("propagation_speed_m_per_s")
        if speed is not None:
            title += f", {speed:.1f} m/s"
    elif os.path.exists(release_path):
        figure, axis = plt.subplots(figsize=(8, 5))
        plot_release_rate(read(release_path), results, axis)
        title = "energy release rate of a saw cut"
    else:
        print(f"plot_pst.py: {args.directory} has neither series.h5 nor energy_release_rate.h5", file=sys.stderr)
        return 2
    figure.suptitle(title)
    figure.tight_layout()
    output = args.output or os.path.join(args.directory, "pst.png")
    save_figure(figure, output, dpi=120)
    print(f"wrote {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

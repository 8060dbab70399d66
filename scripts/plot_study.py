#!/usr/bin/python3
"""Plot a study's run directory (`set Scene = study`, coupling/study.h).

Usage: scripts/plot_study.py DIR

Reads DIR/study.json and writes
  DIR/work_precision.png  error against wall time, log-log, one panel per result and one curve per
                          varied entry (its line of variants, coarsest first); the 5 % and 1 % lines;
                          variants without an error (the reference itself, a missing answer) are left out
  DIR/results.png         each result against each varied entry's values, with the reference value
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
from atomic_output import save_figure  # noqa: E402 (scripts/atomic_output.py)


def numeric(values):
    try:
        return [float(v) for v in values]
    except ValueError:
        return None


def main(directory):
    with open(os.path.join(directory, "study.json")) as f:
        study = json.load(f)
    results = study["results"]
    lines = study["lines"]
    markers = "osd^v<>"

    # At most four panels a row: a study of many results stays readable.
    columns = min(4, len(results))
    rows = -(-len(results) // columns)
    fig, axes = plt.subplots(rows, columns, figsize=(5.2 * columns, 4.4 * rows), squeeze=False)
    for ax in axes.flat[len(results):]:
        ax.set_visible(False)
    for ax, result in zip(axes.flat, results):
        label = result["label"]
        plotted = False
        for k, line in enumerate(lines):
            r = line["results"][label]
            # annotated with the number each value stands for, when the values are entry changes
            names = [f"{m:g}" for m in line["measures"]] if "measures" in line else line["values"]
            points = [(t, e, v) for t, e, v in zip(line["wall_s"], r["errors"], names)
                      if e is not None and e > 0 and t > 0]
            if not points:
                continue
            plotted = True
            ax.loglog([p[0] for p in points], [p[1] for p in points], marker=markers[k % len(markers)],
                      label=f"{line['entry']} ({line['refinement']})")
            for t, e, v in points:
                ax.annotate(v, (t, e), textcoords="offset points", xytext=(4, 4), fontsize=7)
        for tolerance, style in ((0.05, "--"), (0.01, ":")):
            ax.axhline(tolerance, color="grey", lw=0.8, ls=style)
        given = result["reference_value"]
        against = f"the reference value {given:g}" if given is not None else "the finest variant of each entry"
        ax.set_title(f"{label}\nerror against {against}", fontsize=8)
        ax.set_xlabel("wall time of the variant [s]")
        ax.set_ylabel("relative error")
        if plotted:
            ax.legend(fontsize=7)
    fig.suptitle(f"{os.path.basename(study['base_scene'])}: error against run time\n({study['cost']})", fontsize=8)
    fig.tight_layout()
    save_figure(fig, os.path.join(directory, "work_precision.png"), dpi=120)
    plt.close(fig)

    # A row per result and a column per entry; one entry's results four a row, as above.
    columns = len(lines) if len(lines) > 1 else min(4, len(results))
    panels = [(result, line) for result in results for line in lines]
    rows = -(-len(panels) // columns)
    fig, axes = plt.subplots(rows, columns, figsize=(4.6 * columns, 3.6 * rows), squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.set_visible(False)
    for ax, (result, line) in zip(axes.flat, panels):
        label = result["label"]
        r = line["results"][label]
        # Measures: the number each value stands for when the values are not numbers (an entry
        # change such as `DEM/Sample/Particle count = 4096`).
        x = line.get("measures") or numeric(line["values"])
        positions = x if x is not None else list(range(len(line["values"])))
        ys = [(p, y) for p, y in zip(positions, r["values"]) if y is not None]
        ax.plot([p for p, _ in ys], [y for _, y in ys], marker="o")
        if x is None:
            ax.set_xticks(positions)
            ax.set_xticklabels(line["values"], rotation=30, fontsize=7)
        elif line["refinement"] in ("size", "count") and min(x) > 0:
            ax.set_xscale("log")
        if result["reference_value"] is not None:
            ax.axhline(result["reference_value"], color="grey", lw=0.8, ls="--", label="reference")
            ax.legend(fontsize=7)
        if line["base_value"] is not None and x is not None and "measures" not in line:
            try:
                ax.axvline(float(line["base_value"]), color="tab:red", lw=0.8, ls=":")
            except ValueError:
                pass
        ax.set_xlabel(line["entry"])
        ax.set_ylabel(label)
    fig.suptitle(f"{os.path.basename(study['base_scene'])}: answers against the varied entries\n"
                 "(red: the base scene's value)", fontsize=8)
    fig.tight_layout()
    save_figure(fig, os.path.join(directory, "results.png"), dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])

#!/usr/bin/env python3
"""The sliding of a collapsed layer in simple shear (DEM/Loading/Test = simple shear: a friction test
of a campaign, tests/<id>/, or a run of scenes/shs_collapsed_friction.prm): the base's mean shear
over its mean normal stress in blocks of shear strain, and over the campaign's window (the second
half of Campaign/Friction final shear strain, params/friction_calibration.h reads the same ratio
from summary.json). A layer that slides steadily keeps one ratio block after block; one that sticks
and slips swings, through zero when it jams (docs/calibration.md, "Friction of the failed layer").

    scripts/friction_blocks.py RUN_DIR [RUN_DIR ...] [--block 0.05] [--from 0.01] [--window-end 0.15]
"""
import argparse
import os

import h5py
import numpy as np


def blocks(history, block, start, window_end):
    """(block ratios, window ratio) of one history.h5: mean(tau) / mean(sigma) of the base."""
    with h5py.File(history, "r") as f:
        gamma = f["shear_strain"][()]
        tau = f["base_shear_stress"][()]
        sigma = f["base_normal_stress"][()]
    ratios = []
    lower = start
    while lower < gamma.max():
        rows = (gamma >= lower) & (gamma < lower + block)
        if rows.any():
            ratios.append(float(np.mean(tau[rows]) / np.mean(sigma[rows])))
        lower += block
    window = (gamma >= 0.5 * window_end) & (gamma <= window_end)
    return ratios, float(np.mean(tau[window]) / np.mean(sigma[window])) if window.any() else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", help="run directories holding history.h5")
    parser.add_argument("--block", type=float, default=0.05, help="block width in shear strain (0.05)")
    parser.add_argument("--from", dest="start", type=float, default=0.01, help="first block's lower end (0.01)")
    parser.add_argument("--window-end", type=float, default=0.15,
                        help="Campaign/Friction final shear strain whose second half is the window (0.15)")
    args = parser.parse_args()
    for run in args.runs:
        history = os.path.join(run, "history.h5")
        if not os.path.isfile(history):
            raise SystemExit(f"friction_blocks.py: {history} does not exist")
        ratios, window = blocks(history, args.block, args.start, args.window_end)
        print(f"{run}: tau/sigma by blocks of {args.block} from {args.start}: " +
              ", ".join(f"{r:.2f}" for r in ratios) +
              f"; over gamma {0.5 * args.window_end:g}-{args.window_end:g}: {window:.3f}")


if __name__ == "__main__":
    main()

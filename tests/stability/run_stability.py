#!/usr/bin/python3
"""Stability on stiff and extreme cases (ctest label `stability`): each case either runs (exit 0,
no NaN in its series, the energy balance within its bound) or stops before computing anything wrong
(exit 2 naming the entry and the safe range, or exit 1 with summary.json naming the failure).
Nothing in between: no silent garbage and no hang (each run has a time limit).

Usage: run_stability.py --anticrack PATH --source-dir DIR --work-dir DIR [--case NAME ...] [--list]

The FE cases are small variants of scenes/pst_flat.prm (SMALL below: a 1 m column on 2 cm elements,
2 rows through the weak layer), each changing what its name says. Expectations:
  runs       exit 0, status completed, |energy balance error| <= BALANCE, every series finite, and
             the outcome among `outcomes` when given;
  refused    exit 2, the message names every needle, the output folder is not created;
  collapses  exit 1, summary.json status "collapsed under gravity", the message names every needle
             (the weak layer that cannot carry its slab, docs/fem_closed_forms.md Eq. 28).
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from scene_edit import edit_scene  # noqa: E402  (tests/scene_edit.py)

# The energy balance of a run, relative to the external work: pst_flat itself closes to 3e-4.
BALANCE = 0.01
SMALL = {"PST/Column length [m]": "1.0", "PST/Cut length [m]": "0.6", "Mesh/Element length [m]": "0.02",
         "Mesh/Weak layer elements": "2", "Mesh/Slab element height [m]": "0.08",
         "Analysis/Explicit/End time [s]": "0.3", "Output/Field interval [s]": "1", "Output/Progress interval": "0"}
WL = "Snowpack/Weak layer/"
SLAB = "Snowpack/Slab layer 1/"

CASES = {
    # stiff slab on a soft layer: stiffness ratio 1e4 (slab 2 GPa over the layer's 0.2 MPa); the
    # time step follows the slab's wave speed, so the run is shortened
    "stiffness_ratio_1e4": ({SLAB + "Young's modulus [Pa]": "2e9", "Analysis/Explicit/End time [s]": "0.04"},
                            "runs", {}),
    "slab_poisson_0.49_q1": ({SLAB + "Poisson's ratio": "0.49"}, "refused",
                             {"needles": [SLAB + "Poisson's ratio", "nu <= 0.48", "Polynomial degree = 2"]}),
    "weak_layer_poisson_0.49_q1": ({WL + "Poisson's ratio": "0.49"}, "refused",
                                   {"needles": [WL + "Poisson's ratio", "nu <= 0.48"]}),
    "poisson_0.49_q2": ({SLAB + "Poisson's ratio": "0.49", WL + "Poisson's ratio": "0.49",
                         "Mesh/Polynomial degree": "2", "Analysis/Explicit/End time [s]": "0.1"}, "runs", {}),
    "beta_0": ({WL + "Tensile strength ratio beta": "0"}, "runs", {}),
    "beta_1": ({WL + "Tensile strength ratio beta": "1"}, "runs", {}),
    "xi_100": ({WL + "Hardening factor xi": "100"}, "runs", {}),
    "slope_0": ({}, "runs", {"outcomes": ["END"]}),
    "slope_60": ({"Snowpack/Slope angle [deg]": "60"}, "runs", {}),
    # a 2 m slab weighs 4.9 kPa: the layer needs p0 > 7.02 kPa to carry it (Eq. 28), given 10 kPa
    "deep_slab_2m": ({SLAB + "Thickness [m]": "2", "Mesh/Slab element height [m]": "0.2",
                      WL + "Compressive strength p0 [Pa]": "10000"}, "runs", {}),
    # the 0.4 m slab needs 1.42 kPa; with 1 kPa the layer collapses under gravity alone
    "weak_layer_too_weak": ({WL + "Compressive strength p0 [Pa]": "1000"}, "collapses",
                            {"needles": [WL + "Compressive strength p0 [Pa]", "must exceed 1421 Pa",
                                         "collapses under gravity alone"]}),
    "weak_layer_2mm": ({WL + "Thickness [m]": "0.002", WL + "Reference thickness [m]": "0.002",
                        WL + "Collapse height [m]": "0.0003", "Mesh/Weak layer elements": "1"}, "runs", {}),
    "column_20m": ({"PST/Column length [m]": "20", "Analysis/Explicit/End time [s]": "0.1"}, "runs", {}),
    # 8 times the strength the slab needs (Eq. 28), stiffer so that its peak strain stays small, under
    # a 0.35 m cut: the crack must not start, while with the scene's own weak layer that cut runs to
    # the end (case cut_0.35_runs; the power of this one)
    "weak_layer_too_strong": ({WL + "Compressive strength p0 [Pa]": "12000", WL + "Young's modulus [Pa]": "1e6",
                               "PST/Cut length [m]": "0.35"}, "runs",
                              {"outcomes": ["no propagation"]}),
    # p0 -> 0: nothing can carry the slab (1 Pa against the 1421 Pa Eq. 28 asks)
    "strength_1_pa": ({WL + "Compressive strength p0 [Pa]": "1", WL + "Collapse height [m]": "0"}, "collapses",
                      {"needles": [WL + "Compressive strength p0 [Pa]", "must exceed 1421 Pa"]}),
    # Q2 at its stability limit: the step just below sqrt(2/3) of Q1's runs; just above is refused
    "q2_cfl_at_limit": ({"Mesh/Polynomial degree": "2", "Analysis/Explicit/CFL safety factor": "0.8164",
                         "Analysis/Explicit/End time [s]": "0.1"}, "runs", {}),
    "q2_cfl_beyond_limit": ({"Mesh/Polynomial degree": "2", "Analysis/Explicit/CFL safety factor": "0.82"}, "refused",
                            {"needles": ["Analysis/Explicit/CFL safety factor", "must be <= 0.8165"]}),
    # a 3D column, 10 cm wide (coarser elements: the 3D step is the 2D one, the cells 5 times more)
    "column_3d": ({"Mesh/Dimension": "3", "Mesh/Element length [m]": "0.05", "Analysis/Explicit/End time [s]": "0.1"},
                  "runs", {"insert": {"PST": ["set Column width [m] = 0.1"]}}),
    "cut_0.35_runs": ({"PST/Cut length [m]": "0.35"}, "runs", {"outcomes": ["END"]}),
}


def run(anticrack, args, timeout):
    result = subprocess.run([anticrack, *args], capture_output=True, text=True, timeout=timeout)
    return result.returncode, result.stdout, result.stderr


def check_case(name, anticrack, source, work):
    changes, expect, options = CASES[name]
    folder = os.path.join(work, name)
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    text = edit_scene(open(os.path.join(source, "scenes", "pst_flat.prm")).read(), {**SMALL, **changes},
                      insert=options.get("insert"))
    scene = os.path.join(folder, "scene.prm")
    open(scene, "w").write(text)
    out = os.path.join(folder, "not_created" if expect == "refused" else "", "run")
    code, stdout, stderr = run(anticrack, ["run", scene, "-o", out], timeout=600)
    if expect == "refused":
        problems = [] if code == 2 else [f"exit {code}, expected 2"]
        problems += [f"the message lacks {n!r}" for n in [scene, *options["needles"]] if n not in stderr]
        if os.path.exists(os.path.dirname(out)):
            problems.append(f"{os.path.dirname(out)} was created")
        return problems, stderr
    summary_file = os.path.join(out, "summary.json")
    if not os.path.exists(summary_file):
        return [f"exit {code}, no summary.json"], stderr
    summary = json.load(open(summary_file))
    if expect == "collapses":
        problems = [] if code == 1 else [f"exit {code}, expected 1"]
        if summary.get("status") != "collapsed under gravity":
            problems.append(f"status {summary.get('status')!r}, expected 'collapsed under gravity'")
        problems += [f"the message lacks {n!r}" for n in options["needles"] if n not in stderr]
        return problems, stderr.strip()
    problems = [] if code == 0 else [f"exit {code}, expected 0"]
    results = summary.get("results", {})
    if summary.get("status") != "completed":
        problems.append(f"status {summary.get('status')}")
    balance = results.get("energies_per_width", {}).get("balance_error_relative")
    if balance is None or not abs(balance) <= BALANCE:
        problems.append(f"energy balance error {balance}, bound {BALANCE}")
    series_file = os.path.join(out, "series.h5")
    if not os.path.exists(series_file):
        return problems + ["no series.h5"], stderr
    with h5py.File(series_file, "r") as f:
        for key in f:
            data = np.asarray(f[key][()], dtype=float)
            if not np.all(np.isfinite(data)):
                problems.append(f"series.h5/{key} holds non-finite values")
    if "outcomes" in options and results.get("outcome") not in options["outcomes"]:
        problems.append(f"outcome {results.get('outcome')}, expected one of {options['outcomes']}")
    report = f"outcome {results.get('outcome')}, balance {balance:.2e}, {results.get('time_steps')} steps, " \
             f"{summary.get('timing', {}).get('wall_s', float('nan')):.1f} s" if balance is not None else stderr
    return problems, report


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--anticrack")
    parser.add_argument("--source-dir")
    parser.add_argument("--work-dir")
    parser.add_argument("--case", action="append")
    parser.add_argument("--list", action="store_true")
    a = parser.parse_args()
    if a.list:
        print("\n".join(CASES))
        return 0
    failed = 0
    for name in a.case or list(CASES):
        try:
            problems, report = check_case(name, os.path.abspath(a.anticrack), os.path.abspath(a.source_dir),
                                          os.path.abspath(a.work_dir))
        except subprocess.TimeoutExpired:
            problems, report = ["did not end within its time limit (a hang)"], ""
        failed += bool(problems)
        print(("FAIL " if problems else "PASS ") + name + ": " + ("; ".join(problems) + "\n" + report if problems else report))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

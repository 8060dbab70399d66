#!/usr/bin/python3
"""Stability on stiff and extreme cases (ctest label `stability`): each case either runs (exit 0,
no NaN in its series, the energy balance within its bound) or stops before computing anything wrong
(exit 2 naming the entry and the safe range, or exit 1 with summary.json naming the failure).
Nothing in between: no silent garbage and no hang (each run has a time limit).

Usage: run_stability.py --anticrack PATH --source-dir DIR --work-dir DIR [--case NAME ...] [--list]

Three families, each case changing what its name says in a small variant of a shipped scene:
  FE           scenes/pst_flat.prm (SMALL below: a 1 m column on 2 cm elements, 2 weak-layer rows);
  DEM          scenes/uniaxial_compression.prm, triaxial.prm, shs_sample.prm, ballistic_weak_layer.prm
               made a single DEM run (DEM_BASES: fewer steps); the DEM energy balance is its own
               ledger's (summary.json dem.energy_balance_relative_error);
  calibration  `anticrack calibrate` on tests/app's synthetic campaign (a known surface) altered.
Expectations:
  runs       exit 0, status completed, |energy balance error| <= its bound, every series finite,
             the outcome among `outcomes` (FE) and the quasi-static flag as `quasi_static` (DEM)
             when given;
  refused    exit 2, the message names every needle, the output folder is not created;
  collapses  exit 1, summary.json status "collapsed under gravity", the message names every needle
             (the weak layer that cannot carry its slab, docs/fem_closed_forms.md Eq. 28);
  calibrated exit 0, the material written, every needle in the console output, and the tests
             left out named in summary.json (calibration cases).
"""
import argparse
import glob
import json
import math
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

TESTS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, TESTS)
sys.path.insert(0, os.path.join(TESTS, "app"))
from scene_edit import edit_scene  # noqa: E402  (tests/scene_edit.py)
import run_app_tests  # noqa: E402  (its synthetic campaign writer)

# The energy balance of a run, relative to the external work: pst_flat itself closes to 3e-4, the
# DEM uniaxial compression to 1.3e-3.
BALANCE = {"fe": 0.01, "dem": 0.01}
SMALL = {"PST/Saw": "advancing", "PST/Column length [m]": "1.0", "PST/Cut length [m]": "0.6", "Mesh/Element length [m]": "0.02",
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
    "slope_0": ({}, "runs", {"outcomes": ["End"]}),
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
    "cut_0.35_runs": ({"PST/Cut length [m]": "0.35"}, "runs", {"outcomes": ["End"]}),
}
FAMILY = {name: "fe" for name in CASES}

# DEM: the base scene of each case and what makes it small (a single run of a few seconds).
QUIET = {"Output/Snapshot interval [steps]": "0", "Output/Checkpoint interval [steps]": "0",
         "Output/Write ParaView": "false"}
DEM_BASES = {
    "uniaxial_compression.prm": {**QUIET},
    "triaxial.prm": {**QUIET, "DEM/Steps": "20000", "Output/History interval [steps]": "500",
                     "Output/Progress interval [steps]": "5000"},
    "shs_sample.prm": {**QUIET, "DEM/Steps": "2000", "DEM/Sample/Particle count": "512"},
    # a campaign's scene made one DEM run: the deposit settles on a fixed base under gravity
    "ballistic_weak_layer.prm": {**QUIET, "Scene": "dem", "DEM/Steps": "2000", "Output/Progress interval [steps]": "500",
                                 "DEM/Sample/Actuator layer count": "0"},
}
DEM_REMOVE = {"ballistic_weak_layer.prm": ["Campaign", "DEM/Loading", "DEM/Boundary particles"]}
DEM_INSERT = {"ballistic_weak_layer.prm": {"DEM": ["subsection Walls", "subsection z-", "set Active = true",
                                                  "set Control = fixed", "end", "end"]}}
BOND = "DEM/Bond/"
DEM_CASES = {
    # the time step follows the stiffest spring (Time step = 0): 10 times smaller
    "dem_bonds_100x_stiffer": ("uniaxial_compression.prm", {BOND + "Modulus [Pa]": "1e11"}, "runs", {}),
    "dem_bonds_1e-3_strength": ("uniaxial_compression.prm", {BOND + "Tensile strength [Pa]": "1e3",
                                                            BOND + "Cohesion [Pa]": "1e3"}, "runs", {}),
    # the platen at 0.25 m/s reaches I = 2.8e-4 before the peak; 0.08 m/s stays below 1e-4
    # (Ritter et al. 2020's quasi-static limit), 8 m/s is 100 times that rate
    "dem_loading_quasi_static": ("uniaxial_compression.prm", {"DEM/Walls/z+/Velocity [m/s]": "0.08",
                                                             "DEM/Steps": "80000",
                                                             "Output/History interval [steps]": "400"},
                                 "runs", {"quasi_static": True}),
    "dem_loading_100x_quasi_static": ("uniaxial_compression.prm", {"DEM/Walls/z+/Velocity [m/s]": "8",
                                                                  "DEM/Steps": "800",
                                                                  "Output/History interval [steps]": "4"},
                                      "runs", {"quasi_static": False, "needles": ["NOT QUASI-STATIC"]}),
    "dem_no_damping": ("uniaxial_compression.prm", {"DEM/Integration/Local damping": "0"}, "runs", {}),
    # radii 0.1-1 mm (uniform in R): the step follows the smallest sphere
    "dem_polydispersity_10": ("triaxial.prm", {"DEM/Sample/Radius [m]": "5.5e-4",
                                               "DEM/Sample/Radius half width [m]": "4.5e-4"}, "runs", {}),
    # tau_min(0.3) = 0.06994 (Baxter's percolation bound of the Percus-Yevick solution)
    "shs_tau_just_above_minimum": ("shs_sample.prm", {"DEM/Sample/Stickiness": "0.0700"}, "runs", {}),
    "shs_tau_below_minimum": ("shs_sample.prm", {"DEM/Sample/Stickiness": "0.0699"}, "refused",
                              {"needles": ["DEM/Sample/Stickiness", "0.06994"]}),
    # 2900 spheres of 5 mm in a 5 cm x 5 cm column: a deposit about 105 diameters thick
    "ballistic_deposit_100_thick": ("ballistic_weak_layer.prm", {"DEM/Domain/Upper corner [m]": "0.05, 0.05, 0.6",
                                                                 "DEM/Sample/Particle count": "2900"}, "runs", {}),
}
FAMILY.update({name: "dem" for name in DEM_CASES})

# Calibration: the synthetic campaign of tests/app (9 angles x 3 realizations, 2 % scatter) altered.
CALIBRATION_CASES = {
    # one loading angle cannot make a surface: refused naming the file and the count
    "calibration_one_angle": ({"angles": [45], "realizations": 9}, "refused",
                              {"needles": ["1 loading angle", "at least 3 distinct angles"]}),
    # 50 % scatter of every failure stress: calibrated, with intervals that say so
    "calibration_scatter_50_percent": ({"noise": 0.5}, "calibrated",
                                       {"needles": ["WARNING: microstructure 0's surface explains R^2"],
                                        "p0_interval_ratio_above": 4}),
    # one test failed in the campaign: left out and named, not dropped silently
    "calibration_one_test_failed": ({"failed": "m0_r1_psi045.0"}, "calibrated",
                                    {"needles": ["1 test(s) left out", "m0_r1_psi045.0: failed"]}),
}
FAMILY.update({name: "calibration" for name in CALIBRATION_CASES})


def run(anticrack, args, timeout):
    result = subprocess.run([anticrack, *args], capture_output=True, text=True, timeout=timeout)
    return result.returncode, result.stdout, result.stderr


def refusal_problems(code, stderr, needles, out):
    """What is wrong with a refusal: exit 2, every needle (the file, the entry, the range) in the
    message, and the output's parent folder (made for nothing else) not created."""
    problems = [] if code == 2 else [f"exit {code}, expected 2"]
    problems += [f"the message lacks {n!r}" for n in needles if n not in stderr]
    if os.path.exists(os.path.dirname(out)):
        problems.append(f"{os.path.dirname(out)} was created")
    return problems


def case_folder(work, name):
    folder = os.path.join(work, name)
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    return folder


def check_case(name, anticrack, source, work):
    family = FAMILY[name]
    if family == "calibration":
        return check_calibration_case(name, anticrack, work)
    folder = case_folder(work, name)
    if family == "fe":
        changes, expect, options = CASES[name]
        text = edit_scene(open(os.path.join(source, "scenes", "pst_flat.prm")).read(), {**SMALL, **changes},
                          insert=options.get("insert"))
    else:
        base, changes, expect, options = DEM_CASES[name]
        text = edit_scene(open(os.path.join(source, "scenes", base)).read(), {**DEM_BASES[base], **changes},
                          insert=DEM_INSERT.get(base), remove=DEM_REMOVE.get(base, ()))
    scene = os.path.join(folder, "scene.prm")
    open(scene, "w").write(text)
    out = os.path.join(folder, "not_created" if expect == "refused" else "", "run")
    code, stdout, stderr = run(anticrack, ["run", scene, "-o", out], timeout=600)
    if expect == "refused":
        return refusal_problems(code, stderr, [scene, *options["needles"]], out), stderr
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
    if summary.get("status") != "completed":
        problems.append(f"status {summary.get('status')}")
    if family == "fe":
        results = summary.get("results", {})
        balance = results.get("energies_per_width", {}).get("balance_error_relative")
        series_file = os.path.join(out, "series.h5")
        if "outcomes" in options and results.get("outcome") not in options["outcomes"]:
            problems.append(f"outcome {results.get('outcome')}, expected one of {options['outcomes']}")
        report = f"outcome {results.get('outcome')}, {results.get('time_steps')} steps"
    else:
        dem = summary.get("dem", {})
        balance = dem.get("energy_balance_relative_error")
        series_file = os.path.join(out, "history.h5")
        inertial = dem.get("inertial_number", {})
        if "quasi_static" in options and inertial.get("quasi_static") != options["quasi_static"]:
            problems.append(f"inertial number {inertial}: quasi_static should be {options['quasi_static']}")
        problems += [f"the output lacks {n!r}" for n in options.get("needles", []) if n not in stdout]
        report = f"{dem.get('particles')} particles, {dem.get('steps')} steps, dt {dem.get('dt_s', 0):.3g} s, " \
                 f"largest I {inertial.get('largest_before_peak_q')}"
    if balance is None or not abs(balance) <= BALANCE[family]:
        problems.append(f"energy balance error {balance}, bound {BALANCE[family]}")
    if not os.path.exists(series_file):
        return problems + [f"no {os.path.basename(series_file)}"], stderr
    with h5py.File(series_file, "r") as f:
        for key in f:
            data = np.asarray(f[key][()], dtype=float)
            if not np.all(np.isfinite(data)):
                problems.append(f"{os.path.basename(series_file)}/{key} holds non-finite values")
    if balance is not None:
        report += f", balance {balance:.2e}, {summary.get('timing', {}).get('wall_s', float('nan')):.1f} s"
    return problems, report


def check_calibration_case(name, anticrack, work):
    alteration, expect, options = CALIBRATION_CASES[name]
    folder = case_folder(work, name)
    campaign = run_app_tests.write_synthetic_campaign(
        os.path.join(folder, "campaign.h5"), alteration.get("angles", run_app_tests.ANGLES),
        realizations=alteration.get("realizations", 3), noise=alteration.get("noise", 0.02))
    if "failed" in alteration:
        with h5py.File(campaign, "r+") as f:
            status = f["failure_points/status"]
            tests = [t.decode() if isinstance(t, bytes) else t for t in f["failure_points/test"][()]]
            status[tests.index(alteration["failed"])] = "failed"
    out = os.path.join(folder, "not_created" if expect == "refused" else "", "calibration")
    code, stdout, stderr = run(anticrack, ["calibrate", campaign, "-o", out, "--no-plots", "--bootstrap", "50"],
                               timeout=600)
    if expect == "refused":
        return refusal_problems(code, stderr, [campaign, *options["needles"]], out), stderr
    problems = [] if code == 0 else [f"exit {code}, expected 0"]
    problems += [f"the output lacks {n!r}" for n in options["needles"] if n not in stdout]
    summary_file = os.path.join(out, "summary.json")
    if not os.path.exists(summary_file):
        return problems + ["no summary.json"], stderr
    micro = json.load(open(summary_file))["calibration"]["microstructures"][0]
    left_out = micro.get("tests_left_out")
    if "failed" in alteration and left_out != [alteration["failed"] + ": failed"]:
        problems.append(f"tests_left_out {left_out}, expected the failed test")
    materials = glob.glob(os.path.join(out, "*.prm"))
    if not materials:
        problems.append("no material file written")
    elif "p0_interval_ratio_above" in options:
        # the intervals must say how little the scattered points fix: upper / lower of p0's
        line = [l for l in open(materials[0]) if "Compressive strength p0 interval" in l][0]
        lower, upper = (float(v) for v in line.split("=")[1].split(","))
        if not upper / lower > options["p0_interval_ratio_above"]:
            problems.append(f"p0 interval {lower}, {upper}: narrower than the scatter allows")
    return problems, stdout.strip()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--anticrack")
    parser.add_argument("--source-dir")
    parser.add_argument("--work-dir")
    parser.add_argument("--case", action="append")
    parser.add_argument("--list", action="store_true")
    a = parser.parse_args()
    if a.list:
        print("\n".join(FAMILY))
        return 0
    failed = 0
    for name in a.case or list(FAMILY):
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

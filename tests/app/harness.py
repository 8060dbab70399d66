#!/usr/bin/python3
"""The harness of the end-to-end tests (tests/app/run_app_tests.py): the executable and source tree a
run was given, the table of cases, checks, scene writers and the runner. The cases live in
cases_*.py, one file per what they check.

End-to-end tests of the `anticrack` executable (registered with ctest by tests/app/CMakeLists.txt).

Usage: run_app_tests.py --anticrack PATH --source-dir DIR --work-dir DIR CASE [CASE ...]
       run_app_tests.py --list

Every case writes tiny scenes derived from scenes/*.prm (small lattices, few steps), or the
tiny snowpack scene of pst_scene() (the fem_* cases), into WORK-DIR/<case>/, runs the
executable there and checks its exit code, console and files. The case directory is removed
when the case passes and kept for inspection when it fails.
Exit code: 0 when every case passed, 1 otherwise.
"""
import argparse
import concurrent.futures
import glob
import hashlib
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import traceback
import types
import xml.etree.ElementTree as ElementTree

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from scene_edit import as_analysis, edit_scene  # noqa: E402  (tests/scene_edit.py)

PATHS = types.SimpleNamespace(anticrack=None, source=None)  # the executable and the source tree, set by main()
CASES = {}

# The tiny lattice of most cases: 4 x 3 x 5 spheres of R = 1 mm at spacing 2 mm, periodic in x
# and y (distinct sizes, so that a mix-up of axes shows). Bonds: 3 nx ny nz - nx ny.
LATTICE = (4, 3, 5)
N_PARTICLES = LATTICE[0] * LATTICE[1] * LATTICE[2]
N_BONDS = 3 * N_PARTICLES - LATTICE[0] * LATTICE[1]


def case(function):
    CASES[function.__name__] = function
    return function


class Failure(AssertionError):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def check_phases(summary, phases, label, within_wall_time=False):
    """summary.json's timing.phases names `phases` (wall times >= 0, each entered at least once);
    `within_wall_time`: the phases, which do not overlap, add up to no more than timing.wall_s."""
    recorded = summary["timing"]["phases"]
    check(set(phases) <= set(recorded), f"{label}: timing.phases {sorted(recorded)} lacks {sorted(set(phases) - set(recorded))}")
    check(all(p["wall_s"] >= 0 and p["calls"] >= 1 for p in recorded.values()), f"{label}: timing.phases {recorded}")
    if within_wall_time:
        total = sum(p["wall_s"] for p in recorded.values())
        check(total <= summary["timing"]["wall_s"] * (1 + 1e-9), f"{label}: the phases add up to {total} s, "
              f"more than the run's {summary['timing']['wall_s']} s")


# --------------------------------------------------------------------------------------- scenes
def walls_scene(steps, checkpoint=0, snapshot=None, history=50, velocity="10", insert=None, **changes):
    """scenes/uniaxial_compression.prm on the tiny lattice. At 10 m/s the top wall breaks every bond
    between steps ~500 and ~600 (a symmetric lattice fails layer by layer)."""
    text = open(os.path.join(PATHS.source, "scenes", "uniaxial_compression.prm")).read()
    return edit_scene(text, {
        "Output/History interval [steps]": str(history), "Output/Progress interval [steps]": "0",
        "Output/Snapshot interval [steps]": str(snapshot if snapshot is not None else steps),
        "Output/Checkpoint interval [steps]": str(checkpoint),
        "DEM/Steps": str(steps),
        "DEM/Domain/Upper corner [m]": "0.008, 0.006, 0.010", "DEM/Sample/Lattice size": "4, 3, 5",
        "DEM/Walls/z+/Velocity [m/s]": velocity, **changes}, insert)


def clump_scene(steps, checkpoint=0, snapshot=None, history=50):
    """scenes/mixed_mode_clump.prm on a 4 x 3 x 6 lattice: bottom layer fixed, top layer the clump,
    loaded so fast (3e5 N/s on 48 mm^2) that bonds break progressively from step ~200 on and the
    clump crosses the periodic face x = 8 mm near step 1150."""
    text = open(os.path.join(PATHS.source, "scenes", "mixed_mode_clump.prm")).read()
    return edit_scene(text, {
        "Output/History interval [steps]": str(history), "Output/Progress interval [steps]": "0",
        "Output/Snapshot interval [steps]": str(snapshot if snapshot is not None else steps),
        "Output/Checkpoint interval [steps]": str(checkpoint), "DEM/Steps": str(steps),
        "DEM/Domain/Upper corner [m]": "0.008, 0.006, 0.012", "DEM/Sample/Lattice size": "4, 3, 6",
        "DEM/Boundary particles/Fix below [m]": "2e-3", "DEM/Boundary particles/Clump above [m]": "10e-3",
        "DEM/Boundary particles/Clump force rate [N/s]": "3e5"})


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


# ------------------------------------------------------------------------------------- running
def anticrack(*args, expect=0, cwd=None, timeout=300, env=None):
    """Runs anticrack; checks the exit code; returns (stdout, stderr). `timeout` [s] stops a hung run
    (the campaigns of the cross-validation take minutes, and longer when the machine is slow); `env`
    adds to the environment."""
    command = [PATHS.anticrack, *map(str, args)]
    result = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=timeout,
                            env=dict(os.environ, **env) if env else None)
    check(result.returncode == expect,
          f"`{' '.join(command)}` exited with {result.returncode}, expected {expect}\n"
          f"--- stdout\n{result.stdout}--- stderr\n{result.stderr}")
    return result.stdout, result.stderr


def read_history(directory):
    with h5py.File(os.path.join(directory, "history.h5"), "r") as f:
        return {name: (f[name][()], f[name].attrs.get("units")) for name in f}


def read_snapshot(path):
    data = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, item: data.__setitem__(name, item[()]) if isinstance(item, h5py.Dataset) else None)
    return data


def snapshot_path(directory, step):
    return os.path.join(directory, "snapshots", f"snapshot_{step:06d}.h5")


def compare_exactly(a, b, what, names=None):
    """Bitwise equality (NaN equal to NaN) of two {name: array} maps."""
    for name in names if names is not None else sorted(set(a) | set(b)):
        check(name in a and name in b, f"{what}: {name} missing in one of the two")
        x, y = np.asarray(a[name]), np.asarray(b[name])
        same = x.shape == y.shape and (np.array_equal(x, y, equal_nan=True) if x.dtype.kind == "f"
                                       else np.array_equal(x, y))
        if not same and x.shape == y.shape and x.dtype.kind == "f":
            raise Failure(f"{what}: {name} differs, max |difference| = {np.nanmax(np.abs(x - y)):.6g} "
                          f"in {np.count_nonzero(x != y)} of {x.size} values")
        check(same, f"{what}: {name} differs (shapes {x.shape} and {y.shape})")


def files_of(directory):
    """{relative path: sha256} of every file below `directory`."""
    listing = {}
    for root, _, names in os.walk(directory):
        for name in names:
            path = os.path.join(root, name)
            with open(path, "rb") as f:
                listing[os.path.relpath(path, directory)] = hashlib.sha256(f.read()).hexdigest()
    return listing


# ------------------------------------------------------------------------ snowpack scenes (FE)
# tests/fem_solver/test_snowpack_solver.cpp's small_pst: a 1 m column on flat ground, 0.4 m slab,
# 2 cm Cam-Clay weak layer (2 elements through it: crack band 1 cm), 4 cm substratum, elements
# 2 cm long, 400 cells; a fixed saw cut of 0.45 m. With the collapse height of 3 mm of its
# CrackRunsThroughTheColumn the crack runs from the cut to the downslope end at ~17 m/s and gets
# there at 0.05 s (~1 s of wall time). (With 1 mm it stops at 0.88 m at 0.05 s and only the free
# end's failure at 0.19 s makes it "reach the column end"; over that time the softening weak layer
# amplifies round-off, 1 vs 2 ranks, from 1e-15 to 1e-4.)
def quiet_scene(name, history_interval, changes, remove=()):
    """The shipped scene scenes/NAME with its outputs quiet (a history row every `history_interval`
    steps, no progress lines, snapshots, checkpoints or ParaView files) and `changes` on top."""
    text = open(os.path.join(PATHS.source, "scenes", name)).read()
    return edit_scene(text, {
        "Output/History interval [steps]": str(history_interval), "Output/Progress interval [steps]": "0",
        "Output/Snapshot interval [steps]": "0", "Output/Checkpoint interval [steps]": "0",
        "Output/Write ParaView": "false", **changes}, remove=list(remove))


# A rock scene 10 times softer and weaker than the shipped ones: the same failure strain on a 3x
# longer time step, for the small lab tests.
SOFT_ROCK = {"DEM/Material/Contact modulus [Pa]": "1e9", "DEM/Bond/Modulus [Pa]": "1e9",
             "DEM/Bond/Tensile strength [Pa]": "2e6", "DEM/Bond/Cohesion [Pa]": "2e6",
             "DEM/Sample/Packing pressure [Pa]": "1e5"}


WEAK_LAYER_MATERIAL = {
    "Yield surface plane": "invariants", "Density [kg/m^3]": "150", "Young's modulus [Pa]": "2e5", "Poisson's ratio": "0.2",
    "Compressive strength p0 [Pa]": "5000", "Tensile strength ratio beta": "0.5", "Critical state slope M": "1",
    "Hardening law": "collapse", "Hardening factor xi": "4", "Residual strength ratio": "0.1",
    "Reference thickness [m]": "0.02"}
PST_COLUMN_LENGTH, PST_CUT = 1.0, 0.45
PST_CELLS = 50 * (5 + 2 + 1)          # 50 columns x (slab 0.4 / 0.08, weak layer 2, substratum 1) rows
PST_DOFS = 2 * 51 * (5 + 2 + 1 + 1)    # Q1: 2 components x 51 x 9 vertices
SERIES_UNITS = {"time": "s", "cut_length": "m", "crack_tip": "m", "touchdown_front": "m", "elastic_energy": "J/m",
                "kinetic_energy": "J/m", "dissipated_energy": "J/m", "viscous_energy": "J/m", "removed_by_saw": "J/m",
                "external_work": "J/m", "time_step": "s"}
ERR_UNITS = {"cut_length": "m", "potential_energy": "J/m", "midpoint_cut_length": "m",
             "energy_release_rate": "J/m^2", "energy_release_rate_beam": "J/m^2"}


def interrupt_at_line(arguments, marker, timeout=300):
    """Runs anticrack with `arguments`, sends Ctrl-C (SIGINT) when a line of its standard output
    contains `marker`, and returns its exit code and standard error."""
    process = subprocess.Popen([PATHS.anticrack, *arguments], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in process.stdout:
        if marker in line:
            process.send_signal(signal.SIGINT)
            break
    _, stderr = process.communicate(timeout=timeout)
    return process.returncode, stderr


def pst_scene(changes=None, insert=None, material_file=None, remove=()):
    """The tiny dynamic PST; `changes`, `insert` and `remove` as in edit_scene. With `material_file`
    the weak layer's material comes from that file instead of the inline entries."""
    material = ([f"set Material file = {material_file}"] if material_file else
                [f"set {name} = {value}" for name, value in WEAK_LAYER_MATERIAL.items()])
    text = "\n".join([
        "subsection Snowpack",
        "  subsection Slab layer 1",
        "    set Thickness [m] = 0.4", "    set Density [kg/m^3] = 250", "    set Young's modulus [Pa] = 5e6",
        "    set Poisson's ratio = 0.25",
        "  end",
        "  subsection Weak layer",
        "    set Thickness [m] = 0.02", "    set Model = cohesive cam-clay",
        *("    " + line for line in material),
        "    set Collapse height [m] = 0.003", "    set Densification modulus [Pa] = 1e6",
        "    set Friction coefficient = 0.5",
        "  end",
        "  subsection Substratum",
        "    set Thickness [m] = 0.04", "    set Density [kg/m^3] = 300", "    set Young's modulus [Pa] = 1e7",
        "    set Poisson's ratio = 0.25",
        "  end",
        "end",
        "subsection PST",
        f"  set Column length [m] = {PST_COLUMN_LENGTH}", "  set Saw = fixed", f"  set Cut length [m] = {PST_CUT}",
        "end",
        "subsection Mesh",
        "  set Element length [m] = 0.02", "  set Weak layer elements = 2", "  set Slab element height [m] = 0.08",
        "  set Substratum element height [m] = 0.04",
        "end",
        "subsection Analysis",
        "  set Type = explicit dynamics",
        "  subsection Crack detection",
        "    set Self-propagation lead [m] = 0.1",
        "  end",
        "  subsection Explicit",
        "    set End time [s] = 0.25",
        "  end",
        "end",
        "subsection Output",
        "  set Field interval [s] = 0.01", "  set Progress interval = 0",
        "end"]) + "\n"
    return edit_scene(text, changes or {}, insert, remove)


def err_scene():
    """The energy release rate of the tiny PST's snowpack with an elastic weak layer: a 1.5 m column,
    5 cm elements, cuts of 0 to 0.3 m (7 elastic solves, G at 6 midpoints)."""
    return edit_scene(as_analysis(pst_scene(), "energy release rate", PATHS.anticrack,
                                  {"Snowpack/Weak layer/Model": "elastic", "PST/Cut length [m]": "0.3",
                                   "PST/Column length [m]": "1.5", "Mesh/Element length [m]": "0.05"}), {},
                      insert={"Analysis": ["set Fracture energy [J/m^2] = 0.5"]})


def mpirun(*args, ranks=2, cwd=None):
    """Runs anticrack on `ranks` MPI ranks (as root too); checks exit 0; returns stdout."""
    environment = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    command = ["mpirun", "--oversubscribe", "-np", str(ranks), PATHS.anticrack, *map(str, args)]
    result = subprocess.run(command, capture_output=True, text=True, env=environment, cwd=cwd, timeout=300)
    check(result.returncode == 0, f"`{' '.join(command)}` exited with {result.returncode}\n"
                                  f"--- stdout\n{result.stdout}--- stderr\n{result.stderr}")
    return result.stdout


def read_columns(path):
    """{name: (values, units)} of an HDF5 file with one dataset per column."""
    with h5py.File(path, "r") as f:
        return {name: (f[name][()], f[name].attrs.get("units")) for name in f}


def units_text(units):
    return units.decode() if isinstance(units, bytes) else units


def fem_summary(directory):
    with open(os.path.join(directory, "summary.json")) as f:
        summary = json.load(f)
    check(summary.get("status") == "completed", f"{directory}: summary.json status {summary.get('status')!r}: "
                                                f"{summary.get('failure')}")
    return summary


def check_fields(directory, ranks):
    """fields/fields.pvd lists exactly the .pvtu files of fields/ at increasing times, and every
    .pvtu names one existing .vtu piece per rank. Returns the times."""
    fields = os.path.join(directory, "fields")
    sets = ElementTree.parse(os.path.join(fields, "fields.pvd")).getroot().findall("./Collection/DataSet")
    listed = [d.get("file") for d in sets]
    on_disk = sorted(n for n in os.listdir(fields) if n.endswith(".pvtu"))
    check(listed and sorted(listed) == on_disk == [f"fields_{k:05d}.pvtu" for k in range(len(listed))],
          f"fields.pvd lists {listed}, fields/ has {on_disk}")
    times = [float(d.get("timestep")) for d in sets]
    check(times == sorted(times) and len(set(times)) == len(times), f"fields.pvd times {times}")
    pieces_used = set()
    for name in listed:
        root = ElementTree.parse(os.path.join(fields, name)).getroot()
        check(root.get("type") == "PUnstructuredGrid", f"{name} is not a parallel unstructured grid")
        pieces = [p.get("Source") for p in root.iter("Piece")]
        check(len(pieces) == ranks, f"{name} names {len(pieces)} pieces for {ranks} rank(s): {pieces}")
        for piece in pieces:
            path = os.path.join(fields, piece)
            check(os.path.isfile(path), f"{name} names {piece}, which does not exist")
            grid = ElementTree.parse(path).getroot().find("./UnstructuredGrid/Piece")
            check(grid is not None and int(grid.get("NumberOfCells")) > 0, f"{piece} holds no cells")
            pieces_used.add(piece)
    vtu = {n for n in os.listdir(fields) if n.endswith(".vtu")}
    check(vtu == pieces_used, f"fields/ has .vtu files no .pvtu names: {sorted(vtu - pieces_used)}")
    return times


def read_material(path):
    values = {}
    for line in open(path):
        entry = re.match(r"\s*set\s+(.*?)\s*=\s*(.*)$", line)
        if entry:
            values[entry.group(1)] = entry.group(2)
    return values


def main(cases=None, description=None):
    """Runs the cases named on the command line, of `cases` (default: this file's; tests/faults runs
    its own through this)."""
    cases = CASES if cases is None else cases
    parser = argparse.ArgumentParser(description=(description or __doc__).splitlines()[0])
    parser.add_argument("--anticrack", help="the built anticrack executable")
    parser.add_argument("--source-dir", help="the source tree (for scenes/)")
    parser.add_argument("--work-dir", help="where the cases write their files")
    parser.add_argument("--list", action="store_true", help="list the cases")
    parser.add_argument("cases", nargs="*", metavar="CASE", help="one of --list")
    args = parser.parse_args()
    if args.list:
        for name, function in cases.items():
            print(f"{name:24s} {function.__doc__.splitlines()[0]}")
        return 0
    if not (args.anticrack and args.source_dir and args.work_dir and args.cases):
        parser.error("--anticrack, --source-dir, --work-dir and at least one CASE are needed")
    unknown = [c for c in args.cases if c not in cases]
    if unknown:
        parser.error(f"unknown cases {unknown}; --list shows them")
    PATHS.anticrack, PATHS.source = os.path.abspath(args.anticrack), os.path.abspath(args.source_dir)
    failed = 0
    for name in args.cases:
        work = os.path.join(os.path.abspath(args.work_dir), name)
        shutil.rmtree(work, ignore_errors=True)
        os.makedirs(work)
        try:
            cases[name](work)
        except Exception as e:  # noqa: BLE001 (report every kind of failure of the case)
            failed += 1
            detail = str(e) if isinstance(e, Failure) else traceback.format_exc()
            print(f"FAIL {name}: {detail}\n(files kept in {work})")
            continue
        shutil.rmtree(work)
        print(f"ok   {name}")
    return 1 if failed else 0

"""End-to-end cases of tests/app (run by run_app_tests.py): DEM runs: outputs, bad input, resume, threads, check and params, bench, the sample generators."""
from harness import *  # noqa: F401,F403  (the checks, scene writers and runner)


# ----------------------------------------------------------------------------------------- a
@case
def run_outputs(work):
    """A tiny run: exit 0, summary.json, history.h5, snapshots and ParaView files are consistent."""
    steps, snapshot, history = 300, 100, 50
    scene = write(os.path.join(work, "tiny.prm"), walls_scene(steps, checkpoint=150, snapshot=snapshot,
                                                              history=history, velocity="0.25"))
    out = os.path.join(work, "run")
    stdout, _ = anticrack("run", scene, "-o", out, "--threads", 1)
    check("done: 300 steps" in stdout, f"no 'done: 300 steps' in the console output:\n{stdout}")

    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    check(summary["status"] == "completed", f"summary.json status is {summary['status']!r}")
    check_phases(summary, ["sample and model", "time stepping", "output"], "DEM run")
    with open(scene, "rb") as f:
        scene_sha256 = hashlib.sha256(f.read()).hexdigest()
    hashes = summary["scene"]
    check(hashes["file_sha256"] == scene_sha256,
          f"summary.json scene.file_sha256 {hashes['file_sha256']} != sha256 of the scene {scene_sha256}")
    for key in ("parameters_sha256", "resume_key_sha256"):
        check(re.fullmatch(r"[0-9a-f]{64}", hashes.get(key, "")), f"summary.json scene.{key} = {hashes.get(key)!r}")
    dem = summary["dem"]
    check(dem["particles"] == N_PARTICLES, f"summary: {dem['particles']} particles, lattice has {N_PARTICLES}")
    check(dem["bonds"] == N_BONDS, f"summary: {dem['bonds']} bonds, the periodic lattice has {N_BONDS}")
    check(dem["intact_bonds"] + dem["broken_bonds_tension"] + dem["broken_bonds_shear"] == N_BONDS,
          "summary: intact + broken bonds != bonds")
    check(dem["steps"] == steps and dem["steps_requested"] == steps, f"summary: steps {dem['steps']}")
    check(abs(dem["energy_balance_relative_error"]) < 0.01,
          f"energy balance error {dem['energy_balance_relative_error']} of the energy scale")

    # history.h5: every column, with units, one row per history interval plus the first.
    h = read_history(out)
    with h5py.File(os.path.join(out, "history.h5"), "r") as f:
        check(f.attrs.get("parameters_sha256") == hashes["parameters_sha256"],
              "history.h5 parameters_sha256 attribute differs from summary.json")
    expected = {"time": "s", "step": "-", "dt": "s", "kinetic_energy": "J", "elastic_energy_contacts": "J",
                "elastic_energy_bonds": "J", "gravity_potential_energy": "J", "dissipated_friction": "J",
                "dissipated_viscous": "J", "dissipated_local_damping": "J", "dissipated_bond_breakage": "J",
                "dissipated_energy": "J", "external_work": "J", "energy_balance_error": "J", "intact_bonds": "-",
                "broken_bonds_tension": "-", "broken_bonds_shear": "-", "wall_z-_position": "m",
                "wall_z-_normal_stress": "Pa", "wall_z+_position": "m", "wall_z+_normal_stress": "Pa"}
    for name, unit in expected.items():
        check(name in h, f"history.h5 has no column {name}; it has {sorted(h)}")
        check(h[name][1] == unit, f"history.h5 {name}: units {h[name][1]!r}, expected {unit!r}")
    check(all(u for _, u in h.values()), "a history.h5 column has no units attribute")
    check(list(h["step"][0]) == list(range(0, steps + 1, history)), f"history.h5 steps {list(h['step'][0])}")
    check(all(len(v) == len(h["step"][0]) for v, _ in h.values()), "history.h5 columns of different lengths")
    check(np.all(np.diff(h["time"][0]) > 0), "history.h5 time does not increase")
    check(h["intact_bonds"][0][0] == N_BONDS, "history.h5: not every bond intact at step 0")
    stress = h["wall_z+_normal_stress"][0]
    top = next(w for w in dem["walls"] if w["name"] == "z+")
    check(stress[-1] > 0 and np.isclose(stress[-1], top["normal_stress_Pa"], rtol=1e-12),
          "history.h5 wall_z+_normal_stress at the end disagrees with summary.json or is not compressive")

    # Snapshots: every snapshot step, readable, with the lattice's particles and bonds.
    snapshot_steps = list(range(0, steps + 1, snapshot))
    found = sorted(os.listdir(os.path.join(out, "snapshots")))
    check(found == [f"snapshot_{s:06d}.h5" for s in snapshot_steps], f"snapshots/ holds {found}")
    for s in snapshot_steps:
        data = read_snapshot(snapshot_path(out, s))
        check(data["particles/position"].shape == (N_PARTICLES, 3),
              f"snapshot {s}: particles/position has shape {data['particles/position'].shape}")
        check(data["particles/radius"].shape == (N_PARTICLES,) and np.all(data["particles/radius"] == 1e-3),
              f"snapshot {s}: radii")
        check(data["bonds/state"].shape == (N_BONDS,), f"snapshot {s}: {data['bonds/state'].shape} bonds")
        check(np.all(np.isfinite(data["particles/position"])), f"snapshot {s}: non-finite positions")
    check(summary["outputs"]["snapshots_written"] == len(snapshot_steps), "summary: snapshots_written")

    # ParaView: each .pvd lists exactly the .vtp files that exist, at increasing times.
    paraview = os.path.join(out, "paraview")
    for kind in ("particles", "bonds"):
        root = ElementTree.parse(os.path.join(paraview, f"{kind}.pvd")).getroot()
        sets = root.findall("./Collection/DataSet")
        listed = [d.get("file") for d in sets]
        on_disk = sorted(n for n in os.listdir(paraview) if n.startswith(kind + "_") and n.endswith(".vtp"))
        check(sorted(listed) == on_disk == [f"{kind}_{s:06d}.vtp" for s in snapshot_steps],
              f"{kind}.pvd lists {listed}, paraview/ has {on_disk}")
        times = [float(d.get("timestep")) for d in sets]
        check(times == sorted(times) and len(set(times)) == len(times), f"{kind}.pvd times {times}")
        for name in listed:
            piece = ElementTree.parse(os.path.join(paraview, name)).getroot().find("./PolyData/Piece")
            count = int(piece.get("NumberOfPoints" if kind == "particles" else "NumberOfLines"))
            check(count == (N_PARTICLES if kind == "particles" else N_BONDS), f"{name}: {count} points/lines")

    with open(os.path.join(out, "checkpoint.json")) as f:
        check(json.load(f)["step"] == steps, "checkpoint.json is not at the last step")


# ----------------------------------------------------------------------------------------- b
def expect_bad_input(work, scene, *needles):
    """Exit 2, the message names the file and every needle, and -o DIR (and its parent) stays absent."""
    out = os.path.join(work, "not_created", "run")
    _, stderr = anticrack("run", scene, "-o", out, expect=2)
    for needle in (scene, *needles):
        check(needle in stderr, f"the error message does not name {needle!r}:\n{stderr}")
    check(not os.path.exists(os.path.dirname(out)), f"{os.path.dirname(out)} was created for bad input")


@case
def scene_kinds(work):
    """A scene says its kind (`set Scene = ...`) and sets only the entries of its kind and variants:
    an empty scene is refused, a scene without `Scene` is read as the kind it suggests (with a
    note), subsection Campaign in a `dem` scene and an entry of another sample type are refused
    naming the kind or the variant (exit 2, nothing written); `params SCENE` lists what that
    scene can set."""
    expect_bad_input(work, write(os.path.join(work, "empty.prm"), "# no entries\n"), "sets nothing")
    mixed = open(os.path.join(PATHS.source, "scenes", "mixed_mode_clump.prm")).read()
    campaign = open(os.path.join(PATHS.source, "scenes", "shs_yield_surface.prm")).read()
    expect_bad_input(work, write(os.path.join(work, "foreign_campaign.prm"), edit_scene(campaign, {"Scene": "dem"})),
                     "Campaign/Loading angles [deg]", "belongs to scenes of kind campaign", "`dem` scene")
    expect_bad_input(work, write(os.path.join(work, "foreign_sample.prm"),
                                 edit_scene(mixed, {}, insert={"DEM/Sample": ["set Volume fraction = 0.3"]})),
                     "DEM/Sample/Volume fraction", "`sticky hard spheres`", "`simple cubic lattice`")
    unsaid = write(os.path.join(work, "unsaid.prm"), edit_scene(mixed, {}, remove=["Scene"]))
    _, stderr = anticrack("check", unsaid)
    check("note" in stderr and "`dem` scene" in stderr, f"no note on the inferred kind:\n{stderr}")
    listing, _ = anticrack("params", os.path.join(PATHS.source, "scenes", "shs_sample.prm"))
    check("set Volume fraction" in listing and "set Lattice size" not in listing
          and not re.search(r"^\s*subsection Campaign", listing, re.M),
          "`params SCENE` of a sticky-hard-sphere scene lists entries of another variant or kind")
    listing, _ = anticrack("params", "--scene", "campaign")
    check("subsection Campaign" in listing and "set Scene = campaign" in listing, "`params --scene campaign`")


@case
def bad_input_unknown_key(work):
    """An entry that is not declared (a typo of `Poisson ratio`)."""
    text = walls_scene(20, insert={"DEM/Material": ["set Poisson's ratio = 0.2"]})
    expect_bad_input(work, write(os.path.join(work, "unknown.prm"), text), "Poisson's ratio")


@case
def bad_input_out_of_range(work):
    """Values outside a pattern's range, and outside a range that only the validation knows."""
    for name, changes, needles in [
            ("damping", {"DEM/Integration/Local damping": "1.5"}, ["Local damping", "1.5"]),
            ("steps", {"DEM/Steps": "0"}, ["Steps"]),
            ("radius", {"DEM/Sample/Radius [m]": "1.2e-3"}, ["DEM/Sample/Radius [m]", "0.0012"]),
            ("active", {"DEM/Walls/z+/Active": "maybe"}, ["Active", "maybe"])]:
        expect_bad_input(work, write(os.path.join(work, f"{name}.prm"), walls_scene(20, **changes)), *needles)
    # ... and on the command line.
    out = os.path.join(work, "not_created", "run")
    _, stderr = anticrack("run", write(os.path.join(work, "ok.prm"), walls_scene(20)), "-o", out,
                          "--threads", -1, expect=2)
    check("--threads" in stderr, f"the error message does not name --threads:\n{stderr}")
    check(not os.path.exists(os.path.dirname(out)), "output created for --threads -1")


@case
def bad_input_missing_file(work):
    """A scene file that does not exist, and a scene whose snapshot file does not exist."""
    missing = os.path.join(work, "no_such_scene.prm")
    out = os.path.join(work, "not_created", "run")
    _, stderr = anticrack("run", missing, "-o", out, expect=2)
    check(missing in stderr, f"the error message does not name {missing}:\n{stderr}")
    check(not os.path.exists(os.path.dirname(out)), "output created for a missing scene file")
    _, stderr = anticrack("check", missing, expect=2)
    check(missing in stderr, f"`check`: the error message does not name {missing}:\n{stderr}")

    snapshot = os.path.join(work, "no_such_snapshot.h5")
    text = walls_scene(20, **{"DEM/Sample/Type": "snapshot"},
                       insert={"DEM/Sample": [f"set Snapshot file = {snapshot}"]})
    # The lattice's own entries do not belong to a snapshot sample.
    text = edit_scene(text, {}, remove=[f"DEM/Sample/{e}" for e in ("Lattice size", "Radius [m]", "Spacing [m]",
                                                                    "Origin [m]")])
    expect_bad_input(work, write(os.path.join(work, "snapshot.prm"), text), "DEM/Sample/Snapshot file", snapshot)
    write(snapshot, "not HDF5\n")
    expect_bad_input(work, write(os.path.join(work, "snapshot.prm"), text), "DEM/Sample/Snapshot file", snapshot)


@case
def bad_input_existing_run(work):
    """An earlier run is neither overwritten without --overwrite nor resumed with another model."""
    scene = write(os.path.join(work, "a.prm"), walls_scene(40, checkpoint=20, velocity="0.25"))
    out = os.path.join(work, "run")
    anticrack("run", scene, "-o", out, "--threads", 1)
    before = files_of(out)
    _, stderr = anticrack("run", scene, "-o", out, expect=2)
    check("--overwrite" in stderr and out in stderr, f"refusal of an existing run does not explain:\n{stderr}")
    other = write(os.path.join(work, "b.prm"), walls_scene(80, checkpoint=20, velocity="0.25",
                                                           **{"DEM/Material/Density [kg/m^3]": "2e4"}))
    _, stderr = anticrack("run", other, "-o", out, "--resume", expect=2)
    check("different scene" in stderr and other in stderr, f"resume with another model:\n{stderr}")
    check(files_of(out) == before, "a refused run changed the files of the earlier run")
    empty = os.path.join(work, "no_run_here")
    anticrack("run", scene, "-o", empty, "--resume", expect=2)
    check(not os.path.exists(empty), "--resume without a checkpoint created the output directory")


# ----------------------------------------------------------------------------------------- c
def resume_case(work, make_scene, steps):
    """Straight to `steps` vs half-way then --resume: final snapshot, history, summary identical."""
    half = steps // 2
    full = write(os.path.join(work, "full.prm"), make_scene(steps, checkpoint=half, snapshot=half))
    first = write(os.path.join(work, "first_half.prm"), make_scene(half, checkpoint=half, snapshot=half))
    straight, split = os.path.join(work, "straight"), os.path.join(work, "split")
    anticrack("run", full, "-o", straight, "--threads", 1)
    anticrack("run", first, "-o", split, "--threads", 1)
    stdout, _ = anticrack("run", full, "-o", split, "--resume", "--threads", 1)
    check(f"resuming at step {half}" in stdout, f"the resumed run does not say where it resumes:\n{stdout}")

    a, b = read_snapshot(snapshot_path(straight, steps)), read_snapshot(snapshot_path(split, steps))
    compare_exactly(a, b, "final snapshot, straight vs resumed", ["particles/position"])
    compare_exactly(a, b, "final snapshot, straight vs resumed")
    ha, hb = read_history(straight), read_history(split)
    compare_exactly({k: v for k, (v, _) in ha.items()}, {k: v for k, (v, _) in hb.items()},
                    "history.h5, straight vs resumed")
    sa, sb = (json.load(open(os.path.join(d, "summary.json"))) for d in (straight, split))
    for key in ("particles", "bonds", "intact_bonds", "broken_bonds_tension", "broken_bonds_shear", "steps",
                "final_time_s", "energies_J", "energy_balance_error_J"):
        check(sa["dem"][key] == sb["dem"][key], f"summary.json dem.{key}: {sa['dem'][key]} vs {sb['dem'][key]}")
    check(sb["resumed_from_step"] == half, f"summary.json resumed_from_step = {sb['resumed_from_step']}")
    check(sa["scene"]["resume_key_sha256"] == sb["scene"]["resume_key_sha256"], "resume keys differ")
    checkpoint_info = json.load(open(os.path.join(split, "checkpoint.json")))
    check(checkpoint_info["step"] == steps, "checkpoint.json after the resumed run is not at the last step")
    for kind in ("particles", "bonds"):
        listed = [d.get("file") for d in
                  ElementTree.parse(os.path.join(split, "paraview", f"{kind}.pvd")).getroot().iter("DataSet")]
        check(listed == [f"{kind}_{s:06d}.vtp" for s in (0, half, steps)], f"resumed {kind}.pvd lists {listed}")
    bonds = a["bonds/state"]
    return np.count_nonzero(bonds == 0), bonds.size


@case
def resume_walls(work):
    """Walls scene, 1100 steps; bonds break from step ~500 on, across the resume at step 550."""
    intact, total = resume_case(work, walls_scene, 1100)
    check(intact < total, "no bond broke: the case no longer exercises breakage across the resume")


@case
def resume_clump(work):
    """Clump scene, 1600 steps; breakage spans the resume at 800, the clump crosses x = 8 mm later."""
    intact, total = resume_case(work, clump_scene, 1600)
    check(0 < intact < total, "the clump case no longer breaks part of its bonds")


@case
def dem_interrupt(work):
    """Ctrl-C during a DEM run: it stops at the end of its chunk (<= 1000 steps), writes a checkpoint
    at that step whatever its interval, summary.json "interrupted" and exit 130; --resume starts
    from that step."""
    scene = write(os.path.join(work, "long.prm"), walls_scene(
        2_000_000, checkpoint=1_000_000, snapshot=1_000_000, history=1000, velocity="0.01",
        **{"Output/Progress interval [steps]": "5000"}))
    out = os.path.join(work, "run")
    progress_line = "/2000000 ("  # "step    5000/2000000 (  0.2%) ...": the first is at step 5000
    returncode, stderr = interrupt_at_line(["run", scene, "-o", out, "--threads", "1"], progress_line)
    check(returncode == 130, f"Ctrl-C: exit {returncode}, expected 130\n{stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    steps = summary.get("dem", {}).get("steps", 0)
    check(summary.get("status") == "interrupted" and 5000 <= steps < 1_000_000,
          f"Ctrl-C: summary.json status {summary.get('status')!r}, {steps} steps")
    with open(os.path.join(out, "checkpoint.json")) as f:
        checkpoint_step = json.load(f)["step"]
    check(checkpoint_step == steps, f"the checkpoint is at step {checkpoint_step}, the run stopped at {steps}")
    # Interrupted again at its first progress line (the handler is installed after the line that
    # says where it resumes, so that line is too early).
    returncode, stderr = interrupt_at_line(["run", scene, "-o", out, "--resume", "--threads", "1"], progress_line)
    with open(os.path.join(out, "summary.json")) as f:
        resumed = json.load(f)
    check(returncode == 130 and resumed.get("resumed_from_step") == steps and resumed["dem"]["steps"] > steps,
          f"the resume: exit {returncode}, resumed from {resumed.get('resumed_from_step')} (expected {steps}), "
          f"stopped at {resumed['dem']['steps']}\n{stderr}")


@case
def checkpoint_invariance(work):
    """Writing checkpoints is output: a run with checkpoints every 150 steps ends exactly where one
    without checkpoints does (an interrupted run resumes from a checkpoint at any step)."""
    for label, make_scene, steps in (("walls", walls_scene, 600), ("clump", clump_scene, 600)):
        runs = {}
        for checkpoint in (0, 150):
            runs[checkpoint] = os.path.join(work, f"{label}_{checkpoint}")
            scene = write(runs[checkpoint] + ".prm", make_scene(steps, checkpoint=checkpoint))
            anticrack("run", scene, "-o", runs[checkpoint], "--threads", 1)
        compare_exactly(read_snapshot(snapshot_path(runs[0], steps)), read_snapshot(snapshot_path(runs[150], steps)),
                        f"{label}: final snapshot without vs with checkpoints", ["particles/position"])


# ----------------------------------------------------------------------------------------- d
@case
def threads(work):
    """--threads 1 and --threads 2 give the same final state (energies up to summation order)."""
    for label, text, steps in (("walls", walls_scene(800, **{"DEM/Sample/Lattice size": "8, 6, 5",
                                                                "DEM/Domain/Upper corner [m]": "0.016, 0.012, 0.010"}),
                                 800),
                                ("clump", clump_scene(1000), 1000)):
        scene = write(os.path.join(work, f"{label}.prm"), text)
        runs = [os.path.join(work, f"{label}_{t}") for t in (1, 2)]
        for t, out in zip((1, 2), runs):
            stdout, _ = anticrack("run", scene, "-o", out, "--threads", t)
            check(f"; {t} threads" in stdout, f"--threads {t} not in effect:\n{stdout}")
        a, b = (read_snapshot(snapshot_path(out, steps)) for out in runs)
        compare_exactly(a, b, f"{label}: final snapshot, 1 vs 2 threads", ["particles/position"])
        compare_exactly(a, b, f"{label}: final snapshot, 1 vs 2 threads",
                        [k for k in a if k.startswith(("particles/", "bonds/"))])
        ha, hb = read_history(runs[0]), read_history(runs[1])
        for name, (x, unit) in ha.items():
            y = hb[name][0]
            if unit == "J":  # OpenMP reductions sum in another order
                scale = max(np.abs(x).max(), np.abs(y).max(), 1e-300)
                check(np.abs(x - y).max() <= 1e-9 * scale, f"{label}: history {name} differs beyond round-off")
            else:
                compare_exactly({name: x}, {name: y}, f"{label}: history, 1 vs 2 threads")


# ----------------------------------------------------------------------------------------- e
@case
def check_and_params(work):
    """`check` accepts every scenes/*.prm and the field and published studies' pipelines
    (scenes/field/field_psts.prm, its pits' own weak layers scenes/field/field_psts_own_weak_layer.prm,
    scenes/published/published_psts.prm, which name their scenes) and
    writes nothing; `params --format prm` is a valid scene."""
    names = sorted(n for n in os.listdir(os.path.join(PATHS.source, "scenes")) if n.endswith(".prm"))
    check({"uniaxial_compression.prm", "mixed_mode_clump.prm"} <= set(names), f"scenes/ holds {names}")
    # The field and published studies (scripts/field_scenes.py, scripts/published_scenes.py): each
    # pipeline checks each of its scenes.
    scenes = [os.path.join(PATHS.source, "scenes", n) for n in names] + [
        os.path.join(PATHS.source, "scenes", "field", "field_psts.prm"),
        os.path.join(PATHS.source, "scenes", "field", "field_psts_own_weak_layer.prm"),
        os.path.join(PATHS.source, "scenes", "published", "published_psts.prm")]
    cwd = os.path.join(work, "cwd")
    os.makedirs(cwd)
    scenes_before = files_of(os.path.join(PATHS.source, "scenes"))
    # `check` builds each DEM sample (it reports particles, bonds and the time step), so --threads
    # is exercised once, on the cheapest DEM scene, not on every one. The sticky-hard-sphere scenes'
    # samples take 20 000 Monte Carlo sweeps (about 35 s each for 2048 spheres, on one core): two
    # checks at a time.
    threaded = os.path.join(PATHS.source, "scenes", "mixed_mode_clump.prm")

    def check_one(job):
        scene, extra = job
        stdout, _ = anticrack("check", scene, *extra, cwd=cwd)
        check("The scene is valid." in stdout, f"`check {scene}` does not say the scene is valid:\n{stdout}")

    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        list(pool.map(check_one, [(scene, ("--threads", "1")) for scene in scenes] + [(threaded, ("--threads", "2"))]))
    check(os.listdir(cwd) == [], f"`check` wrote into the working directory: {os.listdir(cwd)}")
    check(files_of(os.path.join(PATHS.source, "scenes")) == scenes_before, "`check` changed scenes/")

    stdout, _ = anticrack("params", "--format", "prm")
    listing = write(os.path.join(work, "params.prm"), stdout)
    entries = len(re.findall(r"^\s*set ", stdout, re.M))
    check(entries > 50, f"`params --format prm` lists only {entries} entries")
    stdout, _ = anticrack("check", listing, cwd=cwd)
    check("The scene is valid." in stdout, f"`params --format prm` is not a valid scene:\n{stdout}")
    check(os.listdir(cwd) == [], "`check` of the parameter listing wrote files")
    stdout, _ = anticrack("params")
    check(stdout == open(listing).read(), "`params` without --format differs from --format prm")
    json.loads(anticrack("params", "--format", "json")[0])


# ----------------------------------------------------------------------------------------- f
# The tiny lattice pulled apart: one bond of strength sigma_c = 1 MPa per column of spheres, so the
# mean stress at which it breaks is sigma_c pi R^2 / (2R)^2 [Pa].
LATTICE_TENSION_STRENGTH = math.pi / 4 * 1e6


# A compaction test's rows come at the first control call past their due strain; the calls come
# every 4e-6 of strain at the start's time step (dem/lab/compaction_test.h), 5e-6 with the rounding
# to whole steps and the time step's re-evaluation.
CONTROL_STRAIN_SLACK = 5e-6


def tension_scene():
    """scenes/lattice_tension.prm on a 4 x 3 x 6 lattice, bottom layer fixed, top layer the clump,
    5000 steps, history every 10 steps, no other output."""
    return quiet_scene("lattice_tension.prm", 10, {
        "DEM/Steps": "5000",
        "DEM/Domain/Upper corner [m]": "0.008, 0.006, 0.012", "DEM/Sample/Lattice size": "4, 3, 6",
        "DEM/Boundary particles/Fix below [m]": "2e-3", "DEM/Boundary particles/Clump above [m]": "10e-3"})


@case
def lattice_tension_strength(work):
    """Physics end to end: a bonded simple-cubic lattice pulled by its top clump breaks at the mean
    stress sigma_c pi R^2 / (2R)^2 = pi/4 MPa (one bond of strength sigma_c = 1 MPa per column)."""
    scene = write(os.path.join(work, "tension.prm"), tension_scene())
    out = os.path.join(work, "out")
    anticrack("run", scene, "-o", out)
    history = read_history(out)
    base = history["base_normal_stress"][0]
    clump = history["clump_normal_stress"][0]
    peak = -base.min()
    expected = LATTICE_TENSION_STRENGTH
    # Tolerance 0.5 %: the load grows by 10 steps x 1e4 N/s x dt / 48 mm^2 = 1.7 kPa (0.2 %) between
    # history rows, and the base reaction lags the clump load by the lattice's quasi-static
    # response (the loading is 1e-3 of the bonds' wave time scale).
    check(abs(peak - expected) <= 0.005 * expected,
          f"peak tensile stress {peak:.6g} Pa, expected pi/4 MPa = {expected:.6g} Pa")
    before = base.argmin()
    check(abs(base[before] - clump[before]) <= 0.01 * expected,
          f"base reaction {base[before]:.6g} Pa and clump load {clump[before]:.6g} Pa differ at the peak")
    # The specimen's Love-Weber stress between the platens (docs/physics.md §1.5) is the mean stress
    # of the column, so on the ramp before the first bond breaks it lies between its two end
    # tractions, the base reaction and the clump load, which differ by up to 4 % while elastic waves
    # run (bracket widened by 0.5 % of the peak), and it is the base stress to 0.5 % in the median
    # (quasi-static). The diluted measure over every sphere gave 0.9 of it. At the peak itself
    # bonds are breaking and the base reaction lags the specimen.
    love = -history["love_stress_zz"][0]
    intact = history["broken_bonds_tension"][0] + history["broken_bonds_shear"][0] == 0
    ramp = intact & (base <= -0.1 * peak)
    check(ramp.sum() > 10, f"only {ramp.sum()} history rows of the ramp before the first break")
    outside = np.maximum(np.minimum(base, clump) - love, love - np.maximum(base, clump))[ramp]
    check(outside.max() <= 0.005 * peak,
          f"specimen Love-Weber stress outside the base/clump bracket by {outside.max():.4g} Pa before the first break")
    median = np.median(np.abs(love[ramp] - base[ramp]) / np.abs(base[ramp]))
    check(median <= 0.005, f"specimen Love-Weber stress differs from the base stress by {100 * median:.3g} % (median)")
    summary = json.load(open(os.path.join(out, "summary.json")))
    text = json.dumps(summary)
    check("broken" in text, "summary.json reports no broken bonds")
    tension = history["broken_bonds_tension"][0][-1]
    shear = history["broken_bonds_shear"][0][-1]
    check(tension > 0 and shear == 0, f"bonds broken in tension {tension}, in shear {shear}: expected tension only")


@case
def bench(work):
    """`bench dem` prints exactly one JSON line with the counts of a 4^3 periodic lattice."""
    stdout, _ = anticrack("bench", "dem", "--lattice", 4, "--steps", 20, "--threads", 1, cwd=work)
    lines = stdout.splitlines()
    check(len(lines) == 1, f"`bench dem` printed {len(lines)} lines on stdout:\n{stdout}")
    line = json.loads(lines[0])
    expected = {"particles": 64, "bonds": 192, "steps": 20, "threads": 1}
    for key, value in expected.items():
        check(line.get(key) == value, f"bench: {key} = {line.get(key)!r}, expected {value}")
    wall = line.get("wall_s")
    check(isinstance(wall, float) and wall > 0, f"bench: wall_s = {wall!r}")
    for key, count in (("particle_steps_per_s", 64), ("bond_steps_per_s", 192)):
        check(isinstance(line.get(key), float) and np.isclose(line[key], count * 20 / wall, rtol=1e-9),
              f"bench: {key} = {line.get(key)!r}, expected {count} x 20 / wall_s")
    check(os.listdir(work) == [], f"`bench dem` wrote files: {os.listdir(work)}")
    stdout, _ = anticrack("bench", "dem", "--lattice", 0, "--steps", 20, expect=2)
    check(stdout == "", f"`bench dem --lattice 0` printed on stdout: {stdout!r}")


# -------------------------------------------------------------------------------------- driver
# ------------------------------------------------------------------------- sample generators
def shs_scene(steps, **changes):
    """scenes/shs_sample.prm (N = 1024, phi = 0.3, tau = 0.2) with few steps and quiet outputs."""
    return quiet_scene("shs_sample.prm", 10, {"DEM/Steps": str(steps), **changes})


def ballistic_scene(rule, count, steps=20, **changes):
    """scenes/ballistic_weak_layer.prm shrunk to R = 1 mm in a 2 cm x 2 cm periodic box, no fixed
    base, no clump, no gravity, no campaign: thick enough (sticky 1200, rolling 2000 spheres) for a
    nonempty bulk slab."""
    return quiet_scene("ballistic_weak_layer.prm", 10, {
        "DEM/Steps": str(steps), "DEM/Domain/Upper corner [m]": "0.02, 0.02, 0.01",
        "DEM/Sample/Deposition rule": rule, "DEM/Sample/Particle count": str(count),
        "DEM/Sample/Radius [m]": "1e-3", "DEM/Boundary particles/Base thickness [mean radii]": "",
        "DEM/Boundary particles/Actuator thickness [mean radii]": "",
        "DEM/Boundary particles/Clump force rate [N/s]": "0", "DEM/Domain/Periodic axes": "x, y",
        "DEM/Integration/Gravity [m/s^2]": "0, 0, 0", "Scene": "dem",
        "DEM/Loading/Test": "clump force", "DEM/Loading/Adaptive rate": "false", "DEM/Loading/Stop strain": "0",
        "DEM/Sample/Actuator layer count": "0", **changes}, remove=["Campaign"])


@case
def generated_shs_sample(work):
    """A sticky-hard-sphere sample runs; its report in summary.json has z within 15 % of Percus-
    Yevick, and every contact of the sampler is a bond."""
    scene = write(os.path.join(work, "shs.prm"), shs_scene(20))
    stdout, _ = anticrack("check", scene, cwd=work)
    for needle in ("sticky hard spheres", "Percus-Yevick", "percolating", "acceptance"):
        check(needle in stdout, f"`check` does not print {needle!r}:\n{stdout}")
    out = os.path.join(work, "run")
    anticrack("run", scene, "-o", out)
    summary = json.load(open(os.path.join(out, "summary.json")))
    dem, sample = summary["dem"], summary["dem"]["sample"]
    check(sample["type"] == "sticky hard spheres", f"dem.sample = {sample}")
    check(dem["particles"] == 1024, f"{dem['particles']} particles, expected 1024")
    z, z_py = sample["coordination"], sample["percus_yevick_coordination"]
    check(abs(z - z_py) <= 0.15 * z_py, f"z = {z} is not within 15 % of the Percus-Yevick z = {z_py}")
    check(abs(z - 2 * sample["contacts"] / dem["particles"]) < 1e-12, f"z = {z} is not 2 contacts / N")
    check(dem["bonds"] == sample["contacts"] == sample["initial_bonds"],
          f"bonds {dem['bonds']} != contacts {sample['contacts']} (initial bonds {sample['initial_bonds']})")
    check(sample["stickiness"] == 0.2 and abs(sample["volume_fraction"] - 0.3) < 1e-12, f"dem.sample = {sample}")


@case
def generated_ballistic_fractions(work):
    """Ballistic deposits: bulk solid fraction 0.13-0.22 with the sticky rule, 0.53-0.60 rolling."""
    for rule, count, (low, high) in [("sticky", 1200, (0.13, 0.22)), ("rolling", 2000, (0.53, 0.60))]:
        scene = write(os.path.join(work, f"{rule}.prm"), ballistic_scene(rule, count))
        stdout, _ = anticrack("check", scene, cwd=work)
        check("bulk solid fraction" in stdout, f"`check` does not print the deposit's statistics:\n{stdout}")
        out = os.path.join(work, rule)
        anticrack("run", scene, "-o", out)
        dem = json.load(open(os.path.join(out, "summary.json")))["dem"]
        sample = dem["sample"]
        check(sample["type"] == "ballistic deposition" and sample["rule"] == rule, f"dem.sample = {sample}")
        check(sample["particles"] == count == dem["particles"], f"{rule}: {dem['particles']} particles")
        phi = sample["solid_fraction_bulk"]
        check(low <= phi <= high, f"{rule}: bulk solid fraction {phi} outside [{low}, {high}]")
        check(dem["bonds"] == sample["initial_bonds"] > 0, f"{rule}: {dem['bonds']} bonds")
        # Every deposited contact is bonded: 2 bonds / N = mean contacts over the whole deposit.
        check(abs(2 * dem["bonds"] / count - sample["mean_contacts_all"]) < 1e-9,
              f"{rule}: {dem['bonds']} bonds for mean_contacts_all = {sample['mean_contacts_all']}")


@case
def bad_input_generators(work):
    """Ballistic deposition without a periodic x axis; sticky hard spheres with tau < tau_min, and a
    sticky-hard-sphere sample that does not percolate."""
    scene = write(os.path.join(work, "not_periodic.prm"),
                  ballistic_scene("sticky", 100, **{"DEM/Domain/Periodic axes": "y"}))
    expect_bad_input(work, scene, "DEM/Domain/Periodic axes", "ballistic deposition")
    scene = write(os.path.join(work, "tau.prm"), shs_scene(20, **{"DEM/Sample/Stickiness": "0.05"}))
    expect_bad_input(work, scene, "DEM/Sample/Stickiness", "0.05", "tau_min(phi) = 0.0699")
    scene = write(os.path.join(work, "dilute.prm"), shs_scene(20, **{"DEM/Sample/Volume fraction": "0.1",
                                                                      "DEM/Sample/Stickiness": "1",
                                                                      "DEM/Sample/Sweeps": "400"}))
    expect_bad_input(work, scene, "does not percolate", "phi = 0.1")

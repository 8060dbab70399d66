"""End-to-end cases of tests/app (run by run_app_tests.py): campaigns: envelopes, workers and ranks, quasi-static checks, compaction and friction tests, lab tests, resume, samples."""
from harness import *  # noqa: F401,F403  (the checks, scene writers and runner)
from cases_dem import *  # noqa: F401,F403


# ------------------------------------------------------------------------------------ campaigns
def campaign_scene(angles, check_mode="none", microstructures="", **changes):
    """scenes/shs_yield_surface.prm shrunk 8-fold: N = 256 spheres in a 5 mm cube (the same sphere
    radius, 0.33 mm, as Ritter et al.'s (2020) 2048 in 1 cm), one realization, force rates scaled with the
    4x smaller cross-section (100 N/s fast, 6.25 N/s slow). A test takes ~50 000 steps. 2000 sweeps:
    a sample short of its equilibrium (z about 2.7 against 3.0; docs/work_precision.md), weaker than
    the scenes' by about a third, which tests of the machinery do not need; at 256 spheres its rise
    lies within the sampler's guard (DEM/Sample/Equilibration tolerance)."""
    text = open(os.path.join(PATHS.source, "scenes", "shs_yield_surface.prm")).read()
    return edit_scene(text, {
        "Campaign/Loading angles [deg]": angles, "Campaign/Realizations": "1",
        "Campaign/Quasi-static check": check_mode, "Campaign/Microstructures": microstructures,
        "DEM/Sample/Particle count": "256", "DEM/Sample/Box edge [m]": "0.005",
        "DEM/Sample/Sweeps": "2000", "DEM/Boundary particles/Clump force rate [N/s]": "100",
        "DEM/Loading/Slow rate fraction": "0.0625", "DEM/Loading/Lag tolerance": "0.1", **changes})


# The tiny pipelines' snow units: bonds of 200 kPa at the DEM's own ratio (1 GPa / 1 MPa, so the DEM
# runs as campaign_scene writes it) and the DEM's own grains (0.654 mm: lengths unchanged).
SNOW_UNITS = ["subsection Snow units", "  set Bond tensile strength [Pa] = 2e5", "  set Bond modulus [Pa] = 2e8",
              "  set Grain diameter [m] = 6.54e-4", "  set Particle density [kg/m^3] = 917", "end"]


def failure_points(directory):
    with h5py.File(os.path.join(directory, "campaign.h5"), "r") as f:
        return {name: f["failure_points"][name][()] for name in f["failure_points"]}


def compare_campaigns(a, b):
    """The failure points and every test's history of two campaign directories, bit for bit."""
    compare_exactly(failure_points(a), failure_points(b), "failure points")
    with h5py.File(os.path.join(a, "campaign.h5"), "r") as fa, h5py.File(os.path.join(b, "campaign.h5"), "r") as fb:
        for test_id in fa["tests"]:
            ha, hb = fa["tests"][test_id]["history"], fb["tests"][test_id]["history"]
            compare_exactly({k: ha[k][()] for k in ha}, {k: hb[k][()] for k in hb}, f"history of {test_id}")


@case
def campaign_grain_size_is_a_unit(work):
    """The snow units' length (coupling/snow_units.h): scaling every length of a DEM test by L leaves
    its stresses and strains as they were, so the grain size is a unit. The tiny campaign at 0 and 90
    degrees, and again in a box twice as large with the same 256 spheres (radii 2x) and the force
    rate 2x (forces scale by L^2, times by L): the failure stresses agree to 1e-3 of their size (the
    geometry is scaled exactly; what differs is round-off, about 6e-5 here, far below a length
    effect, which would be of order 1), and campaign.h5 records the spheres' mean diameter, 2x."""
    small = write(os.path.join(work, "small.prm"), campaign_scene("0, 90"))
    large = write(os.path.join(work, "large.prm"), campaign_scene("0, 90", **{
        "DEM/Sample/Box edge [m]": "0.01", "DEM/Boundary particles/Clump force rate [N/s]": "200"}))
    for scene in (small, large):
        anticrack("run", scene, "-o", os.path.join(work, os.path.basename(scene)[:-4]))
    a, b = (failure_points(os.path.join(work, name)) for name in ("small", "large"))
    check(np.all(a["status"] == b"completed") and np.all(b["status"] == b"completed"), f"status {a['status']} {b['status']}")
    for k in range(2):
        size = math.hypot(a["sigma"][k], a["tau"][k])
        for name in ("sigma", "tau", "p", "q"):
            check(abs(a[name][k] - b[name][k]) <= 1e-3 * size,
                  f"test {k}: {name} = {a[name][k]} Pa with the small spheres, {b[name][k]} Pa with the large")
    check(np.allclose(b["particle_diameter"], 2 * a["particle_diameter"], rtol=1e-12) and
          abs(a["particle_diameter"][0] - 6.54e-4) < 1e-6, f"diameters {a['particle_diameter']} {b['particle_diameter']}")


@case
def campaign_box_specimen(work):
    """A specimen that is a layer, not a cube (DEM/Sample/Box aspect ratios, dem/sample/sticky_hard_spheres.h):
    the tiny campaign at 0 and 90 degrees in a 2 : 2 : 1 box of the same height and sphere size (1024
    spheres, the force rate 4x with the 4x cross-section, so the same stress rate). Both samples are
    drawn with 20 000 sweeps: 2000 leave 1024 spheres short of their equilibrium, which the sampler's
    guard refuses, and a levelled box against an unlevelled cube would compare the samplers. Each test
    records its box (10 x 10 x 5 mm) and completes; its failure stresses are the cube's to within a
    factor 2 (a stress computed over a cube's face, or the box's edges swapped, would be off by 4; the
    lateral extent itself moves them by +12 % in compression and -24 % in shear here, one realization
    each, within the realizations' scatter: the extent study of docs/work_precision.md measures it
    properly)."""
    cube = write(os.path.join(work, "cube.prm"), campaign_scene("0, 90", **{"DEM/Sample/Sweeps": "20000"}))
    box = write(os.path.join(work, "box.prm"), campaign_scene("0, 90", **{
        "DEM/Sample/Particle count": "1024", "DEM/Sample/Box aspect ratios": "2, 2, 1",
        "DEM/Sample/Sweeps": "20000", "DEM/Boundary particles/Clump force rate [N/s]": "400"}))
    for scene in (cube, box):
        anticrack("run", scene, "-o", os.path.join(work, os.path.basename(scene)[:-4]))
    for test in ("m0_r0_psi000.0", "m0_r0_psi090.0"):
        with open(os.path.join(work, "box", "tests", test, "summary.json")) as f:
            lengths = json.load(f)["dem"]["sample"]["box_lengths_m"]
        check(np.allclose(lengths, [0.01, 0.01, 0.005], rtol=1e-9), f"{test}: box {lengths} m")
    a, b = (failure_points(os.path.join(work, name)) for name in ("cube", "box"))
    check(np.all(b["status"] == b"completed"), f"status {b['status']}")
    for k, name in ((0, "sigma"), (1, "tau")):
        ratio = b[name][k] / a[name][k]
        print(f"box over cube, {name} at test {k}: {ratio:.3f}")
        check(0.5 < ratio < 2, f"test {k}: {name} = {b[name][k]} Pa in the box, {a[name][k]} Pa in the cube")


@case
def campaign_envelope(work):
    """A campaign at 0, 90 and 180 degrees fails in compression, shear and tension: the envelope is
    closed, compressive strength > tensile and shear strengths (Ritter et al. 2020), and campaign.h5 holds
    every history and a failure-point table consistent with the tests' own summaries."""
    scene = write(os.path.join(work, "campaign.prm"), campaign_scene("0, 90, 180"))
    stdout, _ = anticrack("check", scene, cwd=work)
    check("Campaign" in stdout and "tests               3" in stdout, f"`check` does not describe the campaign:\n{stdout}")
    out = os.path.join(work, "run")
    anticrack("run", scene, "-o", out)
    summary = json.load(open(os.path.join(out, "summary.json")))
    check(summary["status"] == "completed", f"campaign status {summary['status']}")
    check_phases(summary, ["samples", "tests", "output"], "campaign", within_wall_time=True)
    check([t["status"] for t in summary["tests"]] == ["completed"] * 3, f"tests: {summary['tests']}")
    fp = failure_points(out)
    sigma, tau, p, q = fp["sigma"], fp["tau"], fp["p"], fp["q"]
    check(list(fp["loading_angle_deg"]) == [0, 90, 180], f"angles {fp['loading_angle_deg']}")
    # Compression: sigma > 0, little shear. Shear: tau > 0 dominates. Tension: sigma < 0, p < 0.
    check(sigma[0] > 0 and abs(tau[0]) < 0.2 * sigma[0], f"compression failure (sigma, tau) = ({sigma[0]}, {tau[0]})")
    check(tau[1] > 0 and tau[1] > abs(sigma[1]), f"shear failure (sigma, tau) = ({sigma[1]}, {tau[1]})")
    check(sigma[2] < 0 and p[2] < 0 and abs(tau[2]) < 0.2 * abs(sigma[2]),
          f"tension failure (sigma, tau, p) = ({sigma[2]}, {tau[2]}, {p[2]})")
    check(sigma[0] > max(-sigma[2], tau[1]), f"compressive strength {sigma[0]} not above tension {-sigma[2]} and shear {tau[1]}")
    check(np.all(q > 0) and np.all(np.isfinite(fp["love_stress"])), f"q = {q}")
    # Quasi-static loading as failure approaches (Ritter et al. 2020: I < 1e-4; the rate decisions of the
    # adaptive ramp cause short transients of a few 1e-4, hence the bound).
    check(np.all(fp["max_inertial_number"] < 1e-3), f"inertial numbers {fp['max_inertial_number']}")
    with h5py.File(os.path.join(out, "campaign.h5"), "r") as f:
        for test_id, row in zip(fp["test"], range(3)):
            test_id = test_id.decode() if isinstance(test_id, bytes) else test_id
            history = f["tests"][test_id]["history"]
            check("love_stress_zz" in history and history["time"].shape[0] > 10, f"/tests/{test_id}/history")
            own = json.load(open(os.path.join(out, "tests", test_id, "summary.json")))
            failure = own["dem"]["failure_analysis"]["failure"]
            check(failure["base_normal_stress_sigma_Pa"] == sigma[row] and failure["von_mises_q_Pa"] == q[row],
                  f"{test_id}: campaign.h5 and the test's summary.json disagree")


@case
def campaign_mpi_equals_serial(work):
    """The campaign on 2 MPI ranks (one thread each) writes exactly the failure points and the
    histories of the serial campaign on one thread."""
    scene = write(os.path.join(work, "campaign.prm"), campaign_scene("45, 135"))
    serial, parallel = os.path.join(work, "serial"), os.path.join(work, "mpi")
    anticrack("run", scene, "-o", serial, "--threads", "1")
    environment = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    result = subprocess.run(["mpirun", "--oversubscribe", "-np", "2", PATHS.anticrack, "run", scene, "-o", parallel,
                             "--threads", "1"], capture_output=True, text=True, env=environment, cwd=work)
    check(result.returncode == 0, f"mpirun exit {result.returncode}:\n{result.stdout}\n{result.stderr}")
    check("on 2 rank(s)" in result.stdout, f"the campaign did not run on 2 ranks:\n{result.stdout}")
    check("[rank 1]" in result.stdout, f"rank 1 ran no test:\n{result.stdout}")
    compare_campaigns(serial, parallel)
    summary = json.load(open(os.path.join(parallel, "summary.json")))
    check(summary["timing"]["ranks"] == 2, f"summary timing {summary['timing']}")


@case
def campaign_workers_equal_serial(work):
    """Without mpirun, the campaign runs its tests side by side in worker processes (`--threads 2`:
    two, one thread each) and writes exactly the failure points and histories of the tests run one
    after another (`--threads 1`); both workers ran tests, and summary.json says how many there were."""
    scene = write(os.path.join(work, "campaign.prm"), campaign_scene("0, 45, 135, 180"))
    serial, workers = os.path.join(work, "serial"), os.path.join(work, "workers")
    stdout, _ = anticrack("run", scene, "-o", serial, "--threads", "1")
    check("on 1 rank(s)" in stdout and "[worker" not in stdout, f"--threads 1 did not run in the process:\n{stdout}")
    stdout, _ = anticrack("run", scene, "-o", workers, "--threads", "2")
    check("on 2 worker process(es) x 1 thread(s)" in stdout, f"the campaign did not run on 2 workers:\n{stdout}")
    check("[worker 0] test" in stdout and "[worker 1] test" in stdout, f"a worker ran no test:\n{stdout}")
    compare_campaigns(serial, workers)
    summary = json.load(open(os.path.join(workers, "summary.json")))
    check(summary["timing"]["worker_processes"] == 2, f"summary timing {summary['timing']}")
    check_phases(summary, ["samples", "tests", "output"], "campaign on workers", within_wall_time=True)


@case
def campaign_quasi_static(work):
    """The adaptive ramp's failure stress is within the stated 2 % of a 4x slower run (compression
    and shear); summary.json and campaign.h5 report the check."""
    scene = write(os.path.join(work, "campaign.prm"), campaign_scene("0, 90", check_mode="first realization"))
    out = os.path.join(work, "run")
    anticrack("run", scene, "-o", out)
    summary = json.load(open(os.path.join(out, "summary.json")))
    qs = summary["quasi_static_check"]
    check(len(qs["pairs"]) == 2 and qs["tolerance"] == 0.02, f"quasi_static_check = {qs}")
    check(qs["all_within_tolerance"] and qs["largest_relative_difference"] <= 0.02, f"quasi_static_check = {qs}")
    with h5py.File(os.path.join(out, "campaign.h5"), "r") as f:
        difference = f["quasi_static_check"]["relative_difference"][()]
    check(np.allclose(sorted(difference), sorted(p["relative_difference"] for p in qs["pairs"])), f"{difference}")
    print(f"  quasi-static differences (p, q): {[round(100 * p['relative_difference'], 2) for p in qs['pairs']]} %")


@case
def campaign_compaction(work):
    """The displacement-controlled compaction test (Campaign/Compaction strain rate [1/s]; one per
    realization, psi = 0) through the peak, the collapse and the lock-up, calibrated:
    - its first peak is the strength the load-controlled psi = 0 test finds by Ritter et al.'s (2020)
      run-away criterion, within 15 % (two controls, two criteria, one material; on the pipeline's
      2048-sphere layer the three realizations give +7.0, +9.8 and +6.4 %, here +12.8 %: 256 spheres
      break a bond per 0.4 % of the strength);
    - the softening comes from it (summary.json softening.source), with a rate check against the 4x
      slower reference: the peak within 5 % (measured 0.8 %) and the strain at which the read curve
      carries half its peak again (on the densification line: where a slab of that load closes the
      layer) within 15 % (measured 6.4 %). At 2 /s: at 5 /s, the peak of this layer is 6 % above its
      1.25 /s reference, not quasi-static. The plateau's end alone (the densification onset, 21 %
      apart) and the residual ratio follow single force chains in a layer five grains thick: a
      perturbation as small as another staircase of the platen's acceleration moves them by 10 % or
      more (docs/work_precision.md), so they are reported, not checked;
    - the material file states its collapse (Material/Collapse) with a lock-up strain between the
      solid fraction's bounds: positive and below 1 - phi / phi_max = 0.53 for phi = 0.3 and
      random close packing 0.64;
    - the test's own summary.json records the same reading of its curve;
    - the curve is sampled in strain (Campaign/Compaction curve strain interval, here 1e-4): the
      test and its 4x slower reference, whose rows are 4x as many steps apart, both have a row every
      1e-4 of strain and at most one control call (4e-6) more, past the platen's acceleration,
      whatever Output/History interval [steps] says."""
    interval = 1e-4
    text = edit_scene(campaign_scene("0, 45, 90, 135, 180", check_mode="first realization"), {},
                      insert={"Campaign": ["set Compaction strain rate [1/s] = 2",
                                           "set Compaction final strain = 0.35",
                                           f"set Compaction curve strain interval = {interval}"]})
    scene = write(os.path.join(work, "campaign.prm"), text)
    stdout, _ = anticrack("check", scene)
    check("1 compaction test(s) at 2 1/s to strain 0.35, a row every 0.0001 of strain" in stdout,
          f"`check` does not describe the compaction test:\n{stdout}")
    out = os.path.join(work, "cal")
    anticrack("calibrate", scene, "-o", out, "--no-plots", "--bootstrap", "0")
    campaign = os.path.join(out, "campaign")
    test = json.load(open(os.path.join(campaign, "tests", "m0_r0_compaction", "summary.json")))
    analysis = test["dem"]["failure_analysis"]
    check(analysis["criterion"].startswith("first peak of the base normal stress"), f"criterion {analysis.get('criterion')}")
    sampled = [d for d in sorted(os.listdir(os.path.join(campaign, "tests"))) if d.startswith("m0_r0_compaction")]
    check(len(sampled) == 2, f"the compaction test and its slower reference: {sampled}")
    for name in sampled:
        with h5py.File(os.path.join(campaign, "tests", name, "history.h5"), "r") as f:
            strain, step = f["normal_strain"][()], f["step"][()]
        # Between the first row past the acceleration (1e-4 of strain) and the last (the stop).
        spacing = np.diff(strain[(strain > 2 * interval)][:-1])
        check(len(spacing) > 100 and spacing.min() >= interval * (1 - 1e-9)
              and spacing.max() <= interval + CONTROL_STRAIN_SLACK,
              f"{name}: rows {len(spacing)}, strain between rows {spacing.min():.3g}-{spacing.max():.3g}")
        print(f"  {name}: {len(strain)} rows, strain between rows {spacing.min():.3g}-{spacing.max():.3g}, "
              f"{int(np.median(np.diff(step)))} steps apart")
    with h5py.File(os.path.join(campaign, "campaign.h5"), "r") as f:
        check("compaction_tests" in f and list(f["compaction_tests"]["test"].asstr()[()]) == ["m0_r0_compaction"],
              "campaign.h5 has no /compaction_tests table")
        ids = list(f["failure_points"]["test"].asstr()[()])
        load_controlled = f["failure_points"]["sigma"][ids.index("m0_r0_psi000.0")]
        references = list(f["quasi_static_check"]["checks"].asstr()[()])
        check("m0_r0_compaction" in references, f"no slower reference of the compaction test: {references}")
    softening = json.load(open(os.path.join(out, "summary.json")))["calibration"]["microstructures"][0]["softening"]
    check(softening["source"] == "compaction tests", f"softening source {softening['source']}")
    reading = softening["compaction_tests"][0]
    peak = reading["peak_stress_Pa"]
    # The test's own summary.json records its curve's fit (so a standalone compaction run is read
    # without a calibration); only M (its own secant there, the campaign's here) and what follows
    # from it may differ: the peak, residual and lock-up do not depend on M.
    own = analysis["compaction_curve"]
    for key in ("peak_stress_Pa", "residual_stress_Pa", "lock_up_strain", "lock_up_modulus_Pa"):
        check(math.isclose(own[key], reading[key], rel_tol=1e-12), f"the test's summary.json {key} {own[key]}, "
              f"the calibration's {reading[key]}")
    check(abs(peak / load_controlled - 1) < 0.15,
          f"compaction peak {peak} Pa against the load-controlled failure {load_controlled} Pa")
    rate = softening["rate_checks"][0]
    check(abs(rate["peak_stress"]) < 0.05, f"rate check peak_stress: {rate['peak_stress']} (of {rate})")

    def strain_at_half_the_peak(name):
        c = json.load(open(os.path.join(campaign, "tests", name, "summary.json")))["dem"]["failure_analysis"][
            "compaction_curve"]
        return c["lock_up_strain"] + (c["peak_stress_Pa"] / 2 - c["residual_stress_Pa"]) / c["lock_up_modulus_Pa"]
    fast, slow = strain_at_half_the_peak("m0_r0_compaction"), strain_at_half_the_peak("m0_r0_compaction_slow4")
    check(abs(fast / slow - 1) < 0.15, f"rate check: strain at half the peak {fast} against {slow} 4x slower")
    material = read_material(os.path.join(out, "material.prm"))
    lock_up = float(material["Lock-up strain"])
    check(0 < lock_up < 0.53 and float(material["Lock-up modulus [Pa]"]) > 0, f"lock-up strain {lock_up}")
    check(0 < float(material["Residual strength ratio"]) < 1 and float(material["Hardening factor xi"]) > 0,
          "softening parameters")
    print(f"  compaction peak {peak:.4g} Pa vs load-controlled {load_controlled:.4g} Pa; R = "
          f"{float(material['Residual strength ratio']):.3f}, lock-up strain {lock_up:.3f}, w_f = "
          f"{reading['fracture_energy_density_J_per_m3']:.3g} J/m^3; rate check (4x slower): "
          + ", ".join(f"{k} {100 * rate[k]:+.1f} %" for k in ["peak_stress", "residual_ratio", "plastic_softening_strain",
                                                            "fracture_energy", "lock_up_strain"]))


@case
def campaign_friction(work):
    """The failed layer's friction measured in the DEM and handed over (Campaign/Friction normal
    stress [Pa]: one simple shear of the collapsed layer per realization):
    - `check` describes the friction test, and campaign.h5 holds it in /friction_tests with its
      steady sliding;
    - its layer collapsed before it slid: the steady normal stress exceeds the compaction test's peak
      (the calibration refuses a test that does not, naming the entry to raise: checked below);
    - the material file's Collapse/Friction coefficient is the test's steady shear over normal
      stress (one realization: the mean itself), the same in the calibration's summary.json;
    - an FE layer that uses the file takes it (its summary.json says so), and a scene that also
      types one is refused.
    - the friction test shears a sample of its own (Campaign/Friction sample: 200 spheres where the
      loading tests have 256), built beside the others, and campaign.h5 records its entries.
    The tiny layer's mu (200 spheres, five grains thick) is printed, not checked: its sliding is a
    stick-slip of single force chains, its value is measured on 15-grain layers (docs/calibration.md)."""
    # This small layer (shs_yield_surface.prm's) fails at about 40 kPa in compression: 120 kPa
    # crushes it.
    own_sample = "Particle count = 200, Box edge [m] = 0.0046"
    friction = ["set Friction normal stress [Pa] = 1.2e5", "set Friction shear velocity [m/s] = 0.025",
                "set Friction consolidation time [s] = 0.01", "set Friction final shear strain = 0.2",
                f"set Friction sample = {own_sample}"]
    text = edit_scene(campaign_scene("0, 45, 90, 135, 180"), {},
                      insert={"Campaign": ["set Compaction strain rate [1/s] = 2",
                                           "set Compaction final strain = 0.35", *friction]})
    scene = write(os.path.join(work, "campaign.prm"), text)
    stdout, _ = anticrack("check", scene)
    check("a friction test per realization: simple shear at 120000 Pa, 0.025 m/s, to shear strain 0.2" in stdout,
          f"`check` does not describe the friction test:\n{stdout}")
    check(f"on a sample of its own ({own_sample})" in stdout, f"`check` does not name the friction sample:\n{stdout}")
    out = os.path.join(work, "cal")
    stdout, _ = anticrack("calibrate", scene, "-o", out, "--no-plots", "--bootstrap", "0")
    check("sample m0_r0 (friction) built" in stdout, f"no friction sample was built:\n{stdout}")
    test = json.load(open(os.path.join(out, "campaign", "tests", "m0_r0_friction", "summary.json")))
    loading_test = json.load(open(os.path.join(out, "campaign", "tests", "m0_r0_psi000.0", "summary.json")))
    check(test["dem"]["particles"] == 200 and loading_test["dem"]["particles"] == 256,
          f"the friction test has {test['dem']['particles']} spheres, a loading test "
          f"{loading_test['dem']['particles']}: not their own samples")
    results = test["dem"]["lab_test"]["results"]
    with h5py.File(os.path.join(out, "campaign", "campaign.h5"), "r") as f:
        check(f.attrs["friction_sample"] == own_sample, f"campaign.h5 friction_sample = {f.attrs['friction_sample']}")
        table = f["friction_tests"]
        check(list(table["test"].asstr()[()]) == ["m0_r0_friction"], "campaign.h5 has no /friction_tests table")
        ratio = float(table["steady_stress_ratio"][0])
        sigma = float(table["steady_normal_stress"][0])
    check(ratio == results["steady_stress_ratio"] and sigma == results["steady_normal_stress_Pa"],
          f"/friction_tests {ratio}, {sigma} against the test's {results}")
    calibration = json.load(open(os.path.join(out, "summary.json")))["calibration"]["microstructures"][0]
    peak = max(calibration["softening"]["peak_stress_Pa"]["values"])
    check(sigma > peak, f"the friction test slid at {sigma} Pa, not above the compaction peak {peak} Pa")
    mu = calibration["friction"]["friction_coefficient"]["mean"]
    check(mu == ratio, f"calibration mu {mu}, the test's {ratio}")
    material_file = os.path.join(out, "material.prm")
    material = read_material(material_file)
    # The material file writes 6 significant digits.
    check(math.isclose(float(material["Friction coefficient"]), ratio, rel_tol=1e-5),
          f"material file mu {material.get('Friction coefficient')}, the test's {ratio}")
    print(f"  the collapsed layer slid at {sigma:.4g} Pa (compaction peak {peak:.4g} Pa): mu = {ratio:.3f}")

    # The FE layer takes the file's mu; typing one as well is refused. (The file's lock-up strain,
    # about 0.3 for this small layer, lies beyond the small-strain model's range: the copy the PST
    # uses has 0.1.)
    text_of_file = open(material_file).read()
    material_file = write(os.path.join(work, "material_for_the_pst.prm"),
                          re.sub(r"set Lock-up strain = [^\n]*", "set Lock-up strain = 0.1", text_of_file))
    collapse = ("Snowpack/Weak layer/Collapse height [m]", "Snowpack/Weak layer/Densification modulus [Pa]")
    fe = write(os.path.join(work, "pst.prm"), "set Scene = snowpack\n" + pst_scene(
        {"Analysis/Explicit/End time [s]": "0.005"}, material_file=material_file,
        remove=(*collapse, "Snowpack/Weak layer/Friction coefficient")))
    anticrack("run", fe, "-o", os.path.join(work, "pst"))
    taken = fem_summary(os.path.join(work, "pst"))["scene"]["weak_layer_friction"]
    check(taken["friction_coefficient"] == float(material["Friction coefficient"]) and
          taken["source"].startswith("material file"), f"the FE layer's friction {taken}")
    twice = write(os.path.join(work, "pst_twice.prm"), "set Scene = snowpack\n" + pst_scene(
        {"Analysis/Explicit/End time [s]": "0.005"}, material_file=material_file, remove=collapse))
    expect_bad_input(work, twice, "Friction coefficient must then be empty", "give it once")

    # A normal stress below the layer's strength shears the intact layer: refused, naming the entry.
    low = write(os.path.join(work, "campaign_low.prm"), text.replace("Friction normal stress [Pa] = 1.2e5",
                                                                      "Friction normal stress [Pa] = 2e4"))
    _, stderr = anticrack("calibrate", low, "-o", os.path.join(work, "cal_low"), "--no-plots", "--bootstrap", "0",
                          expect=2)
    check("Campaign/Friction normal stress [Pa]" in stderr and "sheared the intact layer" in stderr,
          f"no refusal of the intact layer's friction test:\n{stderr}")


def linear_fit_r2(x, y):
    """Slope, intercept and R^2 of the least-squares line (R^2 = 1 - SS_res / SS_tot)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    slope, intercept = np.polyfit(x, y, 1)
    residual = y - (slope * x + intercept)
    return slope, intercept, 1 - np.sum(residual ** 2) / np.sum((y - y.mean()) ** 2)


@case
def macro_linear_in_micro(work):
    """Eqs. 5-8 of Bobillier et al. (2020) on a small sweep in compression (one sample): the macroscopic strength is
    linear in the bond strength and the secant modulus linear in the particle modulus (E_c = E_bar),
    R^2 > 0.98 each, and both lines pass near the origin (the bonded network has no other scale)."""
    factors = [0.5, 1.0, 1.5, 2.0]
    strength = "; ".join(f"Bond/Tensile strength [Pa] = {f * 1e6:g}, Bond/Cohesion [Pa] = {f * 1e6:g}" for f in factors)
    modulus = "; ".join(f"Bond/Modulus [Pa] = {f * 1e9:g}, Material/Contact modulus [Pa] = {f * 1e9:g}" for f in factors)
    results = {}
    for name, variants in [("strength", strength), ("modulus", modulus)]:
        scene = write(os.path.join(work, f"{name}.prm"), campaign_scene("0", microstructures=variants))
        out = os.path.join(work, name)
        anticrack("run", scene, "-o", out)
        results[name] = failure_points(out)
    sigma = results["strength"]["sigma"]
    slope, intercept, r2 = linear_fit_r2(factors, sigma)
    check(r2 > 0.98, f"strength vs bond strength: R^2 = {r2} (sigma_f = {sigma})")
    check(abs(intercept) < 0.1 * sigma.max(), f"strength line intercept {intercept} Pa (sigma_f = {sigma})")
    modulus_values = results["modulus"]["secant_modulus"]
    slope, intercept, r2 = linear_fit_r2(factors, modulus_values)
    check(np.all(np.isfinite(modulus_values)), f"secant moduli {modulus_values}")
    check(r2 > 0.98, f"secant modulus vs particle modulus: R^2 = {r2} (E = {modulus_values})")
    check(abs(intercept) < 0.1 * modulus_values.max(), f"modulus line intercept {intercept} Pa (E = {modulus_values})")
    print(f"  strength: sigma_f = {np.round(sigma)} Pa, R^2 = {linear_fit_r2(factors, sigma)[2]:.5f}; "
          f"modulus: E = {np.round(modulus_values / 1e6, 3)} MPa, R^2 = {r2:.5f}")


@case
def tilted_gravity_equals_force_ramp(work):
    """Bobillier et al.'s (2020) actuator (density growing under gravity tilted by psi) and Ritter et al.'s (2020) clump force
    ramp load the same specimen at psi = 45 degrees: the failure point lies on the loading
    direction (tau / sigma within 10 % of tan psi) and its (p, q) within 10 % of the force ramp's.
    The two are not the same experiment: at failure the actuator weighs ~1000x its initial mass, so
    its inertia (m a, and the momentum the added mass brings, mdot v) shifts the base reaction by a
    few 100 Pa; measured: 7 % apart in (p, q), sigma 9 % above tau."""
    points = {}
    for test in ("clump force", "tilted gravity"):
        scene = write(os.path.join(work, f"{test.replace(' ', '_')}.prm"),
                      campaign_scene("45", **{"DEM/Loading/Test": test, "DEM/Integration/Gravity [m/s^2]": "0, 0, -9.81"}))
        out = os.path.join(work, test.replace(" ", "_"))
        anticrack("run", scene, "-o", out)
        points[test] = failure_points(out)
    a, b = points["clump force"], points["tilted gravity"]
    difference = math.hypot(a["p"][0] - b["p"][0], a["q"][0] - b["q"][0]) / math.hypot(a["p"][0], a["q"][0])
    check(difference < 0.10, f"(p, q) force ramp ({a['p'][0]}, {a['q'][0]}) vs tilted gravity ({b['p'][0]}, {b['q'][0]}): "
                             f"{100 * difference:.2f} %")
    for name, point in points.items():
        ratio = point["tau"][0] / point["sigma"][0]
        check(abs(ratio - 1) < 0.10, f"{name}: failure tau / sigma = {ratio}, loading direction tan 45 deg = 1")
    print(f"  (p, q) difference {100 * difference:.2f} %")


@case
def simple_shear_constant_normal_stress(work):
    """Mede et al.'s (2018) simple shear of the bonded specimen at sigma_n = 5 kPa (strain rate 1/s): after
    consolidation the base normal stress stays at sigma_n (mean over the shearing within 5 %) while
    the platen shears the specimen; the shear stress peaks (failure = peak tau) and the test ends
    at the requested shear strain."""
    text = campaign_scene("0", **{"DEM/Loading/Test": "simple shear",
                                  "DEM/Boundary particles/Clump force rate [N/s]": "0",
                                  "Output/History interval [steps]": "100"})
    # One run of the simple shear test: no campaign, none of the force ramp's entries.
    ramp = ["Adaptive rate", "Slow rate fraction", "Rate recovery factor", "Lag tolerance", "Stop strain"]
    text = edit_scene(text, {"Scene": "dem"}, remove=["Campaign"] + ["DEM/Loading/" + e for e in ramp],
                      insert={"DEM/Loading": [
        "set Normal stress [Pa] = 5e3", "set Shear velocity [m/s] = 0.005", "set Consolidation time [s] = 2e-3",
        "set Final shear strain = 0.03"]})
    scene = write(os.path.join(work, "shear.prm"), text)
    out = os.path.join(work, "run")
    anticrack("run", scene, "-o", out)
    summary = json.load(open(os.path.join(out, "summary.json")))
    check(summary["status"] == "completed" and "shear strain" in summary.get("message", ""), f"{summary.get('message')}")
    analysis = summary["dem"]["failure_analysis"]
    check("error" not in analysis and "peak of the base shear" in analysis["criterion"], f"{analysis}")
    h = {name: values for name, (values, unit) in read_history(out).items()}
    ux, height = h["clump_displacement_x"], 0.005
    shearing = ux > 1e-9
    check(shearing.sum() > 20, "no shearing stage recorded")
    sigma = h["base_normal_stress"][shearing]
    check(abs(sigma.mean() - 5e3) < 0.05 * 5e3, f"mean base normal stress {sigma.mean()} Pa while shearing, sigma_n = 5e3")
    tau = h["base_shear_stress"]
    peak = analysis["failure"]["base_shear_stress_tau_Pa"]
    check(peak == tau.max() and peak > 0, f"failure tau {peak} vs max {tau.max()}")
    check(ux[-1] / height >= 0.03 * 0.999, f"final shear strain {ux[-1] / height}")
    # The steady sliding the protocol reports (its control calls over the second half of the shear
    # strain) against the history's rows over the same half: the same mean stresses to the
    # sampling's difference (rows every 100 steps, control calls every 200: 5 %).
    results = summary["dem"]["lab_test"]["results"]
    steady = ux / height >= 0.5 * 0.03
    for name, column in (("steady_shear_stress_Pa", "base_shear_stress"), ("steady_normal_stress_Pa", "base_normal_stress")):
        rows = h[column][steady].mean()
        check(abs(results[name] - rows) <= 0.05 * abs(rows), f"{name} {results[name]} Pa, the rows' mean {rows} Pa")
    check(abs(results["steady_stress_ratio"] - results["steady_shear_stress_Pa"] / results["steady_normal_stress_Pa"]) < 1e-12,
          f"steady ratio {results}")


def run_lab_test(work, name, text):
    """Runs the scene `text` (written as WORK/NAME.prm) into WORK/NAME and checks that its lab test
    ended; returns its summary.json and the output folder."""
    scene = write(os.path.join(work, f"{name}.prm"), text)
    out = os.path.join(work, name)
    anticrack("run", scene, "-o", out)
    summary = json.load(open(os.path.join(out, "summary.json")))
    check(summary["dem"]["lab_test"]["finished"], f"{name}: the test did not end: {summary['dem']['lab_test']}")
    return summary, out


@case
def triaxial_small(work):
    """scenes/triaxial.prm shrunk to 300 spheres and 3 % axial strain: consolidation brings the six
    walls to sigma_c = 100 kPa, the lateral walls hold it within 3 % (mean, proportional servo)
    during axial loading, the test stops at the final strain, and the peak mobilised friction angle
    of the dense mu = 0.5 packing lies in 20-45 degrees (dense packings of mu = 0.5 spheres peak at
    ~25-40 degrees; a walled sample of ~7 diameters adds a few; measured 38)."""
    text = quiet_scene("triaxial.prm", 500, {
        "DEM/Domain/Upper corner [m]": "0.004, 0.004, 0.004",
        "DEM/Sample/Particle count": "300", "DEM/Loading/Axial strain rate [1/s]": "2",
        "DEM/Loading/Final axial strain": "0.03"})
    summary, out = run_lab_test(work, "triaxial", text)
    results = summary["dem"]["lab_test"]["results"]
    check(abs(results["axial_strain"] - 0.03) < 0.005, f"final axial strain {results['axial_strain']}")
    phi = results["peak_friction_angle_deg"]
    check(20 <= phi <= 45, f"peak friction angle {phi} deg")
    h = {name: values for name, (values, unit) in read_history(out).items()}
    loading = h["step"] > results["consolidation_end_step"]
    check(loading.sum() > 5, "no axial loading recorded")
    for wall in ("x-", "x+", "y-", "y+"):
        mean = h[f"wall_{wall}_normal_stress"][loading].mean()
        check(abs(mean - 1e5) < 0.03e5, f"wall {wall}: mean stress {mean} Pa while loading axially, sigma_c = 1e5")
    print(f"  peak friction angle {phi:.1f} deg, peak q {results['peak_deviator_stress_Pa']:.4g} Pa")


@case
def brazilian_disc_small(work):
    """scenes/brazilian_disc.prm shrunk to a 5 mm disc: the bonded disc splits, the force falls below
    half its peak (the test's end), and the splitting strength 2F/(pi D t) lies between 0.05 and 1
    times the bond tensile strength (bonds cover only part of the diametral plane; measured ~0.5)."""
    text = quiet_scene("brazilian_disc.prm", 100, {
        "DEM/Domain/Upper corner [m]": "0.005, 0.002, 0.005", "DEM/Sample/Particle count": "500",
        "DEM/Sample/Disc diameter [m]": "0.005", "DEM/Loading/Platen speed [m/s]": "2.5e-3", **SOFT_ROCK})
    summary, _ = run_lab_test(work, "brazilian", text)
    results = summary["dem"]["lab_test"]["results"]
    check(results["force_N"] < 0.5 * results["peak_force_N"] or results["strain"] >= 0.2, f"results {results}")
    ratio = results["brazilian_tensile_strength_Pa"] / 2e6
    check(0.05 <= ratio <= 1, f"splitting strength / bond strength = {ratio}")
    check(summary["dem"]["broken_bonds_tension"] > 0, "no bond broke in tension")
    print(f"  splitting strength / bond strength = {ratio:.3f}")


@case
def bedded_compression_weaker(work):
    """scenes/bedded_uniaxial_compression.prm shrunk to a 3 x 3 x 6 mm prism: weak bedding bands at 45
    degrees lower the uniaxial strength below that of the intact prism (Zhao & Feng 2022: the minimum of the
    U-shaped strength-inclination curve lies at 30-60 degrees), and bedding bands as strong as the
    rock change nothing (same peak force to the bit: the bands only change strengths)."""
    peaks = {}
    for name, changes in [("intact", {"DEM/Bedding/Enabled": "false"}),
                          ("same_strength", {"DEM/Bedding/Tensile strength [Pa]": "2e6", "DEM/Bedding/Cohesion [Pa]": "2e6"}),
                          ("bedded", {"DEM/Bedding/Tensile strength [Pa]": "2e5", "DEM/Bedding/Cohesion [Pa]": "2e5"})]:
        text = quiet_scene("bedded_uniaxial_compression.prm", 200, {
            "DEM/Domain/Upper corner [m]": "0.003, 0.003, 0.006", "DEM/Sample/Particle count": "450",
            **SOFT_ROCK, "DEM/Bedding/Spacing [m]": "1.5e-3", "DEM/Loading/Platen speed [m/s]": "3e-3", **changes})
        summary, _ = run_lab_test(work, name, text)
        peaks[name] = summary["dem"]["lab_test"]["results"]["peak_force_N"]
        if name != "intact":
            check(summary["dem"]["sample"]["bedding_bonds"] > 0, f"{name}: no bond in the bedding bands")
    check(peaks["same_strength"] == peaks["intact"], f"bands as strong as the rock changed the peak: {peaks}")
    check(peaks["bedded"] < 0.9 * peaks["intact"], f"weak bedding at 45 degrees did not lower the strength: {peaks}")
    print(f"  peak forces {peaks} N")


@case
def campaign_resume_and_bad_input(work):
    """--resume runs only the tests that have not completed and ends with the same campaign.h5 tables;
    a microstructure that names no DEM/Sample entry, and a campaign without a stop strain, are
    refused before anything is written (exit 2, message names the entry)."""
    scene = write(os.path.join(work, "campaign.prm"), campaign_scene("0, 180"))
    out = os.path.join(work, "run")
    anticrack("run", scene, "-o", out)
    first = failure_points(out)
    shutil.rmtree(os.path.join(out, "tests", "m0_r0_psi180.0"))
    stdout, _ = anticrack("run", scene, "-o", out, "--resume")
    check("m0_r0_psi000.0: completed earlier, skipped" in stdout, f"the completed test was not skipped:\n{stdout}")
    check("m0_r0_psi180.0: completed" in stdout, f"the missing test did not run:\n{stdout}")
    compare_exactly(first, failure_points(out), "failure points after --resume")
    stdout, stderr = anticrack("run", scene, "-o", out, expect=2)
    check("--resume" in stderr and "--overwrite" in stderr, f"reusing a campaign directory: {stderr}")

    bad = write(os.path.join(work, "bad.prm"), campaign_scene("0", microstructures="Volume fractoin = 0.3"))
    expect_bad_input(work, bad, "Campaign/Microstructures", "Volume fractoin")
    bad = write(os.path.join(work, "no_stop.prm"), campaign_scene("0", **{"DEM/Loading/Stop strain": "0"}))
    expect_bad_input(work, bad, "DEM/Loading/Stop strain", "campaign")



@case
def compaction_sampling_is_not_the_test(work):
    """The compaction test's curve is sampled in strain (DEM/Loading/Curve strain interval), and its
    control calls come every 4e-6 of strain whatever that interval (dem/lab/compaction_test.h): the
    same 256-sphere layer compacted to 1 % strain, sampled every 1e-4 and every 2.5e-5, is one and
    the same test. Every row the two histories share (the same step) is equal bit for bit, both end
    at the same step, and the rows lie at least their interval apart in strain and at most one
    control call (4e-6, with the time step's rounding: CONTROL_STRAIN_SLACK) more. Control calls that
    followed the interval would step the platen's acceleration differently and part the two runs
    (docs/work_precision.md measured the post-peak branch moving by up to 10 % then)."""
    text = open(os.path.join(PATHS.source, "scenes", "weak_layer_compaction_profile.prm")).read()
    histories = {}
    for interval in ("1e-4", "2.5e-5"):
        scene = write(os.path.join(work, f"compaction_{interval}.prm"), edit_scene(text, {
            "DEM/Sample/Particle count": "256", "DEM/Sample/Box edge [m]": "0.005", "DEM/Sample/Sweeps": "2000",
            "DEM/Loading/Stop strain": "0.01", "DEM/Loading/Curve strain interval": interval,
            "Output/Snapshot interval [steps]": "0"}))
        out = os.path.join(work, interval)
        anticrack("run", scene, "-o", out, "--threads", "1")
        with h5py.File(os.path.join(out, "history.h5"), "r") as f:
            histories[interval] = {name: f[name][()] for name in
                                   ("step", "normal_strain", "base_normal_stress", "clump_displacement_z")}
        h = histories[interval]
        spacing = np.diff(h["normal_strain"][h["normal_strain"] > 2e-4][:-1])
        check(len(spacing) > 20 and spacing.min() >= float(interval) * (1 - 1e-9)
              and spacing.max() <= float(interval) + CONTROL_STRAIN_SLACK,
              f"interval {interval}: strain between rows {spacing.min():.3g}-{spacing.max():.3g}")
    coarse, fine = histories["1e-4"], histories["2.5e-5"]
    check(coarse["step"][-1] == fine["step"][-1], f"the runs end at steps {coarse['step'][-1]} and {fine['step'][-1]}")
    shared = np.intersect1d(coarse["step"], fine["step"])
    check(len(shared) >= 10, f"only {len(shared)} rows at the same steps")
    for name in ("normal_strain", "base_normal_stress", "clump_displacement_z"):
        a = coarse[name][np.isin(coarse["step"], shared)]
        b = fine[name][np.isin(fine["step"], shared)]
        check(np.array_equal(a, b), f"{name} differs between the two samplings at the shared steps")
    print(f"  rows {len(coarse['step'])} and {len(fine['step'])}, {len(shared)} at shared steps, equal; "
          f"peak {coarse['base_normal_stress'].max():.4g} and {fine['base_normal_stress'].max():.4g} Pa")


@case
def output_directory_lock(work):
    """Two runs into one output directory (util/output_lock.h): while another process holds the
    directory's lock (here this test, with flock(2) as anticrack takes it), a run and a calibration
    into it exit 2 naming the directory and write nothing into it; released, the run goes ahead. A
    refused scene leaves no directory behind that the lock created (with its missing parents)."""
    import fcntl
    scene = write(os.path.join(work, "tension.prm"), tension_scene())
    out = os.path.join(work, "out")
    os.makedirs(out)
    holder = os.open(out, os.O_RDONLY)
    fcntl.flock(holder, fcntl.LOCK_EX | fcntl.LOCK_NB)
    try:
        for command in (["run", scene, "-o", out], ["calibrate", scene, "-o", out, "--no-plots"]):
            _, stderr = anticrack(*command, expect=2)
            check(f"output directory {out}: another anticrack process is writing into it" in stderr,
                  f"`{command[0]}` into a locked directory:\n{stderr}")
            check(os.listdir(out) == [], f"`{command[0]}` wrote into the locked directory: {os.listdir(out)}")
    finally:
        os.close(holder)
    anticrack("run", scene, "-o", out)
    check(os.path.exists(os.path.join(out, "summary.json")), "the run after the lock was released wrote nothing")
    bad = write(os.path.join(work, "bad.prm"), edit_scene(tension_scene(), {"DEM/Steps": "-1"}))
    anticrack("run", bad, "-o", os.path.join(work, "new", "deeper"), expect=2)
    check(not os.path.exists(os.path.join(work, "new")), "a refused scene left the directory the lock created")


@case
def campaign_without_load_path(work):
    """A realization whose bonds do not connect base and clump (256 spheres at z = 2.2: seed 3 of
    seeds 1-12, found by `anticrack check`) is recorded as `no load path` and the campaign goes on:
    exit 0, the other realization's test completed, the test's summary.json and campaign.h5 say why,
    --resume records it again; the same sample as a single run is refused as bad input."""
    thin = {"DEM/Sample/Target coordination number": "2.2"}
    scene = write(os.path.join(work, "campaign.prm"),
                  campaign_scene("0", **thin, **{"DEM/Random seed": "2", "Campaign/Realizations": "2"}))
    stdout, _ = anticrack("check", scene, cwd=work)
    check("no load path" not in stdout, f"realization 0 (seed 2) has no load path:\n{stdout}")
    out = os.path.join(work, "run")
    stdout, _ = anticrack("run", scene, "-o", out)
    summary = json.load(open(os.path.join(out, "summary.json")))
    status = {t["test"]: t for t in summary["tests"]}
    check(summary["status"] == "completed", f"campaign status {summary['status']}")
    check(status["m0_r0_psi000.0"]["status"] == "completed", f"realization 0: {status['m0_r0_psi000.0']}")
    lost = status["m0_r1_psi000.0"]
    check(lost["status"] == "no load path" and "DEM/Random seed = 3" in lost["message"]
          and "do not connect the fixed base" in lost["message"], f"realization 1: {lost}")
    check(summary["tests_without_load_path"] == ["m0_r1_psi000.0"], f"{summary['tests_without_load_path']}")
    check("m0_r1_psi000.0: no load path" in stdout and "1 test(s) without a load path" in stdout,
          f"the console does not name the test:\n{stdout}")
    with h5py.File(os.path.join(out, "campaign.h5"), "r") as f:
        recorded = f["tests"]["m0_r1_psi000.0"].attrs["status"]
        recorded = recorded.decode() if isinstance(recorded, bytes) else recorded
        check(recorded == "no load path", f"campaign.h5 status {recorded!r}")
    stdout, _ = anticrack("run", scene, "-o", out, "--resume")
    check("m0_r0_psi000.0: completed earlier, skipped" in stdout and "m0_r1_psi000.0: no load path" in stdout,
          f"--resume:\n{stdout}")
    # the same sample as one run: bad input, naming the seed (exit 2, nothing written)
    single = write(os.path.join(work, "single.prm"),
                   edit_scene(campaign_scene("0", **thin, **{"DEM/Random seed": "3", "Scene": "dem"}), {},
                              remove=["Campaign"]))
    expect_bad_input(work, single, "DEM/Random seed = 3", "do not connect the fixed base")


@case
def campaign_samples_before_tests(work):
    """Every sample is built before any test runs: a campaign whose second microstructure's sample
    is refused (1024 spheres at 2000 sweeps, not levelled off, as in tests/bad_input) stops before
    the first microstructure's test, on one thread too, where that test used to run first; exit 2,
    nothing written. Both samples are announced, the refused one named."""
    scene = write(os.path.join(work, "campaign.prm"),
                  campaign_scene("0", microstructures="Sweeps = 2000; Particle count = 1024, Sweeps = 2000"))
    out = os.path.join(work, "not_created", "run")
    stdout, stderr = anticrack("run", scene, "-o", out, "--threads", "1", expect=2)
    check("has not levelled off after 2000 sweeps" in stderr, f"the refusal does not say why:\n{stderr}")
    check("2 sample(s) first" in stdout and "sample m0_r0 built" in stdout, f"the samples are not announced:\n{stdout}")
    check(" test 1/" not in stdout, f"a test ran before the samples were all built:\n{stdout}")
    check(not os.path.exists(os.path.dirname(out)), f"{os.path.dirname(out)} was created for bad input")

"""End-to-end cases of tests/app (run by run_app_tests.py): calibration: synthetic campaigns with known answers, scaling laws, degenerate input, the calibration scene, the FE material point."""
from harness import *  # noqa: F401,F403  (the checks, scene writers and runner)
from cases_dem import *  # noqa: F401,F403
from cases_campaign import *  # noqa: F401,F403


# ----------------------------------------------------------------------------------- calibration
# A synthetic campaign.h5 (format 2, the layout dem/campaign/campaign.cpp writes) whose answers are known:
# failure points on cohesive Cam-Clay ellipses in both planes with 2 % radial noise, associative
# flow angles, and linear-elastic-brittle histories of a laterally confined specimen with
# E = 1.5 MPa, nu = 0.25 (K = 1 MPa, G = 0.6 MPa, constrained modulus K + 4G/3 = 1.8 MPa).
# fe_surface: (p0, beta, M) of the FE point whose failures on the tests' paths (periodic sides) are the
# synthetic (sigma, tau); p_q: the surface of the synthetic Love-Weber (p, q) columns.
SYNTHETIC = {"fe_surface": (12e3, 0.45, 2.0), "p_q": (12e3, 0.5, 1.1), "E": 1.5e6, "nu": 0.25,
             "residual_ratio": 0.25, "peak_strain": 3e-3, "softening_strain": 5e-3}


def cam_clay_radius(angle, p0, beta, M):
    a = (1 + 2 * beta) * math.sin(angle) ** 2 + M * M * math.cos(angle) ** 2
    b = M * M * p0 * (beta - 1) * math.cos(angle)
    c = -M * M * beta * p0 * p0
    return (-b + math.sqrt(b * b - 4 * a * c)) / (2 * a)


def path_failure(psi, surface, nu):
    """The base stresses (sigma, tau) at which the FE point with the invariant-plane surface (p0, beta,
    M) and Poisson's ratio nu fails on the ray psi under periodic sides (no lateral strain, lateral
    stresses nu/(1 - nu) sigma), and the slope d tau/d sigma of the surface's image there."""
    k = nu / (1 - nu)
    c = (1 + 2 * k) / 3
    p_hat = c * math.cos(psi)
    q_hat = math.sqrt((1 - k) ** 2 * math.cos(psi) ** 2 + 3 * math.sin(psi) ** 2)
    radius = cam_clay_radius(math.atan2(q_hat, p_hat), *surface) / math.hypot(p_hat, q_hat)
    sigma, tau = radius * math.cos(psi), radius * math.sin(psi)
    # The image y(sigma, tau) = (1 + 2 beta)((1 - k)^2 sigma^2 + 3 tau^2) + M^2 (c sigma + beta p0)(c sigma - p0).
    p0, beta, M = surface
    y_sigma = 2 * (1 + 2 * beta) * (1 - k) ** 2 * sigma + M * M * c * (2 * c * sigma + (beta - 1) * p0)
    y_tau = 6 * (1 + 2 * beta) * tau
    return sigma, tau, -y_sigma / max(y_tau, 1e-9)


def write_synthetic_campaign(path, angles, realizations=3, version="3", noise=0.02, seed=7, microstructures=None):
    """`microstructures`: list of dicts with phi, z, bond (tensile strength), particle_modulus, E
    (the continuum's Young's modulus) and either sigma_tau (the surface in that plane) or fe_surface
    (the FE point's, failing on the tests' paths); default: one with SYNTHETIC's values."""
    rng = np.random.default_rng(seed)
    nu = SYNTHETIC["nu"]
    microstructures = microstructures or [{"phi": 0.3, "z": 2.8, "bond": 1e6, "particle_modulus": 1e9,
                                           "E": SYNTHETIC["E"], "fe_surface": SYNTHETIC["fe_surface"]}]
    rows = []
    for m, micro in enumerate(microstructures):
        E = micro["E"]
        K, G = E / (3 * (1 - 2 * nu)), E / (2 * (1 + nu))
        for r in range(realizations):
            for psi in angles:
                rows.append(synthetic_row(rng, m, r, psi, micro, K + 4 * G / 3, G, noise))
    write_campaign_file(path, rows, microstructures, version)
    return path


def synthetic_row(rng, m, r, psi, micro, constrained, G, noise):
    """One test of the synthetic campaign: failure point, flow angle and history."""
    psi_rad = math.radians(psi)
    row = {"test": f"m{m}_r{r}_psi{psi:05.1f}", "microstructure": m, "realization": r, "loading_angle_deg": psi,
           "solid_fraction": micro["phi"], "coordination": micro["z"], "secant_modulus": constrained}
    # (sigma, tau): the failure point lies on the loading ray; (p, q): on the ray of a polar angle
    # spread over 30-130 degrees (the Love stress of the DEM never reaches q = 0).
    if "fe_surface" in micro:
        sigma, tau, slope = path_failure(psi_rad, micro["fe_surface"], SYNTHETIC["nu"])
    else:
        s0, beta, M = micro["sigma_tau"]
        radius = cam_clay_radius(psi_rad, s0, beta, M)
        sigma, tau = radius * math.cos(psi_rad), radius * math.sin(psi_rad)
        slope = -M * M * (2 * sigma + (beta - 1) * s0) / (2 * (1 + 2 * beta) * max(tau, 1e-9))
    scatter = 1 + noise * rng.standard_normal()
    row["sigma"], row["tau"] = sigma * scatter, tau * scatter
    angle_pq = math.radians(30 + psi * 100 / 180)
    radius = cam_clay_radius(angle_pq, *SYNTHETIC["p_q"]) * (1 + noise * rng.standard_normal())
    row["p"], row["q"] = radius * math.cos(angle_pq), radius * math.sin(angle_pq)
    # Associative flow (normal to the (sigma, tau) surface): tan(theta) = d tau / d sigma.
    row["flow_angle_deg"] = math.degrees(math.atan(slope)) + 2 * rng.standard_normal()
    # History: linear elastic to the peak at `peak_strain`, a linear drop to R times the peak over
    # `softening_strain`, then the residual stress to 2.5 % (the last half of the post-peak samples,
    # where the calibration takes the residual stress, lies on it); psi = 0 and 90 carry the moduli.
    strain = np.linspace(0, 0.025, 251)
    peak_strain, drop, R = SYNTHETIC["peak_strain"], SYNTHETIC["softening_strain"], SYNTHETIC["residual_ratio"]
    shape = np.where(strain <= peak_strain, strain / peak_strain,
                     np.maximum(R, 1 - (1 - R) * (strain - peak_strain) / drop))
    zeros = np.zeros_like(strain)
    sigma = constrained * peak_strain * shape if psi == 0 else row["sigma"] * shape
    tau = G * peak_strain * shape if psi == 90 else row["tau"] * shape
    nu = SYNTHETIC["nu"]
    # The histories store u / H0 over the whole specimen (H0 = 10 mm); the layer between base and
    # clump (h = 8 mm) carries the strain: u / H0 = strain h / H0.
    stored = strain * 0.008 / 0.01
    row["history"] = {
        "normal_strain": stored if psi != 90 else zeros, "shear_strain": zeros if psi != 90 else stored,
        "base_normal_stress": sigma, "base_shear_stress": tau,
        # Uniaxial strain: lateral stress K0 sigma_zz with K0 = nu / (1 - nu); tension positive.
        "love_stress_zz": -sigma, "love_stress_xx": -nu / (1 - nu) * sigma, "love_stress_yy": -nu / (1 - nu) * sigma}
    return row


def write_campaign_file(path, rows, microstructures, version):
    """campaign.h5 in the layout dem/campaign/campaign.cpp writes (format `version`)."""
    with h5py.File(path, "w") as f:
        for key, value in {"format": "anticrack-campaign", "format_version": version, "scene_file": "synthetic.prm",
                           "scene_file_sha256": "0" * 64, "parameters_sha256": "0" * 64,
                           "anticrack_version": "test", "microstructures": ""}.items():
            f.attrs[key] = value
        if version != "1":
            g = f.create_group("microstructures")
            g["label"] = np.array([f"synthetic {m}" for m in range(len(microstructures))], dtype=h5py.string_dtype())
            g["particle_modulus"] = g["contact_modulus"] = g["bond_modulus"] = \
                np.array([m["particle_modulus"] for m in microstructures])
            g["bond_tensile_strength"] = g["bond_cohesion"] = np.array([m["bond"] for m in microstructures])
            g["particle_density"] = np.full(len(microstructures), 917.0)
            g["laterally_periodic"] = np.ones(len(microstructures))
        fp = f.create_group("failure_points")
        n = len(rows)
        fp["test"] = np.array([row["test"] for row in rows], dtype=h5py.string_dtype())
        fp["status"] = np.array(["completed"] * n, dtype=h5py.string_dtype())
        for name in ["microstructure", "realization", "loading_angle_deg", "sigma", "tau", "p", "q", "flow_angle_deg",
                     "solid_fraction", "coordination", "secant_modulus"]:
            fp[name] = np.array([row[name] for row in rows], dtype=float)
        for name, value in {"softening_ratio": SYNTHETIC["residual_ratio"], "specimen_height": 0.01,
                            "layer_thickness": 0.008, "bonds": 1000.0,
                            "peak_q": 0.0, "max_inertial_number": 1e-4, "failure_time": 0.0, "failure_step": 0.0}.items():
            fp[name] = np.full(n, value)
        fp["love_stress"] = np.zeros((n, 3, 3))
        tests = f.create_group("tests")
        for row in rows:
            h = tests.create_group(row["test"]).create_group("history")
            for name, values in row["history"].items():
                h[name] = values


ANGLES = [0, 22.5, 45, 67.5, 90, 112.5, 135, 157.5, 180]


@case
def calibrate_synthetic(work):
    """`calibrate` on a synthetic campaign recovers the Cam-Clay surface within its intervals, E and
    nu exactly, xi by its formula; writes material.prm (read back), calibration.h5, summary.json and
    the plots; a second call is refused without --overwrite."""
    campaign = write_synthetic_campaign(os.path.join(work, "campaign.h5"), ANGLES)
    out = os.path.join(work, "calibration")
    stdout, _ = anticrack("calibrate", campaign, "-o", out, "--bootstrap", "200")
    check("p0 =" in stdout, f"no result line:\n{stdout}")
    material = read_material(os.path.join(out, "material.prm"))
    truth = dict(zip(["Compressive strength p0 [Pa]", "Tensile strength ratio beta", "Critical state slope M"],
                     SYNTHETIC["fe_surface"]))
    for name, value in truth.items():
        fitted = float(material[name])
        lower, upper = map(float, material[name.replace(" [Pa]", "") + " interval" + (" [Pa]" if "[Pa]" in name else "")].split(","))
        check(lower <= value <= upper and lower <= fitted <= upper,
              f"{name}: truth {value}, fit {fitted}, interval [{lower}, {upper}]")
    # Secant moduli of exactly linear curves: E and nu come back to the printed digits (%.6g).
    check(abs(float(material["Young's modulus [Pa]"]) / SYNTHETIC["E"] - 1) < 1e-5, f"E = {material['Young' + chr(39) + 's modulus [Pa]']}")
    check(abs(float(material["Poisson's ratio"]) - SYNTHETIC["nu"]) < 1e-5, f"nu = {material['Poisson' + chr(39) + 's ratio']}")
    check(abs(float(material["Residual strength ratio"]) - SYNTHETIC["residual_ratio"]) < 1e-9, "residual ratio")
    # xi = [asinh(p0/K) - asinh(R p0/K)] / plastic strain, plastic = drop strain + the elastic strain
    # the falling stress gives back, (sigma_p - sigma_r)/M = (1 - R) x the peak strain.
    p0, K = float(material["Compressive strength p0 [Pa]"]), SYNTHETIC["E"] / (3 * (1 - 2 * SYNTHETIC["nu"]))
    R = SYNTHETIC["residual_ratio"]
    plastic = SYNTHETIC["softening_strain"] + (1 - R) * SYNTHETIC["peak_strain"]
    xi = (math.asinh(p0 / K) - math.asinh(R * p0 / K)) / plastic
    check(abs(float(material["Hardening factor xi"]) / xi - 1) < 1e-4, f"xi = {material['Hardening factor xi']}, expected {xi}")
    check(material["Campaign sha256"] == hashlib.sha256(open(campaign, "rb").read()).hexdigest(), "campaign hash")
    summary = json.load(open(os.path.join(out, "summary.json")))
    check_phases(summary, ["read campaign", "fits and intervals", "output"], "calibration", within_wall_time=True)
    m0 = summary["calibration"]["microstructures"][0]
    check(m0["sigma_tau_plane"]["best_by_aicc"] == "cohesive_cam_clay",
          f"Cam-Clay data, best model {m0['sigma_tau_plane']['best_by_aicc']}")
    flow = m0["flow_rule"]
    check(flow["rms_deviation_from_associative_deg"] < 10 and flow["slope_consistent_with_associative"],
          f"associative synthetic flow judged non-associative: {flow}")
    check(abs(flow["transition_angle_observed_deg"] - flow["transition_angle_predicted_deg"]) < 12,
          f"transition angles {flow}")
    with h5py.File(os.path.join(out, "calibration.h5"), "r") as f:
        check(f.attrs["fe_plane"] == "p_q_path", "fe_plane")
        fit = f["microstructures/m0/fits/p_q_path/cohesive_cam_clay"]
        check(fit.attrs["has_bootstrap"] == 1 and fit["bootstrap_samples"].shape[1] == 3, "bootstrap samples")
        check(len(f["microstructures/m0/curves"]) == len(ANGLES) * 3, "stress-strain curves")
    for png in ["yield_surface", "model_comparison", "normalised_yield_surface", "flow_rule", "stress_strain"]:
        check(os.path.getsize(os.path.join(out, png + ".png")) > 10000, f"{png}.png missing or empty")
    _, stderr = anticrack("calibrate", campaign, "-o", out, "--no-plots", expect=2)
    check("--overwrite" in stderr, f"an earlier calibration is not protected: {stderr}")
    # A given Poisson's ratio (for anisotropic specimens) takes E from the constrained modulus alone:
    # with the true nu it is the same E.
    anticrack("calibrate", campaign, "-o", out, "--no-plots", "--overwrite", "--poisson-ratio", str(SYNTHETIC["nu"]))
    material = read_material(os.path.join(out, "material.prm"))
    check(abs(float(material["Young's modulus [Pa]"]) / SYNTHETIC["E"] - 1) < 1e-5, "E with a given nu")


@case
def calibrate_scaling_laws(work):
    """Four synthetic microstructures whose surfaces follow Ritter et al.'s (2020) power laws in nu_c = z phi and
    whose Young's moduli follow Eq. 7 of Bobillier et al. (2020) in the particle modulus: `calibrate` recovers the
    exponents, prefactors and the micro-macro slope, writes one material file per microstructure and
    the scaling plot. A test whose clump did not move after its failure (no flow angle: NaN) is
    left out of the flow rule, by name, and nothing else. In a second campaign, a microstructure
    with M = 0.3 is weaker in shear than any isotropic invariant-plane surface can be on the tests'
    paths (M/sqrt(1 + 2 beta) below (1 - k)/sqrt(3), params/stress_path.h): it gets no material file,
    summary.json names it and why, and it still enters the laws; its neighbour gets its file."""
    h, kappa, k, lam = 2.81e-3, 3.59, 1.38e-3, 3.09      # Eqs. 2-3 of Ritter et al. (2020)
    beta0, beta1 = 7.3e4, 0.014                          # Eq. 7 of Bobillier et al. (2020)
    micro = []
    for phi, z, modulus, M in [(0.3, 2.5, 2e8, 0.8), (0.35, 3.5, 5e8, 0.8), (0.4, 4.5, 1e9, 0.8), (0.45, 5.5, 2e9, 0.8),
                               (0.5, 6.0, 3e9, 0.3)]:
        nu_c, bond = z * phi, 1e6
        sigma0 = bond * h * nu_c ** kappa
        micro.append({"phi": phi, "z": z, "bond": bond, "particle_modulus": modulus, "E": beta0 + beta1 * modulus,
                      "sigma_tau": (sigma0, bond * k * nu_c ** lam / sigma0, M)})
    refusing, micro = micro[2:], micro[:4]
    campaign = write_synthetic_campaign(os.path.join(work, "campaign.h5"), ANGLES, noise=0.002, microstructures=micro)
    with h5py.File(campaign, "r+") as f:
        no_flow = f["failure_points/test"][0].decode()
        f["failure_points/flow_angle_deg"][0] = np.nan
    out = os.path.join(work, "calibration")
    anticrack("calibrate", campaign, "-o", out, "--bootstrap", "0")
    summary = json.load(open(os.path.join(out, "summary.json")))["calibration"]
    flow = summary["microstructures"][0]["flow_rule"]
    check(flow.get("tests_without_a_flow_angle") == [no_flow] and flow["slope"] is not None,
          f"flow rule without {no_flow}: {flow}")
    # 0.2 % scatter of the strengths: the power laws come back to ~1 % in the prefactor (a few x the
    # scatter over nu_c in [0.75, 2.5]) and 0.02 in the exponent.
    for name, (prefactor, exponent) in {"sigma0_over_bond": (h, kappa), "beta_sigma0_over_bond": (k, lam)}.items():
        law = summary["scaling"][name]
        check(abs(law["exponent"] - exponent) < 0.02 and abs(law["prefactor"] / prefactor - 1) < 0.02,
              f"{name}: {law}, expected prefactor {prefactor}, exponent {exponent}")
        check(law["exponent_interval"][0] <= exponent <= law["exponent_interval"][1], f"{name} interval {law}")
    check(abs(summary["scaling"]["M"]["mean"] - 0.8) < 0.01, f"M {summary['scaling']['M']}")
    # Young's moduli are exact (linear synthetic curves), so the line is too.
    modulus = summary["micro_macro"]["macro_modulus_vs_particle_modulus"]
    check(abs(modulus["slope"] / beta1 - 1) < 1e-5 and abs(modulus["intercept"] / beta0 - 1) < 1e-4,
          f"E_macro = {modulus['intercept']} + {modulus['slope']} E_particle, expected {beta0} + {beta1} E_particle")
    for m in range(4):
        check(os.path.exists(os.path.join(out, f"material_m{m}.prm")), f"material_m{m}.prm missing")
    check(os.path.getsize(os.path.join(out, "scaling.png")) > 10000, "scaling.png missing")

    campaign = write_synthetic_campaign(os.path.join(work, "refusing.h5"), ANGLES, noise=0.002, microstructures=refusing)
    out = os.path.join(work, "refusing")
    anticrack("calibrate", campaign, "-o", out, "--bootstrap", "0", "--no-plots")
    summary = json.load(open(os.path.join(out, "summary.json")))["calibration"]
    for m in (0, 1):
        refused = summary["microstructures"][m]["material_refused"]
        check(refused is None and os.path.exists(os.path.join(out, f"material_m{m}.prm")), f"microstructure {m} refused: {refused}")
    refused = summary["microstructures"][2]["material_refused"]
    check(not os.path.exists(os.path.join(out, "material_m2.prm")) and refused is not None
          and "microstructure 2" in refused and "no isotropic invariant-plane surface" in refused,
          f"microstructure 2 (M = 0.3): material file {os.path.exists(os.path.join(out, 'material_m2.prm'))}, refused {refused}")
    check(summary["scaling"]["M"]["samples"] == 3 and abs(summary["scaling"]["M"]["mean"] - (0.8 + 0.8 + 0.3) / 3) < 0.01,
          f"the refused microstructure is not in the laws: M {summary['scaling']['M']}")


@case
def calibrate_degenerate_input(work):
    """Degenerate data are refused with a message and nothing written: one loading angle, no tensile
    point, fewer points than parameters, a format-1 campaign, a file that is not a campaign."""
    cases = [([45], 4, "1 loading angle"), ([0, 45, 90], 3, "no tensile failure point"),
             ([0, 90, 180], 1, "at least 4")]
    for k, (angles, realizations, message) in enumerate(cases):
        campaign = write_synthetic_campaign(os.path.join(work, f"c{k}.h5"), angles, realizations=realizations)
        out = os.path.join(work, f"out{k}")
        _, stderr = anticrack("calibrate", campaign, "-o", out, expect=2)
        check(message in stderr and f"c{k}.h5" in stderr, f"{angles} x {realizations}: message {stderr}")
        check(not os.path.exists(out), f"{out} was created for refused input")
    old = write_synthetic_campaign(os.path.join(work, "old.h5"), ANGLES, version="1")
    _, stderr = anticrack("calibrate", old, "-o", os.path.join(work, "o"), expect=2)
    check("format version 1" in stderr and "--resume" in stderr, f"format-1 campaign: {stderr}")
    diluted = write_synthetic_campaign(os.path.join(work, "diluted.h5"), ANGLES, version="2")
    _, stderr = anticrack("calibrate", diluted, "-o", os.path.join(work, "o"), expect=2)
    check("format version 2" in stderr and "diluted by the platens" in stderr, f"format-2 campaign: {stderr}")
    with h5py.File(os.path.join(work, "other.h5"), "w") as f:
        f["x"] = 1
    _, stderr = anticrack("calibrate", os.path.join(work, "other.h5"), "-o", os.path.join(work, "o"), expect=2)
    check("not an anticrack campaign file" in stderr, f"foreign file: {stderr}")


@case
def calibrate_scene_small(work):
    """`calibrate SCENE` runs the scene's campaign (5 angles, N = 256) into DIR/campaign and fits the
    FE point on the tests' paths (periodic sides: lateral stress ratio nu/(1 - nu) of the calibrated
    elasticity): a closed surface with the compressive tip beyond the tensile one (Ritter et al. 2020:
    beta < 1) in a material file the solver reads, stating its plane. Where the (sigma, tau) family
    reaches the path family's shape the two fits would be the same least-squares problem
    (params/calibration.h); the path fit's points are the DEM's failures over the FE point's peak
    factors f (coupling/calibrate.h), which move each point by ln f, so the two relative RMSEs differ
    by at most the RMS of ln f; `--fe-plane` (the old choice of a plane) is gone; a second call only
    resumes the campaign."""
    # The microstructure variant restates the scene's own force rate through a path whose unit holds
    # a '/' ([N/s]): overrides split subsections outside brackets only.
    scene = write(os.path.join(work, "campaign.prm"),
                  campaign_scene("0, 45, 90, 135, 180", microstructures="Boundary particles/Clump force rate [N/s] = 100"))
    out = os.path.join(work, "cal")
    _, stderr = anticrack("calibrate", scene, "-o", out, "--no-plots", "--bootstrap", "0", "--fe-plane", "sigma-tau",
                          expect=2)
    check("--fe-plane" in stderr and not os.path.exists(out), f"--fe-plane was not refused: {stderr}")
    anticrack("calibrate", scene, "-o", out, "--no-plots", "--bootstrap", "0")
    check(os.path.exists(os.path.join(out, "campaign", "campaign.h5")), "the campaign was not run into DIR/campaign")
    stdout, _ = anticrack("calibrate", scene, "-o", out, "--no-plots", "--bootstrap", "0", "--overwrite")
    check(stdout.count("completed earlier, skipped") == 5, f"the second call did not resume the campaign:\n{stdout}")
    material = read_material(os.path.join(out, "material.prm"))
    p0, beta, M = (float(material[k]) for k in ["Compressive strength p0 [Pa]", "Tensile strength ratio beta",
                                                "Critical state slope M"])
    check(p0 > 0 and 0 < beta < 1 and 0.2 < M < 5, f"(p0, beta, M) = ({p0}, {beta}, {M})")
    check(material["Yield surface plane"] == "invariants", f"yield surface plane {material['Yield surface plane']}")
    nu = float(material["Poisson's ratio"])
    check(material["Fit plane"].startswith("p-q on the tests' paths, lateral stress ratio ") and
          abs(float(material["Fit plane"].split("ratio ")[1].split()[0]) - nu / (1 - nu)) < 1e-4,
          f"fit plane {material['Fit plane']} (nu = {nu})")
    check(float(material["Young's modulus [Pa]"]) > 0 and -1 < nu < 0.5, "elasticity")
    fits = json.load(open(os.path.join(out, "summary.json")))["calibration"]["microstructures"][0]
    rmse = {plane: fits[plane]["models"]["cohesive_cam_clay"]["relative_rmse"]
            for plane in ["sigma_tau_plane", "p_q_path_plane"]}
    moved = math.sqrt(np.mean([math.log(a["fe_peak_over_first_yield"]) ** 2
                               for a in fits["material_point_replay"]["angles"]]))
    check(abs(rmse["p_q_path_plane"] - rmse["sigma_tau_plane"]) <= moved + 1e-9,
          f"relative RMSEs {rmse}, RMS of ln(peak factor) {moved}")

    # The same as a scene of kind `calibration` (`anticrack run`), its options in subsection
    # Calibration: the same material, the campaign resumed from a copy of the first one's.
    calibration_scene = write(os.path.join(work, "calibration.prm"), edit_scene(
        open(scene).read(), {"Scene": "calibration"}) + "subsection Calibration\n  set Bootstrap resamples = 0\n"
        "  set Plots = false\nend\n")
    stdout, _ = anticrack("check", calibration_scene)
    check("Calibration: Cam-Clay surface of the FE point on the tests' paths" in stdout,
          f"`check` of a calibration scene:\n{stdout}")
    run_dir = os.path.join(work, "run")
    os.makedirs(run_dir)
    shutil.copytree(os.path.join(out, "campaign"), os.path.join(run_dir, "campaign"))
    stdout, _ = anticrack("run", calibration_scene, "-o", run_dir)
    check(stdout.count("completed earlier, skipped") == 5, f"the calibration scene did not resume the campaign:\n{stdout}")
    again = read_material(os.path.join(run_dir, "material.prm"))
    for name in ["Compressive strength p0 [Pa]", "Tensile strength ratio beta", "Critical state slope M",
                 "Young's modulus [Pa]", "Poisson's ratio", "Yield surface plane", "Fit plane"]:
        check(again[name] == material[name], f"{name}: {again[name]} from the scene, {material[name]} from `calibrate`")
    bad = write(os.path.join(work, "bad_calibration.prm"),
                open(calibration_scene).read().replace("set Bootstrap resamples = 0",
                                                       "set Bootstrap resamples = 0\n  set Poisson's ratio = 0.7"))
    expect_bad_input(work, bad, "Calibration/Poisson's ratio", "(-1, 0.5)")


def small_periodic_calibration(work):
    """The small periodic SHS campaign (5 angles) calibrated into work/cal: (its directory, the
    material point replay of its summary.json)."""
    scene = write(os.path.join(work, "campaign.prm"), campaign_scene("0, 45, 90, 135, 180"))
    out = os.path.join(work, "cal")
    anticrack("calibrate", scene, "-o", out, "--no-plots", "--bootstrap", "0")
    m0 = json.load(open(os.path.join(out, "summary.json")))["calibration"]["microstructures"][0]
    return out, m0["material_point_replay"]


@case
def crossval_material_point(work):
    """Cross-validation, DEM tests repeated by the FE material point: the material file of a small
    SHS campaign (5 angles, periodic sides), read as the solver reads it and driven along every
    test's path by the FE's own elasticity and return mapping to the peak of its load
    (coupling/material_point_replay.h), fails on each test's ray where the calibration, fitted
    through these peaks, says (to 3e-5: the peak factors settle to 1e-5): its error ln(r_FE/r_DEM)
    is minus the fit's residual, so the FE-vs-DEM errors are the fit's (RMSE printed). At its first
    yield it holds the lateral stress ratio of its own elasticity, nu/(1 - nu), and has the DEM's normal
    (constrained) and shear stiffness to 6 digits. (With one realization per angle an angle's error
    is a residual, which may exceed the RMSE; the per-angle means of the 3-realization SHS campaign
    are within it: docs/calibration.md.)"""
    out, replay = small_periodic_calibration(work)
    rmse = replay["fit_relative_rmse"]
    print(f"fit RMSE {100 * rmse:.2f} %; per angle ln(r_FE/r_DEM) [%]: " +
          ", ".join(f"{a['loading_angle_deg']:g}: {100 * a['relative_error']:+.2f}" for a in replay["angles"]))
    with h5py.File(os.path.join(out, "calibration.h5"), "r") as f:
        residuals = f["microstructures/m0/fits/p_q_path/cohesive_cam_clay/residuals"][()]
    worst = max(abs(e + r) for e, r in zip(replay["test_errors"], residuals))
    # 3e-5: the fit's peak factors settle to 1e-5 (coupling/calibrate.h), the file's six digits add 1e-6.
    check(worst < 3e-5, f"the FE point's error differs from minus the fit's residual by {worst}")
    nu = float(read_material(os.path.join(out, "material.prm"))["Poisson's ratio"])
    for a in replay["angles"]:
        if abs(a["dem_sigma_Pa"]) > 0.1 * math.hypot(a["dem_sigma_Pa"], a["dem_tau_Pa"]):
            check(abs(a["fe_lateral_stress_ratio"] - nu / (1 - nu)) < 1e-6,
                  f"lateral stress ratio {a['fe_lateral_stress_ratio']} at {a['loading_angle_deg']} deg, nu = {nu}")
    for name in ["normal_stiffness_Pa", "shear_stiffness_Pa"]:
        fe, dem = replay[name]["fe"], replay[name]["dem"]
        check(abs(fe / dem - 1) < 1e-5, f"{name}: FE {fe}, DEM {dem}")

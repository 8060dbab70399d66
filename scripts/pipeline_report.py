#!/usr/bin/python3
"""The report of a pipeline run (`anticrack run PIPELINE.prm -o DIR`, coupling/pipeline.h).

Usage: scripts/pipeline_report.py DIR

Reads DIR/summary.json, DIR/weak_layer/{calibration.h5, summary.json, material.prm,
material_snow.prm} and DIR/<stage>/{summary.json, series.h5}; writes
  DIR/report.md   the calibrated weak layer (snow units, with intervals), how well the FE point
                  repeats the DEM tests, each snowpack stage's answers with their intervals and
                  dominant parameters (the uncertainty stage), the wall time of every stage
  DIR/report.png  the DEM failure points with the fitted surface and its band in both planes (snow
                  units), the crack tip against time of every dynamic PST, the stage wall times
"""
import argparse
import json
import os
import re
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
from atomic_output import save_figure, write_text  # noqa: E402 (scripts/atomic_output.py)

KPA = 1e-3
MATERIAL_ROWS = [  # entry of subsection Material, label, scale, unit
    ("Compressive strength p0 [Pa]", "compressive strength p0", KPA, "kPa"),
    ("Tensile strength ratio beta", "tensile strength ratio β", 1, ""),
    ("Critical state slope M", "critical state slope M", 1, ""),
    ("Young's modulus [Pa]", "Young's modulus E", 1e-6, "MPa"),
    ("Poisson's ratio", "Poisson's ratio ν", 1, ""),
    ("Density [kg/m^3]", "density ρ", 1, "kg/m³"),
    ("Hardening factor xi", "softening factor ξ", 1, ""),
    ("Residual strength ratio", "residual strength ratio", 1, ""),
    ("Reference thickness [m]", "reference thickness h_ref", 1e3, "mm"),
    # subsection Material/Collapse, from the DEM compaction tests (absent without them)
    ("Lock-up strain", "lock-up strain ε_d (collapse height / thickness)", 1, ""),
    ("Lock-up modulus [Pa]", "lock-up modulus K_d", 1e-6, "MPa"),
    ("Fracture energy density [J/m^3]", "fracture energy density w_f", 1, "J/m³"),
    ("Collapse energy density [J/m^3]", "collapse energy density w_c", 1, "J/m³"),
    # ... and from the DEM friction tests (absent without them)
    ("Friction coefficient", "friction coefficient μ of the failed layer", 1, ""),
]


def material_entries(path):
    """`set NAME = VALUE` lines of a material file, by name (Uncertainty's intervals included)."""
    entries = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"\s*set (.+?) = (.*)$", line)
            if m:
                entries[m.group(1)] = m.group(2).strip()
    return entries


def interval(entries, name):
    key = name.replace(" [", " interval [") if "[" in name else name + " interval"
    if not entries.get(key):
        return None  # not in the file, or empty: no interval (one realization)
    low, high = (float(v) for v in entries[key].split(","))
    return (low, high)


def fmt(value, digits=3):
    return "—" if value is None else f"{value:.{digits}g}"


def calibration_stages(summary):
    """The weak layers' stages that calibrated: one, or one per class of the pits' weak layers
    (Pipeline/Weak layer specimen = profile; a class whose campaign or fit failed has no material)."""
    return [s for s in summary["stages"]
            if s["kind"] == "calibration" and s["status"] in ("completed", "completed earlier")]


def weak_layer_section(run_dir, summary, stage):
    weak = os.path.join(run_dir, stage["directory"])
    snow = material_entries(os.path.join(weak, "material_snow.prm"))
    dem = material_entries(os.path.join(weak, "material.prm"))
    calibration = json.load(open(os.path.join(weak, "summary.json")))["calibration"]
    confidence = float(snow.get("Confidence", 0.95))
    several = len(calibration_stages(summary)) > 1
    lines = [f"## Weak layer{': ' + stage['name'][len('weak layer '):] if several else ''}", "",
             f"From `{stage['scene']}`: material `{stage['directory']}/material_snow.prm` "
             f"(snow units; `material.prm` is the same in the DEM's units). Intervals: "
             f"{100 * confidence:g} % (surface: covariance of its fit; elasticity and softening: over the "
             f"realizations).", "",
             "| parameter | value | interval |", "|---|---|---|"]
    for name, label, scale, unit in MATERIAL_ROWS:
        if name not in snow:
            continue
        value = float(snow[name]) * scale
        i = interval(snow, name)
        lines.append(f"| {label} | {fmt(value, 4)} {unit} | "
                     f"{'—' if i is None else f'{fmt(i[0] * scale)} – {fmt(i[1] * scale)} {unit}'} |")
    m0 = calibration["microstructures"][0]
    replay = m0["material_point_replay"]
    lines += ["", "The FE material point of this file, driven along every DEM test's path, against the DEM "
              f"(fit RMSE {100 * replay['fit_relative_rmse']:.2f} %):", "",
              "| ψ [°] | " + " | ".join(f"{a['loading_angle_deg']:g}" for a in replay["angles"]) + " |",
              "|---|" + "---|" * len(replay["angles"]),
              "| ln(r_FE/r_DEM) [%] | " + " | ".join(f"{100 * a['relative_error']:+.1f}" for a in replay["angles"]) + " |",
              "", f"Normal stiffness: FE {replay['normal_stiffness_Pa']['fe'] / 1e6:.4g} MPa, DEM "
              f"{replay['normal_stiffness_Pa']['dem'] / 1e6:.4g} MPa; shear stiffness: FE "
              f"{replay['shear_stiffness_Pa']['fe'] / 1e6:.4g} MPa, DEM {replay['shear_stiffness_Pa']['dem'] / 1e6:.4g} MPa "
              "(DEM units)."]
    scale = float(snow["Compressive strength p0 [Pa]"]) / float(dem["Compressive strength p0 [Pa]"])
    return lines, scale


def snowpack_stages(summary):
    return [s for s in summary["stages"] if s["kind"] == "snowpack"]


def outcome_label(r):
    """The outcome as PST practice writes it, with where: Arr and its arrest distance, SF and where."""
    outcome = r.get("outcome")
    if outcome == "Arr" and r.get("arrest_position_m") is not None:
        return f"Arr at {r['arrest_position_m']:.2f} m"
    if outcome == "SF" and r.get("slab_fracture"):
        return f"SF at {r['slab_fracture']['position_m'][0]:.2f} m"
    return outcome or "—"


def cut_with_bracket(r):
    cut, bracket = r.get("critical_cut_length_m"), r.get("critical_cut_bracket_m")
    if cut is None or not bracket:
        return fmt(cut)
    return f"{fmt(cut)} [{fmt(bracket[0])}, {fmt(bracket[1])}]"


def stage_section(run_dir, summary):
    lines = ["## Snowpack analyses", "",
             "| stage | analysis | status | outcome | critical cut [m] | tip-lead onset [m] | Gaume et al. (2017) [m] | "
             "first tip yield [m] | speed [m/s] | touchdown distance [m] |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for s in snowpack_stages(summary):
        r = s.get("results", {})
        gaume = r.get("gaume2017") or {}
        lines.append(f"| {s['name']} | {r.get('analysis', '—')} | {s['status']} | {outcome_label(r)} | "
                     f"{cut_with_bracket(r)} | {fmt(r.get('tip_lead_onset_m'))} | "
                     f"{fmt(gaume.get('critical_cut_length_m'))} | "
                     f"{fmt(gaume.get('first_tip_yield_cut_length_m'))} | "
                     f"{fmt(r.get('propagation_speed_m_per_s'))} | {fmt(r.get('touchdown_distance_m'))} |")
    lines += ["", "Critical cut: the shortest fixed cut (saw stopped) from which the test ends by itself (the crack "
              "runs, or the slab breaks), with the bracket of the fixed-cut trials (PST/Saw = practice or bisection; "
              "otherwise the saw's own reading). Tip-lead onset: where an advancing saw's crack tip began to lead "
              "the saw, a second figure that depends on the saw's speed. Speed: over the part the crack ran by "
              "itself. Gaume et al. (2017): the closed-form critical cut of each saw test's snowpack with the same "
              "calibrated weak layer (its shear strength at the slab's normal stress, laterally confined, and "
              "G_wl = E/(2(1 + nu))), a shear criterion. First tip yield: the cut at which the tip of the beam on "
              "an elastic foundation first reaches the same surface with its normal traction rising too "
              "(fem/closed_forms.h; fem/analysis/outputs.h)."]
    for s in snowpack_stages(summary):
        onset = (s.get("results") or {}).get("onset") or {}
        if onset and not onset.get("sharp", True):
            lines += ["", f"{s['name']}: the onset of propagation is not sharp (the crack of the longest cut that "
                      f"holds ran {onset['longest_holding_cut_crack_run_m']:.2f} m ahead of it, that of the shortest "
                      f"ending cut {onset['shortest_ending_cut_crack_run_m']:.2f} m, against the self-propagation "
                      f"lead of {onset['self_propagation_lead_m']:.2f} m): its critical cut moves with that lead."]
    lines += field_section(run_dir, summary)
    uncertainty = summary.get("results", {}).get("uncertainty") or {}
    if uncertainty.get("parameters"):
        confidence = next((u["confidence"] for u in uncertainty.values() if isinstance(u, dict) and "confidence" in u), 0.95)
        lines += ["", "## The calibration's uncertainty in the answers", "",
                  f"First-order sensitivities: every snowpack scene again with each parameter raised by one "
                  f"standard error (coupling/pipeline_uncertainty.h); {100 * confidence:g} % intervals.", "",
                  "| parameter | value | standard error |", "|---|---|---|"]
        for name, p in uncertainty["parameters"].items():
            lines.append(f"| {name} | {fmt(p['value'], 4)} | {fmt(p['standard_error'], 3)} |")
        lines += ["", "| stage | answer | value | interval | dominant parameter | change per standard error |",
                  "|---|---|---|---|---|---|"]
        for s in snowpack_stages(summary):
            for key, a in (uncertainty.get(s["name"], {}).get("answers") or {}).items():
                if "interval" in a:
                    # G_c's share of an energy release rate's cut is its mapped interval (its two half-widths).
                    changes = ", ".join(f"{n} {v['change_per_standard_error']:+.3g}" if "change_per_standard_error" in v
                                        else f"{n} −{v['interval_half_widths_m'][0]:.3g}/+{v['interval_half_widths_m'][1]:.3g}"
                                        for n, v in a.get("parameters", {}).items()) or a["status"]
                    lines.append(f"| {s['name']} | {a['label']} | {fmt(a['value'])} | {fmt(a['interval'][0])} – "
                                 f"{fmt(a['interval'][1])} | {a['dominant_parameter']} | {changes} |")
                else:
                    lines.append(f"| {s['name']} | {a['label']} | {fmt(a.get('value'))} | {a['status']} | — | — |")
        lengths = {uncertainty[s['name']].get("element_length_m") for s in snowpack_stages(summary) if s["name"] in uncertainty}
        lines += ["", f"Element length along the column: {', '.join(f'{v:g} m' for v in lengths if v)} "
                  "(changes in the critical cut or the touchdown distance below it are not resolved)."]
    lines += ["", "## Wall time", "", "| stage | status | wall time [s] |", "|---|---|---|"]
    for s in summary["stages"]:
        lines.append(f"| {s['name']} | {s['status']} | {s['wall_s']:.1f} |")
    lines.append(f"| whole run | {summary['status']} | {summary['timing']['wall_s']:.1f} |")
    return lines


def profile_layers_table(run_dir, stage):
    """The pit's layers as the stage's run built them: each value, measured or inferred, and its law."""
    path = os.path.join(run_dir, stage["directory"], "summary.json")
    if not os.path.exists(path):
        return []
    profile = (json.load(open(path)).get("scene") or {}).get("profile") or {}
    if not profile.get("layers"):
        return []
    lines = ["", f"{stage['name']}: the pit `{os.path.basename(profile['file'])}` ({profile['format']}), E by "
             f"{profile['slab_modulus_law']}:", "",
             "| layer | depth [cm] | grain form | grain size [mm] | hardness | role | density [kg/m³] | E [MPa] | σ_t [kPa] |",
             "|---|---|---|---|---|---|---|---|---|"]
    sources = {}

    def sourced(value, scale, digits):
        if not value:
            return "—"
        note = sources.setdefault(value["source"], len(sources) + 1)
        return f"{fmt(value['value'] * scale, digits)} ({'measured' if value['measured'] else 'inferred'}, {note})"
    for k, layer in enumerate(profile["layers"]):
        top = 100 * layer["depth_top_m"]
        grain = layer.get("grain_size_m")
        lines.append(f"| {k + 1} | {top:.4g}–{top + 100 * layer['thickness_m']:.4g} | {layer['grain_form'] or '—'} | "
                     f"{'—' if grain is None else fmt(1e3 * grain)} | {layer['hand_hardness'] or '—'} | {layer['role']} | "
                     f"{sourced(layer.get('density_kg_m3'), 1, 3)} | {sourced(layer.get('youngs_modulus_Pa'), 1e-6, 3)} | "
                     f"{sourced(layer.get('tensile_strength_Pa'), 1e-3, 3)} |")
    lines += [""] + [f"({n}) {source}" for source, n in sources.items()]
    return lines


def field_section(run_dir, summary):
    """Predicted against observed, for the snowpack stages built from a real pit's profile."""
    rows = [(s, s["results"]) for s in snowpack_stages(summary)
            if (s.get("results") or {}).get("observed_saw_test")]
    if not rows:
        return []
    lines = ["", "## Predicted against observed", "",
             "| stage | profile's saw test | outcome: predicted | observed | critical cut [m]: predicted | "
             "observed | ratio |", "|---|---|---|---|---|---|---|"]
    for s, r in rows:
        seen = r["observed_saw_test"]
        cut, observed_cut = r.get("critical_cut_length_m"), seen.get("cut_length_m")
        ratio = "—" if cut is None or not observed_cut else f"{cut / observed_cut:.2f}"
        lines.append(f"| {s['name']} | PST {seen.get('index')} (failed at {100 * seen['failed_depth_m']:.0f} cm, column "
                     f"{fmt(seen.get('column_length_m'))} m) | {outcome_label(r)} | {seen.get('propagation') or '—'} | "
                     f"{cut_with_bracket(r)} | {fmt(observed_cut)} | {ratio} |")
    slab = ("The slab is the pit's (its layers, densities measured or inferred, and moduli: the stage's "
            "summary.json, scene/profile).")
    if all(((s.get("weak_layer") or {}).get("from_profile")) for s, _ in rows):
        lines += ["", slab + " The weak layer is the pit's own (Pipeline/Weak layer specimen = profile): the DEM "
                  "specimen of its failed layer's density class and thickness in grains, calibrated and converted "
                  "to snow, its material rescaled to the pit's grain size, at the thickness of the layer the field "
                  "test failed in. Its grain form does not enter: the sticky-hard-sphere microstructure stands for "
                  "every form."]
    else:
        lines += ["", slab + " The weak layer is not yet the pit's own: it is the pipeline's DEM "
                  "weak layer (its calibrated material in snow units) at the thickness of the layer the field test "
                  "failed in. Of the failed layer, its grain size enters only as the pipeline's Snow units/Grain "
                  "diameter [m] gives it (the reference thickness above scales with it); its grain form and "
                  "density do not enter the prediction."]
    lines += failed_layer_against_model(run_dir, summary, [s for s, _ in rows])
    for s, _ in rows:
        lines += profile_layers_table(run_dir, s)
    return lines


def failed_layer_against_model(run_dir, summary, stages):
    """The failed layer of each pit (grain form, size, density) beside what the model's weak layer
    has: the calibrated material's density and the snow units' grain diameter."""
    units = summary.get("snow_units") or {}
    weak_directory = {s["name"]: s["directory"] for s in calibration_stages(summary)}
    lines = ["", "The failed layer against the model's weak layer (density: the calibrated material's, "
             "the DEM's solid fraction times the grains'; grain size: the pit's where the weak layer is the "
             "pit's own (Pipeline/Weak layer specimen = profile), else the pipeline's Snow units/Grain diameter [m]):",
             "", "| stage | failed layer | grain size [mm]: pit | model | density [kg/m³]: pit | model |",
             "|---|---|---|---|---|---|"]
    for stage in stages:
        path = os.path.join(run_dir, stage["directory"], "summary.json")
        profile = (json.load(open(path)).get("scene") or {}).get("profile") or {} if os.path.exists(path) else {}
        weak = next((l for l in profile.get("layers", []) if l.get("role") == "weak"), None)
        if weak is None:
            continue
        own = stage.get("weak_layer", {})
        material = os.path.join(run_dir, weak_directory.get(own.get("stage"), "weak_layer"), "material_snow.prm")
        snow = material_entries(material) if os.path.exists(material) else {}
        model_density = float(snow["Density [kg/m^3]"]) if "Density [kg/m^3]" in snow else None
        model_grain = own["from_profile"]["grain_size_m"] if "from_profile" in own else units.get("grain_diameter_m")
        density = weak.get("density_kg_m3")
        pit_density = (f"{fmt(density['value'])} ({'measured' if density['measured'] else 'inferred'})"
                       if density else f"— ({weak.get('density_note', 'not recorded')})")
        grain = weak.get("grain_size_m")
        lines.append(f"| {stage['name']} | {weak.get('grain_form') or '—'}, {100 * weak['thickness_m']:.3g} cm | "
                     f"{'—' if grain is None else fmt(1e3 * grain)} | "
                     f"{'—' if model_grain is None else fmt(1e3 * model_grain)} | {pit_density} | {fmt(model_density)} |")
    return lines


def plane(ax, points, fits, x, y, scale, title, xlabel, ylabel):
    band = fits["cohesive_cam_clay"]["band"]
    angle = band["angle"][()]
    for key, style in (("radius", dict(color="C0", lw=1.6)),):
        r = band[key][()] * scale * KPA
        ax.plot(r * np.cos(angle), r * np.sin(angle), **style, label="cohesive Cam-Clay fit")
    lo, hi = band["radius_lower"][()] * scale * KPA, band["radius_upper"][()] * scale * KPA
    ax.fill(np.concatenate([lo * np.cos(angle), (hi * np.cos(angle))[::-1]]),
            np.concatenate([lo * np.sin(angle), (hi * np.sin(angle))[::-1]]), color="C0", alpha=0.2, lw=0,
            label="95 % band")
    ax.scatter(points[x][()] * scale * KPA, points[y][()] * scale * KPA, s=22, color="k", zorder=3,
               label="DEM failure points")
    ax.axhline(0, color="0.7", lw=0.6)
    ax.axvline(0, color="0.7", lw=0.6)
    ax.set_title(title, fontsize=10)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower center")


def plot(run_dir, summary, scale, path):
    fig, axes = plt.subplots(2, 2, figsize=(13, 10))
    # The first weak layer's surface (of several, the others' are in their folders' plots).
    first = calibration_stages(summary)[0]
    several = "" if len(calibration_stages(summary)) == 1 else f" ({first['name']})"
    with h5py.File(os.path.join(run_dir, first["directory"], "calibration.h5"), "r") as f:
        m = f["microstructures/m0"]
        plane(axes[0, 0], m["points"], m["fits/p_q_path"], "p_path", "q_path", scale,
              "(p, q) of the FE point on the tests' paths: the FE's surface" + several, "p [kPa] (compression +)",
              "q [kPa]")
        plane(axes[0, 1], m["points"], m["fits/sigma_tau"], "sigma", "tau", scale,
              "(σ, τ) base stresses (Ritter et al. 2020)" + several, "σ [kPa] (compression +)", "τ [kPa]")
    ax = axes[1, 0]
    for k, s in enumerate(snowpack_stages(summary)):
        # A critical-cut search's series is that of its shortest ending trial.
        series = os.path.join(run_dir, s["directory"], s.get("results", {}).get("series_directory", ""), "series.h5")
        if not os.path.exists(series):
            continue
        with h5py.File(series, "r") as f:
            if "crack_tip" not in f:
                continue
            ax.plot(f["time"][()], f["crack_tip"][()], color=f"C{k}", lw=1.5, label=f"{s['name']}: crack tip")
            ax.plot(f["time"][()], f["cut_length"][()], color=f"C{k}", lw=0.8, ls="--", label=f"{s['name']}: saw")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("position along the column [m]")
    ax.set_title("dynamic PSTs: crack tip and saw", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax = axes[1, 1]
    names = [s["name"] for s in summary["stages"]]
    walls = [s["wall_s"] for s in summary["stages"]]
    ax.barh(names, walls, color=["C2" if s["status"] == "completed" else "0.6" for s in summary["stages"]])
    ax.set_xlabel("wall time [s] (grey: completed in an earlier run)")
    ax.set_title("stages", fontsize=10)
    ax.invert_yaxis()
    fig.suptitle(f"anticrack pipeline {summary['scene']['file']}", fontsize=11)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory")
    args = parser.parse_args()
    run_dir = args.directory
    summary = json.load(open(os.path.join(run_dir, "summary.json")))
    weak_lines, scales = [], []
    for stage in calibration_stages(summary):
        section, scale = weak_layer_section(run_dir, summary, stage)
        weak_lines += section + [""]
        scales.append(scale)
    lines = [f"# Pipeline report: `{summary['scene']['file']}`", "",
             f"Status: {summary['status']}; {len(summary['stages'])} stages; outputs in `{run_dir}`.", "",
             "![report](report.png)", ""] + weak_lines + stage_section(run_dir, summary)
    write_text(os.path.join(run_dir, "report.md"), "\n".join(lines) + "\n")
    if scales:  # no weak layer calibrated: nothing to plot
        plot(run_dir, summary, scales[0], os.path.join(run_dir, "report.png"))
    print(f"wrote {os.path.join(run_dir, 'report.md')} and report.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())

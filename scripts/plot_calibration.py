#!/usr/bin/python3
"""Plot the calibration of the cohesive Cam-Clay yield surface.

Usage: scripts/plot_calibration.py DIR

Reads DIR/calibration.h5 (written by `anticrack calibrate`) and writes into DIR:
  yield_surface.png             failure points, the cohesive Cam-Clay fit and its confidence band in the
                                (p, q) plane of the FE point on the tests' paths (the FE's surface),
                                the (sigma, tau) base-stress plane and the (p, q) Love-Weber plane
  model_comparison.png          the three fitted envelopes per plane and microstructure (R^2, delta AICc)
  normalised_yield_surface.png  (sigma*, tau*) against the unit circle (Ritter et al. 2020, Fig. 5A)
  flow_rule.png                 theta* against psi* (Ritter et al. 2020, Fig. 5B); flow angle against loading angle
  stress_strain.png             total base stress against strain magnitude, one panel per microstructure
  scaling.png                   only with /scaling or /micro_macro: power laws in the contact density,
                                M, and the micro-to-macro relations
Stresses in kPa; one colour per microstructure, one marker per realization.
"""
import argparse
import os
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import FormatStrFormatter, FuncFormatter  # noqa: E402
from matplotlib.transforms import offset_copy  # noqa: E402
from atomic_output import save_figure  # noqa: E402 (scripts/atomic_output.py)

KPA = 1e-3
PLANES = {  # points' keys, axis labels, panel title
    "p_q_path": ("p_path", "q_path", "mean stress p [kPa] (compression +)", "von Mises stress q [kPa]",
                 "(p, q) of the FE point on the tests' paths"),
    "sigma_tau": ("sigma", "tau", "base normal stress σ [kPa] (compression +)", "base shear stress τ [kPa]",
                  "(σ, τ) base stresses, Ritter et al. 2020"),
    "p_q": ("p", "q", "mean stress p [kPa] (compression +)", "von Mises stress q [kPa]",
            "(p, q) Love–Weber invariants"),
}
MODELS = {"cohesive_cam_clay": "cohesive Cam-Clay", "mohr_coulomb_cap": "Mohr–Coulomb with cap",
          "quadratic_polynomial": "quadratic polynomial"}
SYMBOLS = {"sigma0": "σ₀", "p0": "p₀", "beta": "β"}
MARKERS = "osD^v<>ph*"
LINESTYLES = ["-", "--", ":", "-."]


class Group(dict):
    """An HDF5 group read into memory: children by name, attributes in .attrs."""


def load(node):
    """Read a file, group or dataset recursively (strings decoded)."""
    if isinstance(node, h5py.Dataset):
        return node.asstr()[()] if h5py.check_string_dtype(node.dtype) else node[()]
    group = Group((name, load(child)) for name, child in node.items())
    group.attrs = dict(node.attrs)
    return group


def colour(k):
    return plt.cm.tab10(k % 10)


def micro_label(name, micro):
    a = micro.attrs
    label = f"{name} {a.get('label', '')}".strip()
    return f"{label} (ν_c = {a['contact_density']:.3g})" if "contact_density" in a else label


def envelope(band, radius="radius"):
    """The envelope in kPa: normal = r cos(angle), shear = r sin(angle)."""
    return band[radius] * np.cos(band["angle"]) * KPA, band[radius] * np.sin(band["angle"]) * KPA


def draw_band(ax, band, c):
    xl, yl = envelope(band, "radius_lower")
    xu, yu = envelope(band, "radius_upper")
    ax.fill(np.concatenate([xl, xu[::-1]]), np.concatenate([yl, yu[::-1]]), color=c, alpha=0.2, lw=0)


def scatter_points(ax, points, x, y, c):
    for r in np.unique(points["realization"]):
        sel = points["realization"] == r
        ax.scatter(points[x][sel] * KPA, points[y][sel] * KPA, color=c, marker=MARKERS[int(r) % len(MARKERS)],
                   s=28, edgecolor="k", linewidth=0.4, zorder=3)


def style_plane(ax, plane, title):
    ax.axhline(0, color="0.7", lw=0.6)
    ax.axvline(0, color="0.7", lw=0.6)
    ax.set_xlabel(PLANES[plane][2])
    ax.set_ylabel(PLANES[plane][3])
    ax.set_title(title, fontsize=10)
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)


def legend_below(ax, **kwargs):
    """Legend under the axes, clear of the x label whatever the axes' height."""
    below = offset_copy(ax.transAxes, fig=ax.figure, y=-36, units="points")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0), bbox_transform=below, fontsize=8, **kwargs)


def suptitle_above_axes(fig, text):
    """Suptitle right above the axes: equal-aspect axes leave the top of the figure empty (cropped on save)."""
    renderer = fig.canvas.get_renderer()
    top = max(ax.get_tightbbox(renderer).y1 for ax in fig.axes) / fig.bbox.height
    fig.suptitle(text, y=top + 0.01, va="bottom")


def parameter_text(fit, confidence):
    """'σ₀ = 14 kPa [13.6, 14.4], β = …' with the covariance intervals (those of the material file; the
    percentile bootstrap over three realizations is too narrow, see params/envelope_fit.h)."""
    parts = []
    for name, unit, value, lo, hi in zip(fit["parameter_names"], fit["parameter_units"], fit["parameters"],
                                         fit["ci_lower"], fit["ci_upper"]):
        scale, unit = (KPA, " kPa") if unit == "Pa" else (1, f" {unit}" if unit else "")
        parts.append(f"{SYMBOLS.get(name, name)} = {value * scale:.3g}{unit} [{lo * scale:.3g}, {hi * scale:.3g}]")
    return ", ".join(parts) + f"  ({confidence} CI)"


def plot_yield_surface(data, micros):
    confidence = f"{100 * data.attrs.get('confidence', 0.95):g} %"
    fig, axes = plt.subplots(1, len(PLANES), figsize=(7.5 * len(PLANES), 6))
    for ax, plane in zip(axes, PLANES):
        x, y = PLANES[plane][:2]
        for k, (name, m) in enumerate(micros):
            scatter_points(ax, m["points"], x, y, colour(k))
            fit = m["fits"].get(plane, {}).get("cohesive_cam_clay")
            if fit is not None:
                ax.plot(*envelope(fit["band"]), color=colour(k), lw=1.6,
                        label=f"{micro_label(name, m)}: R² = {fit.attrs['r_squared']:.3f}\n"
                              f"{parameter_text(fit, confidence)}")
                draw_band(ax, fit["band"], colour(k))
        used = " — used by the FE solver" if plane == data.attrs.get("fe_plane") else ""
        style_plane(ax, plane, PLANES[plane][4] + used)
        legend_below(ax, title=f"cohesive Cam-Clay fit (shaded: {confidence} band)", title_fontsize=8)
    suptitle_above_axes(fig, f"{data.attrs.get('campaign_file', '')}: yield points (marker = realization)")
    return fig


def plot_model_comparison(data, micros):
    fig, axes = plt.subplots(len(micros), len(PLANES), figsize=(7.5 * len(PLANES), 5 * len(micros)), squeeze=False,
                             gridspec_kw={"hspace": 0.5})
    for row, (name, m) in zip(axes, micros):
        for ax, plane in zip(row, PLANES):
            fits = m["fits"].get(plane, {})
            scatter_points(ax, m["points"], *PLANES[plane][:2], "0.6")
            best = min((fit.attrs["aicc"] for fit in fits.values()), default=0)
            for j, (model, fit) in enumerate(sorted(fits.items())):
                ax.plot(*envelope(fit["band"]), color=colour(j), ls=LINESTYLES[j % len(LINESTYLES)], lw=1.6,
                        label=f"{MODELS.get(model, model)}: R² = {fit.attrs['r_squared']:.3f}, "
                              f"ΔAICc = {fit.attrs['aicc'] - best:.1f}")
            style_plane(ax, plane, f"{micro_label(name, m)}\n{PLANES[plane][4]}")
            legend_below(ax)
    suptitle_above_axes(fig, "envelopes compared (ΔAICc relative to the best model of the plane)")
    return fig


def plot_normalised(data, micros):
    fig, ax = plt.subplots(figsize=(8, 5))
    t = np.linspace(0, np.pi, 181)
    ax.plot(np.cos(t), np.sin(t), "k-", lw=1.2, label="unit circle σ*² + τ*² = 1 (Ritter et al. 2020, Eq. 4)")
    for k, (name, m) in enumerate(micros):
        fr = m["flow_rule"]
        ax.scatter(fr["sigma_star"], fr["tau_star"], color=colour(k), s=28, edgecolor="k", linewidth=0.4,
                   zorder=3, label=micro_label(name, m))
    ax.axhline(0, color="0.7", lw=0.6)
    ax.axvline(0, color="0.7", lw=0.6)
    ax.set_xlabel("normalised normal stress σ* (Eq. 5)")
    ax.set_ylabel("normalised shear stress τ* (Eq. 6)")
    ax.set_title("normalised yield surface (Ritter et al. 2020, Fig. 5A)")
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    legend_below(ax)
    return fig


def plot_flow_rule(data, micros):
    fig, (left, right) = plt.subplots(1, 2, figsize=(15, 5.8))
    psi = np.array([0, 180])
    left.plot(psi, psi - 90, "k--", lw=1.2, label="associative: θ* = ψ* − 90° (Eq. 16)")
    lines = []
    for k, (name, m) in enumerate(micros):
        fr = m["flow_rule"]
        left.scatter(fr["psi_star_deg"], fr["theta_star_deg"], color=colour(k), s=28, edgecolor="k",
                     linewidth=0.4, zorder=3, label=micro_label(name, m))
        a = fr.attrs
        lines.append(f"{name}: RMS deviation {a['rms_deviation_deg']:.1f}°, slope {a['slope']:.2f}, "
                     f"R² about Eq. 16 = {a['r_squared_associative']:.3f}")
        right.scatter(fr["loading_angle_deg"], fr["flow_angle_deg"], color=colour(k), s=28, edgecolor="k",
                      linewidth=0.4, zorder=3)
        right.plot(fr["curve_loading_angle_deg"], fr["curve_flow_angle_deg"], color=colour(k), lw=1.4,
                   label=f"{name}: associative prediction of the fit")
        right.axvline(a["transition_angle_predicted_deg"], color=colour(k), ls="--", lw=1,
                      label=f"{name}: transition predicted (Eq. 7) {a['transition_angle_predicted_deg']:.1f}°")
        if np.isfinite(a["transition_angle_observed_deg"]):
            right.axvline(a["transition_angle_observed_deg"], color=colour(k), ls=":", lw=1.4,
                          label=f"{name}: transition observed {a['transition_angle_observed_deg']:.1f}°")
    left.text(0.03, 0.97, "\n".join(lines), transform=left.transAxes, va="top", fontsize=8,
              bbox=dict(boxstyle="round", facecolor="white", alpha=0.9))
    left.set_xlabel("normalised loading angle ψ* [deg]")
    left.set_ylabel("normalised flow angle θ* [deg]")
    left.set_title("normalised flow rule (Ritter et al. 2020, Fig. 5B)")
    left.legend(loc="lower right", fontsize=8)
    right.axhline(0, color="k", lw=0.8)
    right.text(0.02, 2, "expansion (θ > 0) ↑", transform=right.get_yaxis_transform(), va="bottom", fontsize=9)
    right.text(0.98, -2, "compaction (θ < 0) ↓", transform=right.get_yaxis_transform(), va="top", ha="right",
               fontsize=9)
    right.set_xlabel("loading angle ψ [deg] (0 compression, 90 shear, 180 tension)")
    right.set_ylabel("plastic flow angle θ = arctan(u_z/u_x) [deg]")
    right.set_title("flow angle against loading angle")
    legend_below(right, ncol=2 if len(micros) > 1 else 1)
    for ax in (left, right):
        ax.set_xlim(-5, 185)
        ax.set_ylim(-100, 100)
        ax.set_xticks(np.arange(0, 181, 45))
        ax.set_yticks(np.arange(-90, 91, 45))
        ax.grid(alpha=0.3)
    return fig


def plot_stress_strain(data, micros):
    cols = min(len(micros), 3)
    rows = -(-len(micros) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(5.5 * cols + 1.5, 4.3 * rows), squeeze=False, layout="constrained")
    cmap, norm = plt.cm.viridis, plt.Normalize(0, 180)
    realizations = set()
    for ax, (name, m) in zip(axes.flat, micros):
        for curve in m.get("curves", {}).values():
            r = int(curve.attrs["realization"])
            realizations.add(r)
            ax.plot(100 * np.hypot(curve["normal_strain"], curve["shear_strain"]),
                    np.hypot(curve["sigma"], curve["tau"]) * KPA, color=cmap(norm(curve.attrs["loading_angle_deg"])),
                    ls=LINESTYLES[r % len(LINESTYLES)], lw=1)
        ax.set_xlabel("strain magnitude √(ε² + γ²) [%]")
        ax.set_ylabel("total base stress √(σ² + τ²) [kPa]")
        ax.set_title(micro_label(name, m), fontsize=10)
        ax.grid(alpha=0.3)
    for ax in axes.flat[len(micros):]:
        ax.set_visible(False)
    axes.flat[0].legend(handles=[Line2D([], [], color="k", lw=1, ls=LINESTYLES[r % len(LINESTYLES)],
                                        label=f"realization {r}") for r in sorted(realizations)], fontsize=8)
    fig.colorbar(plt.cm.ScalarMappable(cmap=cmap, norm=norm), ax=axes, label="loading angle ψ [deg]",
                 ticks=np.arange(0, 181, 45))
    return fig


def panel_power_laws(ax, scaling):
    nu = scaling["contact_density"]
    a = scaling.attrs
    x = np.geomspace(nu.min() / 1.1, nu.max() * 1.1, 50)
    # Ritter et al.'s (2020) published laws (Eqs. 2-3) for comparison: h = 2.81e-3, kappa = 3.59; k = 1.38e-3, lambda = 3.09.
    published = {"sigma0": (2.81e-3, 3.59), "tensile": (1.38e-3, 3.09)}
    for key, y, symbol, c in [("sigma0", scaling["sigma0_over_bond"], r"\sigma_0", "C0"),
                              ("tensile", scaling["beta_sigma0_over_bond"], r"\beta\sigma_0", "C3")]:
        prefactor, exponent = a[f"{key}_prefactor"], a[f"{key}_exponent"]
        ax.loglog(x, published[key][0] * x**published[key][1], ":", color=c, lw=1,
                  label=rf"Ritter et al. 2020: ${published[key][0]:.3g}\,\nu_c^{{{published[key][1]}}}$")
        ax.loglog(nu, y, "o", color=c, mec="k", mew=0.4, label=rf"${symbol}/\sigma_b$")
        ax.loglog(x, prefactor * x**exponent, "-", color=c, lw=1.2,
                  label=rf"${symbol}/\sigma_b = {prefactor:.3g}\,\nu_c^{{{exponent:.2f}}}$"
                        f"  (R² = {a[f'{key}_r_squared']:.3f})")
    ax.set_xlabel("contact density ν_c = z φ")
    ax.set_ylabel("strength / bond strength σ_b")
    ax.set_title("size of the yield surface (Ritter et al. 2020, Eqs. 2, 3)")
    # Plain numbers; the strength axis spans decades, so only its minor ticks 2 and 5 are labelled.
    def two_and_five(value, _):
        mantissa = value / 10 ** np.floor(np.log10(value))
        return f"{value:g}" if round(mantissa) in (2, 5) else ""
    for axis, minor in ((ax.xaxis, FormatStrFormatter("%g")), (ax.yaxis, FuncFormatter(two_and_five))):
        axis.set_major_formatter(FormatStrFormatter("%g"))
        axis.set_minor_formatter(minor)
    ax.legend(fontsize=8)


def panel_slope(ax, scaling):
    ax.plot(scaling["contact_density"], scaling["M"], "o", color="C2", mec="k", mew=0.4, label="fitted M")
    ax.axhline(np.mean(scaling["M"]), color="C2", ls="--", label=f"mean M = {np.mean(scaling['M']):.2f}")
    ax.set_xlabel("contact density ν_c = z φ")
    ax.set_ylabel("critical-state slope M")
    ax.set_title("shape of the yield surface")
    ax.legend(fontsize=8)


def panel_linear(ax, mm, key, x, y):
    """Linear micro-to-macro relation y = intercept + slope x; x, y: (dataset, scale, unit, label, symbol)."""
    a = mm.attrs
    intercept, slope = a[f"{key}_intercept"], a[f"{key}_slope"]
    xs = np.linspace(0, mm[x[0]].max() * 1.1, 50)
    ax.plot(mm[x[0]] / x[1], mm[y[0]] / y[1], "o", color="C1", mec="k", mew=0.4, label="data")
    ax.plot(xs / x[1], (intercept + slope * xs) / y[1], "-", color="C1",
            label=f"{y[4]} = {intercept / y[1]:.3g} {y[2]} + {slope:.3g} {x[4]}  (R² = {a[f'{key}_r_squared']:.3f})")
    ax.set_xlabel(f"{x[3]} {x[4]} [{x[2]}]")
    ax.set_ylabel(f"{y[3]} {y[4]} [{y[2]}]")
    ax.set_title(f"micro to macro: {key}")
    ax.legend(fontsize=8)


def plot_scaling(data, micros):
    panels = []
    if "scaling" in data:
        panels += [lambda ax: panel_power_laws(ax, data["scaling"]), lambda ax: panel_slope(ax, data["scaling"])]
    if "micro_macro" in data:
        mm = data["micro_macro"]
        # Each relation is fitted only when its micro value varies (>= 3 distinct values).
        if "modulus_slope" in mm.attrs:
            panels.append(lambda ax: panel_linear(ax, mm, "modulus",
                                                  ("particle_modulus", 1e9, "GPa", "particle modulus", "E_p"),
                                                  ("macro_modulus", 1e6, "MPa", "Young's modulus", "E")))
        if "strength_slope" in mm.attrs:
            panels.append(lambda ax: panel_linear(ax, mm, "strength",
                                                  ("bond_strength", 1e6, "MPa", "bond strength", "σ_b"),
                                                  ("macro_strength", 1e3, "kPa", "compressive strength", "σ_f")))
    if not panels:
        return None
    rows = -(-len(panels) // 2)
    fig, axes = plt.subplots(rows, 2, figsize=(13, 4.8 * rows), squeeze=False, layout="constrained")
    for ax, panel in zip(axes.flat, panels):
        panel(ax)
        ax.grid(alpha=0.3, which="both")
    for ax in axes.flat[len(panels):]:
        fig.delaxes(ax)
    return fig


FIGURES = [("yield_surface.png", plot_yield_surface), ("model_comparison.png", plot_model_comparison),
           ("normalised_yield_surface.png", plot_normalised), ("flow_rule.png", plot_flow_rule),
           ("stress_strain.png", plot_stress_strain), ("scaling.png", plot_scaling)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory", help="calibration output directory (holds calibration.h5)")
    args = parser.parse_args()
    path = os.path.join(args.directory, "calibration.h5")
    if not os.path.exists(path):
        print(f"plot_calibration: {path} does not exist", file=sys.stderr)
        return 1
    with h5py.File(path, "r") as f:
        if f.attrs.get("format") != "anticrack-calibration":
            print(f"plot_calibration: {path} is not an anticrack calibration file", file=sys.stderr)
            return 1
        data = load(f)
    micros = sorted(data["microstructures"].items(), key=lambda item: int(item[0].lstrip("m")))
    for name, plot in FIGURES:
        fig = plot(data, micros)
        if fig is None:
            continue
        output = os.path.join(args.directory, name)
        save_figure(fig, output, dpi=150, bbox_inches="tight")
        plt.close(fig)
        print(f"wrote {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

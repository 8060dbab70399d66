#!/usr/bin/env python3
"""Scores a field study: the predicted outcome (End / Arr / SF) and critical cut of each field PST
against what its observer recorded, and the same for the obvious baseline, "always End at the
median cut" (the SnowPilot median, 45 cm: data/field_psts/README.md, not the median of these
tests). Reads the pipeline's summary.json (scenes/field/field_psts.prm); writes DIR/field_score.json
and DIR/field_score.md (the per-test table and the score, as docs/validation.md quotes them).

    scripts/field_score.py out/field
    scripts/field_score.py out/published --observed scenes/published/observed.csv

Measures (docs/validation.md): the share of outcomes right, overall and per observed class; the
cut's ratio predicted/observed over the tests whose prediction has a cut and whose observer gave
one (median, quartiles, the share within a factor 1.5) and Spearman's rank correlation of the two
(ties by mean ranks). A test the model says does not propagate has no cut and counts as a wrong
outcome; its cut counts as outside the factor. Where the observations give the collapse height
(--observed, a column collapse_height_m), its ratio predicted/observed too: the predicted one is the
height the slab closes the collapsed layer to (summary.json collapsed_layer_under_the_slab).

The observations come from each test's profile (the saw test the scene names: summary.json
observed_saw_test), or, for tests whose profile holds none, from --observed CSV (test, propagation,
cut_length_m, column_length_m, collapse_height_m, failed_depth_m).
"""
import csv
import argparse
import json
import os

import numpy as np

BASELINE_CUT_M = 0.45  # the SnowPilot median cut of 3 871 PSTs (data/field_psts/README.md)
FACTOR = 1.5


def ranks(values):
    order = np.argsort(values, kind="mergesort")
    r = np.empty(len(values))
    r[order] = np.arange(1, len(values) + 1)
    for v in np.unique(values):  # ties share their mean rank
        tied = values == v
        r[tied] = r[tied].mean()
    return r


def spearman(x, y):
    if len(x) < 3 or len(set(x)) < 2 or len(set(y)) < 2:
        return None  # undefined for a constant (the baseline's cuts)
    rx, ry = ranks(np.asarray(x, float)), ranks(np.asarray(y, float))
    return float(np.corrcoef(rx, ry)[0, 1])


def score(cases, predicted_outcome, predicted_cut, predicts_collapse=True):
    """cases: dicts with observed outcome/cut; predicted_*: functions of a case; predicts_collapse:
    whether the predictor gives collapse heights (the baseline does not)."""
    outcomes = [c["observed_outcome"] for c in cases]
    right = [predicted_outcome(c) == c["observed_outcome"] for c in cases]
    per_class = {}
    for cls in sorted(set(outcomes)):
        members = [r for r, o in zip(right, outcomes) if o == cls]
        per_class[cls] = {"tests": len(members), "right": int(sum(members))}
    ratios, observed, predicted = [], [], []
    within = 0
    with_cut = [c for c in cases if c["observed_cut_m"]]
    for c in with_cut:
        p = predicted_cut(c)
        if p is None:
            continue
        ratios.append(p / c["observed_cut_m"])
        observed.append(c["observed_cut_m"])
        predicted.append(p)
        within += 1 / FACTOR <= ratios[-1] <= FACTOR
    r = np.asarray(ratios)
    collapse = np.asarray([c["collapse_height_m"] / c["observed_collapse_height_m"] for c in cases
                           if predicts_collapse and c.get("observed_collapse_height_m") and c.get("collapse_height_m")])
    return {
        "tests": len(cases),
        "outcomes_right": int(sum(right)),
        "outcome_share": sum(right) / len(cases) if cases else None,
        "per_observed_class": per_class,
        "cuts_compared": len(with_cut),
        "cuts_predicted": len(ratios),
        "cut_ratio_median": float(np.median(r)) if len(r) else None,
        "cut_ratio_quartiles": [float(np.percentile(r, 25)), float(np.percentile(r, 75))] if len(r) else None,
        "cuts_within_factor": within,
        "cut_share_within_factor": within / len(with_cut) if with_cut else None,
        "cut_rank_correlation": spearman(observed, predicted),
        "collapse_heights_compared": len(collapse),
        "collapse_height_ratio_median": float(np.median(collapse)) if len(collapse) else None,
        "collapse_height_ratio_quartiles": ([float(np.percentile(collapse, 25)), float(np.percentile(collapse, 75))]
                                            if len(collapse) else None),
    }


def observations(path):
    if not path:
        return {}
    rows = csv.DictReader(line for line in open(path) if not line.startswith("#"))
    number = lambda text: float(text) if text else None
    return {r["test"]: {"propagation": r["propagation"], "cut_length_m": number(r["cut_length_m"]),
                        "column_length_m": number(r["column_length_m"]),
                        "collapse_height_m": number(r["collapse_height_m"]),
                        "failed_depth_m": number(r["failed_depth_m"])} for r in rows}


def weak_layer_of(stage_summary):
    """The profile's own weak layer as the FE run recorded it (summary.json scene/profile, the layer of
    role `weak`): grain form, grain size, thickness, and density with whether it was measured or
    inferred (Geldsetzer & Jamieson 2000 from hand hardness), or None without a profile."""
    layers = ((stage_summary.get("scene") or {}).get("profile") or {}).get("layers") or []
    for layer in layers:
        if layer.get("role") == "weak":
            density = layer.get("density_kg_m3") or {}
            return {"grain_form": layer.get("grain_form"), "grain_size_m": layer.get("grain_size_m"),
                    "thickness_m": layer.get("thickness_m"), "density_kg_m3": density.get("value"),
                    "density_measured": density.get("measured")}
    return None


def weak_layer_text(weak):
    """"FC 1 mm, 5 cm, 460 kg/m³ (measured)", or "–"."""
    if not weak:
        return "–"
    parts = [weak["grain_form"] or "?"]
    if weak["grain_size_m"]:
        parts[0] += f" {1000 * weak['grain_size_m']:g} mm"
    parts.append(f"{100 * weak['thickness_m']:g} cm")
    if weak["density_kg_m3"] is not None:
        parts.append(f"{weak['density_kg_m3']:.0f} kg/m³ ({'measured' if weak['density_measured'] else 'from hardness'})")
    else:
        parts.append("no density")
    return ", ".join(parts)


def cases_of(directory, summary, observed):
    out = []
    for name, a in summary["results"]["analyses"].items():
        obs = a.get("observed_saw_test") or observed.get(name) or {}
        ended = a.get("status") == "completed"
        stage = os.path.join(directory, name, "summary.json")
        stage_summary = json.load(open(stage)) if os.path.exists(stage) else {}
        results = stage_summary.get("results", stage_summary)
        weak = weak_layer_of(stage_summary)
        out.append({
            "test": name,
            "status": a.get("status"),
            "observed_outcome": obs.get("propagation"),
            "observed_cut_m": obs.get("cut_length_m"),
            "observed_collapse_height_m": obs.get("collapse_height_m"),
            "column_m": obs.get("column_length_m"),
            "failed_depth_m": obs.get("failed_depth_m"),
            "predicted_outcome": a.get("outcome") if ended else None,
            "predicted_cut_m": a.get("critical_cut_length_m") if ended else None,
            "bracket_m": a.get("critical_cut_bracket_m"),
            "speed_m_per_s": a.get("propagation_speed_m_per_s"),
            "touchdown_m": a.get("touchdown_distance_m"),
            "arrest_m": a.get("arrest_position_m"),
            "collapse_height_m": (results.get("collapsed_layer_under_the_slab") or {}).get("collapse_height_m"),
            "weak_layer": weak,
        })
    return sorted(out, key=lambda c: c["test"])


def fmt(x, digits=2):
    return "–" if x is None else f"{x:.{digits}f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory")
    parser.add_argument("--observed", help="CSV of observations for tests whose profile holds none")
    args = parser.parse_args()
    directory = args.directory
    summary = json.load(open(os.path.join(directory, "summary.json")))
    cases = [c for c in cases_of(directory, summary, observations(args.observed))
             if c["observed_outcome"] in ("End", "Arr", "SF")]
    model = score(cases, lambda c: c["predicted_outcome"],
                  lambda c: c["predicted_cut_m"] if c["predicted_outcome"] in ("End", "Arr", "SF") else None)
    baseline = score(cases, lambda c: "End", lambda c: BASELINE_CUT_M, predicts_collapse=False)
    result = {"model": model, "baseline_always_end_at_the_median_cut": baseline, "baseline_cut_m": BASELINE_CUT_M,
              "factor": FACTOR, "cases": cases}
    with open(os.path.join(directory, "field_score.json"), "w") as f:
        json.dump(result, f, indent=1)
    lines = ["| test | depth | weak layer (the profile's) | observed | predicted | cut ratio | speed | touchdown | "
             "collapse height (observed) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        obs = f"{c['observed_outcome']} from {fmt(c['observed_cut_m'])} m" if c["observed_cut_m"] else c["observed_outcome"]
        if c["predicted_outcome"] is None:
            pred = f"({c['status']})"
        elif c["predicted_cut_m"] is None:
            pred = c["predicted_outcome"]
        else:
            lo, hi = c["bracket_m"] or (None, None)
            pred = f"{c['predicted_outcome']} from {fmt(c['predicted_cut_m'])} m [{fmt(lo)}, {fmt(hi)}]"
            if c["predicted_outcome"] == "Arr" and c["arrest_m"] is not None:
                pred += f", arrested at {fmt(c['arrest_m'])} m"
        ratio = (c["predicted_cut_m"] / c["observed_cut_m"]
                 if c["predicted_cut_m"] is not None and c["observed_cut_m"] else None)
        lines.append(f"| {c['test']} | {fmt(c['failed_depth_m'])} m | {weak_layer_text(c['weak_layer'])} | {obs} | "
                     f"{pred} | {fmt(ratio)} | "
                     f"{fmt(c['speed_m_per_s'], 1)} | {fmt(c['touchdown_m'])} | "
                     f"{fmt(1000 * c['collapse_height_m'] if c['collapse_height_m'] else None, 1)} mm"
                     + (f" ({fmt(1000 * c['observed_collapse_height_m'], 1)} mm)" if c["observed_collapse_height_m"] else "")
                     + " |")

    def score_lines(label, s):
        classes = ", ".join(f"{k} {v['right']}/{v['tests']}" for k, v in s["per_observed_class"].items())
        q = s["cut_ratio_quartiles"] or (None, None)
        return (f"| {label} | {s['outcomes_right']}/{s['tests']} ({fmt(100 * s['outcome_share'], 0)} %; {classes}) | "
                f"{fmt(s['cut_ratio_median'])} [{fmt(q[0])}, {fmt(q[1])}] | "
                f"{s['cuts_within_factor']}/{s['cuts_compared']} ({fmt(100 * s['cut_share_within_factor'], 0)} %) | "
                f"{fmt(s['cut_rank_correlation'])} | " + (
                    f"{fmt(s['collapse_height_ratio_median'])} [{fmt(s['collapse_height_ratio_quartiles'][0])}, "
                    f"{fmt(s['collapse_height_ratio_quartiles'][1])}] of {s['collapse_heights_compared']}"
                    if s["collapse_heights_compared"] else "–") + " |")
    lines += ["", f"| | outcomes right | cut ratio, median [quartiles] | cuts within a factor {FACTOR} | rank correlation "
              "| collapse height ratio, median [quartiles] |",
              "|---|---|---|---|---|---|", score_lines("model", model),
              score_lines(f"always End at {BASELINE_CUT_M} m", baseline)]
    with open(os.path.join(directory, "field_score.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines[-4:]))


if __name__ == "__main__":
    main()

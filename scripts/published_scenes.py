#!/usr/bin/env python3
"""Writes the published study's scenes: PSTs of van Herwijnen et al. (2016) (the raw data in
data/published_psts/vanherwijnen2016/), each as a layer table (the test's slab and weak layer, top
down, with their measured densities) and a PST scene from the template scenes/pst_pit_65798.prm
with the table, the weak layer by its role, the test's slope and column; keeps the scenes that
`anticrack check` accepts (scenes/published/refused.md lists the others), writes the observations
to compare with (scenes/published/observed.csv: outcome, critical cut, collapse height) and the
pipeline that runs them (scenes/published/published_psts.prm).

Which tests: those whose slab and weak layer all have a measured density (206 of 255), and of
these every N-th by id (--every N, default 8: 26 tests, ids 1, 9, ...; a sample that no result
chooses). The substratum is the scene's, as in the field study; the profile's substratum rows are
kept where their density is measured and dropped where it is not. The saw's travel and the
placeholder weak layer's collapse follow the test (scene_study.fit_template_to_test).

The scenes take nothing from the test's result: r_c, the outcome and dy are only compared with, in
scripts/field_score.py --observed scenes/published/observed.csv.

    scripts/published_scenes.py build/app/anticrack [--every N]
"""
import argparse
import csv
import os
import re

from scene_study import ROOT, check_scenes, fit_template_to_test, template, write_pipeline, write_refused

DATA = os.path.join(ROOT, "data", "published_psts", "vanherwijnen2016")
OUT = os.path.join(ROOT, "scenes", "published")
MISSING = -999
SLAB, WEAK, BASE = 1, 2, 3
ROLE = {SLAB: "slab", WEAK: "weak", BASE: "base"}


def tests():
    """The rows of psts.txt: id, r_c, slope, H, mean density, L, dy, weak-layer thickness,
    propagation, slab fracture, its distance (cm and deg, as the file has them)."""
    keys = ["id", "rc_cm", "slope_deg", "slab_cm", "slab_density", "column_cm", "dy_cm", "weak_cm",
            "propagation", "slab_fracture", "slab_fracture_cm"]
    for line in open(os.path.join(DATA, "psts.txt")):
        if line.startswith("#") or not line.strip():
            continue
        row = dict(zip(keys, map(float, line.split())))
        row["id"] = int(row["id"])
        row["outcome"] = "SF" if row["slab_fracture"] == 1 else "End" if row["propagation"] == 1 else "Arr"
        yield row


def layers(test_id):
    path = os.path.join(DATA, f"{test_id:03d}.txt")
    if not os.path.exists(path):
        return []
    rows = [line.split() for line in open(path).readlines()[1:] if line.strip()]
    return [(int(float(r[0])), float(r[1]), float(r[2])) for r in rows]


def complete(profile):
    slab = [l for l in profile if l[0] == SLAB]
    weak = [l for l in profile if l[0] == WEAK]
    return slab and len(weak) == 1 and all(l[2] != MISSING for l in slab + weak)


def layer_table(test, profile):
    lines = [f"# van Herwijnen et al. (2016), PST {test['id']}: data/published_psts/vanherwijnen2016/"
             f"{test['id']:03d}.txt, written by scripts/published_scenes.py",
             "thickness_cm,density_kg_m3,grain_form,grain_size_mm,hand_hardness,role"]
    for role, thickness, density in profile:
        if role == BASE and density == MISSING:
            continue
        lines.append(f"{thickness:g},{density:g},,,,{ROLE[role]}")
    return "\n".join(lines) + "\n"


def scene_text(text, test, table):
    text = re.sub(r"set Profile file = .*", f"set Profile file = {table}", text)
    text = re.sub(r"set Weak layer from = .*", "set Weak layer from = role", text)
    text = re.sub(r"\n *set Propagation saw test = .*", "", text)
    text = re.sub(r"set Geometry from saw test = .*", "set Geometry from saw test = false", text)
    text = text.replace("subsection Snowpack\n", f"subsection Snowpack\n  set Slope angle [deg] = {test['slope_deg']:g}\n", 1)
    column = test["column_cm"] / 100
    text = text.replace("subsection PST\n", f"subsection PST\n  set Column length [m] = {column:.4g}\n", 1)
    text = fit_template_to_test(text, test["weak_cm"] / 100, column)
    body = text[text.index("set Scene"):]
    header = (f"# PST {test['id']} of van Herwijnen et al. (2016) (data/published_psts/vanherwijnen2016/), written by\n"
              "# scripts/published_scenes.py from scenes/pst_pit_65798.prm: the test's slab and weak layer\n"
              f"# ({table}), slope and column; the weak layer's material is the study's\n"
              "# (scenes/published/published_psts.prm).\n")
    return header + body


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("anticrack", nargs="?", default=os.path.join(ROOT, "build", "app", "anticrack"))
    parser.add_argument("--every", type=int, default=8)
    args = parser.parse_args()
    os.makedirs(OUT, exist_ok=True)
    for old in os.listdir(OUT):
        if old.startswith("vh2016_"):
            os.remove(os.path.join(OUT, old))
    chosen = [t for t in tests() if complete(layers(t["id"]))][::args.every]
    paths, observed = [], {}
    for test in chosen:
        name = f"vh2016_{test['id']:03d}"
        with open(os.path.join(OUT, name + ".csv"), "w") as f:
            f.write(layer_table(test, layers(test["id"])))
        paths.append(os.path.join(OUT, name + ".prm"))
        with open(paths[-1], "w") as f:
            f.write(scene_text(template(), test, name + ".csv"))
        observed[name + ".prm"] = test
    kept, refused = check_scenes(args.anticrack, paths)
    for name, _ in refused:
        os.remove(os.path.join(OUT, name[:-4] + ".csv"))
    write_refused(OUT, "PSTs of van Herwijnen et al. (2016)", "scripts/published_scenes.py",
                  [(n[:-4], f"{observed[n]['outcome']} from {observed[n]['rc_cm']:.1f} cm", r) for n, r in refused])
    with open(os.path.join(OUT, "observed.csv"), "w") as f:
        f.write("# The observations of the published study's tests (scripts/published_scenes.py from\n"
                "# data/published_psts/vanherwijnen2016/psts.txt), for scripts/field_score.py --observed.\n")
        w = csv.writer(f)
        w.writerow(["test", "propagation", "cut_length_m", "column_length_m", "collapse_height_m", "failed_depth_m",
                    "source"])
        for name in kept:
            t = observed[name]
            w.writerow([name[:-4], t["outcome"], f"{t['rc_cm'] / 100:.4f}", f"{t['column_cm'] / 100:.4f}",
                        f"{t['dy_cm'] / 100:.5f}" if t["dy_cm"] != MISSING else "", f"{t['slab_cm'] / 100:.3f}",
                        "van Herwijnen et al. (2016)"])
    total = sum(1 for _ in tests())
    write_pipeline(os.path.join(OUT, "published_psts.prm"),
                   f"""# The published study: PSTs of van Herwijnen et al. (2016) (J. Glaciol. 62(236), 997-1007), every
# {args.every}th of the {sum(1 for t in tests() if complete(layers(t['id'])))} of {total} whose slab and weak layer densities are all measured, {len(kept)} of
# which make a scene (scenes/published/refused.md says why the others do not), predicted with the
# default pipeline's DEM weak layer (scenes/pipeline.prm), without sensitivity runs.
# scripts/field_score.py scores the predictions against observed.csv (docs/validation.md).
# Written by scripts/published_scenes.py.
#
#   anticrack run scenes/published/published_psts.prm -o out/published --material-cache out/material_cache && \\
#     scripts/field_score.py out/published --observed scenes/published/observed.csv
""", kept)
    print(f"{len(kept)} scenes, {len(refused)} refused (scenes/published/refused.md); scenes/published/published_psts.prm")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes the field study's scenes: one PST scene per propagation saw test of the shared SnowPilot
pits (data/field_psts/snowpilot_psts.csv, the pits' CAAML files), from the template
scenes/pst_pit_65798.prm with the pit's file and the test's number swapped; keeps the scenes that
`anticrack check` accepts and lists the others with the reason it gives (scenes/field/refused.md);
writes the pipeline that runs them all (scenes/field/field_psts.prm).

The scenes take nothing from the test's result: the profile gives the slab, the failed layer's
depth and thickness, the slope and the column; the saw test's outcome and cut length are only
compared with, in scripts/field_score.py.

    scripts/field_scenes.py build/app/anticrack
"""
import csv
import os
import re
import sys

from scene_study import (ROOT, check_scenes, fit_template_to_test, template, write_own_weak_layer_pipeline,
                         write_pipeline, write_refused)

FIELD = os.path.join(ROOT, "scenes", "field")
DATA = os.path.join(ROOT, "data", "field_psts")


def scene_text(text, pit_file, test_number, pit, row):
    text = fit_template_to_test(text, float(row["wl_thickness_cm"]) / 100, float(row["column_cm"]) / 100)
    text = re.sub(r"set Profile file = .*", f"set Profile file = ../../data/field_psts/snowpilot/{pit_file}", text)
    text = re.sub(r"set Propagation saw test = .*", f"set Propagation saw test = {test_number}", text)
    body = text[text.index("set Scene"):]
    header = (f"# Field PST {test_number} of SnowPilot pit {pit} (data/field_psts/snowpilot/{pit_file}), written by\n"
              "# scripts/field_scenes.py from scenes/pst_pit_65798.prm: the pit's slab, failed layer, slope and\n"
              "# column; the weak layer's material is the field study's (scenes/field/field_psts.prm).\n")
    return header + body


def main():
    anticrack = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "app", "anticrack")
    rows = list(csv.DictReader(open(os.path.join(DATA, "snowpilot_psts.csv"))))
    os.makedirs(FIELD, exist_ok=True)
    for old in os.listdir(FIELD):
        if old.startswith("pit_") and old.endswith(".prm"):
            os.remove(os.path.join(FIELD, old))
    seen, paths, observed = {}, [], {}
    for row in rows:
        pit = row["pit"]
        seen[pit] = seen.get(pit, 0) + 1
        name = f"pit_{pit}_pst{seen[pit]}.prm"
        paths.append(os.path.join(FIELD, name))
        observed[name] = f"{row['outcome']} at {row['cut_cm']} cm"
        with open(paths[-1], "w") as f:
            f.write(scene_text(template(), row["file"], seen[pit], pit, row))
    kept, refused = check_scenes(anticrack, paths)
    write_refused(FIELD, "Field PSTs of data/field_psts", "scripts/field_scenes.py", [(n[:-4], observed[n], r) for n, r in refused])
    write_pipeline(os.path.join(FIELD, "field_psts.prm"),
                   f"""# The field study: every propagation saw test of the shared SnowPilot pits that makes a scene
# ({len(kept)} of {len(rows)}; scenes/field/refused.md says why the others do not), predicted with the default
# pipeline's DEM weak layer (scenes/pipeline.prm: the same weak-layer scene, snow units and mesh,
# calibrated once and put at every test's failed layer), without sensitivity runs.
# scripts/field_score.py scores the predictions against the observations (docs/validation.md).
# Written by scripts/field_scenes.py.
#
#   anticrack run scenes/field/field_psts.prm -o out/field --material-cache out/material_cache &&
#     scripts/field_score.py out/field
""", kept)
    own, own_refused = write_own_weak_layer_pipeline(
        anticrack, os.path.join(FIELD, "field_psts_own_weak_layer.prm"),
        lambda n: f"""# The field study with each pit's own weak layer: the scenes of scenes/field/field_psts.prm whose
# pit gives its failed layer's density and grain size and whose class the weak layer scene can sample
# ({n} of {len(kept)}; scenes/field/refused_own_weak_layer.md says why the others not), each weak layer
# sampled at its pit's density and thickness in grains (Pipeline/Weak layer specimen = profile,
# docs/pipeline.md), one calibration per class. Written by scripts/field_scenes.py. The classes
# calibrated so far are kept in data/material_cache (its README): seed a cache with them.
#
#   cp -r data/material_cache out/material_cache
#   anticrack run scenes/field/field_psts_own_weak_layer.prm -o out/field_own --material-cache out/material_cache &&
#     scripts/field_score.py out/field_own
""", kept)
    with open(os.path.join(FIELD, "refused_own_weak_layer.md"), "w") as f:
        f.write("# Field PSTs without their own weak layer\n\nWritten by scripts/field_scenes.py: the scenes of "
                "scenes/field/field_psts.prm that scenes/field/field_psts_own_weak_layer.prm leaves out, with the "
                "reason `anticrack check` gives.\n\n| test | observed | reason |\n|---|---|---|\n")
        for name, reason in own_refused:
            f.write(f"| {name[:-4]} | {observed[name]} | {reason.replace('|', '/')} |\n")
    print(f"{len(kept)} scenes, {len(refused)} refused (scenes/field/refused.md); scenes/field/field_psts.prm; "
          f"{len(own)} with their own weak layer (scenes/field/field_psts_own_weak_layer.prm)")


if __name__ == "__main__":
    main()

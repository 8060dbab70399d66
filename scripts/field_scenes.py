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
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FIELD = os.path.join(ROOT, "scenes", "field")
DATA = os.path.join(ROOT, "data", "field_psts")


def scene_text(template, pit_file, test_number, pit):
    text = re.sub(r"set Profile file = .*", f"set Profile file = ../../data/field_psts/snowpilot/{pit_file}", template)
    text = re.sub(r"set Propagation saw test = .*", f"set Propagation saw test = {test_number}", text)
    body = text[text.index("set Scene"):]
    header = (f"# Field PST {test_number} of SnowPilot pit {pit} (data/field_psts/snowpilot/{pit_file}), written by\n"
              "# scripts/field_scenes.py from scenes/pst_pit_65798.prm: the pit's slab, failed layer, slope and\n"
              "# column; the weak layer's material is the field study's (scenes/field/field_psts.prm).\n")
    return header + body


def main():
    anticrack = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "app", "anticrack")
    template = open(os.path.join(ROOT, "scenes", "pst_pit_65798.prm")).read()
    rows = list(csv.DictReader(open(os.path.join(DATA, "snowpilot_psts.csv"))))
    os.makedirs(FIELD, exist_ok=True)
    for old in os.listdir(FIELD):
        if old.startswith("pit_") and old.endswith(".prm"):
            os.remove(os.path.join(FIELD, old))
    seen, kept, refused = {}, [], []
    for row in rows:
        pit = row["pit"]
        seen[pit] = seen.get(pit, 0) + 1
        name = f"pit_{pit}_pst{seen[pit]}.prm"
        path = os.path.join(FIELD, name)
        with open(path, "w") as f:
            f.write(scene_text(template, row["file"], seen[pit], pit))
        check = subprocess.run([anticrack, "check", path], capture_output=True, text=True)
        if check.returncode == 0:
            kept.append(name)
        else:
            os.remove(path)
            reason = " ".join((check.stderr or check.stdout).split()).replace(ROOT + "/", "")
            reason = re.sub(r"^-+ anticrack: invalid input \(nothing was written\) ", "", reason)
            reason = re.sub(r"\s*-{5,}\s*$", "", reason)
            refused.append((name, row, reason))
    with open(os.path.join(FIELD, "refused.md"), "w") as f:
        f.write("# Field PSTs that make no scene\n\nWritten by scripts/field_scenes.py: the saw tests of "
                "data/field_psts whose scene `anticrack check` refuses, with its reason.\n\n"
                "| test | observed | reason |\n|---|---|---|\n")
        for name, row, reason in refused:
            f.write(f"| {name[:-4]} | {row['outcome']} at {row['cut_cm']} cm | {reason.replace('|', '/')} |\n")
    write_pipeline(kept)
    print(f"{len(kept)} scenes, {len(refused)} refused (scenes/field/refused.md); scenes/field/field_psts.prm")
    return kept


def write_pipeline(scenes):
    """The study of all field PSTs: the default pipeline's weak layer and conversion to snow, once,
    then every field scene at the default pipeline's mesh, without sensitivity runs."""
    default = open(os.path.join(ROOT, "scenes", "pipeline.prm")).read()
    changes = re.search(r"set Snowpack scene changes = (.*)", default).group(1).strip()
    snow = default[default.index("subsection Snow units"):]
    listing = ", \\\n                         ".join(scenes)
    with open(os.path.join(FIELD, "field_psts.prm"), "w") as f:
        f.write(f"""# The field study: every propagation saw test of the shared SnowPilot pits that makes a scene
# ({len(scenes)} of 100; scenes/field/refused.md says why the others do not), predicted with the default
# pipeline's DEM weak layer (scenes/pipeline.prm: the same weak-layer scene, snow units and mesh,
# calibrated once and put at every test's failed layer), without sensitivity runs.
# scripts/field_score.py scores the predictions against the observations (docs/validation.md).
# Written by scripts/field_scenes.py.
#
#   anticrack run scenes/field/field_psts.prm -o out/field && scripts/field_score.py out/field
set Scene = pipeline

subsection Pipeline
  set Weak layer scene = ../shs_weak_layer.prm
  set Snowpack scenes  = {listing}
  set Snowpack scene changes = {changes}
  set Uncertainty      = none
end

{snow}""")


if __name__ == "__main__":
    main()

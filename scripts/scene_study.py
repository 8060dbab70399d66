"""What the field and the published studies' scene writers share (scripts/field_scenes.py,
scripts/published_scenes.py): keeping the scenes that `anticrack check` accepts, the list of the
refused ones with the reason it gives, and the pipeline scene that runs the kept ones with the
default pipeline's DEM weak layer, snow units and mesh."""
import os
import re
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def template():
    """The PST scene every study scene starts from: the default pipeline's field test."""
    return open(os.path.join(ROOT, "scenes", "pst_pit_65798.prm")).read()


def check_scenes(anticrack, paths):
    """Runs `anticrack check` on each scene; removes the refused ones. Returns (kept names,
    [(name, reason)])."""
    kept, refused = [], []
    for path in paths:
        name = os.path.basename(path)
        check = subprocess.run([anticrack, "check", path], capture_output=True, text=True)
        if check.returncode == 0:
            kept.append(name)
            continue
        os.remove(path)
        reason = " ".join((check.stderr or check.stdout).split()).replace(ROOT + "/", "")
        reason = re.sub(r"^-+ anticrack: invalid input \(nothing was written\) ", "", reason)
        reason = re.sub(r"\s*-{5,}\s*$", "", reason)
        refused.append((name, reason))
    return kept, refused


def write_refused(directory, what, writer, rows):
    """rows: (test name, observed, reason); writer: the script that wrote them."""
    with open(os.path.join(directory, "refused.md"), "w") as f:
        f.write(f"# {what} that make no scene\n\nWritten by {writer}: the saw tests whose scene "
                "`anticrack check` refuses, with its reason.\n\n| test | observed | reason |\n|---|---|---|\n")
        for name, observed, reason in rows:
            f.write(f"| {name} | {observed} | {reason.replace('|', '/')} |\n")


def write_pipeline(path, header, scenes, specimen="scene"):
    """The study of `scenes` (names relative to the pipeline's folder): the default pipeline's weak
    layer and conversion to snow, calibrated once (specimen "scene"), or once per class of the pits'
    weak layers (specimen "profile": Pipeline/Weak layer specimen), then every scene at the default
    pipeline's mesh, without sensitivity runs. `header`: the comment block that says what the study is."""
    default = open(os.path.join(ROOT, "scenes", "pipeline.prm")).read()
    changes = re.search(r"set Snowpack scene changes = (.*)", default).group(1).strip()
    snow = default[default.index("subsection Snow units"):]
    # The default's grain size is its pit's; here it is one weak layer for every test.
    snow = re.sub(r"  # d: .*\n(  # .*\n)*", "  # d: the default pipeline's (scenes/pipeline.prm): one weak layer for every test\n", snow)
    # A class of its own needs the own-weak-layer pipeline's sweeps (a lighter layer levels off later).
    weak_changes = ""
    if specimen == "profile":
        own = open(os.path.join(ROOT, "scenes", "pipeline_own_weak_layer.prm")).read()
        found = re.search(r"set Weak layer scene changes = (.*)", own)
        weak_changes = f"  set Weak layer scene changes = {found.group(1).strip()}\n" if found else ""
    listing = ", \\\n                         ".join(scenes)
    with open(path, "w") as f:
        f.write(header + f"""set Scene = pipeline

subsection Pipeline
  set Weak layer scene = ../shs_weak_layer.prm
{weak_changes}  set Snowpack scenes  = {listing}
  set Snowpack scene changes = {changes}
  set Uncertainty      = none
  set Weak layer specimen = {specimen}
end

{snow}""")


def write_own_weak_layer_pipeline(anticrack, path, header_of, scenes):
    """write_pipeline with each pit's own weak layer (specimen "profile"), keeping the scenes whose pit
    the pipeline accepts: `anticrack check` names a refused pit (no density, no grain size) or the
    pits of a class the weak layer scene cannot sample; those are left out and the check repeated.
    header_of(n): the comment block for n kept scenes. Returns (kept, [(scene, reason)])."""
    kept, refused = list(scenes), []
    while True:
        write_pipeline(path, header_of(len(kept)), kept, "profile")
        check = subprocess.run([anticrack, "check", path], capture_output=True, text=True)
        if check.returncode == 0:
            return kept, refused
        message = check.stderr or check.stdout
        problems = [p for p in re.split(r"\n  - ", message)[1:]]
        dropped = []
        for problem in problems:
            text = " ".join(problem.split()).replace(ROOT + "/", "")
            named = re.findall(r"snowpack scene \S*?([^/\s]+\.prm):", problem)
            named += [n for group in re.findall(r"\(the weak layers of ([^)]*)\)", problem) for n in group.split(", ")]
            text = re.sub(r"\s*-{5,}\s*$", "", text)
            if not named and refused and refused[-1][0] in dropped:
                # A class's reason, listed by the weak layer scene's reader on the lines after it.
                refused[-1] = (refused[-1][0], refused[-1][1] + ": " + text)
            for name in named:
                if name in kept and name not in dropped:
                    dropped.append(name)
                    refused.append((name, text))
        if not dropped:
            raise RuntimeError(f"{path}: `anticrack check` refuses the pipeline for a reason that names no scene:\n{message}")
        kept = [n for n in kept if n not in dropped]


# The template's illustrative weak layer collapses by 3 mm of its 2 cm (a strain of 0.15); in a study
# the pipeline replaces that layer with the calibrated one, whose collapse is its own lock-up strain
# times the layer's thickness. So that each scene is valid on its own too, the placeholder collapses
# by at most the same strain of a thinner layer.
TEMPLATE_COLLAPSE_HEIGHT_M = 0.003
TEMPLATE_COLLAPSE_STRAIN = 0.15
# The saw may cut up to 90 % of the column (the template's 0.9 m of a 1 m column).
SAW_TRAVEL_OVER_COLUMN = 0.9


def fit_template_to_test(text, weak_layer_thickness_m, column_length_m):
    """The template's placeholder collapse height and the saw's travel, for this test's weak
    layer and column."""
    collapse = min(TEMPLATE_COLLAPSE_HEIGHT_M, TEMPLATE_COLLAPSE_STRAIN * weak_layer_thickness_m)
    text = re.sub(r"set Collapse height \[m\] = .*", f"set Collapse height [m] = {collapse:.4g}", text)
    return re.sub(r"set Cut length \[m\] = .*", f"set Cut length [m] = {SAW_TRAVEL_OVER_COLUMN * column_length_m:.4g}",
                  text)

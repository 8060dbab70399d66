"""Edits of deal.II parameter-file texts for the Python test drivers (tests/app, tests/regression).

edit_scene(text, {"DEM/Steps": "500"}, insert={"DEM/Material": ["set X = 1"]}) sets existing
entries by their subsection path and adds lines right after a subsection opens. An entry or a
subsection that the text does not have is an error: a test must not silently run the unedited
scene after the example scenes change.
"""
import json
import os
import re
import subprocess
import tempfile


class SceneEditError(AssertionError):
    pass


def edit_scene(text, changes, insert=None, remove=()):
    """Sets `changes` {"DEM/Sample/Lattice size": "4, 3, 5", ...} in a .prm text; every entry must
    exist. `insert` {"DEM/Material": ["set X = 1"]} adds lines right after a subsection opens.
    `remove` ["Campaign", "DEM/Loading/Lag tolerance"] drops subsections and entries (each must
    exist): a scene made into another kind or variant must not keep the entries of the old one."""
    lines, path, done = [], [], set()
    removing = None  # depth of the subsection being dropped
    for line in text.splitlines():
        stripped = line.strip()
        opening = re.match(r"subsection\s+(.*\S)\s*$", stripped)
        if opening:
            path.append(opening.group(1))
            if removing is None and "/".join(path) in remove:
                removing = len(path)
                done.add("/".join(path))
        elif stripped == "end":
            path.pop()
            if removing is not None and len(path) < removing:
                removing = None
                continue
        if removing is not None:
            continue
        entry = re.match(r"(\s*)set\s+(.*?)\s*=\s*(.*)$", line)
        if entry and "/".join(path + [entry.group(2)]) in remove:
            done.add("/".join(path + [entry.group(2)]))
            continue
        if entry and "/".join(path + [entry.group(2)]) in changes:
            key = "/".join(path + [entry.group(2)])
            line = f"{entry.group(1)}set {entry.group(2)} = {changes[key]}"
            done.add(key)
        lines.append(line)
        if opening and insert and "/".join(path) in insert:
            lines += ["  " * len(path) + extra for extra in insert["/".join(path)]]
            done.add("/".join(path))
    missing = (set(changes) | set(insert or {}) | set(remove)) - done
    if missing:
        raise SceneEditError(f"the scene no longer has {sorted(missing)}; update the test that edits it")
    return "\n".join(lines) + "\n"


def paths_in(text):
    """Every subsection and entry path of a .prm text, as tuples (("Analysis", "Explicit"),
    ("PST", "Saw speed [m/s]"), ...): entry names may hold a "/" (units)."""
    found, path = set(), []
    for line in text.splitlines():
        stripped = line.strip()
        opening = re.match(r"subsection\s+(.*\S)\s*$", stripped)
        if opening:
            path.append(opening.group(1))
            found.add(tuple(path))
        elif stripped == "end":
            path.pop()
        else:
            entry = re.match(r"set\s+(.*?)\s*=", stripped)
            if entry:
                found.add(tuple(path + [entry.group(1)]))
    return found


def declared_paths(anticrack, text):
    """Every subsection and entry path (tuples, as paths_in) that `anticrack params` declares for the
    scene `text` (its kind and variants): the program's own declaration, not a copy of it."""
    with tempfile.TemporaryDirectory() as directory:
        scene = os.path.join(directory, "scene.prm")
        with open(scene, "w") as f:
            f.write(text)
        listing = subprocess.run([anticrack, "params", scene, "--format", "json"], capture_output=True,
                                 text=True, check=True).stdout
    paths = set()

    def visit(node, path):
        for key, value in node.items():
            paths.add(tuple(path + [key]))
            if isinstance(value, dict) and "value" not in value:  # a subsection
                visit(value, path + [key])
    visit(json.loads(listing), [])
    return paths


def as_analysis(text, analysis_type, anticrack, changes=None):
    """A snowpack scene as one of Analysis/Type `analysis_type` with `changes`, without the entries
    and subsections that the new analysis does not declare (as a user would delete them by hand);
    `anticrack` says which those are."""
    text = edit_scene(text, {**(changes or {}), "Analysis/Type": analysis_type})
    minimal = f"set Scene = snowpack\nsubsection Analysis\n  set Type = {analysis_type}\nend\n"
    declared = declared_paths(anticrack, minimal)
    present = paths_in(text)
    # The outermost undeclared paths: what is inside a dropped subsection goes with it.
    drop = ["/".join(p) for p in present if p not in declared and (len(p) == 1 or p[:-1] in declared)]
    return edit_scene(text, {}, remove=drop)

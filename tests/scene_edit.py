"""Edits of deal.II parameter-file texts for the Python test drivers (tests/app, tests/regression).

edit_scene(text, {"DEM/Steps": "500"}, insert={"DEM/Material": ["set X = 1"]}) sets existing
entries by their subsection path and adds lines right after a subsection opens. An entry or a
subsection that the text does not have is an error: a test must not silently run the unedited
scene after the example scenes change.
"""
import re


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
    """Every subsection and entry path of a .prm text ("Analysis/Explicit", "PST/Saw", ...)."""
    found, path = set(), []
    for line in text.splitlines():
        stripped = line.strip()
        opening = re.match(r"subsection\s+(.*\S)\s*$", stripped)
        if opening:
            path.append(opening.group(1))
            found.add("/".join(path))
        elif stripped == "end":
            path.pop()
        else:
            entry = re.match(r"set\s+(.*?)\s*=", stripped)
            if entry:
                found.add("/".join(path + [entry.group(1)]))
    return found


# What a dynamic PST scene sets that the other analyses do not declare (the snowpack reader refuses
# them there, naming the analysis they belong to): deleted by hand when a user turns a dynamic PST
# into a quasi-static one or an energy release rate.
ONLY_DYNAMIC = ["PST/Saw", "PST/Saw speed [m/s]", "Analysis/Explicit", "Output"]
ONLY_PST = ["Analysis/Crack detection", "Analysis/Crack band regularisation", "Analysis/Newton/Gravity steps"]


def as_analysis(text, analysis_type, changes=None):
    """A dynamic PST scene as one of Analysis/Type `analysis_type` with `changes`: the entries the
    new analysis does not declare (ONLY_DYNAMIC, and ONLY_PST for the energy release rate) dropped."""
    drop = {"quasi-static": ONLY_DYNAMIC, "energy release rate": ONLY_DYNAMIC + ONLY_PST}[analysis_type]
    present = paths_in(text)
    return edit_scene(text, {**(changes or {}), "Analysis/Type": analysis_type},
                      remove=[p for p in drop if p in present])

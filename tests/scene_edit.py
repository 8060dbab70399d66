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

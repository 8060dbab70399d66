#!/usr/bin/env python3
"""The maps match the tree: every source unit of fem/, coupling/ and params/ has a line in its
module's README table, and the root README's layout block names every source folder (each module,
each folder of dem/ and fem/), every test folder, every document of docs/ and every unit of
dem/sample/. A unit without a line, or a line for a unit that is gone,
fails with the file and the name to add or remove.

    check_maps.py SOURCE_DIR
"""
import os
import re
import sys


def units(folder, recursive):
    """Source units (stems of .h/.cpp files) under `folder`, as 'sub/stem' when recursive."""
    found = set()
    for root, _, files in os.walk(folder):
        if not recursive and root != folder:
            continue
        for f in files:
            stem, ext = os.path.splitext(f)
            if ext in (".h", ".cpp"):
                rel = os.path.relpath(os.path.join(root, stem), folder)
                found.add(rel.replace(os.sep, "/"))
    return found


def table_names(readme):
    """The unit names a README table gives: `stem.*`, `stem.h`, `stem.cpp`, `dir/stem.*`, ..."""
    names = set()
    for line in open(readme, encoding="utf-8"):
        if not line.startswith("| `"):
            continue
        first = line.split("|")[1]
        for name in re.findall(r"`([^`]+)`", first):
            names.add(re.sub(r"\.(\*|h|cpp)$", "", name))
    return names


def entry(block, name):
    """The text of the layout block's entry `name` (its line and the indented lines after it)."""
    match = re.search(rf"^{re.escape(name)}(.*?)(?=^\S|\Z)", block, re.S | re.M)
    if not match:
        raise SystemExit(f"README.md layout block: no entry {name}")
    return match.group(1)


def main():
    source = sys.argv[1]
    problems = []
    for module, recursive in (("fem", True), ("coupling", False), ("params", False)):
        readme = os.path.join(source, module, "README.md")
        have, listed = units(os.path.join(source, module), recursive), table_names(readme)
        for name in sorted(have - listed):
            problems.append(f"{module}/README.md: no line for the unit {module}/{name}")
        for name in sorted(listed - have):
            problems.append(f"{module}/README.md: a line for {module}/{name}, which is not in the tree")
    text = open(os.path.join(source, "README.md"), encoding="utf-8").read()
    block = text[text.index("```\nutil/"):]
    block = block[:block.index("```", 4)]
    tests = [d for d in os.listdir(os.path.join(source, "tests")) if os.path.isdir(os.path.join(source, "tests", d))]
    docs = [f for f in os.listdir(os.path.join(source, "docs")) if f.endswith(".md")]
    samples = units(os.path.join(source, "dem", "sample"), False)
    tests_line = entry(block, "tests/")
    for name in sorted(tests):
        if not re.search(rf"\b{re.escape(name)}/", tests_line):
            problems.append(f"README.md layout block: tests/{name}/ is not named (write `{name}/` in the tests/ line)")
    docs_line = entry(block, "docs/")
    for name in sorted(docs):
        if name not in docs_line:
            problems.append(f"README.md layout block: docs/{name} is not named in the docs/ line")
    sample_line = entry(block, "dem/sample/")
    for name in sorted(samples):
        if name.replace("_", " ") not in sample_line.replace("_", " "):
            problems.append(f"README.md layout block: dem/sample/{name} is not named in the dem/sample/ line")
    # Every source folder (a module, and each folder of dem/ and fem/) has its place in the block.
    for module in ("util", "profile", "dem", "params", "fem", "coupling", "app"):
        folders = [module] + [f"{module}/{d}" for d in sorted(os.listdir(os.path.join(source, module)))
                              if os.path.isdir(os.path.join(source, module, d))]
        for folder in folders:
            if units(os.path.join(source, folder), False) and f"{folder}/" not in block:
                problems.append(f"README.md layout block: {folder}/ holds source units and is not named")
    for p in problems:
        print(p)
    print(f"{len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())

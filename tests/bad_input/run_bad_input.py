#!/usr/bin/python3
"""The bad-input corpus: every case of cases.json must be refused with exit code 2, a message naming the
file, the entry and its allowed range, and nothing written.

Usage: run_bad_input.py --anticrack PATH --work-dir DIR [--case NAME ...] [--timeout S] [--list]

The runner copies cases/ to WORK/cases and runs every command from there (the working directory matters:
a relative DEM/Sample/Snapshot file is relative to the working directory, a snowpack Material file to
the scene's folder). The HDF5 inputs, the binary scene and the 50 MB profile are generated into
WORK/cases/generated/ (from runs of cases/helpers/source_dem.prm and source_campaign.prm, a second or
two each), so that no binary file is shipped.

A manifest entry: name, file (relative to cases/; generated files under generated/), command (run,
check, calibrate or resume), expect_in_message (strings the standard error must contain, compared
with runs of white space collapsed, as deal.II wraps its messages), why; optionally generate (the
generator of `file`) and, for resume, prepare {"scene", "damage"}: the scene is run into WORK/<case>/run
first, its checkpoint.h5 then truncated or corrupted (damage null: left intact, the case's own scene is
another one), and `run FILE -o WORK/<case>/run --resume` must change no file there.
Two controls come first: `check` of an intact snapshot scene and of an intact material-file scene
(cases/helpers/) must pass. Every other command gets `-o WORK/not_created/run`, and WORK/not_created must not exist afterwards.
A command that runs longer than --timeout (20 s) is stopped and the case fails.
One PASS/FAIL line per case; exit code 0 when every case passed, 1 otherwise. Standard library only.
"""
import argparse
import json
import os
import random
import shutil
import signal
import struct
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


class Corpus:
    def __init__(self, anticrack, work, timeout):
        self.anticrack, self.work, self.timeout = anticrack, work, timeout
        self.cases = os.path.join(work, "cases")
        self.generated = os.path.join(self.cases, "generated")
        self.made = {}

    # ------------------------------------------------------------------------------- running
    def execute(self, args, timeout=None):
        """Runs anticrack from the cases folder; returns (exit code or None when stopped, stdout,
        stderr, seconds). A process that outlives the timeout gets SIGTERM, then SIGKILL."""
        start = time.time()
        process = subprocess.Popen([self.anticrack, *args], cwd=self.cases, stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, start_new_session=True)
        try:
            out, err = process.communicate(timeout=timeout or self.timeout)
            code = process.returncode
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGTERM)
            try:
                out, err = process.communicate(timeout=5)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                out, err = process.communicate()
            code = None
        return (code, out.decode("utf-8", "replace"), err.decode("utf-8", "replace"), time.time() - start)

    def helper_run(self, scene, out):
        """Runs a helper scene (must succeed) into `out`."""
        if os.path.exists(out):
            shutil.rmtree(out)
        code, stdout, stderr, _ = self.execute(["run", scene, "-o", out], timeout=120)
        if code != 0:
            raise RuntimeError(f"helper run {scene} exited with {code}:\n{stdout}\n{stderr}")
        return out

    # ---------------------------------------------------------------------------- generators
    def source_dem(self):
        if "source_dem" not in self.made:
            self.made["source_dem"] = self.helper_run("helpers/source_dem.prm", os.path.join(self.work, "source_dem_run"))
        return self.made["source_dem"]

    def source_campaign(self):
        if "source_campaign" not in self.made:
            self.made["source_campaign"] = self.helper_run("helpers/source_campaign.prm",
                                                           os.path.join(self.work, "source_campaign_run"))
        return self.made["source_campaign"]

    @staticmethod
    def random_bytes(n, seed):
        rng = random.Random(seed)
        return bytes(rng.randrange(256) for _ in range(n))

    def generate(self, what):
        """Makes generated/<file> for generator `what`; returns nothing (idempotent)."""
        if what in self.made:
            return
        os.makedirs(self.generated, exist_ok=True)
        path = lambda name: os.path.join(self.generated, name)  # noqa: E731
        if what == "binary_scene":
            data = self.random_bytes(4096, 1)
            target = path("binary_scene.prm")
        elif what.startswith("snapshot_"):
            with open(os.path.join(self.source_dem(), "snapshots", "snapshot_000000.h5"), "rb") as f:
                intact = f.read()
            kind = what[len("snapshot_"):]
            if kind == "valid":
                data = intact
            elif kind == "truncated":
                data = intact[:len(intact) // 2]
            elif kind == "corrupt":
                data = self.random_bytes(len(intact), 2)
            elif kind == "scrambled":  # the 8-byte HDF5 signature and superblock start kept, the rest random
                data = intact[:96] + self.random_bytes(len(intact) - 96, 3)
            elif kind == "nan_radius":
                # particles/radius: a run of exactly N copies of R = 1e-3 m (the bonds' radii are another
                # run, of the bond count); its first value becomes NaN.
                r, n = struct.pack("<d", 1e-3), 8 * 8 * 12
                at = intact.find(r * n)
                while at >= 0 and intact[at + 8 * n:at + 8 * n + 8] == r or at > 0 and intact[at - 8:at] == r:
                    at = intact.find(r * n, at + 8)
                if at < 0:
                    raise RuntimeError("snapshot_nan_radius: the particle radii were not found in the snapshot")
                data = intact[:at] + struct.pack("<d", float("nan")) + intact[at + 8:]
            else:
                raise ValueError(what)
            target = path(f"snapshot_{kind}.h5")
        elif what.startswith("campaign_"):
            with open(os.path.join(self.source_campaign(), "campaign.h5"), "rb") as f:
                intact = f.read()
            kind = what[len("campaign_"):]
            data = intact[:len(intact) // 2] if kind == "truncated" else self.random_bytes(len(intact), 4)
            target = path(f"campaign_{kind}.h5")
        elif what == "profile_50_megabytes":
            # The real pit with 50 MB of comment after its XML declaration: still well-formed XML,
            # refused by its size before it is parsed (a profile is a few kB).
            with open(os.path.join(self.cases, "profiles", "snowpits-18288-caaml.xml"), "rb") as f:
                intact = f.read()
            end = intact.index(b"?>") + 2
            data = intact[:end] + b"\n<!-- " + b"padding " * (50 * 1024 * 1024 // 8) + b"-->" + intact[end:]
            target = path("18288_50_megabytes.xml")
        else:
            raise ValueError(f"unknown generator {what}")
        with open(target, "wb") as f:
            f.write(data)
        self.made[what] = target

    # ------------------------------------------------------------------------------ the cases
    def prepare_resume(self, case):
        """Runs prepare.scene into WORK/<case>/run and damages its checkpoint; returns the directory."""
        out = os.path.join(self.work, case["name"], "run")
        self.helper_run(case["prepare"]["scene"], out)
        checkpoint = os.path.join(out, "checkpoint.h5")
        damage = case["prepare"]["damage"]
        if damage:
            with open(checkpoint, "rb") as f:
                intact = f.read()
            data = intact[:len(intact) // 2] if damage == "truncated" else self.random_bytes(len(intact), 5)
            with open(checkpoint, "wb") as f:
                f.write(data)
        return out

    @staticmethod
    def state_of(directory):
        """{relative path: (size, mtime_ns)} of every file and folder under `directory`."""
        state = {}
        for root, dirs, files in os.walk(directory):
            for name in dirs + files:
                full = os.path.join(root, name)
                st = os.stat(full)
                state[os.path.relpath(full, directory)] = (st.st_size, st.st_mtime_ns)
        return state

    def run_case(self, case):
        """Returns (passed, details)."""
        if case.get("generate"):
            self.generate(case["generate"])
        not_created = os.path.join(self.work, "not_created")
        if os.path.exists(not_created):
            shutil.rmtree(not_created)
        command = case["command"]
        if command == "resume":
            out = self.prepare_resume(case)
            args = ["run", case["file"], "-o", out, "--resume"]
            watched = out
        elif command == "check":
            args, watched = ["check", case["file"]], None
        elif command in ("run", "calibrate"):
            args, watched = [command, case["file"], "-o", os.path.join(not_created, "run")], None
        else:
            raise ValueError(f"{case['name']}: unknown command {command}")
        before = self.state_of(watched) if watched else None
        cases_before = self.state_of(self.cases)
        code, stdout, stderr, seconds = self.execute(args)
        problems = []
        if code is None:
            problems.append(f"still running after {self.timeout} s (stopped)")
        elif code < 0:
            problems.append(f"killed by signal {-code} ({signal.Signals(-code).name})")
        elif code != 2:
            problems.append(f"exit code {code}, expected 2")
        message = " ".join(stderr.split())
        missing = [needle for needle in case["expect_in_message"] if needle not in message]
        if missing:
            problems.append("the message lacks " + ", ".join(repr(m) for m in missing))
        if watched:
            after = self.state_of(watched)
            changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
            if changed:
                problems.append(f"changed in {os.path.relpath(watched, self.work)}: {', '.join(changed[:8])}")
        if os.path.exists(not_created):
            written = sorted(self.state_of(not_created))
            problems.append(f"WORK/not_created was created ({len(written)} entries: {', '.join(written[:6])})")
        cases_after = self.state_of(self.cases)
        stray = sorted(k for k in set(cases_after) - set(cases_before) if not k.startswith("generated"))
        if stray:
            problems.append(f"files written into the working directory: {', '.join(stray[:6])}")
        details = {"command": " ".join(["anticrack", *args]), "exit": code, "seconds": round(seconds, 2),
                   "problems": problems, "stderr": message[:600], "stdout_tail": " ".join(stdout.split())[-300:]}
        return not problems, details


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--anticrack", required=False)
    parser.add_argument("--work-dir", required=False)
    parser.add_argument("--case", action="append", default=[], help="run only this case (repeatable)")
    parser.add_argument("--timeout", type=float, default=20.0, help="seconds before a command is stopped (20)")
    parser.add_argument("--list", action="store_true", help="list the cases and exit")
    parser.add_argument("--json", help="also write the results to this JSON file")
    parser.add_argument("--verbose", action="store_true", help="print the command and message of every case")
    args = parser.parse_args()
    with open(os.path.join(HERE, "cases.json")) as f:
        cases = json.load(f)
    if args.list:
        for case in cases:
            print(f"{case['name']:40s} {case['command']:9s} {case['file']}")
        return 0
    if not args.anticrack or not args.work_dir:
        parser.error("--anticrack and --work-dir are required")
    names = {c["name"] for c in cases}
    unknown = [n for n in args.case if n not in names]
    if unknown:
        parser.error(f"unknown case(s) {unknown}; --list lists them")
    selected = [c for c in cases if not args.case or c["name"] in args.case]

    work = os.path.abspath(args.work_dir)
    os.makedirs(work, exist_ok=True)
    corpus = Corpus(os.path.abspath(args.anticrack), work, args.timeout)
    if os.path.exists(corpus.cases):
        shutil.rmtree(corpus.cases)
    shutil.copytree(os.path.join(HERE, "cases"), corpus.cases)

    # Controls: the intact versions of what the cases break must be accepted, or the cases prove nothing.
    failed = 0
    corpus.generate("snapshot_valid")
    for scene in ("helpers/dem_snapshot_valid.prm", "helpers/snow_material_valid.prm"):
        code, _, stderr, _ = corpus.execute(["check", scene])
        ok = code == 0
        failed += not ok
        print(f"{'CONTROL ok' if ok else 'CONTROL FAILED'} check {scene}" + ("" if ok else f": exit {code}: "
              + " ".join(stderr.split())[:400]), flush=True)

    results = []
    for case in selected:
        try:
            passed, details = corpus.run_case(case)
        except Exception as error:  # a helper run or a generator failed: the case cannot be judged
            passed, details = False, {"problems": [f"set-up failed: {error}"], "command": "", "stderr": ""}
        failed += not passed
        print(f"{'PASS' if passed else 'FAIL'} {case['name']}" +
              ("" if passed else ": " + "; ".join(details["problems"])), flush=True)
        if not passed or args.verbose:
            print(f"    cwd {corpus.cases}\n    $ {details['command']}\n    stderr: {details['stderr']}", flush=True)
        results.append({"name": case["name"], "passed": passed, **details})
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    print(f"{sum(r['passed'] for r in results)} of {len(selected)} cases passed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Faults survived: runs killed by SIGKILL and resumed, and files of earlier runs that cannot be used
(registered with ctest by tests/faults/CMakeLists.txt; docs/resume.md).

Usage: run_fault_tests.py --anticrack PATH --source-dir DIR --work-dir DIR CASE [CASE ...]
       run_fault_tests.py --list

A kill is `kill -9` of the run's whole process group (its worker processes included), as a power cut,
an out-of-memory kill or a cluster's wall time would end it. The kill points are chosen from the
run's own progress (a line of its output, or the moment a named file has been written under its
temporary name: ANTICRACK_KILL_WHILE_WRITING, util/atomic_file.cpp), never from a clock, so that a
slow machine moves them only within the run's own sequence. After every kill the run is resumed
with --resume; the last resume runs to its end, and its answers are compared with those of an
uninterrupted run of the same scene.
The scenes are those of tests/app/run_app_tests.py (the tiny pipeline of its pipeline_small case).
"""
import json
import os
import re
import shutil
import signal
import subprocess
import sys


sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "app"))
import run_app_tests as app  # noqa: E402  (the tiny scenes and the helpers of the app tests)

CASES = {}
check = app.check


def case(function):
    CASES[function.__name__] = function
    return function


# ------------------------------------------------------------------------------------------ kills
class KillPoint:
    """Where to kill: when a line of the run's standard output contains `line` (after `after` such
    lines), or when the file whose path ends with `writing` has been written but not yet renamed."""

    def __init__(self, name, line=None, writing=None, after=1):
        self.name, self.line, self.writing, self.after = name, line, writing, after


def run_and_kill(arguments, point, cwd, timeout):
    """Runs anticrack in a process group of its own and kills the whole group with SIGKILL at
    `point`. Returns (killed, exit code, output): `killed` is False when the run ended first."""
    environment = dict(os.environ)
    if point.writing:
        environment["ANTICRACK_KILL_WHILE_WRITING"] = point.writing
    process = subprocess.Popen([app.PATHS.anticrack, *arguments], cwd=cwd, env=environment, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True)
    output, seen, killed = [], 0, False
    try:
        for line in process.stdout:
            output.append(line)
            if point.line and point.line in line:
                seen += 1
                if seen == point.after:
                    os.killpg(process.pid, signal.SIGKILL)
                    killed = True
                    break
        process.wait(timeout=timeout)
    finally:
        try:  # workers left behind by a kill of the group are gone with it; a hung run is not left running
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    rest = process.stdout.read()
    output.append(rest)
    process.stdout.close()
    if point.writing:
        killed = process.returncode == -signal.SIGKILL
    return killed, process.returncode, "".join(output)


def resume_through(arguments, points, cwd, timeout=300, before_each=None, after_each=None):
    """Runs `arguments` and kills it at each point in turn, each time resuming with --resume; then
    resumes once more to its end. `before_each(point)` returns what `after_each(point, output, it)`
    is given after the kill. Returns the last run's output."""
    for k, point in enumerate(points):
        state = before_each(point) if before_each else None
        killed, code, output = run_and_kill(arguments + (["--resume"] if k else []), point, cwd, timeout)
        check(killed, f"kill point `{point.name}` was never reached (exit {code}):\n{output[-3000:]}")
        if after_each:
            after_each(point, output, state)
    result = subprocess.run([app.PATHS.anticrack, *arguments, "--resume"], cwd=cwd, capture_output=True, text=True,
                            timeout=timeout)
    check(result.returncode == 0, f"the last --resume exited with {result.returncode}:\n"
          f"{result.stdout[-4000:]}\n{result.stderr[-4000:]}")
    return result.stdout


def without_run_specifics(value, directory):
    """A result with what differs between two runs of one scene removed: wall times, and the output
    directory in the paths it names."""
    if isinstance(value, dict):
        return {k: without_run_specifics(v, directory) for k, v in value.items() if k not in ("wall_s", "timing")}
    if isinstance(value, list):
        return [without_run_specifics(v, directory) for v in value]
    if isinstance(value, str):
        return value.replace(directory, "<out>")
    return value


def differences(a, b, path=""):
    """Where two JSON values differ (bit for bit for numbers), as a list of paths."""
    if isinstance(a, dict) and isinstance(b, dict):
        found = [f"{path}/{k}: only in one" for k in set(a) ^ set(b)]
        for k in set(a) & set(b):
            found += differences(a[k], b[k], f"{path}/{k}")
        return found
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        return [d for k, (x, y) in enumerate(zip(a, b)) for d in differences(x, y, f"{path}/{k}")]
    return [] if a == b else [f"{path}: {a!r} != {b!r}"]


def completed_tests(campaign_directory):
    """The campaign tests whose summary.json says completed."""
    tests = os.path.join(campaign_directory, "tests")
    done = []
    for name in sorted(os.listdir(tests)) if os.path.isdir(tests) else []:
        path = os.path.join(tests, name, "summary.json")
        if os.path.exists(path) and json.load(open(path)).get("status") == "completed":
            done.append(name)
    return done


def compare_pipelines(reference, resumed):
    """Every result of the resumed pipeline's summary.json equal to the uninterrupted one's, bit for
    bit, and the weak layer's material files byte for byte."""
    a, b = (json.load(open(os.path.join(d, "summary.json"))) for d in (reference, resumed))
    check(b["status"] == "completed", f"resumed pipeline status {b['status']}")
    found = differences(without_run_specifics(a["results"], reference), without_run_specifics(b["results"], resumed))
    check(not found, "the resumed pipeline's results differ from the uninterrupted run's:\n  " + "\n  ".join(found[:20]))
    for name in ("material.prm", "material_snow.prm"):
        # Every value, to the digit; the provenance (paths, and the campaign file's hash, which covers
        # its paths and its tests' wall times) names the run's own directory.
        x, y = ([line.replace(d, "<out>") for line in open(os.path.join(d, "weak_layer", name))
                 if not line.lstrip().startswith("#") and "sha256" not in line] for d in (reference, resumed))
        check(x == y, f"weak_layer/{name} differs from the uninterrupted run's: " +
              str([(p, q) for p, q in zip(x, y) if p != q][:5]))
    # The campaign's failure points and every test's history, bit for bit.
    app.compare_campaigns(*(os.path.join(d, "weak_layer", "campaign") for d in (reference, resumed)))
    return a["results"]


def check_no_torn_file_read(directory):
    """What a kill while writing leaves is the temporary (NAME.tmp), never a torn NAME."""
    for root, _, files in os.walk(directory):
        for name in files:
            if name.endswith(".json") and not name.endswith(".tmp"):
                try:
                    json.load(open(os.path.join(root, name)))
                except ValueError:
                    raise app.Failure(f"{os.path.join(root, name)} is torn")


def pipeline_kill_points(out):
    """The kill points of the tiny pipeline, in the order the run reaches them. Its weak layer is a
    campaign of 5 angles x 1 realization on 2 worker processes, then its calibration; then two PSTs
    side by side and 6 uncertainty runs."""
    return [
        # before any summary exists: the campaign has started its first tests
        KillPoint("campaign started, no summary yet", line="anticrack campaign:"),
        # during a campaign test: one test has completed, its neighbour is running
        KillPoint("during a campaign test", line=": completed,", after=1),
        # while files are written: a test's history, campaign.h5, the calibration's summary
        KillPoint("writing a campaign test's history.h5", writing="/history.h5"),
        KillPoint("writing campaign.h5", writing="campaign/campaign.h5"),
        KillPoint("writing the weak layer's material (snow units)", writing="weak_layer/material_snow.prm"),
        KillPoint("writing the weak layer's summary.json", writing="weak_layer/summary.json"),
        # between stages: the pipeline records the weak layer, before the PSTs start
        KillPoint("between stages (the pipeline's first summary.json)", writing=os.path.join(out, "summary.json")),
        # during a PST: both PSTs are running
        KillPoint("during the PSTs", line="[flat] "),
        KillPoint("writing a PST's summary.json", writing="steep/summary.json"),
        # during the uncertainty runs: one has completed, others are running
        KillPoint("during the uncertainty runs", line="pipeline uncertainty", after=1),
    ]


@case
def pipeline_killed(work):
    """The tiny pipeline killed by SIGKILL at 10 points (before any summary, in a campaign test, while
    a test's history, campaign.h5, the material and the calibration's summary are written, between
    stages, during the PSTs and while one's summary is written, during the uncertainty runs), resumed
    after each: every result of summary.json and the material files equal to an uninterrupted run's
    bit for bit, tests completed before a kill not run again, no torn file left."""
    pipeline, _, _, _ = app.pipeline_files(work)
    reference = os.path.join(work, "reference")
    app.anticrack("run", pipeline, "-o", reference, cwd=work)
    out = os.path.join(work, "killed")
    campaign = os.path.join(out, "weak_layer", "campaign")
    log = []

    def after_kill(point, output, completed_before):
        # The tests completed before this run started were not run again.
        skipped = output.count("completed earlier, skipped")
        check(skipped == len(completed_before) or "weak layer: completed earlier" in output,
              f"`{point.name}`: {len(completed_before)} tests had completed, {skipped} were skipped:\n{output[-3000:]}")
        check_no_torn_file_read(out)
        log.append(f"{point.name}: killed, {len(completed_tests(campaign))} campaign tests completed, summary.json "
                   f"{'present' if os.path.exists(os.path.join(out, 'summary.json')) else 'absent'}")

    stdout = resume_through(["run", pipeline, "-o", out], pipeline_kill_points(out), work,
                            before_each=lambda point: completed_tests(campaign), after_each=after_kill)
    check(re.search(r"pipeline uncertainty \S+: completed earlier", stdout),
          f"the uncertainty runs completed before the kill were run again:\n{stdout[-3000:]}")
    results = compare_pipelines(reference, out)
    print("\n".join(log))
    print(f"resumed pipeline == uninterrupted one, bit for bit: flat critical cut {results['analyses']['flat'].get('critical_cut_length_m')} m")


def without_wall_times(value):
    """A snowpack run's results without its wall times and throughput (they differ between runs)."""
    if isinstance(value, dict):
        return {k: without_wall_times(v) for k, v in value.items() if "wall" not in k and not k.endswith("_per_s_per_rank")}
    if isinstance(value, list):
        return [without_wall_times(v) for v in value]
    return value


@case
def critical_cut_search_killed(work):
    """The tiny PST with the practice critical cut (PST/Saw = practice: its saw run, then fixed-cut
    trials) killed by SIGKILL while the saw run's results.json is written, while the second trial
    runs and while a trial's results.json is written, then resumed: the completed runs are reused
    (not run again) and the results equal an uninterrupted run's, bit for bit."""
    scene = app.write(os.path.join(work, "practice.prm"), "set Scene = snowpack\n" + app.pst_scene(
        changes={"PST/Saw": "practice", "PST/Cut length [m]": "0.8", "Analysis/Explicit/End time [s]": "1"},
        insert={"PST": ["set Saw speed [m/s] = 2"]}))
    reference = os.path.join(work, "reference")
    app.anticrack("run", scene, "-o", reference)
    out = os.path.join(work, "killed")
    stdout = resume_through(["run", scene, "-o", out], [
        KillPoint("writing the saw run's results", writing="saw/results.json"),
        KillPoint("during the second trial", line="fixed-cut trial 2: cut"),
        KillPoint("writing a trial's results", writing="/results.json")], work)
    check(stdout.count("completed earlier, its results reused") >= 2, f"completed runs were run again:\n{stdout[-3000:]}")
    expected = without_wall_times(app.fem_summary(reference)["results"])
    resumed = without_wall_times(app.fem_summary(out)["results"])
    found = differences(expected, resumed)
    check(not found, "the resumed search differs from the uninterrupted one:\n" + "\n".join(found[:20]))
    check(expected["critical_cut_bracket_m"] is not None and len(expected["fixed_cut_trials"]["trials"]) >= 2,
          f"the search found no bracket: {expected.get('fixed_cut_trials')}")
    print(f"resumed practice search == uninterrupted one, bit for bit: critical cut {expected['critical_cut_length_m']} m "
          f"{expected['critical_cut_bracket_m']} after {len(expected['fixed_cut_trials']['trials'])} trials")


@case
def campaign_killed(work):
    """The campaign of the app tests (5 angles, 256 spheres) killed by SIGKILL when two tests have
    completed, while a test's summary.json and while campaign.h5 are written, then resumed: its
    failure points and every test's history equal to an uninterrupted run's, bit for bit."""
    scene = app.write(os.path.join(work, "campaign.prm"), app.campaign_scene("0, 45, 90, 135, 180"))
    reference = os.path.join(work, "reference")
    app.anticrack("run", scene, "-o", reference)
    out = os.path.join(work, "killed")
    stdout = resume_through(["run", scene, "-o", out], [
        KillPoint("two tests completed", line=": completed,", after=2),
        KillPoint("writing a test's summary.json", writing="/summary.json"),
        KillPoint("writing campaign.h5", writing="/campaign.h5")], work)
    check(stdout.count("completed earlier, skipped") == 5, f"tests were run again:\n{stdout[-3000:]}")
    app.compare_campaigns(reference, out)


@case
def study_killed(work):
    """scenes/studies/err_flat_mesh.prm killed by SIGKILL when its first variant has completed and
    again while a variant's record is written, then resumed: study.json's lines (values, errors,
    orders; not the cheapest settings, chosen by wall time) equal to an uninterrupted run's, the
    completed variants not run again."""
    scene = os.path.join(app.PATHS.source, "scenes", "studies", "err_flat_mesh.prm")
    reference = os.path.join(work, "reference")
    app.anticrack("run", scene, "-o", reference)
    out = os.path.join(work, "killed")
    stdout = resume_through(["run", scene, "-o", out], [
        KillPoint("a variant completed", line=") completed in"),
        KillPoint("writing a variant's record", writing="variant.json", after=1)], work)
    check(" to run" in stdout and "6 to run" not in stdout, f"the resumed study ran every variant again:\n{stdout}")
    a, b = (json.load(open(os.path.join(d, "study.json"))) for d in (reference, out))
    # The cheapest settings within 1 and 5 % are chosen by wall time, which differs between any two runs.
    found = [d for d in differences(without_run_specifics(a["lines"], reference), without_run_specifics(b["lines"], out))
             if "/cheapest_within_" not in d]
    check(not found, "the resumed study's lines differ:\n  " + "\n  ".join(found[:20]))


# ------------------------------------------------------------------------ files that cannot be used
def expect_unusable(arguments, file, cwd, *needles):
    """anticrack refuses (exit 2) naming `file`, with what to do, and no library's text."""
    result = subprocess.run([app.PATHS.anticrack, *arguments], cwd=cwd, capture_output=True, text=True, timeout=300)
    message = result.stdout + result.stderr
    check(result.returncode == 2, f"`{' '.join(arguments)}` with {file} damaged exited {result.returncode}, not 2:\n{message[-3000:]}")
    check(file in message, f"the message does not name {file}:\n{message}")
    check(any(remedy in message for remedy in ("--overwrite", "--resume", "elete")),
          f"the message says nothing to do:\n{message}")
    check("json.exception" not in message and "type_error" not in message, f"a library's text:\n{message}")
    for needle in needles:
        check(needle in message, f"`{needle}` missing from:\n{message}")


def damaged(path, how):
    """Replaces `path` by a damaged copy and returns a function that puts the original back."""
    original = open(path, "rb").read()
    if how == "torn":
        content = original[: len(original) // 2]
    elif how == "empty":
        content = b""
    elif how == "foreign":
        content = b'{"status": "completed", "stages": 3, "scene": [], "step": "ten"}\n'
    else:
        content = how
    open(path, "wb").write(content)
    return lambda: open(path, "wb").write(original)


@case
def unusable_files(work):
    """Files an earlier run left that a resume would read, torn (cut in half), empty or foreign (valid
    JSON of another kind): the pipeline's summary.json, the weak layer's and a PST's summary, a
    campaign test's summary, campaign.h5 (read by calibrate), a DEM checkpoint.h5 and its index, an
    FE checkpoint and its index, a study variant's record. Each is refused with exit 2 naming the
    file and what to do, never with a library's text; put back, the run resumes."""
    pipeline, _, _, _ = app.pipeline_files(work)
    out = os.path.join(work, "pipeline")
    app.anticrack("run", pipeline, "-o", out, cwd=work)
    resume = ["run", pipeline, "-o", out, "--resume"]
    cases = [("summary.json", how) for how in ("torn", "empty", "foreign")] + [
        ("weak_layer/summary.json", "torn"), ("weak_layer/summary.json", "foreign"),
        ("flat/summary.json", "torn"), ("steep/summary.json", "foreign")]
    for name, how in cases:
        path = os.path.join(out, name)
        restore = damaged(path, how)
        expect_unusable(resume, path, work)
        restore()
    # A campaign test's summary: read when the weak layer's campaign resumes (the pipeline's record
    # of the stage removed, so that the stage runs again).
    test = sorted(os.listdir(os.path.join(out, "weak_layer", "campaign", "tests")))[0]
    path = os.path.join(out, "weak_layer", "campaign", "tests", test, "summary.json")
    os.remove(os.path.join(out, "summary.json"))
    restore = damaged(path, "torn")
    expect_unusable(resume, path, work)
    restore()
    # campaign.h5, read by `anticrack calibrate`
    campaign = os.path.join(out, "weak_layer", "campaign", "campaign.h5")
    copy = os.path.join(work, "campaign_torn.h5")
    shutil.copy(campaign, copy)
    damaged(copy, "torn")
    expect_unusable(["calibrate", copy, "-o", os.path.join(work, "calibration")], copy, work)
    check(not os.path.exists(os.path.join(work, "calibration")), "calibrate of a torn campaign.h5 wrote its directory")
    # After all that, the pipeline resumes (its summary was removed: every stage reruns, the campaign's
    # tests and the PSTs that completed are kept).
    stdout, _ = app.anticrack(*resume, cwd=work)
    check(stdout.count("completed earlier, skipped") == 5, f"the campaign's tests ran again:\n{stdout[-3000:]}")

    # A DEM run's checkpoint and its index.
    dem = os.path.join(work, "dem")
    scene = app.write(os.path.join(work, "walls.prm"), app.walls_scene(400, checkpoint=100))
    app.anticrack("run", scene, "-o", dem, "--threads", "1")
    resume_dem = ["run", scene, "-o", dem, "--resume", "--threads", "1"]
    for name, how in (("checkpoint.h5", "torn"), ("checkpoint.h5", "empty"), ("checkpoint.json", "torn"),
                      ("checkpoint.json", "foreign")):
        path = os.path.join(dem, name)
        restore = damaged(path, how)
        expect_unusable(resume_dem, path, work)
        restore()

    # An FE dynamic PST's checkpoint and its index.
    # A dynamic PST stopped at 0.03 s (fem_resume of the app tests), to be resumed to its end.
    fem = os.path.join(work, "fem")
    checkpoints = {"Output": ["set Checkpoint interval = 300"]}
    full = app.write(os.path.join(work, "pst.prm"), app.pst_scene(insert=checkpoints))
    part = app.write(os.path.join(work, "pst_part.prm"),
                     app.pst_scene({"Analysis/Explicit/End time [s]": "0.03"}, insert=checkpoints))
    app.anticrack("run", part, "-o", fem)
    resume_fem = ["run", full, "-o", fem, "--resume"]
    index = os.path.join(fem, "checkpoint.json")
    for how in ("torn", "foreign"):
        restore = damaged(index, how)
        expect_unusable(resume_fem, index, work)
        restore()
    step = json.load(open(index))["step"]
    path = os.path.join(fem, "checkpoint", f"step_{step}_rank_0.bin")
    restore = damaged(path, "torn")
    expect_unusable(resume_fem, path, work)
    restore()

    # A study variant's record.
    study_scene = os.path.join(app.PATHS.source, "scenes", "studies", "err_flat_mesh.prm")
    study = os.path.join(work, "study")
    app.anticrack("run", study_scene, "-o", study)
    path = os.path.join(study, "variants", "v001", "variant.json")
    for how in ("torn", "empty"):
        restore = damaged(path, how)
        expect_unusable(["run", study_scene, "-o", study, "--resume"], path, work)
        restore()


@case
def default_pipeline_killed(work):
    """Outside the default set (-DANTICRACK_SLOW_TESTS=ON, ctest -L slow): scenes/pipeline.prm, the default job, killed as a
    user would (kill -9 of the group) 150 s in (here: when its campaign has completed 4 tests),
    during its PSTs and during its uncertainty runs, resumed each time; its summary.json results equal
    to an uninterrupted run's bit for bit. About 20 minutes on 2 cores."""
    scene = os.path.join(app.PATHS.source, "scenes", "pipeline.prm")
    reference = os.path.join(work, "reference")
    app.anticrack("run", scene, "-o", reference, timeout=3600)
    out = os.path.join(work, "killed")
    resume_through(["run", scene, "-o", out], [
        KillPoint("the campaign with 4 tests completed", line=": completed,", after=4),
        KillPoint("writing campaign.h5", writing="campaign/campaign.h5"),
        KillPoint("during the PSTs", line="pipeline stage 2/"),
        KillPoint("during the uncertainty runs", line="pipeline uncertainty", after=2)], work, timeout=3600)
    results = compare_pipelines(reference, out)
    analysis, answers = next(iter(results["analyses"].items()))
    print(f"resumed default pipeline == uninterrupted one, bit for bit: {analysis} critical cut "
          f"{answers.get('critical_cut_length_m')} m")


if __name__ == "__main__":
    sys.exit(app.main(CASES, __doc__))

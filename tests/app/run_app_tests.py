#!/usr/bin/python3
"""End-to-end tests of the `anticrack` executable (registered with ctest by tests/app/CMakeLists.txt).

Usage: run_app_tests.py --anticrack PATH --source-dir DIR --work-dir DIR CASE [CASE ...]
       run_app_tests.py --list

The cases live in one file each by what they check (cases_dem, cases_campaign, cases_calibration,
cases_fem, cases_pipeline, cases_crossval); harness.py has the checks, the scene writers and the
runner. Every case writes tiny scenes derived from scenes/*.prm into WORK-DIR/<case>/, runs the
executable there and checks its exit code, console and files. The case directory is removed when
the case passes and kept for inspection when it fails. tests/faults, tests/stability and
tests/regression import this module for its helpers.
Exit code: 0 when every case passed, 1 otherwise.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import *  # noqa: E402,F401,F403
from cases_dem import *  # noqa: E402,F401,F403
from cases_campaign import *  # noqa: E402,F401,F403
from cases_calibration import *  # noqa: E402,F401,F403
from cases_fem import *  # noqa: E402,F401,F403
from cases_pipeline import *  # noqa: E402,F401,F403
from cases_crossval import *  # noqa: E402,F401,F403
from harness import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())

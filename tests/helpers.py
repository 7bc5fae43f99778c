"""What the test tiers share (tests/unit, tests/integration, tests/acceptance): the repository's paths and the
package's command line run in a process of its own.

Imported by name, ``from tests.helpers import ROOT, run_cli``: tests/ is a package, so pytest puts the repository
root on ``sys.path`` (and a validation script that imports from tests/ puts it there itself). tests/conftest.py
holds the fixtures.
"""

from __future__ import annotations

import csv
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
"""The repository root."""
MER = ROOT / "cases" / "mer"
TEST_CASES = ROOT / "tests" / "cases"


def cli_environment(env: dict | None = None) -> dict:
    """The environment of a process of the package: ``env`` (this process's environment when None, which holds
    conftest's ``PCHUTE_KERNELS``) with the repository root first on ``PYTHONPATH``, so that the child imports the
    checkout under test, as this process does, from any working folder."""
    environment = dict(os.environ if env is None else env)
    paths = [p for p in environment.get("PYTHONPATH", "").split(os.pathsep) if p]
    if str(ROOT) not in paths:
        environment["PYTHONPATH"] = os.pathsep.join([str(ROOT), *paths])
    return environment


def cli_command(*args) -> list:
    """``python -m pchute_exudyn ARGS`` (the ``pchute`` command) with this interpreter."""
    return [sys.executable, "-m", "pchute_exudyn", *map(str, args)]


def run_cli(*args, env: dict | None = None, cwd=None, timeout: float = 300, **options) -> subprocess.CompletedProcess:
    """Run the command line with ``args`` in a process of its own (environment from :func:`cli_environment`) and
    return the finished process; its standard output and error are captured as text unless ``stdout`` or ``stderr``
    is given."""
    if "stdout" not in options and "stderr" not in options:
        options["capture_output"] = True
    return subprocess.run(cli_command(*args), env=cli_environment(env), cwd=cwd, text=True, timeout=timeout,
                          **options)


def start_cli(*args, env: dict | None = None, **options) -> subprocess.Popen:
    """Start the command line with ``args`` in a process of its own (environment from :func:`cli_environment`)
    without waiting for it: for the tests that signal or kill it; ``options`` go to ``subprocess.Popen``."""
    return subprocess.Popen(cli_command(*args), env=cli_environment(env), **options)


def study_runs(folder, drop=("wall_time", "run_time")) -> list:
    """A study's ``runs.csv`` as one dict per row, without the columns that change from run to run (``drop``)."""
    with open(Path(folder) / "runs.csv", newline="") as handle:
        return [{k: v for k, v in row.items() if k not in drop} for row in csv.DictReader(handle)]

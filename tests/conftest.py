"""Shared fixtures: the MER case, the recorded full-mass reference and the full-mass run computed once per session.
The shared paths and the command-line helpers are in tests/helpers.py (``ROOT``, ``MER``, ``run_cli``), importable
by name from every tier.

The suite runs the kernels compiled: the module the install built (rebuilt here first when a kernel's source changed
since; its subprocesses inherit the setting); tests/integration/test_fast_path.py runs the jit and Python forms and
the automatic choice on purpose.
"""

import os
import subprocess
import sys

import pytest

from tests.helpers import MER, ROOT, cli_environment, run_cli  # noqa: F401  (ROOT, run_cli: shared, see helpers)

os.environ.setdefault("PCHUTE_KERNELS", "compiled")
if os.environ["PCHUTE_KERNELS"] == "compiled":   # a source edited since the install: rebuild the module first
    subprocess.run([sys.executable, "-m", "pchute_exudyn.kernels.build", "--if-missing"], check=True,
                   stdout=subprocess.DEVNULL, env=cli_environment())   # the checkout's own package

import pchute_exudyn as pc  # noqa: E402
from tests import reference_runs  # noqa: E402


@pytest.fixture(scope="session")
def mer_case1():
    return pc.load_case(MER / "case1.toml")


@pytest.fixture(scope="session")
def case1_rk4_reference():
    """MER case 1, 60 s, full mass, RK4 at the thesis step 1e-4 s: the recorded run (tests/reference_runs.py,
    ``CASE1_RK4``), read back instead of rerun (20-40 s). Tests compare real runs of the method under test with it;
    the slow test_the_recorded_case1_reference_is_what_the_code_computes checks the recording against the code."""
    return reference_runs.case1_rk4_reference()


@pytest.fixture(scope="session")
def case1_rk4_double_step(mer_case1):
    """MER case 1, 60 s, full mass, RK4 at 2e-4 s: a real run of the full-mass model (about 8-20 s), the one the
    full model's own 60-s checks run on."""
    return pc.simulate(mer_case1, "full", "rk4", 2e-4)

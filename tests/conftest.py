"""Shared fixtures: paths, and the expensive MER runs computed once per test session.

The suite runs the kernels compiled (the first test to need one compiles it into numba's cache; its subprocesses
inherit the setting); tests/test_fast_path.py runs the Python form and the automatic choice on purpose.
"""

import os
from pathlib import Path

import pytest

os.environ.setdefault("PCHUTE_KERNELS", "compiled")

import pchute_exudyn as pc  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
MER = ROOT / "cases" / "mer"


@pytest.fixture(scope="session")
def mer_case1():
    return pc.load_case(MER / "case1.toml")


@pytest.fixture(scope="session")
def case1_rk4_reference(mer_case1):
    """MER case 1, 60 s, full mass, RK4 at the thesis step 1e-4 s (about 40 s of wall time)."""
    return pc.simulate(mer_case1, "full", "rk4", 1e-4)


@pytest.fixture(scope="session")
def case1_rk4_double_step(mer_case1):
    """MER case 1, 60 s, full mass, RK4 at 2e-4 s."""
    return pc.simulate(mer_case1, "full", "rk4", 2e-4)

"""The unit tier's budget: kernels, readers and small checks, none of them a simulation of seconds (those are
tests/integration). A unit test whose call takes more than CPU_BUDGET s of processor time, or WALL_BUDGET s on the
clock, fails saying so: make it cheaper, or move it to tests/integration."""

import os
import time

import pytest

CPU_BUDGET = 2.0
"""s of processor time per test call, this process's and its finished subprocesses': the heaviest unit test takes
about 1 s here; processor time, unlike the clock, hardly grows when other work shares the machine's cores."""
WALL_BUDGET = 10.0
"""s on the clock per test call: a test that waits (a sleep, a subprocess left running) uses no processor time;
generous for a loaded 2-core machine."""


def _processor_time() -> float:
    """s of processor time used so far by this process (all its threads) and its waited-for subprocesses."""
    used = os.times()
    return used.user + used.system + used.children_user + used.children_system


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item):
    """Fail a unit test that passed over its budget (a test that failed keeps its own failure)."""
    cpu, wall = _processor_time(), time.perf_counter()
    result = yield
    cpu, wall = _processor_time() - cpu, time.perf_counter() - wall
    if cpu > CPU_BUDGET or wall > WALL_BUDGET:
        pytest.fail(f"{item.nodeid} took {cpu:.2f} s of processor time and {wall:.2f} s on the clock: a unit test's "
                    f"budget is {CPU_BUDGET:g} s and {WALL_BUDGET:g} s (tests/unit/conftest.py); make it cheaper or "
                    "move it to tests/integration", pytrace=False)
    return result

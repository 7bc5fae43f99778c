"""The reduced method at every line damping (issue 37): SP with a relaxation time tau, each line damped at least
tau K in the solve (``methods.sp`` preset ``any_damping``). Closed forms on the thesis's chapter 2 system (fixed
attach points, no gravity): with no damping it settles exactly on the equilibrium point (Eq. 2.9); its difference
from SP falls in proportion to tau; where every line is damped at least tau K it is SP, bit for bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pchute_exudyn import load_case, simulate
from pchute_exudyn.physics.equilibrium_point import equilibrium_point
from tests.helpers import ROOT

SIMPLE = ROOT / "cases" / "simple" / "simple.toml"
MER1 = ROOT / "cases" / "mer" / "case1.toml"
NAMES = ("bridle1", "bridle2", "bridle3", "riser")


def _anchored(tmp_path: Path) -> Path:
    """The chapter 2 system with a free body beside it (SP moves the confluence inside the moving bodies' force
    item: a case whose every body is fixed has none, and SP refuses it). The body has no line and, without
    gravity, stays where it is."""
    path = tmp_path / "anchored.toml"
    path.write_text(f'extends = "{SIMPLE.as_posix()}"\n[bodies.beside]\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n'
                    '[bodies.beside.initial]\naltitude = 100.0\n[simulation]\nstop_at_ground = false\n')
    return path


def _confluence(result) -> np.ndarray:
    return np.column_stack([result[f"confluence_{axis}"] for axis in ("east", "north", "altitude")])


@pytest.mark.parametrize("damping", [0.0, 1e-9])
def test_without_damping_the_confluence_settles_on_the_equilibrium_point(tmp_path, damping):
    case = load_case(_anchored(tmp_path), [f"confluence.lines.*.damping={damping}"])
    result = simulate(case, "sp", step=1e-3, duration=1.0, preset="any_damping", order=0)
    anchors = case.bodies["anchors"].points
    lines = case.systems["confluence"].lines
    expected = equilibrium_point([anchors[line.point] for line in lines], [line.law for line in lines]).position
    assert _confluence(result)[-1] == pytest.approx(np.asarray(expected), abs=1e-6)


def test_without_damping_it_tends_to_the_equilibrium_point_method_in_proportion_to_tau():
    """MER case 1 with every line undamped, dropped from rest, 3 s: the massless relaxed SP (order 0) against the
    equilibrium-point method (Eq. 2.9 at every stage): the largest confluence position difference after the first
    0.1 s halves with tau (first order) and is below 1e-6 m at tau = 1 ms."""
    case = load_case(MER1, ["main.lines.*.damping=0"])
    reference = _confluence(simulate(case, "equilibrium", step=1e-3, duration=3.0))
    errors = [np.abs(_confluence(simulate(case, "sp", step=2e-4, duration=3.0, preset="accurate", order=0,
                                          relaxation_time=tau))[100:] - reference[100:]).max()
              for tau in (0.004, 0.002, 0.001)]
    ratios = [errors[0] / errors[1], errors[1] / errors[2]]
    assert all(1.6 < r < 2.4 for r in ratios), (errors, ratios)
    assert errors[2] < 1e-6


@pytest.mark.parametrize("step", [1e-2, 5e-3, 2.5e-3])
def test_where_every_line_is_damped_enough_it_is_sp_bit_for_bit(step):
    """MER case 1: C / K = 10 ms for every line, above tau = 5 ms: nothing is raised, and the difference from SP is
    zero at h, h/2 and h/4 (the consistency check of the issue: no error of any order)."""
    case = load_case(MER1)
    sp = simulate(case, "sp", step=step, duration=3.0, preset="accurate")
    relaxed = simulate(case, "sp", step=step, duration=3.0, preset="any_damping")
    for name in sp.columns:
        assert np.array_equal(sp[name], relaxed[name], equal_nan=True), name
    assert relaxed.summary.method_settings["sp_relaxation_time"] == 0.005
    assert "sp_relaxation_time" not in sp.summary.method_settings


@pytest.mark.long
def test_undamped_mer_runs_at_the_thesis_step_and_stays_near_full_mass():
    """MER case 1, every line undamped, 2 s from rest: SP any_damping at 1e-2 s against full mass RK4 at 2e-5 s."""
    overrides = ["main.lines.*.damping=0"]
    full = simulate(load_case(MER1, overrides), "full", "rk4", 2e-5, 2.0, history=False)
    relaxed = simulate(load_case(MER1, overrides), "sp", step=1e-2, duration=2.0, preset="any_damping",
                       history=False)
    for key in ("altitude", "east"):
        assert getattr(relaxed.summary.final, key) == pytest.approx(getattr(full.summary.final, key), abs=0.1)
    for name in NAMES:
        assert relaxed.summary.peak_tension[name] == pytest.approx(full.summary.peak_tension[name], rel=0.03)


BATTERY = [
    ("relaxation time below 0", ["--sp-relaxation-time", "-1"],
     "relaxation_time (--sp-relaxation-time) = -1.0: must be within 0..1 (s)"),
    ("negative line damping", ["--set", "main.lines.riser.damping=-5"],
     "systems.main.lines.riser.damping = -5: must be >= 0 (N s/m)"),
    ("undamped lines without a relaxation time", ["--set", "main.lines.*.damping=0"],
     "use --sp-preset any_damping (a relaxation time), or --method full"),
]


@pytest.mark.parametrize("name, extra, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_bad_relaxation_input_gives_one_line(tmp_path, name, extra, expected):
    from tests.bad_input_harness import assert_one_line, run_bad_input
    code, err, seconds, touched = run_bad_input(
        lambda t: ["run", str(MER1), "--method", "sp", "--quiet", "--out", str(t / "out"), *extra], tmp_path)
    assert_one_line(code, err, expected, touched, seconds)

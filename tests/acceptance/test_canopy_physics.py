"""Canopy physics beyond the thesis (docs/models/canopy.md): apparent mass, fill-constant inflation with reefing,
load-elongation tables. Closed forms through the engine with the full-mass model and SP (``validation/
canopy_checks.py``), kernels against direct formulas, the results unchanged with every new key absent or switched off,
and SP against full mass on the PA1 inflation variant."""

import dataclasses
import json
import math
import sys

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pchute_exudyn import load_case, simulate
from pchute_exudyn.engine.state import initial_body_state
from pchute_exudyn.physics.apparent_mass import ApparentMass, kirchhoff_terms, translational_mass_matrix
from pchute_exudyn.physics.inflation import Inflation, InflationProgress, InflationStage
from pchute_exudyn.physics.lines import LineLaw, LoadElongation
from pchute_exudyn.run.simulation import resolve_run, run
from tests.helpers import ROOT

sys.path.insert(0, str(ROOT / "validation"))
import canopy_checks  # noqa: E402

from tests import reference_runs  # noqa: E402

RUNS = canopy_checks.RUNS


# -- kernels ---------------------------------------------------------------------------------------------------------

def test_apparent_mass_kernel_matches_the_matrix_form():
    apparent = ApparentMass(5.3, 1.0, 0.5, 0.1)
    translational, rotational = apparent.masses(0.02)
    assert translational[0] == pytest.approx(0.02 * 2 / 3 * math.pi * 5.3 ** 3)
    assert rotational == (0.0, pytest.approx(translational[0] * 0.1 * 5.3 ** 2),
                          pytest.approx(translational[0] * 0.1 * 5.3 ** 2))
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    rotation = q * np.sign(np.linalg.det(q))
    velocity, rate = rng.normal(size=3) * 10, rng.normal(size=3)
    force, moment = kirchhoff_terms(rotation.ravel().tolist(), velocity.tolist(), rate.tolist(), translational,
                                    rotational)
    a_t, a_r, local = np.diag(translational), np.diag(rotational), rotation.T @ velocity
    assert np.allclose(force, rotation @ (a_t @ np.cross(rate, local) - np.cross(rate, a_t @ local)), rtol=1e-12)
    assert np.allclose(moment, -np.cross(rate, a_r @ rate) - np.cross(local, a_t @ local), rtol=1e-12)
    assert np.allclose(translational_mass_matrix(rotation.ravel().tolist(), translational), rotation @ a_t @ rotation.T)


def test_inflation_law_stages_overinflation_and_measured_speeds():
    law = Inflation((InflationStage(0.0, 0.1, 1.0, 2.0), InflationStage(5.0, 1.0, 2.0, 1.0)), 0.02, 1.2, 2.0)
    fills = [law.fill_time(0, 20.0, 10.0), law.fill_time(1, 10.0, 10.0)]
    assert fills == [0.5, 2.0]
    assert law.fraction(0.0, fills) == 0.02
    assert law.fraction(0.25, fills) == pytest.approx(0.02 + 0.08 * 0.25)
    assert law.fraction(3.0, fills) == 0.1
    assert law.fraction(6.0, fills) == pytest.approx(0.1 + (1.2 - 0.1) * 0.5)   # exponent 1 to C_x f_n
    assert law.fraction(8.0, fills) == pytest.approx(1.2 - 0.2 * 1.0 / 2.0)      # decaying linearly
    assert law.fraction(10.0, fills) == 1.0
    progress = InflationProgress(law, 10.0, line_stretch=3.0)
    assert progress.due(3.0) and not progress.due(2.9)
    progress.begin(2.99, 19.0)   # the step from 2.99 s to 3.01 s holds line stretch
    progress.complete(3.01, 21.0)
    assert progress.speeds == [20.0] and progress.fill_times == [0.5]
    assert progress.windows(20.0) == [(1, 3.0, 20.0)]


def test_load_elongation_table_tension_slope_energy_and_inverse():
    table = LoadElongation((0.0, 0.02, 0.05, 0.1), (0.0, 500.0, 2000.0, 6000.0))
    assert table(0.01) == 250.0 and table(-0.01) == 0.0
    assert table(0.12) == pytest.approx(6000.0 + 0.02 * 80000.0)   # the last slope continues
    assert table.slope(0.03) == pytest.approx(50000.0, rel=1e-12)
    assert table.strain_at(981.0) == pytest.approx(0.02962)
    strain = np.linspace(0.0, 0.15, 301)
    hinge = LineLaw(10.0, 0.0, 0.0, table).expression(strain * 10.0, 0.0)   # T_el in its hinge form
    assert np.allclose(hinge, [table(e) for e in strain], rtol=1e-12, atol=1e-9)
    energy = [table.energy(e) for e in strain]
    assert np.allclose(np.gradient(energy, strain)[5:-5], [table(e) for e in strain][5:-5], rtol=2e-2)


# -- closed forms through the engine (canopy.md sections 1-3) ---------------------------------------------------------

@pytest.mark.parametrize("method, integrator", RUNS)
@pytest.mark.parametrize("check", [canopy_checks.axial_fall, canopy_checks.lateral_push, canopy_checks.munk_moment],
                         ids=["axial_fall", "lateral_push", "munk_moment"])
def test_apparent_mass_closed_forms(tmp_path, check, method, integrator):
    row = check(tmp_path, method, integrator)
    assert row["relative_error"] <= row["tolerance"], row


@pytest.mark.parametrize("method, integrator", RUNS + (("equilibrium", "rk4"),))
def test_hanging_from_a_table_line_stretches_to_the_tables_strain(tmp_path, method, integrator):
    row = canopy_checks.hanging(tmp_path, method, integrator)
    assert row["relative_error"] <= row["tolerance"], row


@pytest.mark.parametrize("method, integrator", RUNS + (("equilibrium", "rk4"),))
def test_towed_canopy_sees_exactly_q_s_ca_f(tmp_path, method, integrator):
    row = canopy_checks.towed(tmp_path, method, integrator)
    assert row["relative_error"] <= row["tolerance"], row


@pytest.mark.parametrize("method, integrator", [("full", "implicit"), ("sp", "rk4")])
def test_finite_mass_inflation_matches_one_degree_of_freedom(method, integrator):
    for row in canopy_checks.finite_mass(method, integrator):
        assert row["relative_error"] <= row["tolerance"], row


def test_apparent_mass_follows_an_independent_integration_of_kirchhoffs_equations(tmp_path):
    """A tumbling canopy (every velocity and rate component non-zero, gravity along no body axis, no aerodynamics)
    against scipy integrating the body-axis equations of canopy.md (rtol 1e-11)."""
    case = _spinning(canopy_checks.canopy_case(tmp_path, g=9.81, velocity_down=6.0, velocity_east=-4.0, yaw=30.0,
                                               duration=2.0, output_step=1.0, step=1e-3))
    body = case.bodies["canopy"]
    state = initial_body_state(case, body)
    a_t, a_r = (np.diag(v) for v in body.apparent_mass.masses(canopy_checks.DENSITY))
    heavy, spinning = body.mass * np.eye(3) + a_t, body.inertia + a_r
    weight = body.mass * np.array([0.0, 0.0, -9.81])

    def rhs(t, y):
        rotation, local, rate = y[6:].reshape(3, 3), y[:3], y[3:6]
        dv = np.linalg.solve(heavy, rotation.T @ weight - np.cross(rate, heavy @ local))
        dw = np.linalg.solve(spinning, -np.cross(rate, spinning @ rate) - np.cross(local, a_t @ local))
        skew = np.array([[0, -rate[2], rate[1]], [rate[2], 0, -rate[0]], [-rate[1], rate[0], 0]])
        return np.concatenate([dv, dw, (rotation @ skew).ravel()])
    y0 = np.concatenate([state.attitude.T @ state.velocity, state.angular_velocity, state.attitude.ravel()])
    reference = solve_ivp(rhs, (0.0, 2.0), y0, rtol=1e-11, atol=1e-11, method="DOP853").y[:, -1]
    for integrator in ("rk4", "implicit"):
        raw = run(case, resolve_run(case, "full", integrator))[0]
        velocity = raw.bodies["canopy"]["velocity"][-1]
        assert np.allclose(velocity, reference[6:].reshape(3, 3) @ reference[:3], rtol=1e-6, atol=1e-6), integrator
        assert np.allclose(raw.bodies["canopy"]["angular_velocity"][-1], reference[3:6], rtol=1e-6, atol=1e-6)


def _spinning(case):
    """The case with its canopy spinning at (0.3, -0.2, 0.4) rad/s in body axes."""
    body = case.bodies["canopy"]
    initial = dataclasses.replace(body.initial, rate_x=0.3, rate_y=-0.2, rate_z=0.4)
    return dataclasses.replace(case, bodies={"canopy": dataclasses.replace(body, initial=initial)})


# -- nothing changes with the new keys absent or switched off ---------------------------------------------------------

REFERENCE = json.loads((ROOT / "tests" / "data" / "reference_runs.json").read_text())


@pytest.mark.parametrize("name, case_file, method, integrator, duration", reference_runs.RUNS,
                         ids=[run[0] for run in reference_runs.RUNS])
def test_results_are_those_of_the_code_before_the_canopy_physics_and_the_fast_path(name, case_file, method, integrator,
                                                                                   duration):
    """tests/data/reference_runs.json was written by tests/reference_runs.py from commit 53493ef (before issues 13
    and 14): the same events and every number within 1e-9 relative (the compiled kernels and the one force item of
    issue 14 compute the same formulas with round-off of their own)."""
    got = reference_runs.record(name, case_file, method, integrator, duration)
    worst, where = reference_runs.largest_difference(got, REFERENCE[name])
    assert worst <= reference_runs.TOLERANCE[integrator], f"{where}: relative difference {worst:.3g}"


@pytest.mark.parametrize("method, integrator", [("sp", "rk4"), ("full", "implicit")])
def test_apparent_mass_switched_off_is_the_case_without_it(method, integrator):
    off = reference_runs.record("off", "cases/mer/case1_apparent_mass.toml", method, integrator, 10.0,
                                ["parachute.apparent_mass.enabled=false"])
    worst, where = reference_runs.largest_difference(off, REFERENCE[f"mer1_{method}_{integrator}"])
    assert worst <= reference_runs.TOLERANCE[integrator], f"{where}: relative difference {worst:.3g}"


def test_apparent_mass_changes_the_mer_descent():
    on = simulate(load_case(ROOT / "cases" / "mer" / "case1_apparent_mass.toml"), "sp", duration=10.0)
    off = simulate(load_case(ROOT / "cases" / "mer" / "case1.toml"), "sp", duration=10.0)
    assert on.columns["parachute_apparent_mass_axial"][0] == pytest.approx(
        canopy_checks.volume() * load_case(ROOT / "cases" / "mer" / "case1.toml").atmosphere.density(
            on.columns["parachute_altitude"][0] - 1.57), rel=1e-3)
    assert abs(on.summary.final.altitude - off.summary.final.altitude) > 0.01


# -- the PA1 inflation variant: SP against full mass ------------------------------------------------------------------

@pytest.fixture(scope="module")
def pa1_inflation():
    case = load_case(ROOT / "cases" / "cev_pa1_inflation.toml")
    return {method: simulate(case, method) for method in ("sp", "full")}


@pytest.mark.long
def test_pa1_inflation_events_and_stage_loads(pa1_inflation):
    summary = pa1_inflation["sp"].summary
    kinds = [(e.kind, getattr(e, "system", None), getattr(e, "stage", None)) for e in summary.events]
    for expected in [("stage_start", "drogue", 1), ("fill_end", "drogue", 1), ("stage_start", "main", 1),
                     ("disreef", "main", 2), ("disreef", "main", 3), ("fill_end", "main", 3)]:
        assert expected in kinds
    disreefs = summary.events_of("disreef")
    assert [e.time for e in disreefs] == [17.5, 25.5]
    for event in disreefs:   # t_f = n D0 / V with the measured V
        n = load_case(ROOT / "cases" / "cev_pa1_inflation.toml").systems["main"].inflation.stages[event.stage - 1]
        assert event.fill_time == pytest.approx(n.fill_constant * math.sqrt(4 * 2946.0 / math.pi) / event.speed)
    stages = summary.opening_loads["main"]
    assert [s["stage"] for s in stages] == [1, 2, 3]
    for stage in stages:
        assert stage["start"] <= stage["peaks"]["riser"]["time"] < stage["end"]
    assert summary.opening_loads["drogue"][0]["end"] == 9.5   # cut away


@pytest.mark.long
def test_pa1_inflation_sp_matches_full_mass(pa1_inflation):
    sp, full = pa1_inflation["sp"].summary, pa1_inflation["full"].summary
    assert abs(sp.touchdown.time - full.touchdown.time) <= 0.2
    for a, b in zip(sp.opening_loads["main"], full.opening_loads["main"]):
        assert a["peaks"]["riser"]["tension"] == pytest.approx(b["peaks"]["riser"]["tension"], rel=0.03)


@pytest.mark.long
@pytest.mark.benchmark
def test_pa1_inflation_sp_is_eight_times_faster_than_full_mass(pa1_inflation):
    sp, full = pa1_inflation["sp"].summary, pa1_inflation["full"].summary
    # engine solve times side by side in this process, the best of repeated runs of each (best of 2 for full mass,
    # of 3 for the 1 s SP run, which a scheduler hiccup on a loaded 2-core machine moves the most)
    case = load_case(ROOT / "cases" / "cev_pa1_inflation.toml")
    full_time = min(full.wall_time, simulate(case, "full").summary.wall_time)
    sp_time = min([sp.wall_time] + [simulate(case, "sp").summary.wall_time for _ in range(2)])
    assert full_time / sp_time >= 8.0, (full_time, sp_time)

"""Chapter 2 with the engine: Exudyn's integration and linearisation against the analytic method; `pchute
linearize`; the equilibrium-point method in a flight simulation."""

import json

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.cli import main
from pchute_exudyn.engine.linearized import exudyn_eigenvalues
from pchute_exudyn.engine.state import initial_point
from pchute_exudyn.physics.analytic import analytic_response
from pchute_exudyn.physics.equilibrium_point import equilibrium_point
from pchute_exudyn.physics.linearization import linearize, modes
from pchute_exudyn.run.phases import initial_phase
from tests.helpers import MER, ROOT

SIMPLE = ROOT / "cases" / "simple" / "simple.toml"


def _linear(case):
    system = next(iter(case.systems.values()))
    attach = np.array([initial_point(case, l.body, l.point) for l in system.lines])
    args = ([l.free_length for l in system.lines], [l.stiffness for l in system.lines])
    eq = equilibrium_point(attach, [l.law for l in system.lines], require_unique=True).position
    c_bar, k_bar = linearize(attach, eq, *args, [l.damping for l in system.lines])
    return system, eq, c_bar, k_bar


def _analytic_vs_integrated(case, duration):
    system, eq, c_bar, k_bar = _linear(case)
    result = pc.simulate(case, "full", "rk4", 1e-4, duration)
    integrated = np.column_stack([result["confluence_east"], result["confluence_north"],
                                  result["confluence_altitude"]]) - eq
    init = system.confluence.initial
    offset, _ = analytic_response(system.confluence.mass, c_bar, k_bar,
                                  np.array([init.east, init.north, init.altitude]) - eq,
                                  [init.velocity_east, init.velocity_north, -init.velocity_down], result.time)
    return offset, integrated


def test_fig2_3_analytic_z_motion_matches_the_integrated_one():
    offset, integrated = _analytic_vs_integrated(pc.load_case(SIMPLE), 0.5)
    z_error = np.abs(offset[:, 2] - integrated[:, 2]).max()
    # thesis: "within 0.3 mm at the largest deviation"; measured 0.305 mm (converged in step), the model's
    # nonlinearity at the first 46 mm peak: the thesis's number to its one printed digit
    assert z_error < 0.35e-3
    assert np.abs(integrated[:, 2]).max() > 0.04
    assert np.abs(offset[:, :2] - integrated[:, :2]).max() > z_error     # the lateral differences are larger


def test_off_axis_modes_equal_exudyn_linearisation_and_analytic_tracks_a_small_deflection():
    top = {"anchors.points.riser": [2.0, 0.0, 36.2161]}
    system, eq, c_bar, k_bar = _linear(pc.load_case(SIMPLE, top))
    assert abs(k_bar[0, 2]) > 1e4 and abs(c_bar[0, 2]) > 20.0                  # coupled matrices
    at_eq = pc.load_case(SIMPLE, {**top, "confluence.confluence.initial.east": float(eq[0]),
                                  "confluence.confluence.initial.north": float(eq[1]),
                                  "confluence.confluence.initial.altitude": float(eq[2]),
                                  "confluence.confluence.initial.velocity_east": 0.0,
                                  "confluence.confluence.initial.velocity_north": 0.0,
                                  "confluence.confluence.initial.velocity_down": 0.0})
    ours = np.sort_complex(modes(15.0, c_bar, k_bar).eigenvalues)
    engine = np.sort_complex(exudyn_eigenvalues(at_eq, initial_phase(at_eq)))
    np.testing.assert_allclose(engine, ours, rtol=1e-3)                         # measured 1.4e-6
    small = pc.load_case(SIMPLE, {**top, "confluence.confluence.initial.east": float(eq[0] + 0.01),
                                  "confluence.confluence.initial.north": float(eq[1] + 0.01),
                                  "confluence.confluence.initial.altitude": float(eq[2] + 0.005),
                                  "confluence.confluence.initial.velocity_east": 0.1,
                                  "confluence.confluence.initial.velocity_north": -0.1,
                                  "confluence.confluence.initial.velocity_down": -0.2})
    offset, integrated = _analytic_vs_integrated(small, 2.0)
    assert np.abs(offset - integrated).max() < 0.01 * np.abs(integrated).max()  # measured 0.2%


def test_linearize_json_for_the_simple_model(capsys):
    assert main(["linearize", str(SIMPLE), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    for key in ("equilibrium_point", "C_bar", "K_bar", "eigenvalues", "natural_frequencies", "damping_ratios",
                "max_stable_step_full", "max_stable_step_sp"):
        assert key in report
    assert report["equilibrium_point"][2] == pytest.approx(6.0305, abs=5e-5)
    assert np.shape(report["C_bar"]) == (3, 3) and np.shape(report["K_bar"]) == (3, 3)
    assert all(len(pair) == 2 for pair in report["eigenvalues"])
    # RK4 limit of the full-mass confluence: the -19.7 +- 123.9i pair, |lambda h| on the RK4 boundary
    assert 0.02 < report["max_stable_step_full"] < 0.025


def test_linearize_flight_case_at_a_time(capsys):
    assert main(["linearize", str(MER / "case1.toml"), "--time", "30", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["time"] == pytest.approx(30.0)
    # the step limits the runs found: full mass about 4.0e-4 s at 30 s, SP about 2.6e-2 s
    assert 3.9e-4 < report["max_stable_step_full"] < 4.1e-4
    assert 0.02 < report["max_stable_step_sp"] < 0.03
    assert main(["linearize", str(MER / "case1.toml"), "--system", "nope"]) == 1
    assert "unknown system 'nope'" in capsys.readouterr().err


def test_equilibrium_method_in_a_flight_case(mer_case1, case1_rk4_reference):
    result = pc.simulate(mer_case1, "equilibrium", "rk4", 1e-2)
    ref = case1_rk4_reference
    assert abs(result.final("vehicle_altitude") - ref.final("vehicle_altitude")) < 1.0     # measured 0.22 m
    settled = ref.time > 2.0
    for name in ref.tension_names():
        assert np.abs(np.interp(ref.time, result.time, result[name]) - ref[name])[settled].max() < 2.0
    facts = result.summary.method_facts["equilibrium_main"]
    assert facts["failures"] == 0 and facts["solves"] >= 4 * 6000 and facts["max_iterations"] < 20
    assert "equilibrium_iterations" in result and result.units["equilibrium_failures"] == "-"
    with pytest.raises(pc.InputError, match="rk4 only"):
        pc.simulate(mer_case1, "equilibrium", "implicit", 1e-2, 1.0)

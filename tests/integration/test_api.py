"""Python API: input errors, several parachute systems in one case, result files round trip."""

import os
import stat

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.cli import main
from pchute_exudyn.physics.step_rule import StepRule
from tests.helpers import MER

TWIN = """
[bodies.canopy2]
mass = 16.0
inertia = [253.7, 1126.5, 1126.5]
points.riser = [31.321, 0.0, 0.0]
initial.altitude = 8414.6
[bodies.canopy2.aerodynamics]
reference_area = 178.47
axial_coefficient = 0.46
center = [-1.57, 0.0, 0.0]
normal_coefficient = { alpha_deg = [0.0, 90.0], value = [0.0, 0.0] }

[bodies.parachute.aerodynamics.normal_coefficient]
alpha_deg = [0.0, 90.0]
value = [0.0, 0.0]

[systems.second.confluence]
mass = 0.1539
initial.altitude = 8381.447
[systems.second.lines.bridle1]
attach = "vehicle.bridle1"
free_length = 0.7152
stiffness = 47000.0
damping = 470.0
[systems.second.lines.bridle2]
attach = "vehicle.bridle2"
free_length = 0.7152
stiffness = 47000.0
damping = 470.0
[systems.second.lines.bridle3]
attach = "vehicle.bridle3"
free_length = 0.7152
stiffness = 47000.0
damping = 470.0
[systems.second.lines.riser]
attach = "canopy2.riser"
free_length = 1.832
stiffness = 60000.0
damping = 600.0
"""


def test_two_identical_systems_share_the_load_and_name_their_columns(tmp_path):
    path = tmp_path / "twin.toml"
    path.write_text(f'extends = "{(MER / "base.toml").as_posix()}"\n' + TWIN)
    case = pc.load_case(path)
    result = pc.simulate(case, "full", "implicit", 1e-3, 3.0)
    for system in ("main", "second"):
        for line in ("bridle1", "bridle2", "bridle3", "riser"):
            assert f"tension_{system}_{line}" in result
        assert f"{system}_confluence_altitude" in result
    assert "tension_riser" not in result and "confluence_altitude" not in result
    # the two systems are mirror images: equal tensions, and together they carry what one system does alone
    np.testing.assert_allclose(result["tension_main_riser"], result["tension_second_riser"], rtol=1e-6, atol=1e-6)
    # one parachute of twice the mass and area, same lines: the vehicle falls the same way (line stretch aside)
    doubled = pc.load_case(MER / "case1.toml", ["parachute.aerodynamics.reference_area=356.94",
                                                "parachute.aerodynamics.normal_coefficient.alpha_deg=[0.0, 90.0]",
                                                "parachute.aerodynamics.normal_coefficient.value=[0.0, 0.0]",
                                                "parachute.mass=32.0"])
    single = pc.simulate(doubled, "full", "implicit", 1e-3, 3.0)
    np.testing.assert_allclose(result.final("vehicle_altitude"), single.final("vehicle_altitude"), atol=2e-3)


def test_api_input_errors(mer_case1):
    with pytest.raises(pc.InputError, match="unknown method 'magic'; methods are: full, sp"):
        pc.simulate(mer_case1, method="magic")
    with pytest.raises(pc.InputError, match="unknown integrator 'euler'"):
        pc.simulate(mer_case1, integrator="euler")
    with pytest.raises(pc.InputError, match="must be a number > 0"):
        pc.simulate(mer_case1, step=float("nan"))
    with pytest.raises(pc.InputError, match="duration"):
        pc.simulate(mer_case1, duration=-1.0)
    with pytest.raises(pc.InputError, match="step .--dt. = 'fast': must be a number > 0 .s. or 'auto'"):
        pc.simulate(mer_case1, step="fast")
    with pytest.raises(pc.InputError, match="adaptive steps are RK4's; the implicit integrator needs a step in s"):
        pc.simulate(mer_case1, "full", "implicit", step="auto")
    # nothing moves but the confluence of the equilibrium method, which has no dynamics: adaptive steps take the
    # largest step (before adaptive steps this case had no step to choose: "nothing in it limits the step")
    static = pc.simulate(pc.load_case(MER.parent / "simple" / "simple.toml", {"simulation.steps": {}}),
                         method="equilibrium", duration=1.0)
    assert static.summary.step_control["largest"] == StepRule().largest


def test_failed_run_writes_no_result(capsys, tmp_path):
    out = tmp_path / "failed"
    code = main(["run", str(MER / "case1.toml"), "--dt", "1e-3", "--out", str(out)])
    assert code == 1 and "stability limit" in capsys.readouterr().err
    assert not (out / "timeseries.csv").exists() and not (out / "summary.json").exists()


def test_result_round_trip_and_permissions(tmp_path):
    result = pc.simulate(pc.load_case(MER / "case2.toml"), "full", "implicit", 1e-3, 1.0)
    paths = result.save(tmp_path / "r")
    loaded = pc.Result.load(tmp_path / "r")
    assert loaded.names == result.names
    for name in result.names:
        np.testing.assert_allclose(loaded[name], result[name], rtol=1e-11, atol=1e-12)
    assert loaded.summary.method == "full" and loaded.units["tension_riser"] == "N"
    umask = os.umask(0)
    os.umask(umask)
    for path in paths.values():
        assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask
    with pytest.raises(KeyError, match="no column 'tension_x'"):
        result["tension_x"]


def test_times_are_on_the_exact_grid_and_steps_are_counted_once(mer_case1):
    flying_on = pc.load_case(MER / "case1.toml", {"simulation.stop_at_ground": False})
    sp = pc.simulate(flying_on, "sp", "rk4", 1e-2, 300.0)   # 30 000 steps: the solver's time drifts by 1e-10 s
    assert sp.summary.steps == 30000 and sp.summary.final.time == 300.0
    grid = np.array([float(f"{k * 0.01:.15g}") for k in range(30001)])
    assert np.array_equal(sp.time, grid)                     # 55.41, not 55.409999999997545
    odd = pc.simulate(mer_case1, "full", "rk4", 3e-4, 0.05)  # a step that does not divide the output step
    assert odd.summary.steps == 167
    step = 0.05 / 167                                      # Exudyn divides the span evenly
    np.testing.assert_array_equal(odd.time, [float(f"{n * step:.15g}") for n in (0, 33, 67, 100, 134, 167)])


def test_every_run_stops_at_the_ground_unless_the_case_flies_on(mer_case1):
    landed = pc.simulate(mer_case1, "sp", "rk4", 1e-2, 300.0)
    assert landed.summary.end == "touchdown" and landed.summary.ground_altitude == 0.0
    assert 100.0 < landed.summary.touchdown.time < 200.0 and abs(landed.final("vehicle_altitude")) < 1.0
    flying_on = pc.load_case(MER / "case1.toml", {"simulation.stop_at_ground": False})
    below = pc.simulate(flying_on, "sp", "rk4", 1e-2, 300.0)
    assert below.summary.end == "duration" and below.summary.ground_altitude == 0.0   # the ground stays (issue 59)
    assert below.summary.stop_at_ground is False
    assert below.final("vehicle_altitude") < -5000.0

"""Orion PA1: Earth, US76, wind, sequential deployment at line stretch, cut-away, reefing, touchdown."""

import json
import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.engine.full_model import build_full_model
from pchute_exudyn.physics.atmosphere import US76
from pchute_exudyn.run.phases import boundaries, deploy, initial_states, next_phase
from tests.helpers import ROOT

PA1 = ROOT / "cases" / "cev_pa1.toml"


@pytest.fixture(scope="module")
def pa1_sp():
    return pc.simulate(pc.load_case(PA1), "sp", "rk4", 1e-2)


@pytest.fixture(scope="module")
def pa1_implicit():
    return pc.simulate(pc.load_case(PA1), "full", "implicit", 1e-2)


@pytest.mark.parametrize("case_file", [PA1, ROOT / "cases" / "cev_pa1_cluster.toml"])
def test_deployment_at_line_stretch_puts_every_line_at_free_length(case_file):
    case = pc.load_case(case_file)
    bodies, confluences = initial_states(case)
    for name in ("drogue", "main"):
        system = case.systems[name]
        canopies, confluence = deploy(case, system, bodies, system.deploy_time)
        assert set(canopies) == set(system.canopies)
        capsule = bodies["capsule"]
        for line in system.lines:
            body = capsule if line.body == "capsule" else canopies[line.body]
            point = body.position + body.attitude @ np.asarray(case.bodies[line.body].points[line.point])
            length = np.linalg.norm(point - confluence.position)
            assert length == pytest.approx(line.free_length, abs=5e-5), (name, line.name)  # cev_pa1.md: 4 digits
        # the canopies trail behind along the air-relative velocity (a cluster's spread on a cone around it), +x
        # toward the capsule, at the capsule's speed
        for canopy in canopies.values():
            along = canopy.attitude[:, 0] @ (capsule.velocity / np.linalg.norm(capsule.velocity))
            assert along == pytest.approx(1.0) if not system.cluster else 0.9 < along < 1.0
            np.testing.assert_allclose(canopy.velocity, capsule.velocity)


def test_phases_follow_the_event_times():
    case = pc.load_case(PA1)
    assert boundaries(case, 200.0) == [0.0, 3.5, 9.5, 200.0]
    bodies, confluences = initial_states(case)
    first = next_phase(case, 0.0, 3.5, bodies, confluences)
    assert first.systems == [] and first.bodies == ["capsule"]
    bodies["drogue_canopy"] = deploy(case, case.systems["drogue"], bodies, 3.5)[0]
    last = next_phase(case, 9.5, 200.0, bodies, {"drogue": None})
    assert last.systems == ["main"] and "drogue_canopy" not in last.bodies      # the cut-away system is gone
    assert [e.kind for e in last.events] == ["cutaway", "deploy"]


def test_pa1_events_and_touchdown(pa1_sp):
    r = pa1_sp
    events = {(e.kind, getattr(e, "system", None)): e for e in r.summary.events}
    assert events[("deploy", "drogue")].time == 3.5
    assert events[("deploy", "main")].time == 9.5 and events[("cutaway", "drogue")].time == 9.5
    crossing = events[("descent_rate", None)].time
    touchdown = r.summary.touchdown
    assert 9.5 < crossing < touchdown.time
    # touchdown ends the run: the last sample is the step that reached the ground, long before the 200 s limit
    assert r.summary.end == "touchdown" and r.final("time") < 100.0
    assert abs(r.final("time") - touchdown.time) <= 0.01
    assert abs(r.final("capsule_altitude") - 1200.0) < 0.1
    # steady descent under the full mains: the weight of capsule, main canopy and confluence = 1/2 rho v^2 (C_A S)_main,
    # rho at the 1200 m ground (US76): 7.99 m/s
    case = pc.load_case(PA1)
    rho = US76().density(1200.0)
    weight = (7500.0 + 423.0 + 8.0) * 3.986004418e14 / (6371000.0 + 1200.0) ** 2
    hand = math.sqrt(2.0 * weight / (rho * 0.76 * 2946.0))
    assert touchdown.speed == pytest.approx(hand, rel=0.10)                        # measured: -0.3%
    assert case.systems["main"].drag_area_schedule(18.0) == 1.0


def test_cut_away_system_is_gone_from_the_model_and_the_outputs(pa1_sp):
    r = pa1_sp
    after = r.time > 9.5 + 1e-9
    for name in ("tension_drogue_bridle1", "tension_drogue_riser", "drogue_canopy_altitude",
                 "drogue_confluence_altitude"):
        assert np.all(np.isnan(r[name][after])) and np.isfinite(r[name][(r.time > 3.6) & (r.time < 9.4)]).all()
    before = r.time < 9.5 - 1e-9
    assert np.all(np.isnan(r["tension_main_riser"][before])) and np.isnan(r["main_canopy_altitude"][3])


def test_cut_away_exerts_no_force_afterwards():
    """After a cut-away the capsule moves exactly as a capsule-only run started from its state then."""
    with_drogue = pc.load_case(PA1, {"systems.drogue.cutaway_time": 6.0, "systems.main.deploy_time": 150.0})
    a = pc.simulate(with_drogue, "full", "implicit", 1e-3, 9.0)
    row = int(np.argmin(np.abs(a.time - 6.0)))
    state = {f"capsule.initial.{key}": float(a[f"capsule_{column}"][row]) for key, column in (
        ("altitude", "altitude"), ("east", "east"), ("north", "north"), ("velocity_north", "velocity_north"),
        ("velocity_east", "velocity_east"), ("velocity_down", "velocity_down"), ("yaw_deg", "yaw_deg"),
        ("pitch_deg", "pitch_deg"), ("roll_deg", "roll_deg"), ("rate_x", "rate_x"), ("rate_y", "rate_y"),
        ("rate_z", "rate_z"))}
    alone = pc.load_case(PA1, {**state, "systems.drogue.deploy_time": 150.0, "systems.drogue.cutaway_time": 160.0,
                               "systems.main.deploy_time": 150.0})
    b = pc.simulate(alone, "full", "implicit", 1e-3, 3.0)
    for column in ("capsule_altitude", "capsule_east", "capsule_velocity_down", "capsule_yaw_deg"):
        later = a[column][row:row + 301]
        np.testing.assert_allclose(later, b[column][:len(later)], atol=1e-6, rtol=1e-9)


def test_drag_area_schedule_scales_the_canopy_force():
    case = pc.load_case(PA1)
    bodies, confluences = initial_states(case)
    bodies.update(deploy(case, case.systems["drogue"], bodies, 3.5)[0])
    canopies, confluence = deploy(case, case.systems["main"], bodies, 9.5)
    bodies.update(canopies)
    phase = next_phase(case, 9.5, 200.0, bodies, {"drogue": confluences.get("drogue"), "main": confluence})
    items = build_full_model(case, phase)
    load = items.aerodynamic_loads["main_canopy"]
    schedule = case.systems["main"].drag_area_schedule
    full = np.linalg.norm(load(items.mbs, 9.5 + 30.0, None))
    assert full > 1e5
    for since in (0.0, 0.75, 1.5, 5.0, 8.5, 12.0, 17.0, 18.0):
        force = np.linalg.norm(load(items.mbs, 9.5 + since, None))
        assert force == pytest.approx(schedule(since) * full, rel=1e-12, abs=1e-9)
    assert schedule(0.75) == pytest.approx(0.04) and schedule(8.5) == pytest.approx(0.165)


WIND_CASE = """
[case]
vehicle = "probe"
[planet]
model = "flat"
gravity = 9.80665
[atmosphere]
model = "us76"
[atmosphere.wind]
east = 5.0
[bodies.probe]                 # a drag body: C_N(alpha') = C_D sin(alpha') makes its drag follow the air-relative
mass = 100.0                   # velocity; aerodynamic centre at the centre of mass, so it does not turn
inertia = [10.0, 10.0, 10.0]
initial.altitude = 3000.0
initial.velocity_down = 9.5
[bodies.probe.aerodynamics]
reference_area = 20.0
axial_coefficient = 1.0
center = [0.0, 0.0, 0.0]
normal_coefficient = { alpha_deg = [0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0], value = [0.0, 0.2588, 0.5, 0.7071, 0.8660, 0.9659, 1.0] }
[simulation]
duration = 60.0
[simulation.steps]
full = 0.01
"""


def test_wind_shifts_the_drift_of_a_steady_descent(tmp_path):
    path = tmp_path / "probe.toml"
    path.write_text(WIND_CASE)
    windy = pc.simulate(pc.load_case(path))
    still = pc.simulate(pc.load_case(path, {"atmosphere.wind.east": 0.0}))
    drift = windy.final("probe_east") - still.final("probe_east")
    # the probe takes up the wind within its horizontal drag time m / (1/2 rho S C_D V) ~ 0.9 s: after 60 s it has
    # drifted 5 m/s x (60 s - that lag) further, and moves with the air
    assert 5.0 * (60.0 - 2.0) < drift < 5.0 * 60.0
    assert windy.final("probe_velocity_east") == pytest.approx(5.0, abs=1e-3)
    assert abs(still.final("probe_east")) < 1e-9
    assert np.abs(windy["probe_angle_of_attack_deg"][windy.time > 10.0]).max() < 0.01   # falls through still air


@pytest.mark.parametrize("overrides, field, message", [
    ({"systems.main.deploy_time": 250.0}, "systems.main.deploy_time", "before the end of the run"),
    ({"systems.drogue.deploy_time": -1.0}, "systems.drogue.deploy_time", "must be >= 0"),
    ({"systems.drogue.cutaway_time": 2.0}, "systems.drogue.cutaway_time", "after the deployment"),
    ({"systems.main.drag_area_schedule.time": [0.0, 1.5, 1.5, 9.0, 16.0, 18.0]},
     "systems.main.drag_area_schedule.time", "strictly increasing"),
    ({"systems.main.drag_area_schedule.fraction": [0.0, 0.08, 0.08, 0.25, 0.25, 1.2]},
     "systems.main.drag_area_schedule.fraction", "within [0, 1]"),
    ({"simulation.ground_altitude": 2500.0}, "simulation.ground_altitude", "below the vehicle's start altitude"),
    ({"systems.main.canopy": "drogue_canopy", "systems.main.lines.riser.attach": "drogue_canopy.riser"},
     "systems.main.canopy", "already the canopy"),
    ({"systems.main.cutaway_time": 250.0}, "systems.main.cutaway_time", "before the end of the run"),
    ({"systems.main.deploy_point": "capsule.apex"}, "systems.main.deploy_point", "has no point 'apex'"),
    ({"atmosphere.wind.altitude": [0.0, 0.0], "atmosphere.wind.east": [1.0, 2.0], "atmosphere.wind.north": [0, 0]},
     "atmosphere.wind.altitude", "strictly increasing"),
])
def test_bad_event_inputs(overrides, field, message):
    with pytest.raises(pc.CaseError) as info:
        pc.load_case(PA1, overrides)
    assert field in str(info.value) and message in str(info.value)


def test_two_systems_with_the_same_name(tmp_path):
    text = PA1.read_text() + '\n[systems.main]\ncanopy = "main_canopy"\n'
    path = tmp_path / "twice.toml"
    path.write_text(text)
    with pytest.raises(pc.CaseError, match=r"systems\.main: defined twice"):
        pc.load_case(path)


def test_sp_agrees_with_the_implicit_full_mass_model(pa1_sp, pa1_implicit):
    assert abs(pa1_sp.summary.touchdown.time - pa1_implicit.summary.touchdown.time) < 0.5   # measured 0.00 s
    gap = math.hypot(pa1_sp.final("capsule_east") - pa1_implicit.final("capsule_east"),
                     pa1_sp.final("capsule_north") - pa1_implicit.final("capsule_north"))
    assert gap < 5.0                                                                      # measured 0.01 m
    assert pa1_sp.summary.method_settings["sp_order"] == 1   # the case keeps the confluence mass to first order


def test_sp_order1_follows_the_capsule_rocking_that_massless_sp_drifts_from(pa1_sp, pa1_implicit):
    """The capsule rocks on the main bridles at 1.2 Hz with little damping and the 8 kg main confluence moves with
    it: massless SP (order 0, the thesis) runs the mode about 0.5 % fast and drifts out of phase by touchdown;
    order 1 keeps the confluence's inertia and stays on the full-mass rocking."""
    massless = pc.simulate(pc.load_case(PA1), "sp", "rk4", 1e-2, order=0)
    open_ = pa1_implicit.time > 27.5          # the mains are fully open 18 s after their deployment at 9.5 s

    def yaw_gap(result):
        return np.abs(np.interp(pa1_implicit.time[open_], result.time, result["capsule_yaw_deg"])
                      - pa1_implicit["capsule_yaw_deg"][open_]).max()
    assert yaw_gap(pa1_sp) < 0.5                                                          # measured 0.13 deg
    assert yaw_gap(massless) > 1.0                                                        # measured 2.2 deg
    worst = max(np.abs(np.interp(pa1_implicit.time[open_], pa1_sp.time, pa1_sp[n]) - pa1_implicit[n][open_]).max()
                for n in ("tension_main_bridle1", "tension_main_bridle2", "tension_main_bridle3"))
    assert worst < 500.0                                                                  # measured 207 N (order 0: 3.5 kN)


def test_summary_json_is_strict_json_with_null_for_absent_values(pa1_sp, tmp_path):
    def refuse(constant):
        raise ValueError(f"non-standard JSON constant {constant}")

    paths = pa1_sp.save(tmp_path / "pa1", plot=False, csv=False)
    summary = json.loads(paths["summary"].read_text(), parse_constant=refuse)
    assert summary["final"]["drogue_confluence_altitude"] is None      # the drogue system was cut away at 9.5 s
    assert summary["final"]["main_confluence_altitude"] > 1000.0
    with np.load(paths["npz"]) as data:
        json.loads(str(data["summary"]), parse_constant=refuse)

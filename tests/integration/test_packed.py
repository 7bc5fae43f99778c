"""Packed recovery gear (``[systems.<s>] packed = true``, ``case.carried``): a system's canopy and confluence ride in
the vehicle at its deploy point until it deploys, so the suspended mass is the same before and after the deployment
and, in vacuum, the pair falls freely at g through it with its momentum unchanged; without the key nothing changes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pchute_exudyn import load_case, simulate
from pchute_exudyn.case.carried import carried, case_at
from pchute_exudyn.case.events import with_event_times
from pchute_exudyn.errors import CaseError
from pchute_exudyn.registries.methods import METHODS

G = 9.80665
V0 = np.array([15.0, 0.0, -5.0])   # m/s, start frame (x east, y north, z up): 15 east, 5 down
SUSPENDED = 20.0 + 1.06 + 0.04      # kg: vehicle, canopy, confluence
FIXED = "deploy_time = 0.5"
TRIGGERED = 'deploy_trigger = { quantity = "altitude", below = 2996.0 }'   # every step: ~0.53 s, between steps
VACUUM = """
[case]
name = "packed"
vehicle = "vehicle"
[planet]
model = "flat"
gravity = 9.80665
[atmosphere]
model = "us76"                         # no body has aerodynamics: a vacuum
[bodies.vehicle]
mass = 20.0
inertia = [0.5, 10.0, 10.0]
points.harness = [-0.3, 0.2, 0.0]
points.line_stretch = [-1.3, 0.2, 0.0]   # the bridle's length aft of the harness, off the axis
[bodies.vehicle.initial]
altitude = 3000.0
velocity_east = 15.0
velocity_down = 5.0
[bodies.canopy]
mass = 1.06
inertia = [1.31, 0.82, 0.82]
points.riser = [3.8, 0.0, 0.0]
[systems.main]
canopy = "canopy"
deploy_point = "vehicle.line_stretch"
{deploy}
{packed}
[systems.main.confluence]
mass = 0.04
[systems.main.lines.bridle]
attach = "vehicle.harness"
free_length = 1.0
stiffness = 100.0
damping = 1.0
[systems.main.lines.riser]
attach = "canopy.riser"
free_length = 5.0
stiffness = 100.0
damping = 1.0
[simulation]
duration = 1.0
output_step = 0.01
method = "full"
steps.full = 0.005
stop_at_ground = false
"""


def _case(tmp_path: Path, deploy: str = FIXED, packed: str = "packed = true", extra: str = ""):
    path = tmp_path / "packed.toml"
    path.write_text(VACUUM.format(deploy=deploy, packed=packed) + extra)
    return load_case(path)


def recorded_phases(monkeypatch, method_name: str = "full") -> list:
    """Record (case, phase) of every phase model the method builds (what the run flies)."""
    built = []
    method = METHODS.resolve(method_name)
    build = method.build

    def recording(self, case, phase):
        built.append((case, phase))
        return build(self, case, phase)

    monkeypatch.setattr(method, "build", recording)
    return built


def _suspended(case, phase) -> float:
    """The phase's suspended mass (kg): its bodies (the vehicle as the composite it flies) and confluences."""
    return (sum(case.mass_of(body, phase.start) for body in phase.bodies)
            + sum(case.systems[name].confluence.mass for name in phase.systems))


def _momentum(case, phase) -> np.ndarray:
    """sum m v (kg m/s, start frame) over the phase's bodies and confluences at its start."""
    bodies = sum(case.mass_of(b, phase.start) * phase.body_states[b].velocity for b in phase.bodies)
    return bodies + sum(case.systems[s].confluence.mass * phase.confluence_states[s].velocity for s in phase.systems)


def _deploy_time(result) -> float:
    return result.summary.events_of("deploy")[0].time


@pytest.mark.parametrize("deploy", [FIXED, TRIGGERED], ids=["fixed", "triggered"])
def test_the_suspended_mass_is_the_same_before_and_after_the_deployment(tmp_path, monkeypatch, deploy):
    built = recorded_phases(monkeypatch)
    result = simulate(_case(tmp_path, deploy))
    deployed = _deploy_time(result)
    assert [p.bodies for _, p in built if p.start < deployed] and all(p.bodies == ["vehicle"] for _, p in built
                                                                      if p.start < deployed)
    assert any(p.start == deployed and p.bodies == ["vehicle", "canopy"] for _, p in built)
    for case, phase in built:
        assert _suspended(case, phase) == pytest.approx(SUSPENDED, rel=1e-15), phase.start


def test_a_triggered_deployment_packs_until_its_trigger_fires(tmp_path):
    """Pending (inf) the gear rides at any time; with the firing time placed (``with_event_times``, as the run's
    Sequence does) it rides until then and leaves then."""
    case = _case(tmp_path, TRIGGERED)
    assert math.isinf(case.systems["main"].deploy_time)
    assert case_at(case, 100.0).bodies["vehicle"].mass == pytest.approx(SUSPENDED)
    flown = with_event_times(case, {"main.deploy": 0.4321})
    assert case_at(flown, 0.4321 - 1e-9).bodies["vehicle"].mass == pytest.approx(SUSPENDED)
    assert case_at(flown, 0.4321).bodies["vehicle"].mass == 20.0
    assert [r.name for r in carried(flown, 0.4321, before=True)] == ["canopy", "main.confluence"]


def test_the_packed_gear_rides_at_the_deploy_point(tmp_path):
    """The composite: the gear's masses at the deploy point d, the canopy a packed bundle (a point mass) there."""
    vehicle = case_at(_case(tmp_path), 0.0).bodies["vehicle"]
    d = np.array([-1.3, 0.2, 0.0])
    c = (1.06 + 0.04) * d / SUSPENDED
    own = np.diag([0.5, 10.0, 10.0]) + 20.0 * (c @ c * np.eye(3) - np.outer(c, c))
    gear = 1.1 * ((d - c) @ (d - c) * np.eye(3) - np.outer(d - c, d - c))   # not the open canopy's 1.31 kg m^2
    np.testing.assert_allclose(vehicle.inertia, own + gear, rtol=1e-14)
    np.testing.assert_allclose(vehicle.points["line_stretch"], d - c, rtol=1e-14)


@pytest.mark.parametrize("deploy", [FIXED, TRIGGERED], ids=["fixed", "triggered"])
def test_in_vacuum_the_pair_falls_freely_and_keeps_its_momentum_through_the_deployment(tmp_path, monkeypatch,
                                                                                        deploy):
    built = recorded_phases(monkeypatch)
    result = simulate(_case(tmp_path, deploy))
    deployed = _deploy_time(result)
    t = result["time"]
    for body in ("vehicle", "canopy", "confluence"):   # the composite before, each part after
        flying = np.isfinite(result[f"{body}_velocity_down"])
        assert flying.any() and (body == "vehicle" or t[flying].min() >= deployed - 1e-12)
        np.testing.assert_allclose(result[f"{body}_velocity_down"][flying], 5.0 + G * t[flying], rtol=0, atol=1e-9)
        np.testing.assert_allclose(result[f"{body}_velocity_east"][flying], 15.0, rtol=0, atol=1e-9)
    after = t >= deployed - 1e-12   # the vehicle's own centre of mass again: the free fall of its initial state
    fall = {"altitude": 3000.0 - 5.0 * t - 0.5 * G * t ** 2, "east": 15.0 * t, "north": 0.0 * t}
    for axis, expected in fall.items():
        np.testing.assert_allclose(result[f"vehicle_{axis}"][after], expected[after], rtol=0, atol=1e-9)
        assert np.abs(result[f"vehicle_{axis}"][~after] - expected[~after]).max() > 1e-3 or axis == "north"
    case, phase = next((c, p) for c, p in built if p.start == deployed and "canopy" in p.bodies)
    before = SUSPENDED * (V0 + np.array([0.0, 0.0, -G * deployed]))   # the composite's, just before (closed form)
    after = _momentum(case, phase)
    assert np.linalg.norm(after - before) <= 1e-9 * np.linalg.norm(before)


def test_a_system_deployed_from_the_vehicle_is_packed_unless_the_case_says_otherwise(tmp_path):
    plain = simulate(_case(tmp_path, packed=""))
    packed = simulate(_case(tmp_path, packed="packed = true"))
    assert list(packed.columns) == list(plain.columns)
    for name in plain.columns:
        assert np.array_equal(packed[name], plain[name], equal_nan=True), name
    assert case_at(_case(tmp_path, packed=""), 0.0).bodies["vehicle"].mass == SUSPENDED   # the gear aboard
    assert case_at(_case(tmp_path, packed="packed = false"), 0.0).bodies["vehicle"].mass == 20.0   # absent


def test_packed_on_a_system_present_from_the_start_is_an_error_of_the_case(tmp_path):
    present = "[systems.main.confluence.initial]\naltitude = 2994.0\n[bodies.canopy.initial]\naltitude = 2990.0\n"
    with pytest.raises(CaseError) as error:
        _case(tmp_path, deploy="", extra=present)
    message = str(error.value)
    assert "\n" not in message
    assert "systems.main.packed = true: a system present from the start (no deploy_time or deploy_trigger) has " \
           "no packed gear" in message


def test_packed_gear_deployed_from_a_body_other_than_the_vehicle_is_an_error(tmp_path):
    path = tmp_path / "other.toml"
    path.write_text(VACUUM.format(deploy=FIXED, packed="packed = true")
                    .replace('deploy_point = "vehicle.line_stretch"', 'deploy_point = "probe.tip"')
                    + '[bodies.probe]\nmass = 1.0\ninertia = [0.1, 0.1, 0.1]\npoints.tip = [0.0, 0.0, 0.0]\n'
                      '[bodies.probe.initial]\naltitude = 3005.0\n')
    with pytest.raises(CaseError, match=r"systems\.main\.deploy_point = 'probe\.tip': is on body 'probe', not the "
                                        r"vehicle 'vehicle': a packed system rides in the vehicle"):
        load_case(path)


CLUSTER = """
[bodies.spare]
mass = 0.8
inertia = [0.5, 0.3, 0.3]
points.riser = [3.0, 0.0, 0.0]
"""


def test_a_canopy_that_never_leaves_the_vehicle_rides_at_the_deploy_point_throughout(tmp_path, monkeypatch):
    """``failures.not_inflated`` (``absent``): the cluster's second canopy stays packed after the deployment, at
    the deploy point, and is not added again by ``Case.mass_of``; the suspended mass is the same in every phase."""
    aero = '[bodies.{0}.aerodynamics]\nreference_area = 0.2\naxial_coefficient = 0.8\ncenter = [0.0, 0.0, 0.0]\n'
    text = (VACUUM.format(deploy=FIXED, packed="packed = true").replace('canopy = "canopy"',
                                                                          'canopies = ["canopy", "spare"]')
            + CLUSTER + aero.format("canopy") + aero.format("spare")
            + '[systems.main.lines.spare_riser]\nattach = "spare.riser"\nfree_length = 5.0\nstiffness = 100.0\n'
              'damping = 1.0\n[failures]\nnot_inflated = "spare"\n')
    path = tmp_path / "cluster.toml"
    path.write_text(text)
    case = load_case(path)
    assert [r.name for r in carried(case, 0.6)] == ["spare"]
    built = recorded_phases(monkeypatch)
    simulate(case, duration=0.7)
    assert {p.start for _, p in built} == {0.0, 0.5}
    for flown, phase in built:
        assert _suspended(flown, phase) == pytest.approx(SUSPENDED + 0.8, rel=1e-15), phase.start

"""Packed recovery gear (issue 48): the suspended mass is the same before and after every deployment of every
shipped case, and a vehicle whose stated mass includes its gear (``mass_includes_packed``) flies as the same
vehicle stated without it."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from pchute_exudyn import load_case, simulate
from pchute_exudyn.case.carried import carried, suspended_mass, vehicle_with
from pchute_exudyn.case.events import with_event_times
from pchute_exudyn.errors import CaseError
from tests.helpers import ROOT
from tests.integration.test_packed import recorded_phases

SHIPPED = [path for path in sorted((ROOT / "cases").rglob("*.toml")) if path.name != "base.toml"]
ROCKET = ROOT / "cases" / "rocket" / "dual_deploy.toml"


def _deployments(case) -> tuple:
    """``case`` with its triggered deployments placed 1 s apart, and its deployment times."""
    placed = {event: 1.0 + k for k, event in enumerate(e for e in case.triggers if e.endswith(".deploy"))}
    case = with_event_times(case, placed) if placed else case
    times = sorted({s.deploy_time for s in case.systems.values() if s.deploy_time and math.isfinite(s.deploy_time)})
    return case, times


def _unpacked_gear(case, time: float) -> float:
    """kg a deployment at ``time`` (s) brings from outside the model: the gear of the systems deploying then that the
    case does not pack (the thesis's PA1 cases name ``packed = false``: the capsule alone until each deploys)."""
    return sum(sum(case.bodies[c].mass for c in s.canopies) + s.confluence.mass for s in case.systems.values()
               if s.deploy_time == time and not s.packed)


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(ROOT / "cases")))
def test_the_suspended_mass_is_the_same_before_and_after_every_deployment(path):
    case, times = _deployments(load_case(path))
    for time in times:   # what is cut away at the same instant (PA1's drogue) is not part of the deployment
        systems = {n: replace(s, cutaway_time=math.inf) if s.cutaway_time == time else s
                   for n, s in case.systems.items()}
        kept = replace(case, systems=systems)
        before, after = suspended_mass(kept, np.nextafter(time, -np.inf)), suspended_mass(kept, time)
        assert after == pytest.approx(before + _unpacked_gear(case, time), rel=1e-14), (path.name, time)
    unpacked = [name for name, s in case.systems.items() if s.deploy_time is not None and not s.packed]
    assert not unpacked or path.name.startswith("cev_pa1"), f"{path.name}: {unpacked} deploy unpacked"


@pytest.mark.parametrize("name, duration", [("rocket/dual_deploy.toml", 120.0), ("mer/edl.toml", 40.0),
                                            ("cev_pa1.toml", 10.0)])
def test_every_phase_a_run_flies_has_the_mass_the_case_accounts(monkeypatch, name, duration):
    """What the engine is given in each phase (its bodies, the vehicle as the composite it flies, its confluences)
    against ``suspended_mass``; the rocket's and the EDL case's stay constant through their deployments."""
    built = recorded_phases(monkeypatch, "sp")
    case = load_case(ROOT / "cases" / name)
    result = simulate(case, "sp", duration=duration)
    fired = {e.name: e.time for e in result.summary.events if e.kind in ("deploy", "cutaway", "separation")}
    flown = with_event_times(case, {event: time for event, time in fired.items() if event in case.triggers})
    masses = [(phase.start, sum(case.mass_of(b, phase.start) for b in phase.bodies)
               + sum(case.systems[s].confluence.mass for s in phase.systems)) for case, phase in built]
    for start, mass in masses:
        assert mass == pytest.approx(suspended_mass(flown, start), rel=1e-14), (name, start)
    deployed = [e.time for e in result.summary.events_of("deploy")]
    assert deployed and len(built) > len(deployed)
    if not name.startswith("cev_pa1"):
        assert max(m for _, m in masses) == pytest.approx(min(m for _, m in masses), rel=1e-14)


def _stated_with_gear(tmp_path):
    """The shipped rocket (20 kg without its gear) written as one weighs it: 21.31 kg with the gear, the inertia and
    points about that centre of mass, the initial state there (nose east: the centre is 0.080 m west)."""
    case = load_case(ROCKET)
    whole, center = vehicle_with(case, carried(case, 0.0, before=True))
    points = "\n".join(f"{name} = [{', '.join(repr(float(x)) for x in p)}]" for name, p in whole.points.items())
    inertia = ", ".join(repr(float(v)) for v in np.diag(whole.inertia))
    path = tmp_path / "stated.toml"
    path.write_text(f'extends = "{ROCKET.as_posix()}"\n[bodies.rocket]\nmass = {float(whole.mass)!r}\n'
                    f'mass_includes_packed = true\ninertia = [{inertia}]\n[bodies.rocket.points]\n{points}\n'
                    f"[bodies.rocket.initial]\neast = {float(center[0])!r}\n")
    return case, path, center


def test_a_vehicle_stated_with_its_gear_flies_as_the_vehicle_stated_without_it(tmp_path):
    case, path, center = _stated_with_gear(tmp_path)
    assert center[0] == pytest.approx(-0.0799155, abs=1e-6)
    stated = load_case(path)
    own = stated.bodies["rocket"]
    assert own.mass == pytest.approx(20.0, rel=1e-14)
    assert own.inertia == pytest.approx(case.bodies["rocket"].inertia, abs=1e-12)
    assert own.points["harness"] == pytest.approx(case.bodies["rocket"].points["harness"], abs=1e-14)
    original, restated = (simulate(c, "sp", duration=12.0) for c in (case, stated))
    for axis in ("altitude", "east", "north"):
        assert restated[f"rocket_{axis}"] == pytest.approx(original[f"rocket_{axis}"], abs=1e-6), axis
    assert restated.summary.events[1].time == original.summary.events[1].time


@pytest.mark.parametrize("key, value, message", [
    ("mass", 1.0, "bodies.rocket.mass = 1.0: with mass_includes_packed must exceed the packed gear's 1.31 kg"),
    ("inertia", [0.01, 0.01, 0.01], "bodies.rocket.inertia = [0.01, 0.01, 0.01]: with mass_includes_packed must "
                                    "exceed"),
])
def test_a_stated_mass_smaller_than_its_gear_is_refused(key, value, message):
    overrides = {"bodies.rocket.mass_includes_packed": True, f"bodies.rocket.{key}": value}
    with pytest.raises(CaseError) as error:
        load_case(ROCKET, overrides=overrides)
    assert message in str(error.value)

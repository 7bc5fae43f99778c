"""One ground (issue 59): the case's ``simulation.ground_altitude`` is the ground of every height, trigger and output
whether or not the run stops there (``stop_at_ground = false`` only flies on below it), and a run that touches down
reports its final state at the interpolated touchdown, not at its last step past the ground.

The case is the shipped rocket (ground at 1400 m, its main on a trigger 300 m above the ground, about 105 s in; SP at
adaptive steps, touchdown about 155 s in: each run below takes well under a second)."""

from __future__ import annotations

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.registries.columns import column
from pchute_exudyn.results.run_line import run_line
from tests.helpers import ROOT

ROCKET = ROOT / "cases" / "rocket" / "dual_deploy.toml"
GROUND = 1400.0   # m, the case's
FLY_ON = {"simulation.stop_at_ground": False}


@pytest.fixture(scope="module")
def landed():
    """The rocket to touchdown, as shipped."""
    return pc.simulate(pc.load_case(ROCKET))


def _main_deployment(result):
    return next(e for e in result.summary.events if e.kind == "deploy" and e.system == "main")


def test_flying_on_changes_nothing_above_the_ground():
    """To 110 s, past the main's deployment and above the ground: every column of the run that flies on is the run
    that stops at the ground, bit for bit; its main fires 300 m above the case's ground, not above 0 m."""
    stops = pc.simulate(pc.load_case(ROCKET), duration=110.0, history=False)
    flies = pc.simulate(pc.load_case(ROCKET, FLY_ON), duration=110.0, history=False)
    assert stops.columns.keys() == flies.columns.keys()
    assert all(np.array_equal(stops[k], flies[k], equal_nan=True) for k in stops.columns)
    deploy = _main_deployment(flies)
    assert deploy.time == _main_deployment(stops).time and deploy.trigger["true"] == pytest.approx(300.0, abs=0.5)
    assert flies.summary.ground_altitude == GROUND and flies.summary.stop_at_ground is False
    assert flies.summary.to_dict()["stop_at_ground"] is False and "stop_at_ground" not in stops.summary.to_dict()
    assert not any("never fired" in w for w in flies.summary.warnings)


def test_below_the_ground_heights_go_negative_from_the_same_ground(landed):
    flies = pc.simulate(pc.load_case(ROCKET, FLY_ON), duration=160.0, history=False)
    altitude, height = (flies[column(t, "rocket")] for t in ("{owner}_altitude", "{owner}_height"))
    assert np.array_equal(height, altitude - GROUND)
    assert height[-1] < -20.0 and flies.summary.end == "duration" and flies.summary.touchdown is None
    assert _main_deployment(flies).time == _main_deployment(landed).time


def test_the_final_state_is_the_interpolated_touchdown(landed, tmp_path):
    """The last step ends below the ground; the touchdown event holds the crossing's time and place, between the
    last two samples, on the ground; the run line reports them; the last sample stays in ``final`` and the columns."""
    touchdown, final = landed.summary.touchdown, landed.summary.final
    time, altitude, east = (landed[column(t, "rocket")] if t != "time" else landed.time
                            for t in ("time", "{owner}_altitude", "{owner}_east"))
    assert altitude[-1] < GROUND < altitude[-2]                       # the last step overshoots
    assert time[-2] < touchdown.time < time[-1] and final.time == time[-1] and final.altitude == altitude[-1]
    assert touchdown.altitude == GROUND
    assert min(east[-2:]) <= touchdown.east <= max(east[-2:]) and abs(touchdown.north) < 1e-6
    line = run_line(landed.summary, "out")
    assert f"touchdown at {touchdown.time:.2f} s" in line
    assert f"final rocket altitude 1400.00 m, east {touchdown.east:.3f} m, north 0.000 m" in line
    landed.save(tmp_path / "run", plot=False)
    assert pc.Result.load(tmp_path / "run").summary.touchdown == touchdown   # kept in summary.json

"""Normal gravity through a real run (docs/models/gravity.md): a body released at rest relative to the ground in
vacuum 2500 m over the WGS-84 ellipsoid at 33 deg latitude (tests/cases/vacuum_drop.toml). With the frame turning
with the planet it falls along the local vertical; with Earth's rotation on it lands east by the Coriolis deflection
(1/3) Omega g t^3 cos(latitude) and (to second order in Omega) not measurably north or south."""

import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.physics import gravity as gr
from tests.helpers import ROOT

CASE = ROOT / "tests" / "cases" / "vacuum_drop.toml"
LATITUDE = math.radians(33.0)


def touchdown(overrides=()):
    """(fall time in s, east in m, north in m) at touchdown, the position interpolated to the event's time."""
    result = pc.simulate(pc.load_case(CASE, overrides), method="full", integrator="rk4", step=0.002)
    time = result.summary.touchdown.time
    c = result.columns
    return time, float(np.interp(time, c["time"], c["ball_east"])), float(np.interp(time, c["time"], c["ball_north"]))


def test_falls_along_the_local_vertical_without_rotation():
    time, east, north = touchdown()
    assert math.hypot(east, north) < 1e-3
    g = gr.NormalGravity(gr.WGS84_GM, gr.WGS84_A, gr.WGS84_B, gr.WGS84_OMEGA).magnitude(LATITUDE, 1250.0)
    assert time == pytest.approx(math.sqrt(2 * 2500.0 / g), rel=1e-3)   # g grows 8e-4 over the drop


def test_rotation_deflects_east_by_coriolis():
    time, east, north = touchdown({"planet.rotation_rate": gr.WGS84_OMEGA})
    g = gr.NormalGravity(gr.WGS84_GM, gr.WGS84_A, gr.WGS84_B, gr.WGS84_OMEGA).magnitude(LATITUDE, 1250.0)
    expected = gr.WGS84_OMEGA * g * time**3 * math.cos(LATITUDE) / 3.0
    assert east == pytest.approx(expected, rel=0.01)
    assert abs(north) < 0.01


def test_spherical_gravity_drifts_poleward():
    # the thesis's gravity toward the centre is 0.175 deg off the normal at 33 deg: about 7.7 m north over 2500 m
    _, east, north = touchdown({"planet.gravity_model": "spherical"})
    assert east == 0.0 and 7.0 < north < 8.5

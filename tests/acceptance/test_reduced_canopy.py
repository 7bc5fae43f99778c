"""The reduced canopy (docs/models/reduced_canopy.md): a light canopy as a massless drag point at its riser's end,
against full mass with the canopy rigid, and its bad inputs."""

import numpy as np
import pytest

import pchute_exudyn as pc
from tests.helpers import ROOT

ROCKET = ROOT / "cases" / "rocket" / "dual_deploy.toml"


def test_a_reduced_drogue_opens_and_descends_as_the_rigid_one_of_full_mass():
    """The rocket from apogee to 8 s past its drogue's deployment (the opening, the swing under the drogue): SP with
    the reduced canopy at adaptive steps against full mass RK4 at 1e-4 s with the rigid canopy. Measured: the rocket's
    descent rate at 9 s within 0.02 %, its altitude within 0.38 m (the reduced canopy cannot slide across the air,
    so the rocket swings down from 90 degrees a little more slowly: 0.7 % in the rate at 3 s, none once it hangs),
    the drogue's peak riser tension within 0.5 %."""
    case = pc.load_case(ROCKET, {"systems.drogue.deploy_trigger": {"time": 1.01}})   # as sampled at 100 Hz, both
    full = pc.simulate(case, "full", "rk4", 1e-4, 9.0)
    reduced = pc.simulate(case, "sp", "rk4", None, 9.0)
    assert reduced.summary.step_control["count"] < 0.01 * full.summary.steps
    assert reduced.final("rocket_velocity_down") == pytest.approx(full.final("rocket_velocity_down"), rel=1e-3)
    assert reduced.final("rocket_altitude") == pytest.approx(full.final("rocket_altitude"), abs=0.5)
    peak = {r: float(np.nanmax(r["tension_drogue_riser"])) for r in (full, reduced)}
    assert peak[reduced] == pytest.approx(peak[full], rel=1e-2)
    # the canopy flies at zero incidence, at its apex's distance above the drag point
    assert np.nanmax(reduced["drogue_canopy_angle_of_attack_deg"][reduced.time > 2.0]) < 1e-6


@pytest.mark.parametrize("override, message", [
    ({"systems.drogue.lines.bridle2": {"attach": "rocket.harness", "free_length": 1.0, "stiffness": 7845.32,
                                       "damping": 78.45}},
     "reduced needs one canopy on one riser in series with one bridle from another body"),
    ({"drogue_canopy.apparent_mass": {"projected_radius": 0.43, "axial": 1.0, "lateral": 0.5, "rotational": 0.1}},
     "so it takes no apparent_mass"),
    ({"systems.drogue.canopy_model": "soft"}, "must be one of: auto, rigid, reduced"),
])
def test_a_reduced_canopy_where_it_cannot_fly_is_one_line(override, message):
    with pytest.raises(pc.CaseError, match=message):
        pc.load_case(ROCKET, override)

"""The reduced canopy (docs/models/reduced_canopy.md): a light canopy as a massless drag point at its riser's end,
against full mass with the canopy rigid, and its bad inputs."""

import numpy as np
import pytest

import pchute_exudyn as pc
from tests import reference_runs
from tests.helpers import ROOT

ROCKET = ROOT / "cases" / "rocket" / "dual_deploy.toml"


def test_a_reduced_drogue_opens_and_descends_as_the_rigid_one_of_full_mass():
    """The rocket from apogee to 8 s past its drogue's deployment (the opening, the swing under the drogue): SP with
    the reduced canopy at adaptive steps against full mass RK4 at 1e-4 s with the rigid canopy (its recorded figures,
    tests/reference_runs.py ``ROCKET_DROGUE``; checked against the code by the slow test below). Measured: the
    rocket's descent rate at 9 s within 0.02 %, its altitude within 0.38 m (the reduced canopy cannot slide across the
    air, so the rocket swings down from 90 degrees a little more slowly: 0.7 % in the rate at 3 s, none once it
    hangs), the drogue's peak riser tension within 0.5 %."""
    full = reference_runs.rocket_drogue_reference()
    reduced = pc.simulate(reference_runs.rocket_drogue_case(), "sp", "rk4", None, reference_runs.ROCKET_DROGUE_RUN[-1])
    assert reduced.summary.step_control["count"] < 0.01 * full["steps"]
    assert reduced.final("rocket_velocity_down") == pytest.approx(full["rocket_velocity_down"], rel=1e-3)
    assert reduced.final("rocket_altitude") == pytest.approx(full["rocket_altitude"], abs=0.5)
    assert float(np.nanmax(reduced["tension_drogue_riser"])) == pytest.approx(full["peak_tension_drogue_riser"],
                                                                             rel=1e-2)
    # the canopy flies at zero incidence, at its apex's distance above the drag point
    assert np.nanmax(reduced["drogue_canopy_angle_of_attack_deg"][reduced.time > 2.0]) < 1e-6


@pytest.mark.slow
def test_the_recorded_rigid_drogue_reference_is_what_the_code_computes():
    """The figures the test above reads (``ROCKET_DROGUE``) against the full-mass run made again (10-20 s): within
    1e-9 relative, the RK4 tolerance of the other recorded runs; the step count exact. When the full model's numbers
    change on purpose, record them again: ``python tests/reference_runs.py --rocket-drogue``."""
    run = reference_runs.rocket_drogue_figures(reference_runs.rocket_drogue_full_run())
    recorded = reference_runs.rocket_drogue_reference()
    assert run["steps"] == recorded["steps"]
    for name in ("rocket_velocity_down", "rocket_altitude", "peak_tension_drogue_riser"):
        assert run[name] == pytest.approx(recorded[name], rel=reference_runs.TOLERANCE["rk4"]), name


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

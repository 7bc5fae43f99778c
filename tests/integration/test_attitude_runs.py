"""Runs at every attitude (docs/models/aerodatabase.md, "Every attitude"): a model that adds energy is stopped as a
runaway named with its body, quantity, value and time; an implicit step across a constant coefficient's jump at
90 deg names the edge-on canopy. The kernel's own checks are tests/unit/test_every_attitude.py."""

from __future__ import annotations

import pytest

import pchute_exudyn as pc
from pchute_exudyn.errors import SimulationError
from pchute_exudyn.physics.runaway import SPEED_MULTIPLE


def test_a_model_that_adds_energy_is_stopped_as_a_named_runaway(tmp_path):
    """A total C_A table kept positive beyond 90 deg (the old constant-C_A law, with MER's C_N) pumps energy into a
    cluster's canopy that a sudden 10 m/s crosswind turns past 90 deg (the issue's cargo drop, started still over the
    ground): the run stops with one line naming the body, the quantity, its value and the time (not 'altitude
    outside the atmosphere'); with the law of every attitude the same start flies on."""
    path = tmp_path / "cargo.toml"
    path.write_text(pc.new_case_text(planet="earth", mass=2000.0, canopy_diameter=30.5, canopy_type="flat_circular",
                                     canopies=3, altitude=1500.0))
    overrides = {"start.velocities_relative_to": "ground", "atmosphere.wind.east": 10.0, "simulation.duration": 2.0}
    for i in (1, 2, 3):   # C_A positive beyond 90 deg (a total table), C_N of MER's canopy (0 at 90 deg)
        overrides[f"canopy{i}.aerodynamics.axial_coefficient"] = {"alpha_deg": [0.0, 180.0], "value": [0.77, 0.77]}
        overrides[f"canopy{i}.aerodynamics.normal_coefficient.value"] = [0, 0.04, 0.08, 0.11, 0.13, 0.15, 0.14, 0.11, 0]
    with pytest.raises(SimulationError) as caught:
        pc.simulate(pc.load_case(path, overrides), "sp")
    text = str(caught.value)
    assert text.startswith("body canopy") and "ran away at t = " in text and "its speed reached" in text
    assert f"{SPEED_MULTIPLE:g} times" in text and "\n" not in text
    with_the_law = pc.load_case(path, {key: value for key, value in overrides.items() if "axial" not in key})
    assert pc.simulate(with_the_law, "sp").summary.end == "duration"   # the same start, every attitude's law


def test_an_implicit_step_across_a_constant_coefficients_jump_names_the_edge_on_canopy(tmp_path):
    """A constant C_A changes sign at 90 deg: the implicit integrator's step has no solution while a canopy slides
    along it, so the run stops naming the canopy and its angle, and what to use instead (`pchute new`'s table, which
    falls to 0 at 90 deg, runs: tests/integration/test_starts.py and validation/release.py)."""
    path = tmp_path / "release.toml"
    path.write_text(pc.new_case_text(planet="earth", mass=2000.0, canopy_diameter=30.5, canopy_type="flat_circular",
                                     canopies=3, altitude=1500.0, release_airspeed=65.0, release_heading_deg=90.0))
    constant = {f"canopy{i}.aerodynamics.axial_coefficient": 0.77 for i in (1, 2, 3)}
    with pytest.raises(SimulationError) as caught:
        pc.simulate(pc.load_case(path, constant), "full", "implicit", 1e-2, duration=10.0)
    text = str(caught.value)
    assert "flies edge-on to the air (angle of attack" in text and "use RK4" in text and text.startswith(
        "the implicit integration stopped at t = ")

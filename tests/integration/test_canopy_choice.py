"""The canopy model a case does not name (``canopy_model = "auto"``, docs/models/reduced_canopy.md, "Chosen by
itself"): reduced for a light canopy where a reduced canopy is valid, rigid for a heavy one; a named model obeyed; the
choice in the summary and the run line."""

import math

import pytest

import pchute_exudyn as pc
from pchute_exudyn.authoring.choices import NewCase
from pchute_exudyn.authoring.layout import layout
from pchute_exudyn.case.canopy_choice import (
    LIGHT_CANOPY_TIME,
    canopy_models_flown,
    drag_time_constant,
    steady_drag_time,
)
from pchute_exudyn.results.run_line import run_line
from tests.helpers import ROOT

ROCKET = ROOT / "cases" / "rocket" / "dual_deploy.toml"


@pytest.fixture(scope="module")
def by_hand(tmp_path_factory):
    """The shipped dual deploy as written by hand before the reduced canopy: no ``canopy_model``."""
    path = tmp_path_factory.mktemp("by_hand") / "dual_deploy.toml"
    path.write_text("".join(line for line in ROCKET.read_text().splitlines(keepends=True)
                            if not line.startswith("canopy_model")))
    return path


def test_the_drag_time_constant_at_the_steady_rate_is_its_closed_form():
    """m / (rho C S V) at V = sqrt(2 M g / (rho C S)) is m / sqrt(2 M g rho C S): the drogue of 0.17 kg (C_D0 0.77,
    S0 1.3 m^2) under 21.31 kg at 3900 m (rho 0.8 kg/m^3) is light, 9.3 ms."""
    m, big_m, g, rho, c, s = 0.17, 21.31, 9.79, 0.8, 0.77, 1.3
    speed = math.sqrt(2.0 * big_m * g / (rho * c * s))
    assert drag_time_constant(m, rho, c, s, speed) == pytest.approx(m / (rho * c * s * speed), rel=1e-15)
    assert steady_drag_time(m, big_m, g, rho, c, s) == pytest.approx(m / math.sqrt(2.0 * big_m * g * rho * c * s),
                                                                     rel=1e-14)
    assert steady_drag_time(m, big_m, g, rho, c, s) == pytest.approx(0.0093, abs=1e-4)
    assert steady_drag_time(m, big_m, g, rho, c, s) < LIGHT_CANOPY_TIME
    assert drag_time_constant(m, rho, c, s, 0.0) == math.inf


def test_a_case_without_canopy_model_gets_reduced_when_light_rigid_when_heavy_and_a_named_model_is_obeyed(by_hand):
    light = pc.load_case(by_hand)
    assert {n: (s.canopy_model, s.canopy_model_chosen) for n, s in light.systems.items()} == {
        "drogue": ("reduced", True), "main": ("reduced", True)}
    heavy = pc.load_case(by_hand, {"drogue_canopy.mass": 5.0})   # 0.27 s: its drag's time constant
    assert (heavy.systems["drogue"].canopy_model, heavy.systems["main"].canopy_model) == ("rigid", "reduced")
    named = pc.load_case(by_hand, {"systems.drogue.canopy_model": "rigid", "drogue_canopy.mass": 0.17})
    assert (named.systems["drogue"].canopy_model, named.systems["drogue"].canopy_model_chosen) == ("rigid", False)
    assert pc.load_case(ROCKET, {"drogue_canopy.mass": 5.0}).systems["drogue"].canopy_model == "reduced"
    # pchute new's rule is the same: Mars's thin air makes its canopy heavy, and the loader agrees
    mars = NewCase(planet="mars", mass=100.0, drag_area=10.0, bridles=1, altitude=100.0)
    assert layout(mars).canopy_drag_time(layout(mars).steady_rate(100.0)) > LIGHT_CANOPY_TIME
    assert pc.new_case(planet="mars", mass=100.0, drag_area=10.0, bridles=1,
                       altitude=100.0).systems["main"].canopy_model == "rigid"


def test_the_choice_is_in_the_summary_and_the_run_line(by_hand, tmp_path):
    result = pc.simulate(pc.load_case(by_hand), duration=0.5)
    assert result.summary.canopy_models == {"drogue": {"model": "reduced", "chosen": "auto"},
                                            "main": {"model": "reduced", "chosen": "auto"}}
    assert result.summary.to_dict()["canopy_models"] == result.summary.canopy_models
    assert "; canopy model chosen: drogue reduced, main reduced -> out" in run_line(result.summary, "out")
    assert "canopy model chosen" not in run_line(pc.simulate(pc.load_case(ROCKET), duration=0.5).summary, "out")
    flown = canopy_models_flown(pc.load_case(by_hand).systems, pc.METHODS["full"].flies_reduced_canopies)   # rigid
    assert flown["drogue"] == {"model": "rigid", "chosen": "auto"}

"""The quantities a trigger's sensor reads (``registries.quantities.QUANTITIES``, issue 47): one record each, complete —
its true value computed, its sensed value formed, its unit in the column registry when a study keeps it, its line in
docs/case-format.md, and a threshold on it read from a case."""


import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.case.sensing import true_values
from pchute_exudyn.registries.columns import unit
from pchute_exudyn.registries.quantities import QUANTITIES, SENSED, THRESHOLD_QUANTITIES
from pchute_exudyn.triggers.definition import Sensor
from pchute_exudyn.triggers.sensors import sense
from tests.helpers import ROOT


def test_every_quantity_is_computed_sensed_documented_and_has_its_units():
    case = pc.load_case(ROOT / "cases" / "cev_pa1_winds.toml")
    truth = true_values(case, [0.0, 0.0, 3000.0], [10.0, 0.0, -60.0], 1.0)   # start frame, m and m/s
    sensed = sense(truth, Sensor(), 10.0, 2.0, lambda h: (101325.0 * np.exp(-h / 8000.0), 1.2))
    docs = (ROOT / "docs" / "case-format.md").read_text()
    assert set(SENSED) == {q.name for q in QUANTITIES}
    for quantity in QUANTITIES:
        assert np.isfinite(truth[quantity.name]) and np.isfinite(sensed[quantity.name]), quantity.name
        assert f"`{quantity.name}`" in docs, quantity.name
        if quantity.studied:
            assert unit(f"deploy_{quantity.name}_main") == quantity.unit
        if quantity.error == "speed":
            assert sensed[quantity.name] == pytest.approx(truth[quantity.name] + 2.0)
    assert sensed["mach"] == pytest.approx(sensed["airspeed"] / truth["speed_of_sound"])
    assert truth["dynamic_pressure"] == pytest.approx(0.5 * truth["density"] * truth["airspeed"] ** 2)


@pytest.mark.parametrize("quantity", sorted(THRESHOLD_QUANTITIES))
def test_a_threshold_on_every_watched_quantity_is_read_from_a_case(quantity):
    case = pc.load_case(ROOT / "cases" / "cev_pa1_triggers.toml",
                        {"systems.main.deploy_trigger": {"quantity": quantity, "below": 1.0}})
    condition = case.triggers["main.deploy"].condition
    assert condition.quantity == quantity and condition.value == 1.0

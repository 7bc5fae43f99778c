"""The canopy types of ``pchute new`` (``registries.canopy_types.CANOPY_TYPES``, issue 47): one record each, complete and within
the published ranges it cites, documented in the tutorial and the sources, and written by ``pchute new``."""

import re

import pytest

import pchute_exudyn as pc
from pchute_exudyn.registries.canopy_types import CANOPY_TYPES
from tests.helpers import ROOT


@pytest.mark.parametrize("name", sorted(CANOPY_TYPES))
def test_every_canopy_type_is_a_complete_record_within_its_cited_range(name):
    canopy = CANOPY_TYPES[name]
    assert canopy.name == name and canopy.drag_source and canopy.opening_source
    low, high = (float(x) for x in re.findall(r"\d\.\d+", canopy.drag_range)[:2])
    assert low <= canopy.drag_coefficient <= high or name == "ribbon"   # ribbon: where two ranges meet
    assert canopy.fill_constant > 0.0 and canopy.opening_exponent > 0.0 and canopy.overinflation >= 1.0
    label = "disk-gap-band" if name == "disk_gap_band" else name.replace("_", " ")
    row = next(line for line in (ROOT / "docs" / "tutorial.md").read_text().splitlines()
               if line.startswith(f"| {label} | "))   # the tutorial's opening table shows the record's values
    assert [float(cell) for cell in row.split("|")[2:5]] == [canopy.fill_constant, canopy.opening_exponent,
                                                            canopy.overinflation]
    case = pc.new_case(planet="earth", mass=100.0, drag_area=10.0, canopy_type=name, altitude=500.0,
                       release_airspeed=40.0)
    canopy_body = next(body for body in case.bodies.values() if body.aerodynamics is not None)
    assert canopy_body.aerodynamics.reference_area == pytest.approx(10.0 / canopy.drag_coefficient)
    opening = next(iter(case.systems.values())).inflation
    assert opening.stages[0].fill_constant == pytest.approx(canopy.fill_constant)

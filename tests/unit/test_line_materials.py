"""Line materials (docs/models/line_materials.md): the records' curves, and a case line that names a material and its
breaking strength read as the load-elongation table T_b f(eps)."""

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.physics.line_materials import LINE_MATERIALS, toe_and_line
from tests.helpers import TEST_CASES

HANGING = TEST_CASES / "hanging_kevlar.toml"
BREAKING = {"kevlar": 0.045, "technora": 0.054, "nylon": 0.20}
FIBRE = {"kevlar": (0.036, 0.009), "technora": (0.045, 0.009)}   # fibre breaking strain, structural stretch


def test_the_materials_are_the_documented_three():
    assert list(LINE_MATERIALS) == ["kevlar", "technora", "nylon"]
    assert {name: m.breaking_strain for name, m in LINE_MATERIALS.items()} == BREAKING


@pytest.mark.parametrize("name", list(LINE_MATERIALS))
def test_each_curve_runs_from_zero_to_the_break_and_stiffens(name):
    material = LINE_MATERIALS[name]
    strain, fraction = np.array(material.strain), np.array(material.fraction)
    assert (strain[0], fraction[0], fraction[-1]) == (0.0, 0.0, 1.0)
    assert len(strain) == len(fraction) >= 5 and (np.diff(strain) > 0).all() and (np.diff(fraction) > 0).all()
    slopes = np.diff(fraction) / np.diff(strain)
    assert (np.diff(slopes) >= -1e-3 * slopes[1:]).all()   # stiffening, within the 4-digit rounding
    assert material.source and material.description


@pytest.mark.parametrize("name", list(FIBRE))
def test_aramid_cords_are_the_toe_and_the_fibres_line(name):
    material = LINE_MATERIALS[name]
    fibre, structural = FIBRE[name]
    assert np.allclose(material.fraction, toe_and_line(fibre, structural, material.strain), atol=5e-5, rtol=0)
    assert material.breaking_strain == pytest.approx(fibre + structural, abs=1e-12)
    last = (material.fraction[-1] - material.fraction[-2]) / (material.strain[-1] - material.strain[-2])
    assert last == pytest.approx(1.0 / fibre, rel=1e-3)   # the straight part: the fibre's T_b / eps_fibre


def test_nylon_is_the_assumed_power_law():
    nylon = LINE_MATERIALS["nylon"]
    assert np.allclose(nylon.fraction, (np.array(nylon.strain) / 0.2) ** 1.5, atol=5e-5, rtol=0)


@pytest.mark.parametrize("name", list(LINE_MATERIALS))
def test_a_material_line_reads_as_its_curve_times_the_breaking_strength(name):
    case = pc.load_case(HANGING, {"systems.hang.lines.lower.material": name,
                                  "systems.hang.lines.lower.breaking_strength": 3000.0})
    line = case.systems["hang"].lines[1]
    material = LINE_MATERIALS[name]
    assert line.rating.material is material and line.rating.breaking_strength == 3000.0
    assert line.rating.breaking_strain == BREAKING[name]
    assert line.load_elongation.strain == material.strain
    assert line.load_elongation.tension == tuple(3000.0 * f for f in material.fraction)
    assert line.stiffness == pytest.approx(line.load_elongation.slopes()[0] / line.free_length, rel=1e-15)
    assert line.load_elongation(BREAKING[name]) == pytest.approx(3000.0, rel=1e-12)
    assert case.warnings == ()


def test_a_line_without_a_material_has_no_rating():
    case = pc.load_case(TEST_CASES / "hanging_table.toml")
    assert all(line.rating is None for line in case.systems["hang"].lines)

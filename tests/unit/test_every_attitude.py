"""Aerodynamics at every attitude (docs/models/aerodatabase.md, "Every attitude"): the force never adds energy to a
body's motion through the air for C_A, C_N >= 0 at any of 10,000 random attitudes and air velocities; a body
symmetric fore and aft, turned round, gets the same force and moment; a runaway is named with its body, quantity,
value and time."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.errors import SimulationError
from pchute_exudyn.physics.aerodynamics import CoefficientTable, aerodynamic_load, pack_body, pack_tables
from pchute_exudyn.physics.runaway import SPEED_MULTIPLE

SAMPLES = 10_000
ANGLES = [0.0, 10.0, 20.0, 30.0, 45.0, 60.0, 75.0, 90.0]
TOTAL = [0.0, 20.0, 45.0, 70.0, 90.0, 110.0, 135.0, 160.0, 180.0]


def random_rotation(rng) -> np.ndarray:
    """A uniformly random attitude (body -> start frame), from a random unit quaternion."""
    q = rng.standard_normal(4)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def random_tables(rng, kind: str) -> tuple:
    """(C_A, C_N, C_m) of one of three kinds, C_A and C_N >= 0: constants, folded tables (0..90 deg), total tables
    (0..180 deg) with C_A of the sign of cos(alpha) (body-axis data: a capsule's C_A < 0 apex forward)."""
    if kind == "constant":
        return (CoefficientTable.constant(rng.uniform(0.0, 2.0)), CoefficientTable.constant(rng.uniform(0.0, 1.0)),
                CoefficientTable.constant(rng.uniform(-0.5, 0.5)))
    if kind == "folded":
        return tuple(CoefficientTable(tuple(ANGLES), tuple(rng.uniform(low, high, len(ANGLES))))
                     for low, high in ((0.0, 2.0), (0.0, 1.0), (-0.5, 0.5)))
    signs = np.sign(np.cos(np.radians(TOTAL)))
    axial = signs * rng.uniform(0.0, 2.0, len(TOTAL))
    axial[TOTAL.index(90.0)] = 0.0   # the sign changes there: continuous data passes through 0
    return (CoefficientTable(tuple(TOTAL), tuple(axial)), CoefficientTable(tuple(TOTAL), tuple(rng.uniform(0, 1, 9))),
            CoefficientTable(tuple(TOTAL), tuple(rng.uniform(-0.5, 0.5, 9))))


def load(tables, velocity, rotation, rates=(0.0, 0.0, 0.0), density=1.1, area=30.0):
    """(force in N, start frame; moment in N m, body axes) of ``aerodynamic_load`` for these coefficients."""
    packed, offsets = pack_tables(list(tables) + [CoefficientTable.constant(-0.3)])
    body = np.array(pack_body(area, 2.0, {"axial": offsets[0], "normal": offsets[1], "moment": offsets[2],
                                          "pitch_damping": offsets[3]}))
    out = aerodynamic_load(packed, body, *map(float, velocity), np.ascontiguousarray(rotation).ravel(),
                           np.asarray(rates, float), density, 340.0, 1.0)
    return np.array(out[:3]), np.array(out[3:6])


@pytest.mark.parametrize("kind", ["constant", "folded", "total"])
def test_the_force_never_adds_energy_to_the_motion_through_the_air(kind):
    """F . V <= 0 (to round-off) at random attitudes, air velocities (0.1 to 500 m/s) and C_A, C_N >= 0: the axial
    force opposes the axial airspeed at every angle, the normal force the cross-flow."""
    rng = np.random.default_rng(33)
    worst, beyond_90, tables = -math.inf, 0, None
    for i in range(SAMPLES):
        if i % 100 == 0:   # a hundred coefficient sets, each at a hundred attitudes
            tables = random_tables(rng, kind)
        rotation = random_rotation(rng)
        velocity = rng.standard_normal(3)
        velocity *= rng.uniform(0.1, 500.0) / np.linalg.norm(velocity)
        force, _ = load(tables, velocity, rotation)
        beyond_90 += velocity @ rotation[:, 0] < 0.0
        worst = max(worst, force @ velocity / (np.linalg.norm(force) * np.linalg.norm(velocity) + 1e-300))
    assert worst <= 1e-12
    assert beyond_90 > 0.4 * SAMPLES   # half of the attitudes fly backwards


def test_a_body_symmetric_fore_and_aft_turned_round_gets_the_same_loads():
    """Folded tables (and constants) describe a body symmetric fore and aft: turned round about its z axis (x and y
    reversed) it flies at 180 - alpha with the same shape to the air, so the force (start frame) and the moment
    (start frame) are the same; the damping moments too, with the rates expressed in the turned axes."""
    rng = np.random.default_rng(7)
    turn = np.diag([-1.0, -1.0, 1.0])
    for kind in ("constant", "folded"):
        tables = random_tables(rng, kind)
        for _ in range(500):
            rotation, velocity, rates = random_rotation(rng), rng.standard_normal(3) * 40.0, rng.standard_normal(3)
            force, moment = load(tables, velocity, rotation, rates)
            turned_force, turned_moment = load(tables, velocity, rotation @ turn, turn @ rates)
            scale = np.linalg.norm(force) + np.linalg.norm(moment) + 1.0
            np.testing.assert_allclose(turned_force, force, atol=1e-12 * scale)
            np.testing.assert_allclose(rotation @ turn @ turned_moment, rotation @ moment, atol=1e-11 * scale)


def test_the_axial_force_below_90_degrees_is_the_constant_coefficient_law():
    """Below 90 deg nothing changed: F = -q S C_A e - q S C_N V_perp / |V_perp| (the thesis's cases fly there)."""
    rng = np.random.default_rng(3)
    tables = random_tables(rng, "folded")
    for _ in range(200):
        rotation = random_rotation(rng)
        e = rotation[:, 0]
        velocity = rng.standard_normal(3) * 30.0
        if velocity @ e < 0.0:
            velocity -= 2.0 * (velocity @ e) * e
        alpha = math.degrees(math.atan2(np.linalg.norm(np.cross(velocity, e)), velocity @ e))
        q_s = 0.5 * 1.1 * (velocity @ velocity) * 30.0
        perp = velocity - (velocity @ e) * e
        expected = -q_s * tables[0](alpha) * e - q_s * tables[1](alpha) * perp / np.linalg.norm(perp)
        np.testing.assert_allclose(load(tables, velocity, rotation)[0], expected, rtol=1e-13, atol=1e-9)


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

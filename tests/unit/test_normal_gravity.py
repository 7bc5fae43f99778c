"""Normal gravity (physics.gravity, docs/models/gravity.md): the closed forms against WGS-84's published values and
Mars's own constants, the kernel's direction and height correction, and the [planet] keys' bad input."""

import math

import numpy as np
import pytest

from pchute_exudyn.errors import CaseError
from pchute_exudyn.physics import gravity as gr
from pchute_exudyn.physics.planet import Planet, StartFrame
from tests.helpers import ROOT

WGS84 = gr.NormalGravity(gr.WGS84_GM, gr.WGS84_A, gr.WGS84_B, gr.WGS84_OMEGA)
MARS = gr.NormalGravity(gr.MARS_GM, gr.MARS_A, gr.MARS_B, gr.MARS_OMEGA)


def closed_form(n: gr.NormalGravity) -> tuple:
    """gamma_e, gamma_p by Heiskanen & Moritz 2-141/2-142 with q0, q0' in their closed (atan) forms."""
    a, b, gm = n.equatorial_radius, n.polar_radius, n.gravitational_parameter
    e1 = math.sqrt(a * a - b * b) / b
    q0 = 0.5 * ((1.0 + 3.0 / e1**2) * math.atan(e1) - 3.0 / e1)
    q0p = 3.0 * (1.0 + 1.0 / e1**2) * (1.0 - math.atan(e1) / e1) - 1.0
    m = n.spin_rate**2 * a * a * b / gm
    return gm / (a * b) * (1 - m - m * e1 * q0p / (6 * q0)), gm / (a * a) * (1 + m * e1 * q0p / (3 * q0))


def test_wgs84_published_equator_and_pole():
    gamma_e, gamma_p = WGS84.equator_and_pole
    assert gamma_e == pytest.approx(gr.WGS84_GAMMA_E, rel=1e-9, abs=0)   # NIMA TR8350.2 table 3.4
    assert gamma_p == pytest.approx(gr.WGS84_GAMMA_P, rel=1e-9, abs=0)
    assert WGS84.k == pytest.approx(0.00193185265241, rel=1e-9)   # NIMA TR8350.2 table 3.4
    assert WGS84.m == pytest.approx(0.00344978650684, rel=1e-9)
    # Somigliana at the poles gives gamma_p back
    assert WGS84.on_ellipsoid(math.pi / 2) == pytest.approx(gamma_p, rel=1e-14)


def test_mars_against_its_closed_form():
    ours, theirs = MARS.equator_and_pole, closed_form(MARS)
    for value, reference in zip(ours, theirs):
        assert value == pytest.approx(reference, rel=1e-9, abs=0)
    assert 3.70 < ours[0] < ours[1] < 3.74


def test_q0_is_the_series_up_to_its_limit_and_the_closed_form_beyond():
    """The shipped planets' e' (Earth 0.082, Mars 0.109) keep the series, bit for bit; beyond SERIES_LIMIT (the
    series diverges from e' = 1) the closed forms; the two agree at the switch and e' = 1 gives pi/2 - 3/2 and
    5 - 3 pi/2 exactly."""
    for planet in (WGS84, MARS):
        a, b = planet.equatorial_radius, planet.polar_radius
        e1 = math.sqrt(a * a - b * b) / b
        assert gr.q0_pair(e1) == gr._q0_series(e1)
    limit = gr.SERIES_LIMIT
    for series, closed in zip(gr.q0_pair(limit), gr.q0_pair(math.nextafter(limit, 2.0))):
        assert closed == pytest.approx(series, rel=1e-13)
    assert gr.q0_pair(1.0) == pytest.approx((math.pi / 2 - 1.5, 5.0 - 1.5 * math.pi), rel=4e-15)
    for e1 in (0.95, 1.333, 2.0, 6.25, 50.0):
        q0, q0p = gr.q0_pair(e1)
        atan = math.atan(e1)
        assert q0 == pytest.approx(0.5 * ((1 + 3 / e1**2) * atan - 3 / e1), rel=1e-15)
        assert q0p == pytest.approx(3 * (1 + 1 / e1**2) * (1 - atan / e1) - 1, rel=1e-15)


@pytest.mark.parametrize("ratio", [0.6, 1e6 / gr.WGS84_A])
def test_a_strongly_flattened_ellipsoid_has_its_closed_form_gravity(ratio):
    """b = 0.6 a (e' = 1.33; the series' value was 0.16 % off in gamma_e) and b = 1e6 m (e' = 6.3; the series gave
    NaN): gamma_e and gamma_p are the closed forms', and Somigliana at the pole is gamma_p."""
    flat = gr.NormalGravity(gr.WGS84_GM, gr.WGS84_A, ratio * gr.WGS84_A, gr.WGS84_OMEGA)
    for value, reference in zip(flat.equator_and_pole, closed_form(flat)):
        assert value == pytest.approx(reference, rel=1e-14)
    assert flat.on_ellipsoid(math.pi / 2) == pytest.approx(flat.equator_and_pole[1], rel=1e-14)
    assert math.isfinite(flat.magnitude(0.5, 1000.0))


def test_kernel_on_the_ellipsoid_and_above():
    planet = Planet(gr.WGS84_GM, gr.WGS84_A, gr.WGS84_B, 0.0, "Earth", gr.WGS84_OMEGA, "normal")
    for latitude in (0.0, 33.0, -60.0, 90.0):
        for height in (0.0, 2500.0, 40_000.0):
            frame = StartFrame(planet, latitude, 20.0)   # straight above the start point: along its up axis
            g = np.array(frame.gravity_scalar(*frame.local_position(height, 0.0, 0.0)))
            expected = WGS84.magnitude(math.radians(latitude), height)
            assert np.linalg.norm(g) == pytest.approx(expected, rel=1e-12)
            assert g[:2] == pytest.approx([0.0, 0.0], abs=1e-12)   # along the start point's normal (up)
    equator = StartFrame(planet, 0.0, 0.0)
    assert -equator.gravity_scalar(0.0, 0.0, 0.0)[2] == pytest.approx(gr.WGS84_GAMMA_E, rel=1e-9)
    # NIMA TR8350.2 eq. 4-3 at 10 km and 45 deg: the free-air gradient, about -3.08e-6 (m/s^2)/m
    drop = WGS84.magnitude(math.pi / 4, 10_000.0) - WGS84.magnitude(math.pi / 4, 0.0)
    assert drop / 10_000.0 == pytest.approx(-3.086e-6, rel=3e-3)


def test_inertial_frame_takes_the_centrifugal_term_out():
    rotating = Planet(gr.WGS84_GM, gr.WGS84_A, gr.WGS84_B, gr.WGS84_OMEGA, "Earth", gr.WGS84_OMEGA, "normal")
    frame = StartFrame(rotating, 0.0, 0.0)
    up = frame.gravity_scalar(0.0, 0.0, 0.0)[2]
    assert -up == pytest.approx(9.7803253359 + gr.WGS84_OMEGA**2 * gr.WGS84_A, rel=1e-12)


PLANET = """
[case]
vehicle = "ball"
[planet]
{planet}
[start]
latitude_deg = 33.0
[atmosphere]
model = "us76"
[bodies.ball]
mass = 1.0
inertia = [1.0, 1.0, 1.0]
initial = {{ altitude = 100.0 }}
[simulation]
duration = 1.0
"""
EARTH = ('name = "Earth"\ngravitational_parameter = 3.986004418e14\nequatorial_radius = 6378137.0\n'
         'polar_radius = 6356752.314245\n')


def load(tmp_path, planet: str):
    from pchute_exudyn import load_case
    path = tmp_path / "case.toml"
    path.write_text(PLANET.format(planet=planet))
    return load_case(path)


def test_spin_defaults(tmp_path):
    assert load(tmp_path, EARTH).planet.spin_rate == gr.WGS84_OMEGA
    assert load(tmp_path, EARTH).planet.gravity_model == "normal"
    mars = 'name = "Mars"\ngravitational_parameter = 4.282837e13\nequatorial_radius = 3396190.0\npolar_radius = 3376200.0'
    assert load(tmp_path, mars).planet.spin_rate == gr.MARS_OMEGA
    rotating = load(tmp_path, EARTH + "rotation_rate = 7.292115e-5\n").planet
    assert rotating.spin_rate == rotating.rotation_rate == 7.292115e-5
    spherical = EARTH.replace("Earth", "Other") + 'gravity_model = "spherical"\n'
    assert load(tmp_path, spherical).planet.spin_rate == 0.0


@pytest.mark.parametrize("lines, message", [
    ('gravity_model = "ellipsoidal"', r'planet\.gravity_model = .ellipsoidal.: must be one of: normal, spherical'),
    ("spin_rate = -1e-5", r"planet\.spin_rate = -1e-05: must be >= 0"),
    ("spin_rate = nan", r"planet\.spin_rate = nan: must be a finite number"),
    ("rotation_rate = 7.292115e-5\nspin_rate = 7e-5", r"planet\.spin_rate = 7e-05: must equal \|rotation_rate\|"),
])
def test_bad_input_names_field_value_and_allowed(tmp_path, lines, message):
    with pytest.raises(CaseError, match=message):
        load(tmp_path, EARTH + lines + "\n")


def test_normal_gravity_needs_a_spin_it_can_default(tmp_path):
    other = EARTH.replace('"Earth"', '"Tellus"')
    with pytest.raises(CaseError, match=r"planet\.spin_rate: required .*Tellus.*gravity_model = \"spherical\""):
        load(tmp_path, other)
    assert load(tmp_path, other + "spin_rate = 7.292115e-5\n").planet.spin_rate == 7.292115e-5
    sphere = 'gravitational_parameter = 4e14\nequatorial_radius = 6.4e6\npolar_radius = 6.4e6\n'
    with pytest.raises(CaseError, match=r"planet\.gravity_model = .normal.: normal gravity needs an ellipsoid"):
        load(tmp_path, sphere)


def test_thesis_cases_name_spherical():
    from pchute_exudyn import load_case
    for case in ("cases/mer/case1.toml", "cases/mer/edl.toml", "cases/cev_pa1.toml", "cases/cev_pa1_winds.toml",
                 "cases/cev_pa1_cluster.toml", "cases/simple/descent_440s.toml"):
        assert load_case(ROOT / case).planet.gravity_model == "spherical", case
    assert load_case(ROOT / "cases/rocket/dual_deploy.toml").planet.gravity_model == "normal"

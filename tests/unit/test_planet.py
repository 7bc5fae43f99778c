"""Planet: spherical gravity, geodetic altitude and the start-point frame (thesis Table 3.3, mer.md "Frames")."""

import numpy as np
import pytest

from pchute_exudyn.physics.planet import EARTH_WGS84, MARS, FlatPlanet, Planet, StartFrame


def test_gravity_hand_values():
    # g = mu / r^2 at the Mars equator: 4.282828685e13 / 3393940^2 = 3.71811 m/s^2, pointing at the centre
    g = MARS.gravity([MARS.equatorial_radius, 0.0, 0.0])
    assert g[0] == pytest.approx(-4.282828685e13 / 3393940.0**2, rel=1e-13)
    assert g[0] == pytest.approx(-3.71811, abs=1e-5)
    assert g[1] == g[2] == 0.0
    # at the MER start altitude 8380.217 m above the equator
    r = MARS.equatorial_radius + 8380.217
    assert np.linalg.norm(MARS.gravity([0.0, r, 0.0])) == pytest.approx(4.282828685e13 / r**2, rel=1e-13)
    # Earth: 9.798 m/s^2 at the equator with spherical gravity
    assert np.linalg.norm(EARTH_WGS84.gravity([EARTH_WGS84.equatorial_radius, 0, 0])) == pytest.approx(9.7983, abs=1e-4)


def test_geodetic_round_trip_and_poles():
    rng = np.random.default_rng(2)
    lat = rng.uniform(-89.9, 89.9, 500)
    lon = rng.uniform(-180, 180, 500)
    h = rng.uniform(-2000, 80000, 500)
    for planet in (MARS, EARTH_WGS84):
        r = planet.cartesian(lat, lon, h)
        lat2, lon2, h2 = planet.geodetic(r)
        np.testing.assert_allclose(h2, h, atol=1e-6)
        np.testing.assert_allclose(lat2, lat, atol=1e-10)
        np.testing.assert_allclose(lon2, lon, atol=1e-10)
        for point, height in zip(r[:20], h[:20]):
            assert planet.altitude_scalar(*point) == pytest.approx(height, abs=1e-6)
    # the pole is Rp from the centre
    assert MARS.altitude([0.0, 0.0, MARS.polar_radius + 100.0]) == pytest.approx(100.0, abs=1e-6)


def test_start_frame_axes_at_lat0_lon0():
    frame = StartFrame(MARS, 0.0, 0.0)   # mer.md: up = +X, east = +Y, north = +Z
    np.testing.assert_allclose(frame.axes, [[0, 0, 1], [1, 0, 0], [0, 1, 0]], atol=1e-15)
    np.testing.assert_allclose(frame.planet_center, [0, 0, -MARS.equatorial_radius])


@pytest.mark.parametrize("lat, lon", [(0.0, 0.0), (32.9, -106.4), (-60.0, 140.0)])
def test_local_position_reports_back_its_inputs(lat, lon):
    frame = StartFrame(EARTH_WGS84, lat, lon)
    local = frame.local_position(1234.5, 250.0, -400.0)
    assert local[0] == 250.0 and local[1] == -400.0
    assert frame.altitude(local) == pytest.approx(1234.5, abs=1e-7)
    axes = frame.axes
    np.testing.assert_allclose(axes.T @ axes, np.eye(3), atol=1e-15)
    assert np.linalg.det(axes) == pytest.approx(1.0)


def test_rotating_planet_ground_frame():
    earth = Planet(3.986004418e14, 6378137.0, 6356752.314245, 7.292115e-5, "Earth")
    frame = StartFrame(earth, 0.0, 0.0)
    # a point fixed to the ground moves inertially at omega x r; in the ground frame it does not move
    local = frame.local_position(0.0, 0.0, 0.0)
    v = frame.inertial_velocity(local, [0.0, 0.0, 0.0])
    assert v[0] == pytest.approx(7.292115e-5 * 6378137.0)   # eastward at the equator, 465.1 m/s
    t = np.array([10.0])
    carried = frame.planet_center + (local - frame.planet_center) @ _rot_about(frame.rotation_vector, 10.0).T
    np.testing.assert_allclose(frame.to_planet_fixed(carried[None, :], t)[0], local, atol=1e-6)
    np.testing.assert_allclose(frame.velocity_to_planet_fixed(carried[None, :], (_rot_about(
        frame.rotation_vector, 10.0) @ v)[None, :], t)[0], [0, 0, 0], atol=1e-9)


def _rot_about(rate_vector, t):
    rate = np.linalg.norm(rate_vector)
    k = rate_vector / rate
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    a = rate * t
    return np.eye(3) + np.sin(a) * kx + (1 - np.cos(a)) * kx @ kx


def test_gravity_scalar_is_the_planet_gravity_in_start_frame_axes():
    frame = StartFrame(EARTH_WGS84, 32.9, -106.4)
    for point in ([0.0, 0.0, 2300.0], [1500.0, -800.0, 50.0], [-3.0e4, 2.0e4, 9000.0]):
        expected = frame.axes.T @ EARTH_WGS84.gravity(frame.to_planet(np.array(point)))
        np.testing.assert_allclose(frame.gravity_scalar(*point), expected, rtol=0.0, atol=1e-12)
    assert StartFrame(FlatPlanet(3.71), 0.0, 0.0).gravity_scalar(1.0, 2.0, 3.0) == (0.0, 0.0, -3.71)

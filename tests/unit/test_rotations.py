"""Attitude conventions (physics.rotations)."""

import numpy as np
import pytest

from pchute_exudyn.physics.rotations import (
    DESCENT_FRAME,
    attitude_angles_deg,
    attitude_matrix,
    euler321_angles,
    euler321_matrix,
    rotation_vector,
    tilt_deg,
)


def test_descent_frame_is_down_east_south():
    np.testing.assert_array_equal(DESCENT_FRAME[:, 0], [0, 0, -1])   # x: down
    np.testing.assert_array_equal(DESCENT_FRAME[:, 1], [1, 0, 0])    # y: east
    np.testing.assert_array_equal(DESCENT_FRAME[:, 2], [0, -1, 0])   # z: south
    assert np.linalg.det(DESCENT_FRAME) == pytest.approx(1.0)


def test_euler_round_trip():
    rng = np.random.default_rng(3)
    yaw, pitch, roll = rng.uniform(-3, 3, 50), rng.uniform(-1.5, 1.5, 50), rng.uniform(-3, 3, 50)
    back = euler321_angles(euler321_matrix(yaw, pitch, roll))
    np.testing.assert_allclose(back, (yaw, pitch, roll), atol=1e-12)


def test_mer_case5_and_case6_rotations():
    # case 5: +10 deg about body z (south): body x (down) tips toward east; case 6: about body y (east): toward north
    x5 = attitude_matrix(10.0, 0.0, 0.0)[:, 0]
    np.testing.assert_allclose(x5, [np.sin(np.radians(10)), 0.0, -np.cos(np.radians(10))], atol=1e-15)
    x6 = attitude_matrix(0.0, 10.0, 0.0)[:, 0]
    np.testing.assert_allclose(x6, [0.0, np.sin(np.radians(10)), -np.cos(np.radians(10))], atol=1e-15)
    assert attitude_angles_deg(attitude_matrix(10.0, 0.0, 0.0))[0] == pytest.approx(10.0)
    assert tilt_deg(attitude_matrix(0.0, 10.0, 0.0)) == pytest.approx(10.0)


def test_rotation_vector_reproduces_the_matrix():
    from scipy.spatial.transform import Rotation
    for angles in ([10, 20, 30], [90, 0, -90], [0, 0, 179.9999999], [0, 0, 0]):
        matrix = attitude_matrix(*angles)
        np.testing.assert_allclose(Rotation.from_rotvec(rotation_vector(matrix)).as_matrix(), matrix, atol=1e-9)

"""Rigid-body point kinematics: the one home of r_p = r + R p and v_p = v + w x (R p).

``R`` maps body axes to the start frame (an attitude matrix), ``p`` is a point in body axes relative to the centre of
mass (m), ``w`` the angular velocity. Two forms of the same formula: ``point_motion`` in plain floats for the
per-stage user functions (a function call on lists is cheaper there than any numpy call), and ``body_point`` in numpy
for whole histories (any leading axes). The tests check that they agree.
"""

from __future__ import annotations

import numpy as np


def point_motion(body_state, local) -> tuple:
    """Position (m) and velocity (m/s) of the body point ``local`` (body axes, m), start-frame components.

    ``body_state`` is (position, velocity, rotation matrix row-major as 9 floats, angular velocity in start-frame
    components), each a sequence of floats. Plain floats in and out.
    """
    x, v, r, w = body_state
    lx, ly, lz = local
    ax, ay, az = r[0] * lx + r[1] * ly + r[2] * lz, r[3] * lx + r[4] * ly + r[5] * lz, r[6] * lx + r[7] * ly + r[8] * lz
    return ((x[0] + ax, x[1] + ay, x[2] + az),
            (v[0] + w[1] * az - w[2] * ay, v[1] + w[2] * ax - w[0] * az, v[2] + w[0] * ay - w[1] * ax))


def body_point(position, rotation, velocity=None, angular_velocity_local=None, local=(0.0, 0.0, 0.0)):
    """Position (m) and velocity (m/s) of the body point ``local`` (body axes, m) in the start frame, for arrays.

    Parameters
    ----------
    position : array_like (..., 3)
        Centre of mass (m).
    rotation : array_like (..., 3, 3)
        Attitude matrices, body -> start frame.
    velocity : array_like (..., 3), optional
        Centre-of-mass velocity (m/s); without it the returned velocity is None.
    angular_velocity_local : array_like (..., 3), optional
        Angular velocity in body axes (rad/s); zero when omitted.
    local : array_like (3,)

    Returns
    -------
    position, velocity : ndarray (..., 3) (velocity None when ``velocity`` is None)
    """
    rotation = np.asarray(rotation, float)
    arm = rotation @ np.asarray(local, float)
    point = np.asarray(position, float) + arm
    if velocity is None:
        return point, None
    point_velocity = np.asarray(velocity, float)
    if angular_velocity_local is not None:
        omega = np.einsum("...ij,...j->...i", rotation, np.asarray(angular_velocity_local, float))
        point_velocity = point_velocity + np.cross(omega, arm)
    return point, point_velocity


def relative_to_body(position, rotation, velocity, angular_velocity_local, point_position, point_velocity):
    """A point's position (m) and velocity (m/s) relative to a body, in that body's axes: the inverse of
    ``body_point`` (the velocity as seen from the rotating body). Arrays with leading axes."""
    rotation = np.asarray(rotation, float)
    arm = np.asarray(point_position, float) - np.asarray(position, float)
    omega = np.einsum("...ij,...j->...i", rotation, np.asarray(angular_velocity_local, float))
    relative_velocity = np.asarray(point_velocity, float) - np.asarray(velocity, float) - np.cross(omega, arm)
    return (np.einsum("...ji,...j->...i", rotation, arm), np.einsum("...ji,...j->...i", rotation, relative_velocity))

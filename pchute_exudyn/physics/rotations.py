"""Attitude conventions (the only place they are defined).

* A body's attitude matrix A maps body components to start-frame (east/north/up) components: x_ENU = A x_body.
  Its columns are the body x, y, z axes.
* Attitude angles are 3-2-1 Euler angles (yaw psi, then pitch theta, then roll phi) of the body axes relative to the
  **descent frame** D of the start point, whose axes are

      x_D = local down (nadir),  y_D = local east,  z_D = local south.

  This is the thesis's MER starting attitude ("x body axis pointed to nadir, y East, z South"), so a body hanging
  in its nominal attitude has all three angles zero: yaw is a swing in the down-east plane (rotation about south),
  pitch a swing in the down-north plane, roll a spin about the vertical. The angles are singular only when the body
  x axis is horizontal towards north or south (pitch = +-90 deg); the tilt angle (body x from nadir) is never
  singular. A = D @ Rz(yaw) @ Ry(pitch) @ Rx(roll).
"""

from __future__ import annotations

import math

import numpy as np

from .compiled import kernel

DESCENT_FRAME = np.array([[0.0, 1.0, 0.0],
                          [0.0, 0.0, -1.0],
                          [-1.0, 0.0, 0.0]])
"""Columns: descent-frame axes x_D (down), y_D (east), z_D (south) in start-frame (ENU) components."""


def euler321_matrix(yaw, pitch, roll) -> np.ndarray:
    """Rotation matrix Rz(yaw) Ry(pitch) Rx(roll) (angles in rad), broadcast over leading axes -> (..., 3, 3)."""
    cy, sy = np.cos(yaw), np.sin(yaw)
    cp, sp = np.cos(pitch), np.sin(pitch)
    cr, sr = np.cos(roll), np.sin(roll)
    return np.stack([
        np.stack([cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr], axis=-1),
        np.stack([sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr], axis=-1),
        np.stack([-sp, cp * sr, cp * cr], axis=-1),
    ], axis=-2)


def euler321_angles(matrix):
    """3-2-1 Euler angles (yaw, pitch, roll) in rad of rotation matrices (..., 3, 3); inverse of euler321_matrix."""
    r = np.asarray(matrix, dtype=float)
    yaw = np.arctan2(r[..., 1, 0], r[..., 0, 0])
    pitch = -np.arcsin(np.clip(r[..., 2, 0], -1.0, 1.0))
    roll = np.arctan2(r[..., 2, 1], r[..., 2, 2])
    return yaw, pitch, roll


def attitude_matrix(yaw_deg: float, pitch_deg: float, roll_deg: float) -> np.ndarray:
    """Body attitude matrix A (body -> ENU) from attitude angles (deg) relative to the descent frame."""
    return DESCENT_FRAME @ euler321_matrix(*np.radians([yaw_deg, pitch_deg, roll_deg]))


def attitude_angles_deg(attitude):
    """Attitude angles (yaw, pitch, roll) in deg relative to the descent frame, from attitude matrices (..., 3, 3)."""
    relative = DESCENT_FRAME.T @ np.asarray(attitude, dtype=float)
    return tuple(np.degrees(angle) for angle in euler321_angles(relative))


def tilt_deg(attitude) -> np.ndarray:
    """Angle (deg) between the body +x axis and local down (nadir), from attitude matrices (..., 3, 3)."""
    x_axis = np.asarray(attitude, dtype=float)[..., :, 0]
    return np.degrees(np.arccos(np.clip(-x_axis[..., 2], -1.0, 1.0)))


def rotation_vector(matrix) -> np.ndarray:
    """Rotation vector (axis times angle, rad) of a 3x3 rotation matrix."""
    r = np.asarray(matrix, dtype=float)
    angle = np.arccos(np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0))
    if angle < 1e-12:
        return np.zeros(3)
    if np.pi - angle < 1e-6:  # near 180 deg: the axis from the symmetric part
        b = (r + np.eye(3)) / 2.0
        axis = b[:, np.argmax(np.diag(b))]
        axis = axis / np.linalg.norm(axis)
        return angle * axis
    axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / (2.0 * np.sin(angle))
    return angle * axis


@kernel
def rotation_from_vector(vx, vy, vz, out):
    """Attitude matrix of the rotation vector (vx, vy, vz) (rad; axis times angle), row-major into ``out`` (9):
    Rodrigues' formula R = I + (sin a / a) K + ((1 - cos a) / a^2) K^2, K the cross-product matrix of the vector
    (Taylor series below 1e-4 rad, exact there to round-off). The inverse of ``rotation_vector``."""
    angle2 = vx * vx + vy * vy + vz * vz
    if angle2 < 1e-8:
        s = 1.0 - angle2 / 6.0
        c = 0.5 - angle2 / 24.0
    else:
        angle = math.sqrt(angle2)
        s = math.sin(angle) / angle
        c = (1.0 - math.cos(angle)) / angle2
    out[0] = 1.0 - c * (vy * vy + vz * vz)
    out[1] = -s * vz + c * vx * vy
    out[2] = s * vy + c * vx * vz
    out[3] = s * vz + c * vx * vy
    out[4] = 1.0 - c * (vx * vx + vz * vz)
    out[5] = -s * vx + c * vy * vz
    out[6] = -s * vy + c * vx * vz
    out[7] = s * vx + c * vy * vz
    out[8] = 1.0 - c * (vx * vx + vy * vy)

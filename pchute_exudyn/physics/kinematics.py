"""Rigid-body point kinematics: the one home of r_p = r + R p and v_p = v + w x (R p), and of a point force's
generalized force on a rotation-vector body node.

``R`` maps body axes to the start frame (an attitude matrix), ``p`` is a point in body axes relative to the centre of
mass (m), ``w`` the angular velocity. Two forms of the same formula: compiled kernels on a stage's body states
(``body_states``, ``point_motions``) for the per-stage user functions, and ``body_point`` in numpy for whole
histories (any leading axes). The tests check that they agree.

A stage's body states are rows of STATE_COLUMNS = 21 floats: position (m), attitude matrix R row-major, velocity
(m/s), angular velocity in start-frame components (rad/s), angular velocity in body axes (rad/s). A body's
generalized force on its node (Exudyn's ``NodeRigidBodyRotVecLG``, whose velocity coordinates are the velocity and
the body-axis angular velocity) is the force (N, start frame) and the moment about the centre of mass in body axes
(N m).
"""

from __future__ import annotations

import numpy as np

from .compiled import kernel
from .gravity import normal_gravity
from .planet import engine_gravity_force
from .rotations import rotation_from_vector

STATE_COLUMNS = 21
POSITION_AT, ROTATION_AT, VELOCITY_AT, ANGULAR_VELOCITY_AT, BODY_RATE_AT = 0, 3, 12, 15, 18
"""Where each part of a state row starts (kernels index with these: numba takes int globals, not slices):
position (3), attitude matrix R (9, row-major), velocity (3), angular velocity in start-frame components (3) and
in body axes (3)."""
ROW_POSITION = slice(POSITION_AT, POSITION_AT + 3)
ROW_ROTATION = slice(ROTATION_AT, ROTATION_AT + 9)
ROW_VELOCITY = slice(VELOCITY_AT, VELOCITY_AT + 3)
ROW_ANGULAR_VELOCITY = slice(ANGULAR_VELOCITY_AT, ANGULAR_VELOCITY_AT + 3)
ROW_BODY_RATE = slice(BODY_RATE_AT, BODY_RATE_AT + 3)
"""The same parts as slices of a row, for Python callers."""
POINT_COLUMNS = 5
"""Columns of a point layout row: body (index into the states), point in body axes (m), and the body's first
generalized-force index (-1: a fixed body, which takes none). SP's line layout continues it
(``methods.sp.memory``)."""


@kernel
def body_states(q, q_t, bodies, states):
    """Fill ``states`` (one row per body, see the module doc) from node coordinates: ``bodies`` rows are (index of
    the node's first coordinate in ``q`` and ``q_t``, or -1 for a fixed body whose row is left as it is; reference
    position (m); reference rotation vector (rad)). The position is reference + q, the attitude the rotation vector
    reference + q (Lie-group node), the angular velocity R times the body-axis rate in ``q_t``."""
    for b in range(bodies.shape[0]):
        k = int(bodies[b, 0])
        if k < 0:
            continue
        row = states[b]
        for i in range(3):
            row[POSITION_AT + i] = bodies[b, 1 + i] + q[k + i]
            row[VELOCITY_AT + i] = q_t[k + i]
        rotation_from_vector(bodies[b, 4] + q[k + 3], bodies[b, 5] + q[k + 4], bodies[b, 6] + q[k + 5],
                             row[ROTATION_AT:ROTATION_AT + 9])
        wx, wy, wz = q_t[k + 3], q_t[k + 4], q_t[k + 5]
        row[BODY_RATE_AT], row[BODY_RATE_AT + 1], row[BODY_RATE_AT + 2] = wx, wy, wz
        for i in range(3):
            r = ROTATION_AT + 3 * i   # row i of R
            row[ANGULAR_VELOCITY_AT + i] = row[r] * wx + row[r + 1] * wy + row[r + 2] * wz


@kernel
def point_motion(row, lx, ly, lz):
    """(x, y, z, vx, vy, vz): position (m) and velocity (m/s) of the point (lx, ly, lz) (m, body axes) of the body
    whose state is ``row``."""
    r, w, p, v = ROTATION_AT, ANGULAR_VELOCITY_AT, POSITION_AT, VELOCITY_AT
    ax = row[r] * lx + row[r + 1] * ly + row[r + 2] * lz
    ay = row[r + 3] * lx + row[r + 4] * ly + row[r + 5] * lz
    az = row[r + 6] * lx + row[r + 7] * ly + row[r + 8] * lz
    wx, wy, wz = row[w], row[w + 1], row[w + 2]
    return (row[p] + ax, row[p + 1] + ay, row[p + 2] + az, row[v] + wy * az - wz * ay,
            row[v + 1] + wz * ax - wx * az, row[v + 2] + wx * ay - wy * ax)


@kernel
def point_motions(states, points, motion):
    """Position (m) and velocity (m/s) of body points into ``motion`` rows (x, y, z, vx, vy, vz): ``points`` rows
    as POINT_COLUMNS."""
    for j in range(points.shape[0]):
        x, y, z, vx, vy, vz = point_motion(states[int(points[j, 0])], points[j, 1], points[j, 2], points[j, 3])
        motion[j, 0], motion[j, 1], motion[j, 2] = x, y, z
        motion[j, 3], motion[j, 4], motion[j, 5] = vx, vy, vz


@kernel
def add_point_force(row, lx, ly, lz, fx, fy, fz, generalized, k):
    """Add the generalized force of force (fx, fy, fz) (N, start frame) at the point (lx, ly, lz) (m, body axes) of
    the body whose state is ``row`` and whose generalized forces start at ``generalized[k]``: the force, and the
    body-axis moment p x (R^T F) about the centre of mass (N m)."""
    r = ROTATION_AT
    bx = row[r] * fx + row[r + 3] * fy + row[r + 6] * fz   # R^T F
    by = row[r + 1] * fx + row[r + 4] * fy + row[r + 7] * fz
    bz = row[r + 2] * fx + row[r + 5] * fy + row[r + 8] * fz
    generalized[k] += fx
    generalized[k + 1] += fy
    generalized[k + 2] += fz
    generalized[k + 3] += ly * bz - lz * by
    generalized[k + 4] += lz * bx - lx * bz
    generalized[k + 5] += lx * by - ly * bx


@kernel
def add_point_forces(states, points, forces, generalized):
    """Add the generalized forces of point forces ``forces`` (N, start frame, one row per point) to
    ``generalized`` (``add_point_force``; a point of a fixed body adds none)."""
    for j in range(points.shape[0]):
        k = int(points[j, 4])
        if k >= 0:
            add_point_force(states[int(points[j, 0])], points[j, 1], points[j, 2], points[j, 3], forces[j, 0],
                            forces[j, 1], forces[j, 2], generalized, k)


BODY_COORDINATE_AT, BODY_REFERENCE_AT, BODY_MASS_AT = 0, 1, 7
"""The columns of a stage's body layout (``body_states``' ``bodies``): the node's first coordinate (-1: a fixed
body), its reference coordinates (6: position in m, rotation vector in rad) and the mass (kg) whose gravity
``add_gravity_forces`` adds, 0 where the engine adds it."""
POINT_BODY_AT, POINT_LOCAL_AT, POINT_FORCE_AT = 0, 1, 4
"""The columns of a point layout row (POINT_COLUMNS): its body's row in the states, the point in body axes (3, m),
and the body's first generalized-force index (-1: a fixed body)."""


@kernel
def add_gravity_forces(bodies, states, mu, cx, cy, cz, generalized):
    """Add the gravity of the bodies that carry a mass in their layout row (BODY_MASS_AT) to ``generalized``:
    ``planet.engine_gravity_force`` at each centre of mass, from a planet of ``mu`` (m^3/s^2) centred at (cx, cy,
    cz) (m), on the node's force coordinates."""
    for b in range(bodies.shape[0]):
        mass, k = bodies[b, BODY_MASS_AT], int(bodies[b, 0])
        if mass > 0.0 and k >= 0:
            row = states[b]
            fx, fy, fz = engine_gravity_force(mu, mass, cx, cy, cz, row[POSITION_AT], row[POSITION_AT + 1],
                                              row[POSITION_AT + 2])
            generalized[k] += fx
            generalized[k + 1] += fy
            generalized[k + 2] += fz


@kernel
def add_normal_gravity_forces(bodies, states, cx, cy, cz, ux, uy, uz, a, b, gamma_e, k, m, rate, generalized):
    """Add the normal gravity (``gravity.normal_gravity`` times the mass, N) of the bodies that carry a mass in
    their layout row (BODY_MASS_AT) to ``generalized``, at each centre of mass; the arguments between the arrays
    are ``normal_gravity``'s (``StartFrame.normal_gravity_parameters``)."""
    for j in range(bodies.shape[0]):
        mass, i = bodies[j, BODY_MASS_AT], int(bodies[j, 0])
        if mass > 0.0 and i >= 0:
            row = states[j]
            gx, gy, gz = normal_gravity(cx, cy, cz, ux, uy, uz, a, b, gamma_e, k, m, rate, row[POSITION_AT],
                                        row[POSITION_AT + 1], row[POSITION_AT + 2])
            generalized[i] += mass * gx
            generalized[i + 1] += mass * gy
            generalized[i + 2] += mass * gz


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

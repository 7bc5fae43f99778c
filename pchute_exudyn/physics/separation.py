"""Separation of a carried body (heat shield, forward bay cover) from the vehicle: the mass properties of the vehicle
with what it carries, and the states of the two after they part.

While carried, a body is rigidly part of the vehicle: the pair is one rigid body whose centre of mass lies at
c = sum(m_k d_k) / m (vehicle axes, from the vehicle's own centre of mass; d_0 = 0 for the vehicle itself) and whose
inertia about c is sum(I_k + m_k (|r_k|^2 E - r_k r_k^T)), r_k = d_k - c (parallel-axis theorem). A carried body's
axes are the vehicle's. At separation the two leave with the rigid-body velocity of their own centres of mass plus a
relative speed s along a vehicle-fixed direction e, shared so that momentum is conserved: the body gains
m_a / (m_a + m_b) s e, the vehicle (with what it still carries, mass m_a) loses m_b / (m_a + m_b) s e.
"""

from __future__ import annotations

import numpy as np


def shifted_inertia(inertia, mass: float, offset) -> np.ndarray:
    """Inertia (kg m^2, 3x3) about a point ``offset`` (m) away from the centre of mass (parallel-axis theorem)."""
    r = np.asarray(offset, float)
    return np.asarray(inertia, float) + mass * (float(r @ r) * np.eye(3) - np.outer(r, r))


def composite(parts) -> tuple:
    """(mass in kg, centre of mass in m, inertia about it in kg m^2) of rigidly joined ``parts``: (mass, inertia
    3x3 about its own centre of mass, position of that centre of mass) each, in one set of axes."""
    mass = sum(m for m, _, _ in parts)
    center = sum(m * np.asarray(d, float) for m, _, d in parts) / mass
    inertia = sum(shifted_inertia(i, m, np.asarray(d, float) - center) for m, i, d in parts)
    return mass, center, inertia


def speed_shares(remaining_mass: float, body_mass: float, speed: float) -> tuple:
    """(vehicle's, body's) velocity change (m/s) along the separation direction for a relative speed ``speed``."""
    total = remaining_mass + body_mass
    return -body_mass / total * speed, remaining_mass / total * speed


def rigid_point_state(position, attitude, velocity, angular_velocity, offset) -> tuple:
    """(position m, velocity m/s) of a point ``offset`` (m, body axes from the reference point) of a rigid body with
    that reference point's ``position`` and ``velocity``, ``attitude`` (body -> frame) and body-axis
    ``angular_velocity`` (rad/s)."""
    offset = np.asarray(offset, float)
    attitude = np.asarray(attitude, float)
    return (np.asarray(position, float) + attitude @ offset,
            np.asarray(velocity, float) + attitude @ np.cross(np.asarray(angular_velocity, float), offset))

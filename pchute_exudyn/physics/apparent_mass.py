"""Apparent (added) mass of a canopy: the air it carries, as a rigid body moving through an ideal fluid (Kirchhoff's
equations; ``docs/models/canopy.md``, "Apparent mass").

The apparent-mass tensors are diagonal in canopy axes (+x from the canopy toward the payload), centred at the body's
centre of mass::

    V   = (2/3) pi R_p^3                                   reference volume (m^3), R_p the projected radius
    A_t = rho V diag(k_axial, k_lateral, k_lateral)        translational apparent mass (kg)
    A_r = rho V R_p^2 diag(0, k_rotational, k_rotational)  rotational apparent inertia (kg m^2)

With v the air-relative velocity and w the angular velocity, both in canopy axes, the body's equations gain
(on top of its own m and I)::

    translation (inertial axes):  (m I + R A_t R^T) a  = F + R [A_t (w x v) - w x (A_t v)]
    rotation (canopy axes):       (I_b + A_r) dw/dt    = M - w x ((I_b + A_r) w) - v x (A_t v)     (Munk moment)

Neglected: the rate of change of rho along the path (rho is taken at the current altitude, as if constant), the
air's own acceleration (wind gradients, turbulence, the rotating planet's air) and apparent-mass coupling between
bodies (each canopy carries its own air). Plain floats: the terms run at every solver stage.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .invalid import InvalidField


class ApparentMassError(InvalidField):
    """Invalid apparent-mass input; ``field`` names it."""


@dataclass(frozen=True)
class ApparentMass:
    """A body's apparent-mass coefficients.

    Attributes
    ----------
    projected_radius : float
        R_p, the inflated canopy's projected radius (m), > 0.
    axial : float
        k_axial (-), >= 0: along canopy x.
    lateral : float
        k_lateral (-), >= 0: along canopy y and z.
    rotational : float
        k_rotational (-), >= 0: about canopy y and z (none about the axis of symmetry).
    """

    projected_radius: float
    axial: float
    lateral: float
    rotational: float

    def __post_init__(self):
        for name in ("projected_radius", "axial", "lateral", "rotational"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0) or (name == "projected_radius" and value == 0.0):
                allowed = "> 0 (m)" if name == "projected_radius" else ">= 0 (-)"
                raise ApparentMassError(name, value, f"must be a number {allowed}")

    @property
    def volume(self) -> float:
        """Reference volume V = (2/3) pi R_p^3 (m^3)."""
        return 2.0 / 3.0 * math.pi * self.projected_radius ** 3

    def masses(self, density: float) -> tuple[tuple, tuple]:
        """Diagonals of A_t (kg) and A_r (kg m^2) in canopy axes at air density ``density`` (kg/m^3)."""
        rho_v = density * self.volume
        rotational = rho_v * self.projected_radius ** 2 * self.rotational
        return (rho_v * self.axial, rho_v * self.lateral, rho_v * self.lateral), (0.0, rotational, rotational)


def cross(a, b) -> tuple:
    """a x b in plain floats."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def kirchhoff_terms(rotation, air_velocity, angular_velocity, translational, rotational) -> tuple[tuple, tuple]:
    """The apparent mass's velocity terms: the force (N, inertial axes) R [A_t (w x v) - w x (A_t v)] and the moment
    (N m, canopy axes) -w x (A_r w) - v x (A_t v).

    Parameters
    ----------
    rotation : sequence of 9 float
        R, canopy axes -> inertial, row-major.
    air_velocity : (x, y, z)
        The body's air-relative velocity (m/s) in inertial axes.
    angular_velocity : (x, y, z)
        w (rad/s) in canopy axes.
    translational, rotational : (x, y, z)
        Diagonals of A_t (kg) and A_r (kg m^2) (``ApparentMass.masses``).
    """
    r = rotation
    vx, vy, vz = air_velocity
    v = (r[0] * vx + r[3] * vy + r[6] * vz, r[1] * vx + r[4] * vy + r[7] * vz, r[2] * vx + r[5] * vy + r[8] * vz)
    w = angular_velocity
    at_v = (translational[0] * v[0], translational[1] * v[1], translational[2] * v[2])
    w_v = cross(w, v)
    w_atv = cross(w, at_v)
    local = [translational[i] * w_v[i] - w_atv[i] for i in range(3)]
    force = (r[0] * local[0] + r[1] * local[1] + r[2] * local[2], r[3] * local[0] + r[4] * local[1]
             + r[5] * local[2], r[6] * local[0] + r[7] * local[1] + r[8] * local[2])
    ar_w = (rotational[0] * w[0], rotational[1] * w[1], rotational[2] * w[2])
    gyro, munk = cross(w, ar_w), cross(v, at_v)
    return force, (-gyro[0] - munk[0], -gyro[1] - munk[1], -gyro[2] - munk[2])


def translational_mass_matrix(rotation, translational) -> list:
    """R A_t R^T (kg), the translational apparent mass in inertial axes, as 3 rows (symmetric)."""
    r = rotation
    a, b, c = translational
    r0, r1, r2 = a * r[0], b * r[1], c * r[2]   # row i of R A_t
    r3, r4, r5 = a * r[3], b * r[4], c * r[5]
    r6, r7, r8 = a * r[6], b * r[7], c * r[8]
    m00 = r0 * r[0] + r1 * r[1] + r2 * r[2]
    m01 = r0 * r[3] + r1 * r[4] + r2 * r[5]
    m02 = r0 * r[6] + r1 * r[7] + r2 * r[8]
    m11 = r3 * r[3] + r4 * r[4] + r5 * r[5]
    m12 = r3 * r[6] + r4 * r[7] + r5 * r[8]
    m22 = r6 * r[6] + r7 * r[7] + r8 * r[8]
    return [[m00, m01, m02], [m01, m11, m12], [m02, m12, m22]]

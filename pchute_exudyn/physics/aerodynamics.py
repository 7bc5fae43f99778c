"""Body aerodynamics: constant axial coefficient, tabulated normal coefficient, force at the aerodynamic centre.

Force law (``docs/models/mer.md``, "Parachute aerodynamics"), for air-relative velocity V of the aerodynamic centre
and body +x axis e (unit, inertial components)::

    q = 1/2 rho |V|^2,     alpha = angle(V, e) in [0, 180] deg,     alpha' = min(alpha, 180 - alpha)
    V_perp = V - (V.e) e
    F = -q S C_A e  -  q S C_N(alpha') V_perp / |V_perp|        (second term 0 when V_perp = 0)

For a parachute, +x points from the canopy toward the payload, so in a steady descent e is along V (alpha = 0) and
-q S C_A e is the drag. Plain floats throughout: the function runs in per-stage user functions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .interpolation import interpolate_held


@dataclass(frozen=True)
class CoefficientTable:
    """A coefficient tabulated against the folded angle of attack alpha' (deg), linear between the points.

    Parameters
    ----------
    angle_deg : tuple of float
        Strictly increasing alpha' breakpoints (deg) spanning [0, 90].
    value : tuple of float
        Coefficient at each breakpoint (-).
    """

    angle_deg: tuple
    value: tuple

    def __call__(self, angle_deg: float) -> float:
        """Coefficient at ``angle_deg`` (deg), linear interpolation (held constant beyond the end points)."""
        return interpolate_held(self.angle_deg, self.value, angle_deg)


def angle_of_attack_deg(velocity, axis) -> float:
    """Total angle of attack alpha (deg, in [0, 180]) between velocity ``velocity`` and the body axis ``axis``."""
    vx, vy, vz = velocity
    ex, ey, ez = axis
    along = vx * ex + vy * ey + vz * ez
    cx, cy, cz = vy * ez - vz * ey, vz * ex - vx * ez, vx * ey - vy * ex
    return math.degrees(math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), along))


def aerodynamic_force(velocity, axis, density: float, reference_area: float, axial_coefficient: float,
                      normal_coefficient: CoefficientTable, area_fraction: float = 1.0):
    """Aerodynamic force (N) on a body, to be applied at its aerodynamic centre.

    Parameters
    ----------
    velocity : sequence of 3 float
        Air-relative velocity of the aerodynamic centre (m/s), inertial components.
    axis : sequence of 3 float
        Unit body +x axis, inertial components.
    density : float
        Air density (kg/m^3).
    reference_area : float
        Reference area S (m^2).
    axial_coefficient : float
        C_A (-).
    normal_coefficient : CoefficientTable
        C_N(alpha') (-).
    area_fraction : float
        Fraction of the full drag area in effect (inflation or reefing), multiplying both coefficients (-).

    Returns
    -------
    tuple of 3 float
        Force (N), inertial components.
    """
    vx, vy, vz = velocity
    ex, ey, ez = axis
    speed2 = vx * vx + vy * vy + vz * vz
    if speed2 == 0.0:
        return (0.0, 0.0, 0.0)
    qs = 0.5 * density * speed2 * reference_area * area_fraction
    along = vx * ex + vy * ey + vz * ez
    px, py, pz = vx - along * ex, vy - along * ey, vz - along * ez
    perp = math.sqrt(px * px + py * py + pz * pz)
    fa = -qs * axial_coefficient
    if perp == 0.0:
        return (fa * ex, fa * ey, fa * ez)
    alpha = math.degrees(math.atan2(perp, along))
    fn = -qs * normal_coefficient(min(alpha, 180.0 - alpha)) / perp
    return (fa * ex + fn * px, fa * ey + fn * py, fa * ez + fn * pz)

"""Principal moments of inertia of the simple shapes ``pchute new`` sizes bodies as (kg m^2, about the centre of
mass, the symmetry axis first: a body's +x)."""

from __future__ import annotations


def solid_cylinder_inertia(mass: float, diameter: float, length: float) -> list:
    """A solid cylinder of ``mass`` (kg), ``diameter`` and ``length`` (m) along its axis: [m r^2 / 2, m (3 r^2 +
    L^2) / 12, the same] (kg m^2), r = diameter / 2."""
    radius = 0.5 * diameter
    across = mass * (3.0 * radius**2 + length**2) / 12.0
    return [mass * radius**2 / 2.0, across, across]


def hemispherical_shell_inertia(mass: float, radius: float) -> list:
    """A thin hemispherical shell of ``mass`` (kg) and ``radius`` (m): [(2/3) m R^2 about its axis, (5/12) m R^2
    across, the same] (kg m^2)."""
    across = 5.0 / 12.0 * mass * radius**2
    return [2.0 / 3.0 * mass * radius**2, across, across]

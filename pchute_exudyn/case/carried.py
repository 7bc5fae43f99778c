"""The vehicle while it carries bodies that separate later (``Case.separations``; ``physics.separation``).

A phase built while bodies ride with the vehicle uses ``case_at``: the vehicle becomes the composite body (its mass
and inertia with theirs, about their common centre of mass, its points and aerodynamic centre measured from that
centre). The vehicle's own aerodynamics stand for the whole until a body leaves; the carried bodies' own act once
they fly alone. The vehicle's position columns are then the composite's centre of mass.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..physics.separation import composite
from .model import Case


def carried(case: Case, time: float, before: bool = False) -> list:
    """The separations whose bodies ride with the vehicle at ``time`` (s) (``before``: just before it)."""
    return [s for s in case.separations.values() if (s.time >= time if before else s.time > time)]


def vehicle_with(case: Case, separations: list) -> tuple:
    """(composite Body, its centre of mass in the vehicle's own axes, m) of the vehicle carrying ``separations``'
    bodies."""
    vehicle = case.bodies[case.vehicle]
    if not separations:
        return vehicle, np.zeros(3)
    parts = [(vehicle.mass, vehicle.inertia, np.zeros(3))]
    parts += [(case.bodies[s.body].mass, case.bodies[s.body].inertia, s.position) for s in separations]
    mass, center, inertia = composite(parts)
    points = {name: tuple((np.asarray(p, float) - center).tolist()) for name, p in vehicle.points.items()}
    aerodynamics = vehicle.aerodynamics
    if aerodynamics is not None:
        aerodynamics = replace(aerodynamics, center=tuple((np.asarray(aerodynamics.center, float) - center).tolist()))
    return replace(vehicle, mass=mass, inertia=inertia, points=points, aerodynamics=aerodynamics), center


def case_at(case: Case, time: float) -> Case:
    """``case`` as a phase starting at ``time`` (s) flies it: the vehicle with the bodies it still carries (``case``
    itself when it carries none)."""
    riding = carried(case, time)
    if not riding:
        return case
    vehicle, _ = vehicle_with(case, riding)
    return replace(case, bodies={**case.bodies, case.vehicle: vehicle})

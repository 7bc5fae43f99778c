"""What rides with the vehicle at a time: the bodies it carries until they separate (``Case.separations``) and the
packed gear of each ``packed`` system until it deploys (``ParachuteSystem.packed``); ``physics.separation``.

A phase built while anything rides with the vehicle uses ``case_at``: the vehicle becomes the composite body (its
mass and inertia with theirs, about their common centre of mass, its points and aerodynamic centre measured from that
centre). The vehicle's own aerodynamics stand for the whole until a part leaves; a carried body's own act once it
flies alone, a canopy's once it is placed at line stretch. The vehicle's position columns are then the composite's
centre of mass.

A packed system's gear rides at its deploy point (a vehicle point): each of its canopies that leaves the vehicle,
with its own inertia about its own centre of mass (its axes the vehicle's), and its confluence as a point mass. A
canopy that never leaves the vehicle (``Failures.absent``) rides there throughout, and with it the confluence of a
system none of whose canopies leaves.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..physics.separation import composite
from .model import Case, ParachuteSystem


@dataclass(frozen=True)
class Rider:
    """A part riding with the vehicle.

    Attributes
    ----------
    name : str
        The body's name, or ``<system>.confluence`` for a packed confluence.
    mass : float
        kg.
    inertia : ndarray (3, 3)
        About its own centre of mass, in vehicle axes (kg m^2; zero for a confluence).
    position : tuple of 3 float
        Where its centre of mass rides, in vehicle axes from the vehicle's own centre of mass (m).
    """

    name: str
    mass: float
    inertia: np.ndarray
    position: tuple


def carried(case: Case, time: float, before: bool = False) -> list:
    """The ``Rider``s with the vehicle at ``time`` (s) (``before``: just before it, with what leaves then) of ``case``
    as loaded (its vehicle's own points): the separations' bodies, then each packed system's gear."""
    riders = [Rider(s.body, case.bodies[s.body].mass, case.bodies[s.body].inertia, s.position)
              for s in case.separations.values() if (s.time >= time if before else s.time > time)]
    for system in case.systems.values():
        riders += packed_gear(case, system, time, before)
    return riders


def packed_gear(case: Case, system: ParachuteSystem, time: float, before: bool = False) -> list:
    """The ``Rider``s of ``system``'s packed gear at ``time`` (s) (``before``: just before it): none unless it is
    ``packed``; before its deployment its canopies and confluence at the deploy point, afterwards the canopies that
    never leave the vehicle (and the confluence of a system that deploys none)."""
    if not system.packed or system.deploy_point is None:
        return []
    deploy = system.deploy_time if system.deploy_time is not None else -np.inf
    packed = deploy >= time if before else deploy > time
    leaving = [c for c in system.canopies if not case.failures.absent(c)]
    staying = [c for c in system.canopies if case.failures.absent(c)]
    body, point = system.deploy_point
    at = tuple(float(x) for x in case.bodies[body].points[point])
    riders = [Rider(c, case.bodies[c].mass, case.bodies[c].inertia, at)
              for c in system.canopies if (packed and c in leaving) or c in staying]
    if packed or not leaving:
        riders.append(Rider(f"{system.name}.confluence", system.confluence.mass, np.zeros((3, 3)), at))
    return riders


def vehicle_with(case: Case, riders: list) -> tuple:
    """(composite Body, its centre of mass in the vehicle's own axes, m) of the vehicle carrying ``riders``
    (``carried``)."""
    vehicle = case.bodies[case.vehicle]
    if not riders:
        return vehicle, np.zeros(3)
    parts = [(vehicle.mass, vehicle.inertia, np.zeros(3))]
    parts += [(rider.mass, rider.inertia, rider.position) for rider in riders]
    mass, center, inertia = composite(parts)
    points = {name: tuple((np.asarray(p, float) - center).tolist()) for name, p in vehicle.points.items()}
    aerodynamics = vehicle.aerodynamics
    if aerodynamics is not None:
        aerodynamics = replace(aerodynamics, center=tuple((np.asarray(aerodynamics.center, float) - center).tolist()))
    return replace(vehicle, mass=mass, inertia=inertia, points=points, aerodynamics=aerodynamics), center


def case_at(case: Case, time: float) -> Case:
    """``case`` as a phase starting at ``time`` (s) flies it: the vehicle with what it still carries (``case``
    itself when it carries nothing)."""
    riding = carried(case, time)
    if not riding:
        return case
    vehicle, _ = vehicle_with(case, riding)
    return replace(case, bodies={**case.bodies, case.vehicle: vehicle})

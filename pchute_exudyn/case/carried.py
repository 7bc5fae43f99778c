"""What rides with the vehicle at a time: the bodies it carries until they separate (``Case.separations``) and the
packed gear of each ``packed`` system until it deploys (``ParachuteSystem.packed``); ``physics.separation``.

A phase built while anything rides with the vehicle uses ``case_at``: the vehicle becomes the composite body (its
mass and inertia with theirs, about their common centre of mass, its points and aerodynamic centre measured from that
centre). The vehicle's own aerodynamics stand for the whole until a part leaves; a carried body's own act once it
flies alone, a canopy's once it is placed at line stretch. The vehicle's position columns are then the composite's
centre of mass.

A packed system's gear rides at its deploy point (a vehicle point): each of its canopies that leaves the vehicle and
its confluence, as point masses (a packed canopy is a compact bag; the inertia of the open canopy, which the case
gives, can exceed a slender rocket's own about its axis). A
canopy that never leaves the vehicle (``Failures.absent``) rides there throughout, and with it the confluence of a
system none of whose canopies leaves.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..physics.separation import composite, shifted_inertia
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
    bundle = np.zeros((3, 3))   # a packed canopy is a compact bag: its open inertia would be orders too large
    riders = [Rider(c, case.bodies[c].mass, bundle, at) for c in system.canopies if (packed and c in leaving)
              or c in staying]
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
    return replace(_measured_from(vehicle, center), mass=mass, inertia=inertia), center


def case_at(case: Case, time: float) -> Case:
    """``case`` as a phase starting at ``time`` (s) flies it: the vehicle with what it still carries (``case``
    itself when it carries nothing)."""
    riding = carried(case, time)
    if not riding:
        return case
    vehicle, _ = vehicle_with(case, riding)
    return replace(case, bodies={**case.bodies, case.vehicle: vehicle})


def packed_by_default(system: ParachuteSystem, vehicle: str) -> ParachuteSystem:
    """``system`` with ``packed`` decided where the case does not say: a system that deploys after the start from a
    point of the vehicle rides in it until then, so the suspended mass is the same before and after its deployment;
    any other has no packed gear."""
    if system.packed is not None:
        return system
    packs = system.deploy_time is not None and system.deploy_point is not None and system.deploy_point[0] == vehicle
    return replace(system, packed=packs)


def stated_center(case: Case) -> np.ndarray:
    """Where the vehicle's stated centre of mass lies, in its own axes from its own centre of mass (m): that of the
    vehicle with its packed gear at the start for a vehicle whose mass includes it (``mass_includes_packed``), else
    its own (zero)."""
    if not case.bodies[case.vehicle].mass_includes_packed:
        return np.zeros(3)
    gear = [rider for system in case.systems.values() for rider in packed_gear(case, system, 0.0, before=True)]
    return vehicle_with(case, gear)[1]


def own_vehicle(case: Case, error) -> Case:
    """``case`` whose vehicle's stated mass, inertia and points include its packed gear (``mass_includes_packed``)
    with the vehicle as its own body: the gear's mass and inertia (parallel axes) taken out, points measured from
    the vehicle's own centre of mass. ``error(key, message, value)`` makes the CaseError of an impossible remainder."""
    vehicle = case.bodies[case.vehicle]
    gear = [rider for system in case.systems.values() for rider in packed_gear(case, system, 0.0, before=True)]
    if not gear:
        raise error("mass_includes_packed", "the vehicle carries no packed system: remove it, or give a system "
                                            "that deploys from the vehicle packed = true", True)
    gear_mass = sum(rider.mass for rider in gear)
    own_mass = vehicle.mass - gear_mass
    if own_mass <= 0.0:
        raise error("mass", f"with mass_includes_packed must exceed the packed gear's {gear_mass:g} kg",
                    vehicle.mass)
    own_center = -sum(rider.mass * np.asarray(rider.position, float) for rider in gear) / own_mass
    inertia = vehicle.inertia - shifted_inertia(np.zeros((3, 3)), own_mass, own_center)
    inertia = inertia - sum(shifted_inertia(rider.inertia, rider.mass, np.asarray(rider.position, float))
                            for rider in gear)
    if np.any(np.linalg.eigvalsh(0.5 * (inertia + inertia.T)) <= 0.0):
        raise error("inertia", "with mass_includes_packed must exceed the packed gear's own inertia and its "
                               "parallel-axis part (the remainder is not positive definite)",
                    np.diag(vehicle.inertia).tolist())
    own = _measured_from(vehicle, own_center)
    return replace(case, bodies={**case.bodies, case.vehicle: replace(own, mass=own_mass, inertia=inertia)})


def _measured_from(body, center) -> object:
    """``body`` with its points and aerodynamic centre measured from ``center`` (m, in its axes) instead."""
    points = {name: tuple((np.asarray(p, float) - center).tolist()) for name, p in body.points.items()}
    aerodynamics = body.aerodynamics
    if aerodynamics is not None:
        aerodynamics = replace(aerodynamics, center=tuple((np.asarray(aerodynamics.center, float) - center).tolist()))
    return replace(body, points=points, aerodynamics=aerodynamics)


def suspended_mass(case: Case, time: float) -> float:
    """Everything the run flies at ``time`` (s), in kg: the vehicle with what rides in it, every other body present
    and the confluence of every acting system (whether its method gives it mass or not). Constant through a
    deployment when its gear was packed (``packed``); it changes only where a part is cut away or separates."""
    vehicle = case.mass_of(case.vehicle, time) + sum(rider.mass for rider in carried(case, time))
    others = sum(case.mass_of(name, time) for name in case.active_bodies(time) if name != case.vehicle)
    return vehicle + others + sum(system.confluence.mass for system in case.systems.values()
                                  if case.acting(system, time))


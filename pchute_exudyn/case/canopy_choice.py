"""The canopy model of a system whose case does not name one (``canopy_model = "auto"``, the default): reduced where a
reduced canopy is valid (``read_systems.reduced_refusal``) and the canopy is light against its drag, rigid otherwise.
The lightness rule (``LIGHT_CANOPY_TIME``, ``drag_time_constant``) is also the one ``pchute new`` writes by
(``authoring.layout``). docs/models/reduced_canopy.md, "Chosen by itself"."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..physics.atmosphere import OutsideAtmosphereError
from .read_systems import reduced_refusal

LIGHT_CANOPY_TIME = 0.05
"""The drag time constant (s) below which a canopy is light: m_canopy / (rho C_D0 S0 V). A light canopy's speed along
its riser settles faster than the steps its descent needs, so it may fly as a reduced canopy (SP: a massless drag
point at the riser's end), without its fast modes."""

HEAVY_CANOPY_TIME = 2.0 * LIGHT_CANOPY_TIME
"""The drag time constant (s) above which a canopy the case names reduced is warned (``heavy_reduced_warnings``): twice
the choice's LIGHT_CANOPY_TIME, which keeps that margin. Between the two (a fit's calibrated main of the synthetic
rocket logs: 0.063 s) the model is still close; a 40 kg canopy under the 20 kg rocket is at 0.28 to 0.87 s."""


def drag_time_constant(mass: float, density: float, drag_coefficient: float, reference_area: float,
                       speed: float) -> float:
    """A canopy's drag time constant m / (rho C_D0 S0 V) (s): ``mass`` m (kg), air ``density`` rho (kg/m^3),
    ``drag_coefficient`` C_D0 (-) on ``reference_area`` S0 (m^2), airspeed ``speed`` V (m/s); inf at rest."""
    drag = density * drag_coefficient * reference_area * speed
    return mass / drag if drag > 0.0 else math.inf


def steady_drag_time(canopy_mass: float, suspended_mass: float, gravity: float, density: float,
                     drag_coefficient: float, reference_area: float) -> float:
    """``drag_time_constant`` (s) at the steady rate of descent V = sqrt(2 M g / (rho C_D0 S0)) under the canopy
    alone: m / sqrt(2 M g rho C_D0 S0), ``canopy_mass`` m and ``suspended_mass`` M (kg, everything it holds up),
    ``gravity`` g (m/s^2), ``density`` rho (kg/m^3)."""
    rate = math.sqrt(2.0 * suspended_mass * gravity / (density * drag_coefficient * reference_area))
    return drag_time_constant(canopy_mass, density, drag_coefficient, reference_area, rate)


def with_canopy_models(systems: dict, bodies: dict, vehicle: str, atmosphere, planet, start, tethers: dict,
                       release) -> dict:
    """``systems`` with each ``"auto"`` canopy model resolved (``canopy_model_chosen`` set True): reduced where valid
    and light (``canopy_drag_time`` below LIGHT_CANOPY_TIME), rigid otherwise and in a ``release`` from an aircraft
    (as ``pchute new`` writes it: the canopy opens at the aircraft's airspeed, its motion before it fills kept)."""
    suspended, tethered = _suspended_and_tethered(systems, bodies, tethers)
    resolved = {}
    for name, system in systems.items():
        if system.canopy_model == "auto":
            light = release is None and canopy_drag_time(system, bodies, vehicle, atmosphere, planet, start,
                                                         tethered, suspended) < LIGHT_CANOPY_TIME
            system = replace(system, canopy_model="reduced" if light else "rigid", canopy_model_chosen=True)
        resolved[name] = system
    return resolved


def heavy_reduced_warnings(systems: dict, bodies: dict, vehicle: str, atmosphere, planet, start,
                           tethers: dict, simulation) -> tuple:
    """One line per system the case names ``canopy_model = "reduced"`` whose canopy is heavy (its
    ``canopy_drag_time`` above HEAVY_CANOPY_TIME, twice the rule ``"auto"`` and ``pchute new`` choose by): its speed
    along the riser then lags the descent by a time the massless drag point leaves out. Judged in the densest air
    the descent reaches (the start or the ground it stops on (``simulation``'s), the lower), where the time constant
    is shortest: a canopy deployed far below a high start is not warned for the thin air it never opens in."""
    ground_altitude = simulation.ground_altitude if simulation.stop_at_ground else math.inf
    suspended, tethered = _suspended_and_tethered(systems, bodies, tethers)
    warned = []
    for name, system in systems.items():
        if system.canopy_model != "reduced" or system.canopy_model_chosen:
            continue
        time = canopy_drag_time(system, bodies, vehicle, atmosphere, planet, start, tethered, suspended,
                                ground_altitude)
        if HEAVY_CANOPY_TIME < time < math.inf:
            warned.append(f"systems.{name}.canopy_model = 'reduced': canopy '{system.canopies[0]}' has a drag time "
                          f"constant m / (rho C_D0 S0 V) of {time:.3g} s, above the {HEAVY_CANOPY_TIME:g} s a reduced "
                          f"canopy is valid to (auto chooses it below {LIGHT_CANOPY_TIME:g} s): it flies as a massless "
                          "drag point and its own inertia is lost (use canopy_model = \"rigid\" or \"auto\")")
    return tuple(warned)


def _suspended_and_tethered(systems: dict, bodies: dict, tethers: dict) -> tuple:
    """(every free body's and confluence's mass (kg), the bodies at a tether's end)."""
    suspended = sum(b.mass for b in bodies.values() if not b.fixed and b.mass is not None) \
        + sum(s.confluence.mass for s in systems.values())
    return suspended, {body for tether in tethers.values() for body, _ in tether.ends}


def _densest(atmosphere, start_altitude: float, lowest_altitude: float) -> float:
    """The air's density (kg/m^3) at the lower of the two altitudes (m), the start's where the atmosphere ends above
    the other (the run then stops there; ``checks.ground_air_warnings`` says so)."""
    try:
        return atmosphere.density(min(start_altitude, lowest_altitude))
    except OutsideAtmosphereError:
        return atmosphere.density(start_altitude)


def canopy_drag_time(system, bodies: dict, vehicle: str, atmosphere, planet, start, tethered: set,
                     suspended_mass: float, lowest_altitude: float = math.inf) -> float:
    """The drag time constant (s, ``steady_drag_time``) of ``system``'s canopy at the vehicle's start: rho at its
    altitude (or at ``lowest_altitude`` (m) where that is lower, ``_densest``), g the planet's at the start point's
    surface, C_D0 the canopy's C_A at zero angle (Mach 0), ``suspended_mass`` (kg) every free body's and
    confluence's; inf where a reduced canopy is not valid (its layout, a bag anchor, a canopy among the ``tethered``
    bodies) or there is no air or start to judge by."""
    if reduced_refusal(system.canopies, system.lines, bodies, system.bag_anchor) is not None \
            or system.canopies[0] in tethered or atmosphere is None or bodies[vehicle].initial is None:
        return math.inf
    canopy = bodies[system.canopies[0]]
    if canopy.fixed or canopy.mass is None:
        return math.inf
    drag_coefficient = canopy.aerodynamics.axial_coefficient(0.0)
    gravity = float(np.linalg.norm(planet.gravity(start.origin)))
    density = _densest(atmosphere, bodies[vehicle].initial.altitude, lowest_altitude)
    if not (drag_coefficient > 0.0 and density > 0.0 and gravity > 0.0):
        return math.inf
    return steady_drag_time(canopy.mass, suspended_mass, gravity, density, drag_coefficient,
                            canopy.aerodynamics.reference_area)


def canopy_models_flown(systems: dict, flies_reduced: bool) -> dict:
    """Per system with canopies, ``{"model", "chosen"}``: the canopy model the run flies (a reduced canopy only where
    the method ``flies_reduced`` canopies, ``Method.flies_reduced_canopies``) and "auto" when the loader chose it (the
    case named none), "case" when the case named it."""
    return {name: {"model": system.canopy_model if flies_reduced else "rigid",
                   "chosen": "auto" if system.canopy_model_chosen else "case"}
            for name, system in systems.items() if system.canopies}

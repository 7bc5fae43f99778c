"""How a descent starts: the meaning of the case's initial velocities (relative to the ground or to the air) and the
release from an aircraft (``[start]``, ``[start.release]``; docs/case-format.md).

Both are resolved when the case is loaded: every ``InitialState`` of a loaded case holds velocities relative to the
ground, whatever the file said, so that nothing downstream needs to know how the run began.

The air the start moves with is the steady wind at the vehicle's start altitude (turbulence and gusts are departures
from it, not the air a payload was carried in). A release gives the vehicle the aircraft's air-relative velocity

    v_air = V (cos(gamma) sin(psi), cos(gamma) cos(psi), sin(gamma))        (east, north, up; m/s)

V the airspeed, psi the heading (clockwise from north), gamma the flight-path angle (positive climbing); its systems
deploy at line stretch at their ``deploy_time`` (a static line's time from the release).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..physics.conditions import altitude_and_speed, slowest_sound
from ..physics.deployment import bag_reach
from ..triggers.definition import LineStretch, Sensor, Trigger
from .plausible import range_of

VELOCITY_FRAMES = ("ground", "air")
"""What the ``velocity_*`` keys of the ``initial`` tables are relative to (``[start] velocities_relative_to``)."""


@dataclass(frozen=True)
class Release:
    """A payload released from an aircraft.

    Attributes
    ----------
    airspeed : float
        The aircraft's speed through the air (m/s, >= 0).
    heading_deg : float
        Its direction of flight, clockwise from north (deg).
    flight_path_deg : float
        Its flight-path angle above the horizontal (deg, -90 to 90; 0 in level flight).
    """

    airspeed: float
    heading_deg: float
    flight_path_deg: float = 0.0

    def air_velocity(self) -> tuple:
        """The released payload's velocity relative to the air (east, north, up) (m/s)."""
        heading, climb = math.radians(self.heading_deg), math.radians(self.flight_path_deg)
        horizontal = self.airspeed * math.cos(climb)
        return horizontal * math.sin(heading), horizontal * math.cos(heading), self.airspeed * math.sin(climb)


def moved_with(initial, east: float, north: float, up: float = 0.0):
    """``initial`` (an ``InitialState``) with (east, north, up) (m/s) added to its velocity."""
    return replace(initial, velocity_east=initial.velocity_east + east, velocity_north=initial.velocity_north + north,
                   velocity_down=initial.velocity_down - up)


def ground_relative(bodies: dict, systems: dict, vehicle: str, wind, frame: str, release: Release | None) -> tuple:
    """The ``bodies`` and ``systems`` with every initial velocity relative to the ground: the air's (the steady
    ``wind`` at the vehicle's start altitude) added where the case's velocities are relative to the air
    (``frame`` "air") and to a released vehicle's air-relative velocity."""
    if frame == "ground" and release is None:
        return bodies, systems
    altitude = bodies[vehicle].initial.altitude
    east, north = wind.at(altitude) if wind is not None else (0.0, 0.0)
    if frame == "air":
        bodies = {name: body if body.initial is None or body.fixed else
                  replace(body, initial=moved_with(body.initial, east, north)) for name, body in bodies.items()}
        systems = {name: system if system.confluence.initial is None else
                   replace(system, confluence=replace(system.confluence,
                                                      initial=moved_with(system.confluence.initial, east, north)))
                   for name, system in systems.items()}
    if release is not None:
        air_east, air_north, air_up = release.air_velocity()
        released = bodies[vehicle]
        if frame == "ground":   # the release is relative to the air whatever the file's velocities are
            air_east, air_north = air_east + east, air_north + north
        bodies = {**bodies, vehicle: replace(released, initial=moved_with(released.initial, air_east, air_north,
                                                                          air_up))}
    return bodies, systems


CONDITION_KEYS = ("mach", "dynamic_pressure", "flight_path_deg", "heading_deg")
"""The ``[bodies.<vehicle>.initial]`` keys that give the start as flight conditions (together, instead of
``altitude`` and the ``velocity_*`` keys)."""


@dataclass(frozen=True)
class FlightConditions:
    """The vehicle's start as flight conditions (line stretch or mortar fire as reconstructions state it).

    Attributes
    ----------
    mach : float
        Mach number (-, > 0) of the vehicle's speed through the air.
    dynamic_pressure : float
        rho V^2 / 2 (Pa, > 0) with V that speed.
    flight_path_deg : float
        Flight-path angle of the air-relative velocity above the horizontal (deg, -90 to 90; negative descending).
    heading_deg : float
        Its direction, clockwise from north (deg).
    """

    mach: float
    dynamic_pressure: float
    flight_path_deg: float
    heading_deg: float


SPEED_KEY = "bodies.vehicle.initial.velocity_east"
"""The case key whose range (``case.plausible.RANGES``) a start's speed through the air must be within."""


def mach_refusal(atmosphere, mach: float) -> str | None:
    """What is allowed for a start's Mach number ``mach`` (-), when no altitude of ``atmosphere`` gives a speed M a(h)
    within the range of SPEED_KEY (faster than its limit over the slowest speed of sound: no flight-condition solve,
    no overflow), else None."""
    if not atmosphere.has_speed_of_sound:
        return None   # the solve's own refusal says so
    fastest = range_of(SPEED_KEY).impossible[1]
    ceiling = fastest / slowest_sound(atmosphere)
    if mach <= ceiling:
        return None
    return (f"must be <= {ceiling:.4g}: a faster start moves at more than {fastest:g} m/s (the range of "
            f"initial.velocity_*) at every altitude of the {atmosphere.name} atmosphere")


def at_conditions(initial, atmosphere, wind, frame: str):
    """``initial`` (an ``InitialState`` with ``conditions``) with the altitude (m) and velocity (m/s) the conditions
    give in ``atmosphere`` (``physics.conditions.altitude_and_speed``): the velocity relative to the air, the
    steady ``wind`` at that altitude added when the case's velocities are relative to the ground (``frame``), as a
    release's is. Raises ``physics.conditions.ConditionsError``."""
    c = initial.conditions
    altitude, speed = altitude_and_speed(atmosphere, c.mach, c.dynamic_pressure)
    east, north, up = Release(speed, c.heading_deg, c.flight_path_deg).air_velocity()
    if frame == "ground" and wind is not None:
        wind_east, wind_north = wind.at(altitude)
        east, north = east + wind_east, north + wind_north
    return replace(initial, altitude=altitude, velocity_east=east, velocity_north=north, velocity_down=-up)


def with_bag_anchors(systems: dict, bodies: dict, vehicle: str, start, release: Release | None, triggers: dict,
                     system_tables: dict) -> dict:
    """The ``systems`` with each static line's anchor resolved (``physics.deployment.StaticLine``: at the release,
    ``anchor`` from the vehicle's centre of mass, flying on at the vehicle's released velocity) and the line stretch
    of each static line or pilot chute (``physics.deployment.PilotChute``: its body's centre of mass, read as the run
    goes) recorded in ``triggers`` as the system's deployment (``triggers.definition.LineStretch``)."""
    resolved = dict(systems)
    for name, system in systems.items():
        line = system.bag_anchor
        if line is None:
            continue
        if system.static_line is not None:
            line = _anchored_in_aircraft(line, bodies[vehicle].initial, start, release, system_tables[name])
        elif line.body == vehicle:
            raise system_tables[name].error("pilot_chute.body", "is the vehicle: the pilot chute is a body of its own "
                                                                "that extracts the bag from it", line.body)
        riser = system.risers(system.canopies[0])[0]
        reach = bag_reach(line, riser.free_length, bodies[system.canopies[0]].points[riser.point],
                                  bodies[system.deploy_point[0]].points[system.deploy_point[1]])
        triggers[f"{name}.deploy"] = Trigger(LineStretch(line, reach), Sensor(), f"systems.{name}.{line.key}")
        resolved[name] = replace(system, **{line.key: line})
    return resolved


def _anchored_in_aircraft(line, initial, start, release: Release | None, table):
    """A static line with its anchor's start-frame origin and velocity (the aircraft's at the release, ``initial``
    the vehicle's initial state); refused (on ``table``) without a release."""
    if release is None:
        raise table.error("static_line", "needs start.release: the aircraft the static line is anchored in, flying "
                                         "at the release velocity")
    east, north, up = line.anchor
    origin = start.local_position(initial.altitude + up, initial.east + east, initial.north + north)
    velocity = start.inertial_velocity(start.local_position(initial.altitude, initial.east, initial.north),
                                       initial.velocity_enu)
    return replace(line, origin=tuple(origin.tolist()), velocity=tuple(np.asarray(velocity, float).tolist()))

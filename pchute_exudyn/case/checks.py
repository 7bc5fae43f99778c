"""Whole-case checks: what no single table can tell (events against the run's duration, canopies against systems,
a release, Mach tables against the atmosphere, the plausibility of every number read)."""

from __future__ import annotations

import math

import numpy as np

from ..errors import CaseError
from ..physics.atmosphere import OutsideAtmosphereError
from ..physics.inflation import nominal_diameter
from ..physics.planet import Planet
from .fields import Context, Table
from .plausible import IMPLAUSIBLE, check_value
from .read_bodies import MOMENTS
from .read_systems import canopy_key_of


def check_vehicle(info: Table, vehicle: str, systems: dict) -> None:
    """The vehicle is the body the parachutes hang from, never one of their canopies (a canopy placed at
    deployment has no initial state to start from)."""
    for name, system in systems.items():
        if vehicle in system.canopies:
            raise info.error("vehicle", f"is a canopy of system '{name}': case.vehicle must name the body the "
                                        "parachutes hang from", vehicle)


def check_packed_mass(body_tables: dict, bodies: dict, vehicle: str) -> None:
    """Only the vehicle carries packed gear, so only its stated mass can include it."""
    for name, body in bodies.items():
        if body.mass_includes_packed and name != vehicle:
            raise body_tables[name].error("mass_includes_packed", f"only the vehicle ('{vehicle}') carries packed "
                                                                  "gear", True)


def check_grounds(atmosphere_table: Table, wind, turbulence, start_altitude: float | None) -> None:
    """A power-law wind or a turbulence field whose ground is at or above the vehicle's start would do nothing
    (no wind below its ground, a field frozen at its ground value)."""
    if start_altitude is None:
        return
    for key, model in (("wind.ground_altitude", wind), ("turbulence.ground_altitude", turbulence)):
        ground = getattr(model, "ground_altitude", None)
        if ground is not None and ground >= start_altitude:
            raise atmosphere_table.error(key, f"must be below the vehicle's start altitude ({start_altitude:g} m): "
                                              "above the flight it does nothing", ground)


def ground_air_warnings(simulation, atmosphere) -> tuple:
    """A ground the run stops on outside the atmosphere: the run stops where the air ends, before touchdown (a table
    that covers only the altitudes a short run flies is fine; its run is then not meant to land)."""
    if atmosphere is None or not simulation.stop_at_ground:
        return ()
    try:
        atmosphere.density(simulation.ground_altitude)
    except OutsideAtmosphereError as exc:
        return (f"simulation.ground_altitude = {simulation.ground_altitude:g}{IMPLAUSIBLE}outside the atmosphere the "
                f"descent flies through ({exc.low:g} to {exc.high:g} m, {exc.model}): the run stops where the air "
                "ends, before touchdown",)
    return ()


def check_mach(body_tables, bodies, atmosphere) -> None:
    """A coefficient tabulated over Mach number needs the atmosphere's speed of sound."""
    if atmosphere is None or atmosphere.has_speed_of_sound:
        return
    for name, body in bodies.items():
        aero = body.aerodynamics
        for key, table in (() if aero is None else zip(("axial_coefficient", "normal_coefficient") + MOMENTS,
                                                       aero.coefficients().values())):
            if table is not None and table.uses_mach:
                raise body_tables[name].error(f"aerodynamics.{key}.mach", "a Mach-number table needs the speed of "
                                              "sound, and the atmosphere table has no temperature column: add one "
                                              "(K) or give atmosphere.speed_of_sound (m/s)", list(table.mach))


def check_supersonic_openings(system_tables, systems, bodies, atmosphere) -> None:
    """A supersonic opening takes its load factor from the Mach number at line stretch: it needs the speed of
    sound, and its wake factor 1 - k_w d / D_0 must stay positive for each of its canopies."""
    for name, system in systems.items():
        opening = None if system.inflation is None else system.inflation.supersonic
        if opening is None:
            continue
        if atmosphere is not None and not atmosphere.has_speed_of_sound:
            raise system_tables[name].error("inflation.supersonic", "a supersonic opening needs the speed of sound, "
                                            "and the atmosphere table has no temperature column: add one (K) or "
                                            "give atmosphere.speed_of_sound (m/s)")
        for canopy in system.canopies:
            aerodynamics = bodies[canopy].aerodynamics
            share = 0.0 if aerodynamics is None else \
                opening.wake_coefficient * opening.forebody_diameter / nominal_diameter(aerodynamics.reference_area)
            if share >= 1.0:
                raise system_tables[name].error("inflation.supersonic.wake_coefficient", f"gives k_w d / D_0 = "
                                                f"{share:.3g} for canopy '{canopy}': it must stay below 1 (the wake "
                                                "factor 1 - k_w d / D_0 scales the load factor)",
                                                opening.wake_coefficient)


RELEASED_KEYS = ("velocity_north", "velocity_east", "velocity_down", "rate_x", "rate_y", "rate_z")
"""Initial-state keys a released vehicle may not have: its motion is the release's."""


def check_release(body_tables, system_tables, bodies, systems, vehicle: str, release) -> None:
    """A release (``release``, None: none, nothing to check) gives the vehicle its velocity and deploys every system
    at line stretch: the vehicle has no velocities or rates of its own, every system a deploy_time (the static line's
    time from the release) or a static_line, and no other free body an initial state."""
    if release is None:
        return
    given = [key for key in RELEASED_KEYS if key in body_tables[vehicle].data.get("initial", {})]
    if given:
        raise body_tables[vehicle].error(f"initial.{given[0]}", "a vehicle released from an aircraft "
                                         "(start.release) takes its velocity and rates from the release; remove it",
                                         body_tables[vehicle].data["initial"][given[0]])
    for name, system in systems.items():
        if system.deploy_time is None:
            raise system_tables[name].error("deploy_time", "required with start.release (s: the static line's time "
                                                           "from the release to line stretch), or a static_line")
    for name, body in bodies.items():
        if name != vehicle and not body.fixed and body.initial is not None:
            raise body_tables[name].error("initial", "with start.release only the vehicle starts with a state; its "
                                                     "canopies are placed at line stretch: remove this table")


def _given(st, event: str) -> str:
    """The key the case gave an event's fixed time with: ``<event>_time``, or a ``{ time = t }`` trigger."""
    return f"{event}_trigger.time" if f"{event}_trigger" in st.data else f"{event}_time"


def check_events(top, body_tables, system_tables, simulation_table, bodies, systems, simulation, vehicle) -> None:
    """Cross-checks of deployments, cut-aways, canopies, initial states and the ground."""
    duration = simulation.duration
    canopies = {}
    for name, system in systems.items():
        st = system_tables[name]
        key = canopy_key_of(st)
        if system.deploy_time is not None and math.isfinite(system.deploy_time) and system.deploy_time >= duration:
            raise st.error(_given(st, "deploy"), f"must be before the end of the run (simulation.duration = "
                                                 f"{duration:g} s)", system.deploy_time)
        if system.cutaway_time is not None and math.isfinite(system.cutaway_time) and system.cutaway_time >= duration:
            raise st.error(_given(st, "cutaway"), f"must be before the end of the run (simulation.duration = "
                                                  f"{duration:g} s)", system.cutaway_time)
        for canopy in system.canopies:
            if canopy in canopies:
                raise st.error(key, f"body '{canopy}' is already the canopy of system '{canopies[canopy]}'", canopy)
            if canopy == vehicle:
                raise st.error(key, "the vehicle cannot be a canopy", canopy)
            canopies[canopy] = name
        placed = system.deploy_time is not None
        for canopy in system.canopies:
            if placed and bodies[canopy].initial is not None:
                raise body_tables[canopy].error("initial", f"a canopy deployed at line stretch (system '{name}', "
                                                           "deploy_time) gets its initial state at deployment; "
                                                           "remove this table")
        if placed and system.confluence.initial is not None:
            raise st.error("confluence.initial", "a system deployed at line stretch gets its confluence state at "
                                                 "deployment; remove this table")
        if not placed and system.confluence.initial is None:
            raise st.error("confluence.initial", "required (or give the system a deploy_time)")
    carried = top.data.get("separations", {})
    for name, body in bodies.items():
        if name in carried if isinstance(carried, dict) else False:
            continue   # rides with the vehicle until it separates (case.read_triggers.read_separations)
        if body.initial is None and name not in canopies or \
                body.initial is None and systems[canopies[name]].deploy_time is None:
            raise body_tables[name].error("initial", "required (only a canopy deployed at line stretch has none)")
    ground = simulation.ground_altitude
    if simulation.stop_at_ground and not bodies[vehicle].fixed and ground >= bodies[vehicle].initial.altitude:
        raise simulation_table.error("ground_altitude", f"must be below the vehicle's start altitude "
                                                        f"({bodies[vehicle].initial.altitude:g} m; the default is the "
                                                        "surface, 0 m; stop_at_ground = false flies on)", ground)


def check_connections(system_tables, bodies, systems, vehicle, tethers=None) -> None:
    """A system must join different bodies: lines that all end on one free body tie it to itself (its canopy would
    fall free), a system with canopies must hang them from the vehicle (or from a body tethered to it: a nose cone on
    the shock cord, ``case.sections.Tether``), no line may run to another system's canopy
    (each canopy hangs on risers to its own system's confluence), and a packed system's gear rides in the vehicle
    (its deploy point a vehicle point, ``case.carried``)."""
    owner = {canopy: name for name, system in systems.items() for canopy in system.canopies}
    holding = {vehicle}   # the vehicle and the bodies tied to it, through tethers
    for _ in range(len(tethers or {})):
        for tether in (tethers or {}).values():
            ends = {body for body, _ in tether.ends}
            if ends & holding:
                holding |= ends
    for name, system in systems.items():
        if system.packed and system.deploy_point[0] != vehicle:
            raise system_tables[name].error("deploy_point", f"is on body '{system.deploy_point[0]}', not the vehicle "
                                                            f"'{vehicle}': a packed system rides in the vehicle until "
                                                            "it deploys (remove packed, or deploy from the vehicle)",
                                            ".".join(system.deploy_point))
        attached = {line.body for line in system.lines}
        if len(attached) == 1 and not bodies[next(iter(attached))].fixed:
            raise system_tables[name].error("lines", f"every line attaches to body '{next(iter(attached))}': the "
                                                     "system would join that body to itself; attach its lines to two "
                                                     "bodies (e.g. bridles to the vehicle, a riser to the canopy)")
        if system.canopies and not attached & holding:
            key = canopy_key_of(system_tables[name])
            raise system_tables[name].error(key, f"canopy '{system.canopies[0]}' is not connected to the vehicle "
                                                 f"'{vehicle}': no line of the system attaches to it (or to a "
                                                 "body tethered to it)",
                                            system.canopies[0])
        for line in system.lines:
            if owner.get(line.body, name) != name:
                raise system_tables[name].error(f"lines.{line.name}.attach", f"runs to canopy '{line.body}' of system "
                                                                             f"'{owner[line.body]}': a canopy's risers "
                                                                             "run to its own system's confluence",
                                                f"{line.body}.{line.point}")


def check_escape(body_tables: dict, bodies: dict, planet) -> None:
    """A body starting faster than the planet's escape speed at its altitude leaves the planet: impossible for a
    parachute descent (``case.plausible``; a flat planet has no escape speed)."""
    if not isinstance(planet, Planet):
        return
    for name, body in bodies.items():
        if body.initial is None or body.fixed:
            continue
        speed = float(np.linalg.norm(body.initial.velocity_enu))
        radius = planet.equatorial_radius + max(body.initial.altitude, 0.0)
        escape = math.sqrt(2.0 * planet.gravitational_parameter / radius)
        if speed > escape:   # named by its largest component (the key most likely mistyped)
            key = max(("velocity_north", "velocity_east", "velocity_down"),
                      key=lambda k: abs(getattr(body.initial, k)))
            raise body_tables[name].error(f"initial.{key}", f"gives a start speed of {speed:.6g} m/s, faster than "
                                          f"the escape speed there ({escape:.6g} m/s): impossible for a descent",
                                          getattr(body.initial, key))


def check_plausible(data: dict, ctx: Context) -> tuple:
    """Every number read against its plausibility range (``case.plausible``): an impossible value raises the
    CaseError of its key; the implausible ones give the warnings (one line each)."""
    warnings = []
    for key, path in ctx.paths.items():
        node = data
        for part in path:
            node = node[part] if isinstance(node, (dict, list)) and _has(node, part) else None
        if node is None:
            continue
        error, warning = check_value(key, node)
        if error is not None:
            raise CaseError(ctx.source(path), key, error, node)
        if warning is not None:
            warnings.append(warning)
    return tuple(warnings)


def _has(node, part) -> bool:
    return part in node if isinstance(node, dict) else isinstance(part, int) and part < len(node)

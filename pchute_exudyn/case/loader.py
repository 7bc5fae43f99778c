"""Load a case: merge its files (``case.files``), apply the overrides (``case.overrides``), read every section
(``case.read_bodies``, ``case.read_systems``, ``case.read_world``) and check the whole (``case.checks``).

Everything is validated once; an error names the file (or override) the value came from, the dotted field, the bad
value and what is allowed. See ``docs/case-format.md`` for every key and its unit.
"""

from __future__ import annotations

import copy
import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

from ..physics.conditions import ConditionsError
from ..registries.columns import UNNAMED_VEHICLE
from .canopy_choice import heavy_reduced_warnings, with_canopy_models
from .carried import own_vehicle, packed_by_default
from .checks import (
    check_connections,
    check_escape,
    check_events,
    check_grounds,
    check_mach,
    check_packed_mass,
    check_plausible,
    check_release,
    check_supersonic_openings,
    check_vehicle,
    ground_air_warnings,
)
from .fields import Context, Table
from .files import display_path, load_merged
from .model import Body, Case
from .overrides import apply_override, parse_override
from .read_bodies import read_body
from .read_systems import read_failures, read_system
from .read_tethers import check_ejections, check_tethers, read_tethers
from .read_triggers import check_triggers, read_separations
from .read_world import planet_warnings, read_atmosphere, read_planet, read_simulation, read_start
from .start import Release, at_conditions, ground_relative, mach_refusal, with_bag_anchors
from .trigger_reach import unreachable_triggers
from .unit_slips import unit_slips


def load_case(path, overrides: Mapping[str, Any] | Iterable[str] = ()) -> Case:
    """Load and validate a case file.

    Parameters
    ----------
    path : str or Path
        The case TOML file.
    overrides : mapping or iterable of str
        Dotted keys to values, or ``"key=value"`` strings. Applied after the file (and its ``extends`` chain) is
        merged; see ``case.overrides`` for the key syntax.

    Returns
    -------
    Case

    Raises
    ------
    CaseError
        With the file (or override), the field, the bad value and what is allowed.
    """
    path = Path(path)
    origins: dict = {}
    data = load_merged(path, origins)
    items = overrides.items() if isinstance(overrides, Mapping) else (parse_override(o) for o in overrides)
    applied = []
    for key, value in items:
        apply_override(data, origins, key, value, f"--set {key}={value}")
        applied.append(f"{key}={value}")
    source = display_path(path) + (f" with {', '.join(applied)}" if applied else "")
    origins_top = display_path(path)
    case = build_case(data, origins, origins_top)
    return _with_source(case, source)


def _read_info(top: Table, source: str) -> tuple:
    """(the ``[case]`` table, the case's name (default: its file's stem), description and vehicle body's name)."""
    info = top.table("case", {})
    name = info.string("name", Path(source.split(" ")[0]).stem)
    description = info.string("description", "")
    vehicle = info.string("vehicle", UNNAMED_VEHICLE)
    info.finish()
    return info, name, description, vehicle


def build_case(data: dict, origins: dict, source: str) -> Case:
    """Validate merged case ``data`` and build the Case (``origins`` maps key paths to the file they came from)."""
    ctx = Context(source, origins)
    top = Table(data, (), ctx)
    info, name, description, vehicle = _read_info(top, source)
    planet_table = top.table("planet")
    planet = read_planet(planet_table)
    start, frame, release, site = read_start(top.table("start", {}), planet)
    atmosphere_table = top.table("atmosphere", None)
    body_tables = top.named_tables("bodies")
    if not body_tables:
        raise top.error("bodies", "a case needs at least one body")
    bodies = {body_name: read_body(body_name, bt) for body_name, bt in body_tables.items()}
    aerodynamic = [name for name, body in bodies.items() if body.aerodynamics is not None]
    if atmosphere_table is None and aerodynamic:
        raise top.error("atmosphere", f"required because body '{aerodynamic[0]}' has aerodynamics")
    if vehicle not in bodies:
        raise info.error("vehicle", f"must name a body; bodies are: {', '.join(bodies)}", vehicle)
    system_tables = top.named_tables("systems", {})
    triggers: dict = {}
    systems = {sys_name: read_system(sys_name, st, bodies, triggers) for sys_name, st in system_tables.items()}
    check_vehicle(info, vehicle, systems)
    check_packed_mass(body_tables, bodies, vehicle)
    systems = {name: packed_by_default(system, vehicle) for name, system in systems.items()}
    simulation_table = top.table("simulation")
    simulation = read_simulation(simulation_table)
    bodies, atmosphere, wind, turbulence, gusts = _with_air(atmosphere_table, simulation, body_tables, bodies,
                                                            vehicle, frame, release, site)
    check_mach(body_tables, bodies, atmosphere)
    check_supersonic_openings(system_tables, systems, bodies, atmosphere)
    check_release(body_tables, system_tables, bodies, systems, vehicle, release)
    check_events(top, body_tables, system_tables, simulation_table, bodies, systems, simulation, vehicle)
    bodies, systems = ground_relative(bodies, systems, vehicle, wind, frame, release)
    systems = with_bag_anchors(systems, bodies, vehicle, start, release, triggers, system_tables)   # after: its speed
    tethers = read_tethers(top.table("tethers", None), bodies, systems)
    systems = with_canopy_models(systems, bodies, vehicle, atmosphere, planet, start, tethers, release)
    check_connections(system_tables, bodies, systems, vehicle, tethers)
    failures = read_failures(top.table("failures", None), systems, simulation.duration, bodies, triggers)
    separations = read_separations(top.table("separations", None), bodies, vehicle, triggers, systems,
                                   simulation.duration)
    check_triggers(top, triggers, systems, failures, separations, atmosphere)
    check_ejections(top.table("separations", None), separations)
    tether_warnings = check_tethers(top.table("tethers", None), tethers, bodies, separations, vehicle)
    top.allowed.extend(("extends", "remove"))
    top.finish()
    warnings = check_plausible(data, ctx) + unit_slips(bodies[vehicle]) + unreachable_triggers(
        triggers, None if release is not None else bodies[vehicle].initial, simulation.ground_altitude,
        simulation.stop_at_ground) \
        + tether_warnings + heavy_reduced_warnings(systems, bodies, vehicle, atmosphere, planet, start, tethers,
                                                   simulation) \
        + planet_warnings(planet_table, planet) + ground_air_warnings(simulation, atmosphere)
    check_escape(body_tables, bodies, planet)
    case = Case(name=name, description=description, source=source, planet=planet, start=start,
                atmosphere=atmosphere, bodies=bodies, systems=systems, simulation=simulation, vehicle=vehicle,
                wind=wind, turbulence=turbulence, gusts=gusts, key_units=dict(ctx.units), failures=failures,
                velocities_relative_to=frame, release=release, warnings=warnings, triggers=triggers,
                separations=separations, tethers=tethers)
    return own_vehicle(case, body_tables[vehicle].error) if bodies[vehicle].mass_includes_packed else case


def _with_air(atmosphere_table, simulation, body_tables, bodies, vehicle, frame, release, site) -> tuple:
    """(bodies, atmosphere, wind, turbulence, gusts): ``[atmosphere]`` read (all None and no gusts without one; a
    forecast's at ``site``, the start's (latitude, longitude) deg or None), the vehicle's start found from its flight
    conditions when the case gives them, the grounds checked against it."""
    atmosphere, wind, turbulence, gusts = None, None, None, ()
    if atmosphere_table is not None:
        atmosphere, wind, turbulence, gusts = read_atmosphere(atmosphere_table, simulation.ground_altitude,
                                                               _heading(bodies[vehicle], release), site)
    bodies = _at_conditions(body_tables, bodies, vehicle, atmosphere, wind, frame, release)
    if atmosphere_table is not None:
        initial = bodies[vehicle].initial
        check_grounds(atmosphere_table, wind, turbulence, None if initial is None else initial.altitude)
    return bodies, atmosphere, wind, turbulence, gusts


def _at_conditions(body_tables, bodies, vehicle, atmosphere, wind, frame, release) -> dict:
    """``bodies`` with the vehicle's start found from its flight conditions when the case gives them
    (``case.start.at_conditions``); they belong to the vehicle alone, need an atmosphere and exclude a release."""
    for name, body in bodies.items():
        conditions = body.initial.conditions if body.initial is not None else None
        if conditions is None:
            continue
        table = body_tables[name]
        if name != vehicle:
            raise table.error("initial.mach", f"only the vehicle ('{vehicle}') can start at flight conditions "
                                              "(mach, dynamic_pressure, flight_path_deg, heading_deg)", conditions.mach)
        if release is not None:
            raise table.error("initial.mach", "a vehicle released from an aircraft (start.release) takes its state "
                                              "from the release; remove the flight conditions", conditions.mach)
        if atmosphere is None:
            raise table.error("initial.mach", "needs an [atmosphere] to find the altitude and speed of the flight "
                                              "conditions (mach, dynamic_pressure)", conditions.mach)
        refusal = mach_refusal(atmosphere, conditions.mach)
        if refusal is not None:
            raise table.error("initial.mach", refusal, conditions.mach)
        try:
            initial = at_conditions(body.initial, atmosphere, wind, frame)
        except ConditionsError as exc:
            raise table.error(f"initial.{exc.field}", f"with initial.mach = {conditions.mach:g}: {exc}",
                              getattr(conditions, exc.field)) from None
        bodies = {**bodies, name: replace(body, initial=initial)}
    return bodies


def _heading(vehicle: Body, release: Release | None) -> tuple:
    """Unit (east, north) direction of the vehicle's initial horizontal velocity as the case gives it (a release's
    heading, or its flight conditions'; east when it has none): where turbulence's u points without a mean wind."""
    conditions = vehicle.initial.conditions if vehicle.initial is not None else None
    if conditions is not None:
        release = Release(1.0, conditions.heading_deg, conditions.flight_path_deg)
    east, north = (release.air_velocity()[:2] if release is not None
                   else (vehicle.initial.velocity_east, vehicle.initial.velocity_north))
    speed = math.hypot(east, north)
    return (east / speed, north / speed) if speed > 0.0 else (1.0, 0.0)


def override_leaves(path, overrides: Mapping[str, Any]) -> dict:
    """The case values ``overrides`` change, as full dotted keys to whole values (an indexed override gives its whole
    array): what a case file extending ``path`` must set to hold them."""
    origins: dict = {}
    before = load_merged(Path(path), origins)
    after = copy.deepcopy(before)
    for key, value in overrides.items():
        apply_override(after, origins, key, value)
    changed: dict = {}

    def walk(old, new, prefix):
        if isinstance(new, dict):
            for name, value in new.items():
                walk(old.get(name) if isinstance(old, dict) else None, value, prefix + (name,))
        elif new != old:
            changed[".".join(prefix)] = new
    walk(before, after, ())
    return changed


def extending_case_text(path, overrides: Mapping[str, Any], folder, header: str) -> str:
    """A case file, to be written in ``folder``, extending the case file ``path`` with the values ``overrides``
    change (``override_leaves``; whole arrays where a key indexed one), under the comment line ``header``."""
    leaves = override_leaves(path, overrides)
    relative = Path(os.path.relpath(path, folder)).as_posix()
    lines = [f"# {header}", f'extends = "{relative}"', ""]
    tables: dict = {}
    for full, value in leaves.items():
        table, _, key = full.rpartition(".")
        tables.setdefault(table, []).append(f"{key} = {_toml(value)}")
    for table, entries in tables.items():
        lines += [f"[{table}]", *entries, ""]
    return "\n".join(lines)


def _toml(value) -> str:
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return repr(float(value)) if isinstance(value, float) else repr(value)


def _with_source(case: Case, source: str) -> Case:
    from dataclasses import replace
    return replace(case, source=source)

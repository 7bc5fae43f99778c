"""From engine samples to named time histories (pure numpy, no Exudyn), and the checks that a run did not diverge.

Column names (units in ``units``):

* per body ``<b>``: ``<b>_altitude``, ``<b>_height`` (above the case's ground), ``<b>_east``, ``<b>_north`` (m;
  east/north along the start point's axes, relative to the ground); ``<b>_velocity_north|east|down`` (m/s, relative
  to the ground, start-point axes); on an ellipsoidal planet ``<b>_latitude`` and ``<b>_longitude`` (deg,
  geodetic, relative to the ground; after every other column);
  ``<b>_yaw_deg|pitch_deg|roll_deg`` (attitude angles, ``physics.rotations``), ``<b>_tilt_deg`` (body +x from
  nadir); ``<b>_rate_x|y|z`` (rad/s, body axes); for aerodynamic bodies ``<b>_angle_of_attack_deg`` (total),
  ``<b>_alpha_deg`` and ``<b>_beta_deg`` (atan2(w, u) and asin(v/|V|) of the air-relative velocity (u, v, w) in body
  axes) and ``<b>_dynamic_pressure`` (Pa); for bodies other than the vehicle ``<b>_relative_position_x|y|z`` (m) and
  ``<b>_relative_velocity_x|y|z`` (m/s) relative to the vehicle in vehicle body axes.
* per confluence (``confluence``, or ``<system>_confluence`` with several systems): altitude, east, north, the
  three velocities and the relative position and velocity as above.
* per line: ``tension_<line>`` (or ``tension_<system>_<line>``), N.

A body or system absent from part of a run (not yet deployed, or cut away) has NaN there.
"""

from __future__ import annotations

import numpy as np

from ..case.model import Case
from ..engine.state import BODY_QUANTITIES, CONFLUENCE_QUANTITIES, ColumnChannel, RawHistory
from ..errors import SimulationError
from ..physics.aerodynamics import angles_of_attack_deg, dynamic_pressure_of_speed, mach_number
from ..physics.kinematics import body_point, relative_to_body
from ..physics.lines import line_states
from ..physics.planet import FlatPlanet
from ..physics.rotations import attitude_angles_deg, tilt_deg
from ..physics.step_rule import merge_summaries
from ..registries.columns import GEODETIC_TEMPLATES, POINT_TEMPLATES, column, derived, method_column, unit
from ..registries.columns import owner as column_owner

MAX_LINE_STRAIN = 1.0
"""A line without a material stretched beyond (1 + MAX_LINE_STRAIN) times its free length is over-stretched: no
parachute line stretches that far (they break at a few per cent to a few tens of per cent strain), so such a run stops
with an error instead of returning numbers. A line with a material stops at its material's breaking strain."""


def concatenate(case: Case, histories: list) -> RawHistory:
    """One history from the phases of a run. A quantity absent from a phase (a system not deployed yet, or cut
    away) is NaN there; at a phase boundary the later phase's first sample replaces the earlier one's last."""
    keep = []
    for i, raw in enumerate(histories):
        rows = np.ones(len(raw.time), dtype=bool)
        if i + 1 < len(histories) and len(raw.time) and len(histories[i + 1].time) \
                and abs(histories[i + 1].time[0] - raw.time[-1]) < 1e-9:
            rows[-1] = False
        keep.append(rows)
    time = np.concatenate([raw.time[rows] for raw, rows in zip(histories, keep)])
    out = RawHistory(time=time, steps=sum(r.steps for r in histories), wall_time=sum(r.wall_time for r in histories),
                     stopped_at=histories[-1].stopped_at)
    if any(r.step_control is not None for r in histories):
        out.step_control = merge_summaries([r.step_control for r in histories])

    def gather(get, shape):
        parts = []
        for raw, rows in zip(histories, keep):
            value = get(raw)
            parts.append(value[rows] if value is not None else np.full((int(rows.sum()),) + shape, np.nan))
        return np.concatenate(parts)

    shapes = dict(zip(BODY_QUANTITIES, [(3,), (3,), (3, 3), (3,)]))
    for name in case.bodies:   # every body and system gets columns, NaN where absent (e.g. never deployed)
        out.bodies[name] = {key: gather(lambda r, k=key, n=name: r.bodies.get(n, {}).get(k), shape)
                            for key, shape in shapes.items()}
    for name, system in case.systems.items():
        out.confluences[name] = {key: gather(lambda r, k=key, n=name: r.confluences.get(n, {}).get(k), (3,))
                                 for key in CONFLUENCE_QUANTITIES}
        for line in system.lines:
            out.tensions[(name, line.name)] = gather(lambda r, k=(name, line.name): r.tensions.get(k), ())
    for key in dict.fromkeys(k for r in histories for k in r.method):   # ordered union
        out.method[key] = gather(lambda r, k=key: r.method.get(k), ())
    return out


def attach_points(case: Case, raw: RawHistory, system, velocities: bool = True) -> tuple:
    """Positions and velocities (n_samples, n_lines, 3) of a system's attach points, from the body histories
    (``velocities=False``: None for the velocities, not computed)."""
    positions, speeds = [], []
    for line in system.lines:
        body = raw.bodies[line.body]
        position, velocity = body_point(body["position"], body["rotation"],
                                        body["velocity"] if velocities else None, body["angular_velocity"],
                                        case.bodies[line.body].points[line.point])
        positions.append(position)
        speeds.append(velocity)
    return np.stack(positions, axis=1), np.stack(speeds, axis=1) if velocities else None


def scene(case: Case, raw: RawHistory) -> tuple[dict, dict]:
    """What an animation draws, from the sampled states: arrays in the start frame (x east, y north, z up from the
    start point on the ellipsoid, m; NaN where absent) and a JSON-able description of the bodies and lines.

    Arrays: ``<body>/position`` (n, 3), ``<body>/rotation`` (n, 3, 3: body axes to start frame),
    ``<system>/confluence`` (n, 3) and ``<system>/<line>`` (n, 3), the line's attach point on its body. The
    description gives each body's drawing (``Case.drawing``: role, diameter, apex, line points) and each system's
    confluence label and lines (body, its point in body axes in m, tension column)."""
    arrays, bodies, systems = {}, {}, {}
    for name in case.bodies:
        arrays[f"{name}/position"] = raw.bodies[name]["position"]
        arrays[f"{name}/rotation"] = raw.bodies[name]["rotation"]
        bodies[name] = case.drawing(name)
    for system in case.systems.values():
        if system.name not in raw.confluences:
            continue
        arrays[f"{system.name}/confluence"] = raw.confluences[system.name]["position"]
        positions, _ = attach_points(case, raw, system, velocities=False)
        lines = []
        for i, line in enumerate(system.lines):
            arrays[f"{system.name}/{line.name}"] = positions[:, i]
            lines.append({"name": line.name, "body": line.body,
                          "tension": column("tension_{owner}", case.line_label(system, line)),
                          "point": list(map(float, case.bodies[line.body].points[line.point]))})
        systems[system.name] = {"confluence": case.confluence_label(system), "canopies": list(system.canopies),
                                "lines": lines}
    description = {"frame": "start frame: x east, y north, z up (m)", "vehicle": case.vehicle, "bodies": bodies,
                   "systems": systems}
    return arrays, description


def check_history(case: Case, raw: RawHistory, step: float) -> None:
    """Raise SimulationError if a body ran away (``check_runaway``), any sample is NaN/inf (a divergence) or a line
    is over-stretched (``check_line_strains``)."""
    arrays = [raw.time] + [a for b in raw.bodies.values() for a in b.values()] \
        + [a for c in raw.confluences.values() for a in c.values()] + list(raw.tensions.values())
    bad_rows = np.zeros(len(raw.time), dtype=bool)
    for array in arrays:
        bad_rows |= ~np.isfinite(array.reshape(len(raw.time), -1)).all(axis=1)
    check_runaway(case, raw, np.argmax(bad_rows) if bad_rows.any() else len(raw.time))
    if bad_rows.any():
        t = raw.time[np.argmax(bad_rows)]
        raise SimulationError(f"the state became NaN or infinite at t = {t:.4f} s: the integration diverged; "
                              f"try a smaller step than {step:g} s", float(t))
    for system in case.systems.values():
        if system.name in raw.confluences:
            check_line_strains(case, raw, system.with_bodies(raw.bodies))   # without canopies not in this phase


def check_line_strains(case: Case, raw: RawHistory, system) -> None:
    """Raise SimulationError at the first sample where a line of ``system`` is over-stretched: beyond its material's
    breaking strain (a line with ``material``: it broke), else beyond (1 + MAX_LINE_STRAIN) times its free length.
    The message starts with the line's name and gives the system, the time, the strain, the limit and the tension."""
    positions, _ = attach_points(case, raw, system, velocities=False)
    length = np.linalg.norm(positions - raw.confluences[system.name]["position"][:, None, :], axis=-1)
    free = np.array([line.free_length for line in system.lines])
    limits = np.array([MAX_LINE_STRAIN if line.rating is None else line.rating.breaking_strain
                       for line in system.lines])
    beyond = (length - free) / free > limits
    if not beyond.any():
        return
    row, col = np.unravel_index(np.argmax(beyond), beyond.shape)
    line = system.lines[col]
    tension = raw.tensions.get((system.name, line.name))
    raise SimulationError(over_stretch_message(case.line_label(system, line), system.name, line,
                                               float(raw.time[row]), float(length[row, col] / free[col] - 1.0),
                                               None if tension is None else float(tension[row])),
                          float(raw.time[row]))


def over_stretch_message(label: str, system: str, line, time: float, strain: float, tension: float | None) -> str:
    """What a run that over-stretched ``line`` says: the line, its system, the time (s), the strain reached, the
    limit and the tension (N; None: not sampled)."""
    pulled = "" if tension is None else f", tension {tension:.6g} N"
    rating = line.rating
    if rating is not None:
        verb, cause = "broke", "the load exceeds what the line can carry: raise its breaking_strength or lower the load"
        if tension is not None and tension < 0.5 * rating.breaking_strength:   # past its breaking strain at half load
            verb, cause = "stretched past breaking", ("its tension is under half its breaking strength, so the stretch "
                                                      "and the load disagree: a step too long for the line (try a "
                                                      "smaller --dt)")
        return (f"{label} (system {system}) {verb} at t = {time:.4f} s: strain {strain:.2%} beyond the "
                f"{rating.material.name} line's breaking strain {rating.breaking_strain:.2%}{pulled} (breaking "
                f"strength {rating.breaking_strength:.6g} N); {cause}")
    return (f"{label} (system {system}) over-stretched at t = {time:.4f} s: strain {strain:.2%} "
            f"({1.0 + strain:.2f} times its free length), beyond twice its free length (strain "
            f"{MAX_LINE_STRAIN:.0%}){pulled}; no parachute line stretches that far: check its stiffness or "
            "load_elongation, or give its material and breaking_strength; with lines that are right, the step may "
            "be too long for them (try a smaller --dt)")


def check_runaway(case: Case, raw: RawHistory, rows: int) -> None:
    """Raise SimulationError naming the first body whose sampled speed or angular rate, in the first ``rows``
    samples, is beyond the case's limits (``Case.runaway_limits``: a body without aerodynamics, which the per-stage
    check does not see)."""
    limits, first = case.runaway_limits, None
    for name, body in raw.bodies.items():
        for quantity, values, limit in (("speed", body["velocity"], limits.speed),
                                        ("rate", body["angular_velocity"], limits.rate(name))):
            beyond = np.flatnonzero(np.linalg.norm(values[:rows], axis=1) > limit)
            if len(beyond) and (first is None or beyond[0] < first[0]):
                first = (beyond[0], name, quantity, float(np.linalg.norm(values[beyond[0]])))
    if first is not None:
        row, name, quantity, value = first
        raise SimulationError(limits.message(name, quantity, value, float(raw.time[row])), float(raw.time[row]))


def _point_columns(case: Case, owner: str, time, position, velocity, columns: dict, places: dict) -> None:
    """A point's POINT_TEMPLATES columns into ``columns``; its latitude and longitude (GEODETIC_TEMPLATES, an
    ellipsoidal planet only) into ``places``, which ``derive_columns`` puts after every other column."""
    start, planet = case.start, case.start.planet
    fixed = start.to_planet_fixed(position, time)
    ground_velocity = start.velocity_to_planet_fixed(position, velocity, time)
    if isinstance(planet, FlatPlanet):
        altitude = start.altitude(position)
    else:   # one geodetic pass gives the altitude (StartFrame.altitude's own) and the place
        latitude, longitude, altitude = planet.geodetic(start.to_planet(position))
        if planet.rotation_rate != 0.0:
            # where it is over the turning planet: the position relative to the ground in planet-fixed axes (they
            # coincide with the start's inertial ones at t = 0)
            latitude, longitude, _ = planet.geodetic(start.to_planet(fixed))
        for template, value in zip(GEODETIC_TEMPLATES, (latitude, longitude)):
            places[column(template, owner)] = value
    values = (altitude, altitude - case.simulation.ground_altitude, fixed[:, 0], fixed[:, 1], ground_velocity[:, 1],
              ground_velocity[:, 0], -ground_velocity[:, 2])
    for template, value in zip(POINT_TEMPLATES, values):
        columns[column(template, owner)] = value


def derive_columns(case: Case, raw: RawHistory, history: bool = True) -> tuple[dict, dict]:
    """Named time histories and their units (``registries.columns``) from an engine run; see the module docstring for
    the names. ``history=False`` (a run whose history nobody keeps: a study's) leaves out what the summary never reads:
    each aerodynamic body's air-relative columns (angles of attack, dynamic pressure, Mach number, wind and
    turbulence at its centre), the bodies' attitude angles, the other bodies' point columns and every relative
    column."""
    columns: dict = {column("time"): raw.time}
    places: dict = {}
    order = [case.vehicle] + [name for name in case.bodies if name != case.vehicle]
    for name in order if history else [case.vehicle]:
        body = raw.bodies[name]
        _point_columns(case, name, raw.time, body["position"], body["velocity"], columns, places)
        if history:
            _attitude_columns(case, name, raw, columns)
    for system in case.systems.values():
        if system.name in raw.confluences:
            point = raw.confluences[system.name]
            label = case.confluence_label(system)
            _point_columns(case, label, raw.time, point["position"], point["velocity"], columns, places)
            if history and not case.bodies[case.vehicle].fixed:
                _relative_columns(label, raw.bodies[case.vehicle], point["position"], point["velocity"], columns)
    for system in case.systems.values():
        for line in system.lines:
            columns[column("tension_{owner}", case.line_label(system, line))] = raw.tensions[(system.name, line.name)]
    for key, value in raw.method.items():
        name = key.column if isinstance(key, ColumnChannel) else method_column(key.name, key.system,
                                                                                len(case.systems))
        columns[name] = value
    columns.update(places)   # after the others (``places_last`` moves them behind the columns made later)
    return columns, units_of(columns)


def places_last(*tables: dict) -> None:
    """Move the latitude and longitude columns (GEODETIC_TEMPLATES) after every other in each of ``tables`` (the
    columns and their units, once every column is made): the columns a run wrote before them keep their places."""
    for table in tables:
        for name in [n for n in table if any(column_owner(n, t) is not None for t in GEODETIC_TEMPLATES)]:
            table[name] = table.pop(name)


def units_of(columns) -> dict:
    """The unit of each column (``registries.columns``); a column the registry does not know is a programming error."""
    units = {}
    for name in columns:
        units[name] = unit(name)
        if units[name] is None:
            raise KeyError(f"output column {name!r} has no record in pchute_exudyn.registries.columns")
    return units


def _attitude_columns(case: Case, name: str, raw: RawHistory, columns: dict) -> None:
    """A body's attitude angles and rates, its air-relative columns (an aerodynamic body) and its position and
    velocity relative to the vehicle (a moving body other than the vehicle)."""
    body = raw.bodies[name]
    yaw, pitch, roll = attitude_angles_deg(body["rotation"])
    for template, value in (("{owner}_yaw_deg", yaw), ("{owner}_pitch_deg", pitch), ("{owner}_roll_deg", roll),
                            ("{owner}_tilt_deg", tilt_deg(body["rotation"]))):
        columns[column(template, name)] = value
    for i, template in enumerate(("{owner}_rate_x", "{owner}_rate_y", "{owner}_rate_z")):
        columns[column(template, name)] = body["angular_velocity"][:, i]
    aero = case.bodies[name].aerodynamics
    if aero is not None and aero.enabled:
        total, alpha, beta, pressure, mach, wind, turbulence = _aero_columns(case, body, aero.center, raw.time)
        for template, value in (("{owner}_angle_of_attack_deg", total), ("{owner}_alpha_deg", alpha),
                                ("{owner}_beta_deg", beta), ("{owner}_dynamic_pressure", pressure),
                                ("{owner}_mach", mach)):
            if value is not None:
                columns[column(template, name)] = value
        if wind is not None:   # the air's motion at the aerodynamic centre, relative to the ground
            for templates, value in ((("{owner}_wind_east", "{owner}_wind_north", "{owner}_wind_up"), wind),
                                     (("{owner}_turbulence_east", "{owner}_turbulence_north",
                                       "{owner}_turbulence_up"), turbulence)):
                for i, template in enumerate(templates):
                    columns[column(template, name)] = value[:, i]
    if name != case.vehicle and not case.bodies[name].fixed and not case.bodies[case.vehicle].fixed:
        _relative_columns(name, raw.bodies[case.vehicle], body["position"], body["velocity"], columns)
    for entry in derived("body"):   # the registry's columns that say how they are computed
        columns[entry.name(name)] = entry.derive(body)


def _aero_columns(case: Case, body: dict, center, time):
    """Total angle of attack, aerodynamic angles alpha and beta (deg), dynamic pressure (Pa) and Mach number (-; None
    when the atmosphere has no speed of sound) from the velocity of the aerodynamic centre relative to the air
    (planet rotation and wind); NaN where the body is absent. With a moving air mass also the steady wind plus gusts
    and the turbulence there ((n, 3) east, north, up in m/s, relative to the ground), else None for both."""
    rotation = body["rotation"]
    position, velocity = body_point(body["position"], rotation, body["velocity"], body["angular_velocity"], center)
    air = case.air_motion()
    n = len(time)
    alpha, beta, total, pressure = (np.full(n, np.nan) for _ in range(4))
    atmosphere = case.atmosphere
    mach = np.full(n, np.nan) if atmosphere.has_speed_of_sound else None
    present = np.flatnonzero(np.isfinite(position).all(axis=1))
    altitudes = np.full(n, np.nan)
    altitudes[present] = case.start.altitude(position[present])   # vectorised geodetic
    wind, turbulence = air.local_history(altitudes, time) if air.moving else (None, None)
    relatives = air.relative(position, velocity, altitudes, time)
    angles_of_attack_deg(relatives, np.ascontiguousarray(rotation), present, total)
    # body axes and speed sample by sample as one matrix product each (numpy calls BLAS per sample either way)
    relative = relatives[present]
    u, v, w = np.matmul(rotation[present].transpose(0, 2, 1), relative[:, :, None])[:, :, 0].T
    speed = np.sqrt(np.matmul(relative[:, None, :], relative[:, :, None])[:, 0, 0])
    alpha[present] = np.degrees(np.arctan2(w, u))
    with np.errstate(invalid="ignore", divide="ignore"):
        beta[present] = np.where(speed > 0, np.degrees(np.arcsin(np.clip(v / speed, -1.0, 1.0))), 0.0)
    density, sound = atmosphere.states(altitudes[present])   # one kernel call for all samples
    pressure[present] = dynamic_pressure_of_speed(density, speed)
    if mach is not None:
        mach[present] = mach_number(speed, sound)
    return total, alpha, beta, pressure, mach, wind, turbulence


def _relative_columns(owner: str, vehicle: dict, position, velocity, columns: dict) -> None:
    """Position and velocity of a point relative to the vehicle, in vehicle body axes (m, m/s): the velocity as
    seen from the vehicle, its rotation included."""
    body_arm, body_velocity = relative_to_body(vehicle["position"], vehicle["rotation"], vehicle["velocity"],
                                               vehicle["angular_velocity"], position, velocity)
    positions = ("{owner}_relative_position_x", "{owner}_relative_position_y", "{owner}_relative_position_z")
    velocities = ("{owner}_relative_velocity_x", "{owner}_relative_velocity_y", "{owner}_relative_velocity_z")
    for i, (arm_template, velocity_template) in enumerate(zip(positions, velocities)):
        columns[column(arm_template, owner)] = body_arm[:, i]
        columns[column(velocity_template, owner)] = body_velocity[:, i]


def line_tensions_from_states(case: Case, raw: RawHistory, system) -> np.ndarray:
    """Tensions (n_samples, n_lines) recomputed with ``physics.lines`` from the sampled states (N)."""
    positions, velocities = attach_points(case, raw, system)
    point = raw.confluences[system.name]
    return line_states(positions, velocities, point["position"], point["velocity"],
                       [line.law for line in system.lines]).tension

"""From engine samples to named time histories (pure numpy, no Exudyn), and the checks that a run did not diverge.

Column names (units in ``units``):

* per body ``<b>``: ``<b>_altitude``, ``<b>_east``, ``<b>_north`` (m; east/north along the start point's axes,
  relative to the ground); ``<b>_velocity_north|east|down`` (m/s, relative to the ground, start-point axes);
  ``<b>_yaw_deg|pitch_deg|roll_deg`` (attitude angles, ``physics.rotations``), ``<b>_tilt_deg`` (body +x from
  nadir); ``<b>_rate_x|y|z`` (rad/s, body axes); for aerodynamic bodies ``<b>_angle_of_attack_deg`` and
  ``<b>_dynamic_pressure`` (Pa).
* per confluence (``confluence``, or ``<system>_confluence`` with several systems): altitude, east, north and the
  three velocities as above.
* per line: ``tension_<line>`` (or ``tension_<system>_<line>``), N.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .case.model import Case
from .errors import SimulationError
from .physics.aerodynamics import angle_of_attack_deg
from .physics.lines import line_states
from .physics.rotations import attitude_angles_deg, tilt_deg

MAX_LINE_STRAIN = 1.0
"""A line stretched beyond (1 + MAX_LINE_STRAIN) times its free length means the integration diverged (parachute
lines fail at a few per cent strain); such a run stops with an error instead of returning numbers."""


@dataclass
class RawHistory:
    """Sampled histories from an engine run, in start-frame coordinates (m, m/s, rad/s)."""

    time: np.ndarray
    bodies: dict = field(default_factory=dict)        # name -> {position, velocity, rotation, angular_velocity}
    confluences: dict = field(default_factory=dict)   # system -> {position, velocity}
    tensions: dict = field(default_factory=dict)      # (system, line) -> tension (N)
    extra: dict = field(default_factory=dict)         # column name -> method-specific history
    units: dict = field(default_factory=dict)         # column name -> unit of the extra columns
    steps: int = 0
    wall_time: float = 0.0


def attach_points(case: Case, raw: RawHistory, system) -> tuple[np.ndarray, np.ndarray]:
    """Positions and velocities (n_samples, n_lines, 3) of a system's attach points, from the body histories."""
    positions, velocities = [], []
    for line in system.lines:
        body = raw.bodies[line.body]
        rotation = body["rotation"]
        arm = rotation @ np.asarray(case.bodies[line.body].points[line.point])           # (n, 3)
        omega = np.einsum("nij,nj->ni", rotation, body["angular_velocity"])              # global components
        positions.append(body["position"] + arm)
        velocities.append(body["velocity"] + np.cross(omega, arm))
    return np.stack(positions, axis=1), np.stack(velocities, axis=1)


def check_history(case: Case, raw: RawHistory, step: float) -> None:
    """Raise SimulationError if any sample is NaN/inf or a line is torn (strain > MAX_LINE_STRAIN)."""
    arrays = [raw.time] + [a for b in raw.bodies.values() for a in b.values()] \
        + [a for c in raw.confluences.values() for a in c.values()] + list(raw.tensions.values())
    bad_rows = np.zeros(len(raw.time), dtype=bool)
    for array in arrays:
        bad_rows |= ~np.isfinite(array.reshape(len(raw.time), -1)).all(axis=1)
    if bad_rows.any():
        t = raw.time[np.argmax(bad_rows)]
        raise SimulationError(f"the state became NaN or infinite at t = {t:.4f} s: the integration diverged; "
                              f"try a smaller step than {step:g} s", float(t))
    for system in case.systems.values():
        if system.name not in raw.confluences:
            continue
        positions, _ = attach_points(case, raw, system)
        length = np.linalg.norm(positions - raw.confluences[system.name]["position"][:, None, :], axis=-1)
        free = np.array([line.free_length for line in system.lines])
        strain = (length - free) / free
        if (strain > MAX_LINE_STRAIN).any():
            row, col = np.unravel_index(np.argmax(strain > MAX_LINE_STRAIN), strain.shape)
            line = system.lines[col]
            raise SimulationError(
                f"line {case.line_label(system, line)} reached {length[row, col] / free[col]:.2f} times its free "
                f"length at t = {raw.time[row]:.4f} s: the integration diverged; try a smaller step than {step:g} s",
                float(raw.time[row]))


def _point_columns(case: Case, prefix: str, time, position, velocity, columns: dict, units: dict) -> None:
    fixed = case.start.to_planet_fixed(position, time)
    ground_velocity = case.start.velocity_to_planet_fixed(position, velocity, time)
    for name, value, unit in (
            ("altitude", case.start.altitude(position), "m"),
            ("east", fixed[:, 0], "m"), ("north", fixed[:, 1], "m"),
            ("velocity_north", ground_velocity[:, 1], "m/s"), ("velocity_east", ground_velocity[:, 0], "m/s"),
            ("velocity_down", -ground_velocity[:, 2], "m/s")):
        columns[f"{prefix}_{name}"] = value
        units[f"{prefix}_{name}"] = unit


def derive_columns(case: Case, raw: RawHistory) -> tuple[dict, dict]:
    """Named time histories and their units from an engine run; see the module docstring for the names."""
    columns: dict = {"time": raw.time}
    units: dict = {"time": "s"}
    order = [case.vehicle] + [name for name in case.bodies if name != case.vehicle]
    for name in order:
        body = raw.bodies[name]
        _point_columns(case, name, raw.time, body["position"], body["velocity"], columns, units)
        yaw, pitch, roll = attitude_angles_deg(body["rotation"])
        for key, value in (("yaw_deg", yaw), ("pitch_deg", pitch), ("roll_deg", roll),
                           ("tilt_deg", tilt_deg(body["rotation"]))):
            columns[f"{name}_{key}"] = value
            units[f"{name}_{key}"] = "deg"
        for i, axis in enumerate("xyz"):
            columns[f"{name}_rate_{axis}"] = body["angular_velocity"][:, i]
            units[f"{name}_rate_{axis}"] = "rad/s"
        aero = case.bodies[name].aerodynamics
        if aero is not None and aero.enabled:
            alpha, pressure = _aero_columns(case, body, aero.center, raw.time)
            columns[f"{name}_angle_of_attack_deg"], units[f"{name}_angle_of_attack_deg"] = alpha, "deg"
            columns[f"{name}_dynamic_pressure"], units[f"{name}_dynamic_pressure"] = pressure, "Pa"
    for system in case.systems.values():
        if system.name in raw.confluences:
            point = raw.confluences[system.name]
            _point_columns(case, case.confluence_label(system), raw.time, point["position"], point["velocity"],
                           columns, units)
    for system in case.systems.values():
        for line in system.lines:
            key = f"tension_{case.line_label(system, line)}"
            columns[key] = raw.tensions[(system.name, line.name)]
            units[key] = "N"
    for key, value in raw.extra.items():
        columns[key] = value
        units[key] = raw.units.get(key, "")
    return columns, units


def _aero_columns(case: Case, body: dict, center, time):
    rotation = body["rotation"]
    arm = rotation @ np.asarray(center)
    omega = np.einsum("nij,nj->ni", rotation, body["angular_velocity"])
    position = body["position"] + arm
    velocity = body["velocity"] + np.cross(omega, arm) - np.cross(case.start.rotation_vector,
                                                                  position - case.start.planet_center)
    alpha = np.array([angle_of_attack_deg(v, r[:, 0]) for v, r in zip(velocity, rotation)])
    density = case.atmosphere.density_profile(case.start.altitude(position))
    return alpha, 0.5 * density * np.einsum("ni,ni->n", velocity, velocity)


def line_tensions_from_states(case: Case, raw: RawHistory, system) -> np.ndarray:
    """Tensions (n_samples, n_lines) recomputed with ``physics.lines`` from the sampled states (N)."""
    positions, velocities = attach_points(case, raw, system)
    point = raw.confluences[system.name]
    lines = system.lines
    return line_states(positions, velocities, point["position"], point["velocity"],
                       np.array([l.free_length for l in lines]), np.array([l.stiffness for l in lines]),
                       np.array([l.damping for l in lines])).tension

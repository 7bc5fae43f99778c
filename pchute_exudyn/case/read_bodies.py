"""Readers of ``[bodies.<name>]``: mass, inertia, points, initial state, aerodynamics and apparent mass."""

from __future__ import annotations

import math

import numpy as np

from ..physics.aerodynamics import CoefficientTable, CoefficientTableError
from ..physics.apparent_mass import ApparentMass
from .fields import REQUIRED, Table, check_vector, default_of
from .model import Aerodynamics, Body, InitialState
from .start import CONDITION_KEYS, FlightConditions


def read_initial(t: Table, *, attitude: bool) -> InitialState:
    """``initial`` table: the altitude, position, velocity (and for a body its attitude and rates); a body's start may
    instead be given as flight conditions (``CONDITION_KEYS``; ``_read_conditions``), the altitude then NaN until the
    loader finds it in the atmosphere (``case.start.at_conditions``)."""
    conditions = _read_conditions(t) if attitude and any(key in t.data for key in CONDITION_KEYS) else None
    values = {"altitude": math.nan if conditions is not None else t.number("altitude", "m"), "conditions": conditions}
    for key in ("east", "north"):
        values[key] = t.number(key, "m", default_of(InitialState, key))
    for key in ("velocity_north", "velocity_east", "velocity_down"):
        values[key] = t.number(key, "m/s", default_of(InitialState, key))
    if attitude:
        values["yaw_deg"] = t.number("yaw_deg", "deg", default_of(InitialState, "yaw_deg"), minimum=-180.0,
                                     maximum=180.0)
        values["pitch_deg"] = t.number("pitch_deg", "deg", default_of(InitialState, "pitch_deg"), minimum=-90.0,
                                       maximum=90.0)
        values["roll_deg"] = t.number("roll_deg", "deg", default_of(InitialState, "roll_deg"), minimum=-180.0,
                                      maximum=180.0)
        for key in ("rate_x", "rate_y", "rate_z"):
            values[key] = t.number(key, "rad/s", default_of(InitialState, key))
    t.finish()
    return InitialState(**values)


def _read_conditions(t: Table) -> FlightConditions:
    """The flight-condition keys of an ``initial`` table (all four together; none of the altitude and velocity keys
    they replace)."""
    missing = [key for key in CONDITION_KEYS if key not in t.data]
    if missing:
        given = ", ".join(key for key in CONDITION_KEYS if key in t.data)
        raise t.error(missing[0], f"required with {given}: a start given as flight conditions needs "
                                  f"{', '.join(CONDITION_KEYS)} together")
    replaced = [key for key in ("altitude", "velocity_north", "velocity_east", "velocity_down") if key in t.data]
    if replaced:
        raise t.error(replaced[0], "give either altitude and the velocity_* keys or the flight conditions "
                                   f"({', '.join(CONDITION_KEYS)}), not both", t.data[replaced[0]])
    return FlightConditions(t.number("mach", "", above=0.0), t.number("dynamic_pressure", "Pa", above=0.0),
                            t.number("flight_path_deg", "deg", minimum=-90.0, maximum=90.0),
                            t.number("heading_deg", "deg", minimum=-360.0, maximum=360.0))


def _read_inertia(t: Table) -> np.ndarray:
    value = t.raw("inertia", REQUIRED, "kg m^2")
    error = lambda m: t.error("inertia", m, value)  # noqa: E731
    if isinstance(value, list) and len(value) == 3 and all(isinstance(v, list) for v in value):
        matrix = np.array([check_vector(row, "kg m^2", 3, error) for row in value])
        if not np.allclose(matrix, matrix.T, rtol=1e-9, atol=1e-9 * np.abs(matrix).max()):
            raise error("an inertia matrix must be symmetric")
    elif isinstance(value, list) and len(value) == 3:
        matrix = np.diag(check_vector(value, "kg m^2", 3, error))
    else:
        raise error("must be [Ixx, Iyy, Izz] (principal moments, kg m^2) or a symmetric 3x3 matrix")
    moments = np.linalg.eigvalsh(matrix)
    if moments[0] <= 0.0:
        raise error("must be positive definite (all principal moments > 0 kg m^2)")
    if moments[0] + moments[1] < moments[2] * (1.0 - 1e-9):
        raise error(f"is not a rigid body's: principal moments {moments.round(6).tolist()} break I1 + I2 >= I3")
    return matrix


MOMENTS = ("moment_coefficient", "pitch_damping", "roll_damping")
"""The coefficients that need a body's reference length."""


def _read_aerodynamics(t: Table) -> Aerodynamics:
    area = t.number("reference_area", "m^2", above=0.0)
    center = t.vector("center", "m")
    enabled = t.boolean("enabled", default_of(Aerodynamics, "enabled"))
    axial = _read_coefficient(t, "axial_coefficient", minimum=0.0)
    normal = _read_coefficient(t, "normal_coefficient", default=0.0)
    moments = {key: _read_coefficient(t, key, default=None) for key in MOMENTS}
    length = t.number("reference_length", "m", None, above=0.0)
    given = [key for key, value in moments.items() if value is not None]
    if given and length is None:
        raise t.error("reference_length", f"required (m): the {given[0]} is per unit of it")
    t.finish()
    return Aerodynamics(area, axial, normal, center, enabled, *moments.values(), length)


def _read_coefficient(t: Table, key: str, default=REQUIRED, minimum: float | None = None):
    """A coefficient (-): a number (at least ``minimum``) or a table ``{ alpha_deg = [...], value = [...] }`` over the
    angle of attack (deg), ``{ mach = [...], value = [...] }`` over Mach number, or both with ``value`` one row per
    Mach number (``physics.aerodynamics.CoefficientTable``); ``default`` (a number, or None for none) when absent."""
    if key not in t.data:
        t.raw(key, default, "")
        return None if default is None else CoefficientTable.constant(default)
    raw = t.data[key]
    if not isinstance(raw, dict):
        return CoefficientTable.constant(t.number(key, "", minimum=minimum))
    table = t.table(key)
    mach = table.raw("mach", [], "")
    angles = table.raw("alpha_deg", [], "deg")
    value = table.raw("value", REQUIRED, "")
    table.finish()
    for name, axis in (("mach", mach), ("alpha_deg", angles)):
        if not isinstance(axis, list):
            raise table.error(name, "must be a list of numbers", axis)
    if not mach and not angles:
        raise table.error("value", "a table needs alpha_deg, mach or both (a constant is a plain number)", value)
    try:
        return CoefficientTable(tuple(angles), value, tuple(mach))
    except CoefficientTableError as exc:
        raise table.error(exc.field, str(exc), exc.value) from None


def read_body(name: str, t: Table) -> Body:
    fixed = t.boolean("fixed", default_of(Body, "fixed"))
    includes_packed = t.boolean("mass_includes_packed", default_of(Body, "mass_includes_packed"))
    if fixed:
        for key in ("mass", "inertia", "aerodynamics"):
            t.allowed.append(key)
            if key in t.data:
                raise t.error(key, "a fixed body (fixed = true) has no mass, inertia or aerodynamics")
        mass, inertia = None, None
    else:
        mass = t.number("mass", "kg", above=0.0)
        inertia = _read_inertia(t)
    points = {}
    table = t.table("points", None)
    if table is not None:
        for point in list(table.data):
            points[point] = table.vector(point, "m")
        table.finish()
    initial_table = t.table("initial", None)   # absent only for a canopy placed at deployment (checked later)
    initial = read_initial(initial_table, attitude=True) if initial_table is not None else None
    moving = [key for key in ("velocity_north", "velocity_east", "velocity_down", "rate_x", "rate_y", "rate_z")
              if initial is not None and getattr(initial, key) != 0.0]
    if fixed and moving:
        raise initial_table.error(moving[0], "a fixed body cannot move: its velocities and rates must be 0",
                                  getattr(initial, moving[0]))
    aero_table = None if fixed else t.table("aerodynamics", None)
    aero = _read_aerodynamics(aero_table) if aero_table is not None else None
    apparent_table = None if fixed else t.table("apparent_mass", None)
    apparent = _read_apparent_mass(apparent_table) if apparent_table is not None else None
    if apparent is not None and (aero is None or not aero.enabled):
        raise t.error("apparent_mass", "needs the body's aerodynamics (its centre gives the air density)")
    t.finish()
    return Body(name, mass, inertia, points, initial, aero, fixed, apparent, includes_packed)


def _read_apparent_mass(t: Table) -> ApparentMass | None:
    """``[bodies.<name>.apparent_mass]``; None when switched off (``enabled = false``)."""
    enabled = t.boolean("enabled", True)
    values = (t.number("projected_radius", "m", above=0.0), t.number("axial", "", minimum=0.0),
              t.number("lateral", "", minimum=0.0), t.number("rotational", "", minimum=0.0))
    t.finish()
    return ApparentMass(*values) if enabled else None

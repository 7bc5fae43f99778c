"""Body aerodynamics: coefficients over Mach number and angle of attack, the force at the aerodynamic centre and the
moments about it (``docs/models/aerodatabase.md``; the constant-coefficient form of ``docs/models/mer.md``).

For the air-relative velocity V of the aerodynamic centre, body +x axis e, body axes x y z and body-axis angular
velocity (p, q, r)::

    qS    = 1/2 rho |V|^2 S f                 f: the drag-area fraction (inflation, reefing), multiplying every
                                              coefficient
    alpha = angle(V, e) in [0, 180] deg       the total angle of attack; a table whose angles end at 90 deg takes
                                              alpha' = min(alpha, 180 - alpha) (a canopy, symmetric fore and aft)
    M     = |V| / a                           Mach number, a the speed of sound there
    V_perp = V - (V.e) e
    F     = -s qS C_A e  -  qS C_N V_perp / |V_perp|                     (the second term 0 when V_perp = 0)
    M_b   = -s qS d C_m (0, -V_z, V_y) / |(V_y, V_z)|                     (body axes; V_y, V_z of V in body axes)
            + qS d (d / (2 |V|)) (C_lp p, C_mq q, C_mq r)
    s     = -1 when V.e < 0 (alpha > 90 deg) and the coefficient is folded (a constant, or a table ending at 90
            deg), else +1: a body symmetric fore and aft flying backwards is the same body flying forwards turned
            round, so its axial force opposes the axial airspeed and F.V = -qS (C_A |V.e| + C_N |V_perp|) <= 0
            for C_A, C_N >= 0 at every attitude. A table to 180 deg is the body-axis data as given (a capsule's
            C_A < 0 apex forward).

C_A, C_N, C_m and the damping derivatives C_mq (= C_mq + C_malphadot, per radian) and C_lp are each a constant or a
table over (Mach, alpha), linear in each (bilinear) and held at the edges. C_m is about the aerodynamic centre, the
point the force acts at, with the reference length d; C_m > 0 turns e away from V (raises alpha: nose up), so
C_malpha < 0 is statically stable, and C_mq < 0, C_lp < 0 damp. An axisymmetric model: the moment at alpha = 0 has
no direction and is zero.

The per-stage form (``aerodynamics_stage``, with ``air``, ``atmosphere`` and ``planet``) is compiled; Python callers
(``aerodynamic_force``, the engine's single evaluations) use the same kernels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .air import air_velocity
from .atmosphere import atmosphere_state
from .compiled import kernel
from .interpolation import bracket_packed
from .invalid import InvalidField
from .kinematics import BODY_RATE_AT, POINT_COLUMNS, ROTATION_AT, add_point_force, point_motion
from .planet import start_altitude
from .runaway import RUNAWAY
from .wind import GUST_COLUMNS


class CoefficientTableError(InvalidField):
    """An invalid coefficient table; ``field`` is its key (``mach``, ``alpha_deg`` or ``value``)."""


@dataclass(frozen=True)
class CoefficientTable:
    """An aerodynamic coefficient (-) over the angle of attack (deg) and Mach number, linear in each and held beyond
    the ends.

    Parameters
    ----------
    angle_deg : tuple of float
        Angle breakpoints (deg), strictly increasing from 0 to 90 (the folded alpha', for bodies symmetric fore and
        aft) or to 180 (the total alpha); empty: constant in the angle.
    value : tuple
        The coefficient: one value per angle (no Mach axis), one row of them per Mach number, or a single value.
    mach : tuple of float
        Mach breakpoints (-), strictly increasing from >= 0; empty: constant in Mach.
    """

    angle_deg: tuple
    value: tuple
    mach: tuple = ()
    packed: tuple = field(default=(), init=False, repr=False, compare=False)

    def __post_init__(self):
        angles = _axis(self.angle_deg, "alpha_deg")
        machs = _axis(self.mach, "mach")
        if angles:
            _check(len(angles) >= 2 and angles[0] == 0.0 and angles[-1] in (90.0, 180.0)
                   and all(b > a for a, b in zip(angles, angles[1:])), "alpha_deg", list(angles),
                   "must increase strictly from 0 to 90 deg (the folded alpha') or to 180 deg (the total alpha)")
        if machs:
            _check(len(machs) >= 2 and machs[0] >= 0.0 and all(b > a for a, b in zip(machs, machs[1:])), "mach",
                   list(machs), "must increase strictly from >= 0 (at least two Mach numbers)")
        grid = _grid(self.value, angles, machs)
        object.__setattr__(self, "angle_deg", angles)
        object.__setattr__(self, "mach", machs)
        object.__setattr__(self, "value", (tuple(tuple(row) for row in grid) if machs and angles else
                                           tuple(values[0] for values in grid) if machs else
                                           tuple(grid[0]) if angles else grid[0][0]))
        total = 1.0 if angles and angles[-1] == 180.0 else 0.0
        packed = ([float(len(machs) or 1), float(len(angles) or 1), total] + list(machs or (0.0,))
                  + list(angles or (0.0,)) + [v for row in grid for v in row])
        object.__setattr__(self, "packed", tuple(packed))

    @classmethod
    def constant(cls, value: float) -> CoefficientTable:
        """A coefficient that is the same at every angle and Mach number."""
        return cls((), float(value))

    @property
    def uses_mach(self) -> bool:
        """Whether the coefficient changes with Mach number."""
        return bool(self.mach)

    def __call__(self, angle_deg: float, mach: float = 0.0) -> float:
        """The coefficient at the total angle of attack ``angle_deg`` (deg; folded here when the table is) and Mach
        number ``mach``."""
        return coefficient(np.array(self.packed), 0, float(mach), float(angle_deg))


def _check(condition: bool, key: str, value, message: str) -> None:
    if not condition:
        raise CoefficientTableError(key, value, message)


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _axis(values, key: str) -> tuple:
    """A table's breakpoints as floats; CoefficientTableError unless finite numbers."""
    values = tuple(values)
    _check(all(_number(v) for v in values), key, list(values), "must be finite numbers")
    return tuple(float(v) for v in values)


def _grid(value, angles: tuple, machs: tuple) -> list:
    """The values as rows, one per Mach number (one row without a Mach axis), of one value per angle (one without
    an angle axis); CoefficientTableError for a ragged or non-finite table."""
    if machs and angles:
        rows = value if isinstance(value, (tuple, list)) else None
        shape = f"{len(machs)} rows (one per Mach number) of {len(angles)} numbers (one per angle)"
        _check(rows is not None and len(rows) == len(machs)
               and all(isinstance(r, (tuple, list)) and len(r) == len(angles) for r in rows), "value", value,
               f"must be {shape}")
    elif machs or angles:
        width = len(machs) or len(angles)
        _check(isinstance(value, (tuple, list)) and len(value) == width, "value", value,
               f"must be {width} numbers, one per {'Mach number' if machs else 'angle'}")
        rows = [[v] for v in value] if machs else [value]
    else:
        rows = [[value]]
    _check(all(_number(v) for row in rows for v in row), "value", value, "must be finite numbers")
    return [[float(v) for v in row] for row in rows]


@kernel
def _row_value(tables, start, n, angle_index, weight, row):
    """Row ``row`` of a packed table's values (n per row from ``start``) at the angle bracket (index, weight)."""
    values = start + row * n
    if n == 1:
        return tables[values]
    return tables[values + angle_index - 1] + weight * (tables[values + angle_index] - tables[values + angle_index - 1])


@kernel
def folded(tables, offset):
    """Whether the packed table at ``offset`` is over the folded angle (a table ending at 90 deg, or a constant): a
    body symmetric fore and aft, whose loads flying backwards (alpha > 90 deg) are those at 180 - alpha turned
    round with it."""
    return tables[offset + 2] == 0.0


@kernel
def coefficient(tables, offset, mach, alpha_deg):
    """The packed coefficient table at ``offset`` in ``tables`` (``CoefficientTable.packed``: Mach count, angle
    count, 1 for the total angle, the Mach numbers, the angles, the values row by row) at ``mach`` and the total angle
    of attack ``alpha_deg`` (deg)."""
    machs, angles, total = int(tables[offset]), int(tables[offset + 1]), tables[offset + 2]
    mach_start = offset + 3
    angle_start = mach_start + machs
    value_start = angle_start + angles
    angle = alpha_deg if total > 0.0 else min(alpha_deg, 180.0 - alpha_deg)
    i, w = (1, 0.0) if angles == 1 else bracket_packed(tables, angle_start, angles, angle)
    if machs == 1:
        return _row_value(tables, value_start, angles, i, w, 0)
    j, u = bracket_packed(tables, mach_start, machs, mach)
    low = _row_value(tables, value_start, angles, i, w, j - 1)
    high = _row_value(tables, value_start, angles, i, w, j)
    return low + u * (high - low)


LOAD_COLUMNS = 11
"""A body's aerodynamics for the kernels (``pack_body``): reference area S (m^2), reference length d (m), the
offsets in the packed tables of C_A, C_N, C_m, C_mq, C_lp (-1: none), the cluster drag efficiency multiplying C_A
(-), 1 when a coefficient depends on Mach, and the start-frame speed (m/s) and angular rate (rad/s) beyond which the
body has run away (``physics.runaway``)."""
(AREA, LENGTH, AXIAL, NORMAL, MOMENT, PITCH_DAMPING, ROLL_DAMPING, EFFICIENCY, USES_MACH, SPEED_LIMIT,
 RATE_LIMIT) = range(LOAD_COLUMNS)
TABLE_OFFSET_COLUMNS = range(AXIAL, ROLL_DAMPING + 1)
"""The columns of LOAD_COLUMNS that hold a coefficient's table offset (-1: none)."""
VALUE_COLUMNS = 9
"""Per body and stage (``aerodynamics_stage``): force (N, start frame), moment (N m, body axes), dynamic pressure
1/2 rho V^2 (Pa), Mach number (-; NaN when no coefficient needs it), total angle of attack (deg)."""
VALUE_FORCE, VALUE_MOMENT, VALUE_PRESSURE, VALUE_MACH, VALUE_ALPHA = 0, 3, 6, 7, 8
"""Where each of those values starts in a body's VALUE_COLUMNS."""


@kernel
def aerodynamic_load(tables, body, vx, vy, vz, rotation, rates, density, sound, fraction):
    """Force (N, start frame) and moment (N m, body axes) on a body, with the Mach number and the total angle of
    attack (deg), for the air-relative velocity (vx, vy, vz) (m/s, start frame) of its aerodynamic centre, its
    attitude ``rotation`` (9, row-major body -> start frame), body-axis ``rates`` (rad/s), the air's ``density``
    (kg/m^3) and speed of ``sound`` (m/s) and the drag-area ``fraction`` (-); ``body`` is its row of LOAD_COLUMNS.
    Returns (fx, fy, fz, mx, my, mz, mach, alpha)."""
    ex, ey, ez = rotation[0], rotation[3], rotation[6]
    speed2 = vx * vx + vy * vy + vz * vz
    if speed2 == 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    qs = dynamic_pressure(density, speed2) * body[AREA] * fraction
    along = vx * ex + vy * ey + vz * ez
    px, py, pz = vx - along * ex, vy - along * ey, vz - along * ez
    perp = math.sqrt(px * px + py * py + pz * pz)
    alpha = math.degrees(math.atan2(perp, along))
    mach = math.sqrt(speed2) / sound if body[USES_MACH] > 0.0 else math.nan   # ``mach_number`` (kernel form)
    look_up = 0.0 if body[USES_MACH] == 0.0 else mach
    axial = coefficient(tables, int(body[AXIAL]), look_up, alpha)
    if body[EFFICIENCY] != 1.0:
        axial = axial * body[EFFICIENCY]
    fa = -qs * axial
    if along < 0.0 and folded(tables, int(body[AXIAL])):   # flying backwards: the same body turned round
        fa = -fa
    if perp == 0.0:
        fx, fy, fz = fa * ex, fa * ey, fa * ez
    else:
        fn = -qs * coefficient(tables, int(body[NORMAL]), look_up, alpha) / perp
        fx, fy, fz = fa * ex + fn * px, fa * ey + fn * py, fa * ez + fn * pz
    mx = my = mz = 0.0
    d = body[LENGTH]
    if body[MOMENT] >= 0.0:
        by = rotation[1] * vx + rotation[4] * vy + rotation[7] * vz   # V in body axes (y, z): R^T V
        bz = rotation[2] * vx + rotation[5] * vy + rotation[8] * vz
        cross = math.sqrt(by * by + bz * bz)
        if cross > 0.0:
            moment = -qs * d * coefficient(tables, int(body[MOMENT]), look_up, alpha) / cross
            if along < 0.0 and folded(tables, int(body[MOMENT])):   # turned round, it turns the other way
                moment = -moment
            my, mz = -moment * bz, moment * by
    if body[PITCH_DAMPING] >= 0.0 or body[ROLL_DAMPING] >= 0.0:
        damping = qs * d * d / (2.0 * math.sqrt(speed2))
        if body[ROLL_DAMPING] >= 0.0:
            mx += damping * coefficient(tables, int(body[ROLL_DAMPING]), look_up, alpha) * rates[0]
        if body[PITCH_DAMPING] >= 0.0:
            pitch = damping * coefficient(tables, int(body[PITCH_DAMPING]), look_up, alpha)
            my += pitch * rates[1]
            mz += pitch * rates[2]
    return fx, fy, fz, mx, my, mz, mach, alpha


@kernel
def dynamic_pressure(density, speed_squared):
    """q = 1/2 rho V^2 (Pa) from the air's ``density`` (kg/m^3) and the air-relative speed squared (m^2/s^2): the
    one formula of every dynamic pressure (``dynamic_pressure_of_speed`` from a speed)."""
    return 0.5 * density * speed_squared


def dynamic_pressure_of_speed(density, speed):
    """q = 1/2 rho V V (Pa) from the air-relative ``speed`` (m/s; a float or an array), as the sensed values and the
    output columns have always rounded it (the half density times V, times V)."""
    return 0.5 * density * speed * speed


def mach_number(speed, sound):
    """M = V / a (-) from the air-relative ``speed`` and the speed of ``sound`` (m/s; floats or arrays)."""
    return speed / sound


OUTSIDE, FIELD = 1.0, 2.0
"""Status codes of ``centre_load`` and ``aerodynamics_stage``: an aerodynamic centre outside the atmosphere (the
value: its altitude, m), the turbulence field too short (the value: the cells it needs); and ``aerodynamics_stage``'s
``physics.runaway.RUNAWAY``."""


@kernel
def ran_away(body, vx, vy, vz, rates):
    """Whether a body (its LOAD_COLUMNS row) whose aerodynamic centre moves at (vx, vy, vz) (m/s, start frame) and
    turns at body-axis ``rates`` (rad/s) is beyond its limits: checked before the air is looked up, so that a
    runaway is named before it leaves the atmosphere."""
    speed_limit, rate_limit = body[SPEED_LIMIT], body[RATE_LIMIT]
    return (vx * vx + vy * vy + vz * vz > speed_limit * speed_limit
            or rates[0] * rates[0] + rates[1] * rates[1] + rates[2] * rates[2] > rate_limit * rate_limit)


@kernel
def air_at(t, x, y, z, frame, atmosphere, air, wind, gusts, turbulence, field):
    """The air at start-frame point (x, y, z) (m) at time ``t`` (s): (status, value, density in kg/m^3, speed of
    sound in m/s, its velocity in m/s, start frame); status 0, or OUTSIDE (value: the altitude, m) or FIELD (value:
    the turbulence cells needed). The planet ``frame``, ``atmosphere`` and air packed as STAGE_PARTS."""
    h = start_altitude(frame, x, y, z)
    density, sound, outside = atmosphere_state(atmosphere, h)
    if outside != 0.0:
        return OUTSIDE, h, 0.0, 0.0, 0.0, 0.0, 0.0
    if air[0] == 0.0 and air[2] == 0.0:   # still air on a planet that does not turn
        return 0.0, 0.0, density, sound, 0.0, 0.0, 0.0
    ux, uy, uz, needed = air_velocity(air, wind, gusts, turbulence, field, x, y, z, h, t)
    if needed:
        return FIELD, float(needed), 0.0, 0.0, 0.0, 0.0, 0.0
    return 0.0, 0.0, density, sound, ux, uy, uz


@kernel
def centre_load(t, x, y, z, vx, vy, vz, rotation, rates, body, tables, fraction, frame, atmosphere, air, wind, gusts,
                turbulence, field):
    """A body's aerodynamic load at time ``t`` (s) for its aerodynamic centre at start-frame (x, y, z) (m) moving
    at (vx, vy, vz) (m/s, inertial), its attitude ``rotation`` (9) and body-axis ``rates`` (rad/s): ``air_at``, then
    ``aerodynamic_load``. ``body``: its LOAD_COLUMNS row. Returns (status, value, fx, fy, fz, mx, my, mz, dynamic
    pressure in Pa, mach, alpha in deg); status 0, or ``air_at``'s problem with its value (the load then zero)."""
    code, value, density, sound, ux, uy, uz = air_at(t, x, y, z, frame, atmosphere, air, wind, gusts, turbulence,
                                                     field)
    if code != 0.0:
        return code, value, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    vx, vy, vz = vx - ux, vy - uy, vz - uz
    fx, fy, fz, mx, my, mz, mach, alpha = aerodynamic_load(tables, body, vx, vy, vz, rotation, rates, density, sound,
                                                           fraction)
    return 0.0, 0.0, fx, fy, fz, mx, my, mz, dynamic_pressure(density, vx * vx + vy * vy + vz * vz), mach, alpha


STAGE_PARTS = ("points", "bodies", "tables", "frame", "atmosphere", "air", "wind", "gusts", "turbulence")
"""The constant inputs of ``aerodynamics_stage``, laid end to end in one array by ``pack_stage`` after a header of
(body count, gust count, the parts' starts and the end): one array crosses into the kernel instead of nine (an array
argument costs about 55 ns a call). ``points``: rows of ``physics.kinematics.POINT_COLUMNS`` (the aerodynamic
centres), ``bodies``: rows of LOAD_COLUMNS, ``tables``: ``pack_tables``, then the packed planet frame
(``physics.planet.FRAME_COLUMNS``), atmosphere and air (``physics.air.AirMotion``'s parts)."""
_HEADER = 2 + len(STAGE_PARTS) + 1


def pack_stage(**parts) -> np.ndarray:
    """The ``STAGE_PARTS`` (keyword arguments) in one array for ``aerodynamics_stage``."""
    flat = [np.ascontiguousarray(parts[name], float).ravel() for name in STAGE_PARTS]
    starts = np.cumsum([_HEADER] + [part.size for part in flat])
    return np.concatenate([[float(len(parts["points"])), float(len(parts["gusts"]))], starts.astype(float), *flat])


@kernel
def _part(data, index):
    """Part ``index`` of STAGE_PARTS in ``pack_stage``'s array (flat)."""
    return data[int(data[2 + index]):int(data[3 + index])]


WORK_STATUS, WORK_STATUS_VALUE, WORK_FRACTIONS = 0, 1, 2
"""Where the status code and its value are in ``aerodynamics_stage``'s work array, and where the drag-area fractions
start after them."""
HEADER_BODY_COUNT = 0
"""Where the body count is in ``pack_stage``'s array (0: no aerodynamics)."""

# A fused stage kernel (the model's only confluence doing a stage's kernel work, the aerodynamics' included, in one
# call: ``engine.stage.Stage``) returns the sum of these flags (0: neither)
STAGE_SETTLED = 1.0
"""It did the last step's deferred end-of-step work."""
STAGE_AERODYNAMICS_FAILED = 2.0
"""The aerodynamics met a problem and added nothing (nor the gravity): the caller mends and adds them."""


def work_size(count: int) -> int:
    """The length of ``aerodynamics_stage``'s work array for ``count`` bodies: the status (code, value), the
    drag-area fractions (-), then VALUE_COLUMNS per body."""
    return WORK_FRACTIONS + count * (1 + VALUE_COLUMNS)


@kernel
def aerodynamics_stage(t, states, data, field, work, generalized):
    """Every body's aerodynamic load at one solver stage, added to ``generalized``: the force at each aerodynamic
    centre and the moment (body axes), for the stage's body ``states`` at time ``t`` (s); ``data`` the packed
    STAGE_PARTS (``pack_stage``), ``field`` the turbulence's field so far, ``work`` (``work_size``) the drag-area
    fractions in, each body's values out. On a problem the status gets (code, value) (OUTSIDE, FIELD) and nothing is
    added to ``generalized``, so the caller can mend it and call again."""
    count = int(data[0])
    points, bodies, tables = _part(data, 0), _part(data, 1), _part(data, 2)
    frame, atmosphere, air, wind = _part(data, 3), _part(data, 4), _part(data, 5), _part(data, 6)
    gusts, turbulence = _part(data, 7).reshape((int(data[1]), GUST_COLUMNS)), _part(data, 8)
    for j in range(count):
        point = points[j * POINT_COLUMNS:(j + 1) * POINT_COLUMNS]
        row = states[int(point[0])]
        body = bodies[j * LOAD_COLUMNS:(j + 1) * LOAD_COLUMNS]
        x, y, z, vx, vy, vz = point_motion(row, point[1], point[2], point[3])
        rates = row[BODY_RATE_AT:BODY_RATE_AT + 3]
        if ran_away(body, vx, vy, vz, rates):
            work[0], work[1] = RUNAWAY, float(j)
            return
        code, value, density, sound, ux, uy, uz = air_at(t, x, y, z, frame, atmosphere, air, wind, gusts, turbulence,
                                                         field)
        if code != 0.0:
            work[0], work[1] = code, value
            return
        vx, vy, vz = vx - ux, vy - uy, vz - uz
        load = aerodynamic_load(tables, body, vx, vy, vz, row[ROTATION_AT:ROTATION_AT + 9], rates, density, sound,
                                work[WORK_FRACTIONS + j])
        v = WORK_FRACTIONS + count + j * VALUE_COLUMNS
        for c in range(6):
            work[v + c] = load[c]
        pressure = dynamic_pressure(density, vx * vx + vy * vy + vz * vz)
        work[v + VALUE_PRESSURE], work[v + VALUE_MACH], work[v + VALUE_ALPHA] = pressure, load[6], load[7]
    work[0] = 0.0
    for j in range(count):   # after every body, so that a problem adds nothing
        point = points[j * POINT_COLUMNS:(j + 1) * POINT_COLUMNS]
        k = int(point[4])
        if k < 0:   # a fixed body takes no generalized force
            continue
        v = WORK_FRACTIONS + count + j * VALUE_COLUMNS
        add_point_force(states[int(point[0])], point[1], point[2], point[3], work[v], work[v + 1], work[v + 2],
                        generalized, k)
        if work[v + 3] != 0.0 or work[v + 4] != 0.0 or work[v + 5] != 0.0:
            generalized[k + 3] += work[v + 3]
            generalized[k + 4] += work[v + 4]
            generalized[k + 5] += work[v + 5]


def pack_body(area: float, length: float, offsets: dict, efficiency: float = 1.0, uses_mach: bool = False,
              speed_limit: float = math.inf, rate_limit: float = math.inf) -> list:
    """A body's row of LOAD_COLUMNS from its reference area (m^2) and length (m), the packed-table ``offsets`` of
    its coefficients (keys ``axial``, ``normal`` and, when it has them, ``moment``, ``pitch_damping``,
    ``roll_damping``), its cluster drag efficiency (-), whether a coefficient depends on Mach, and its runaway
    limits: speed (m/s) and angular rate (rad/s)."""
    return [area, length, offsets["axial"], offsets["normal"], offsets.get("moment", -1.0),
            offsets.get("pitch_damping", -1.0), offsets.get("roll_damping", -1.0), efficiency,
            1.0 if uses_mach else 0.0, speed_limit, rate_limit]


def pack_tables(tables) -> tuple[np.ndarray, list]:
    """(the packed ``CoefficientTable``s one after another, their offsets)."""
    packed, offsets = [], []
    for table in tables:
        offsets.append(float(len(packed)))
        packed.extend(table.packed)
    return np.array(packed, float), offsets


def angle_of_attack_deg(velocity, axis) -> float:
    """Total angle of attack alpha (deg, in [0, 180]) between velocity ``velocity`` and the body axis ``axis``."""
    return total_angle_deg(*map(float, velocity), *map(float, axis))


@kernel
def total_angle_deg(vx, vy, vz, ex, ey, ez):
    """The angle (deg, in [0, 180]) between the vectors (vx, vy, vz) and (ex, ey, ez): atan2 of the cross
    product's length and the dot product (accurate at every angle)."""
    along = vx * ex + vy * ey + vz * ez
    cx, cy, cz = vy * ez - vz * ey, vz * ex - vx * ez, vx * ey - vy * ex
    return math.degrees(math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), along))


@kernel
def angles_of_attack_deg(velocities, rotations, rows, out):
    """``total_angle_deg`` between each of ``velocities`` (n, 3) and the body x axis of ``rotations`` (n, 3, 3), at
    the sample indices ``rows``, into ``out`` (n,)."""
    for i in rows:
        out[i] = total_angle_deg(velocities[i, 0], velocities[i, 1], velocities[i, 2], rotations[i, 0, 0],
                                 rotations[i, 1, 0], rotations[i, 2, 0])


def aerodynamic_force(velocity, axis, density: float, reference_area: float, axial_coefficient,
                      normal_coefficient: CoefficientTable, area_fraction: float = 1.0, mach: float = 0.0):
    """Aerodynamic force (N) on a body, to be applied at its aerodynamic centre (``aerodynamic_load`` alone, for
    Python callers and tests).

    Parameters
    ----------
    velocity : sequence of 3 float
        Air-relative velocity of the aerodynamic centre (m/s), inertial components.
    axis : sequence of 3 float
        Unit body +x axis, inertial components.
    density : float
        Air density (kg/m^3).
    reference_area : float
        Reference area S (m^2).
    axial_coefficient : float or CoefficientTable
        C_A (-).
    normal_coefficient : CoefficientTable
        C_N (-).
    area_fraction : float
        Fraction of the full drag area in effect (inflation or reefing), multiplying both coefficients (-).
    mach : float
        The Mach number (-) the coefficients are looked up at (the speed of sound is taken as |V| / mach).

    Returns
    -------
    tuple of 3 float
        Force (N), inertial components.
    """
    axial = axial_coefficient if isinstance(axial_coefficient, CoefficientTable) else \
        CoefficientTable.constant(axial_coefficient)
    tables, offsets = pack_tables([axial, normal_coefficient])
    body = np.array(pack_body(reference_area, 0.0, {"axial": offsets[0], "normal": offsets[1]},
                              uses_mach=axial.uses_mach or normal_coefficient.uses_mach))
    ex, ey, ez = axis
    rotation = np.array([ex, 0.0, 0.0, ey, 0.0, 0.0, ez, 0.0, 0.0])   # only body x enters the force
    speed = math.sqrt(sum(v * v for v in velocity))
    sound = speed / mach if mach > 0.0 else 1.0
    load = aerodynamic_load(tables, body, *map(float, velocity), rotation, np.zeros(3), float(density), sound,
                            float(area_fraction))
    return load[0], load[1], load[2]

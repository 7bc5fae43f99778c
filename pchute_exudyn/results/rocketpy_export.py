"""RocketPy's flight export, read as it comes: its one home in this package.

RocketPy 1.13 writes a flight with ``FlightDataExporter(flight).export_data(path, *variables, time_step=...)``
(``numpy.savetxt``: one header line starting with ``#``, then numeric rows, ``,`` between cells). Its frame is the
launch site's: X east, Y north, Z up; ``Z (m)`` is the altitude above sea level, ``Vx``, ``Vy``, ``Vz`` (m/s) the
velocity over the ground (the frame turns with the Earth), ``e0`` to ``e3`` the attitude quaternion (body to
launch frame; body z is the rocket's axis, nose forward), ``Latitude (°)``, ``Longitude (°)`` and ``Altitude AGL
(m)`` where exported. Two header forms:

* with variables named: ``# Time (s),Z (m),Vz (m/s),...``, one column per variable (RocketPy's own labels);
* with none (``export_data(path)``): the solver's whole state, 14 values a row (time, x, y, z, vx, vy, vz, e0..e3,
  w1..w3), under a header that names 11 (``# Time (s),X (m),Y (m),Z (m),E0,...,W3 (rad/s)``: RocketPy's label
  omits the velocities); read by position as that state.

A file is RocketPy's when its header holds ``Time (s)``, ``Z (m)`` and ``Vz (m/s)`` (``is_rocketpy``), or the
solver-state header. ``pchute compare`` then reads it without a column map (``column_map``); ``pchute new
--from-rocketpy`` starts a descent from its apogee (``apogee_state``), once every row is checked (``check_rows``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..registries.columns import UNNAMED_VEHICLE, column
from .csv_dialects import read_csv_rows, time_fault

SOLVER_HEADER = ("Time (s),X (m),Y (m),Z (m),E0,E1,E2,E3,W1 (rad/s),W2 (rad/s),W3 (rad/s)")
"""The header ``export_data(path)`` writes over its 14-value rows (the velocities unnamed)."""
SOLVER_COLUMNS = ("time", "X", "Y", "Z", "Vx", "Vy", "Vz", "e0", "e1", "e2", "e3", "ω1", "ω2", "ω3")
"""What the 14 values of such a row are (RocketPy's ``Flight.solution``)."""
REQUIRED = ("time", "Z", "Vz")
"""The columns a start state needs: time (s), altitude above sea level (m), vertical velocity (m/s, up)."""


def _header_line(path: Path) -> str:
    """The last ``#`` line before the first numeric row, without its ``#``."""
    header = ""
    for line in path.read_text(encoding="utf-8-sig", errors="replace").splitlines():
        if line.lstrip().startswith("#"):
            header = line.lstrip().lstrip("#").strip()
        elif line.strip():
            break
    return header


def read_columns(path) -> tuple[dict, dict, dict]:
    """Columns of any CSV ``csv_dialects`` reads, and of RocketPy's solver-state export: (columns by name, units
    by name, header text by name); a RocketPy export's ``e0`` to ``e3`` are named in lower case either way."""
    return read_rows(path)[:3]


def _data_lines(path: Path) -> list:
    """The line numbers (from 1) of the rows ``numpy.loadtxt`` reads: every line with a value before any ``#``."""
    return [number for number, line in enumerate(path.read_text(encoding="utf-8-sig", errors="replace")
                                                 .splitlines(), start=1) if line.split("#", 1)[0].strip()]


def read_rows(path) -> tuple[dict, dict, dict, list]:
    """``read_columns``, and the file's line number (from 1) of each data row."""
    path = Path(path)
    if path.is_file() and _header_line(path) == SOLVER_HEADER:
        try:
            data = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
        except ValueError as error:
            raise InputError(f"{path}: RocketPy's solver-state export with a row that is not 14 numbers ({error})") \
                from None
        if data.shape[1] != len(SOLVER_COLUMNS) or not len(data):
            raise InputError(f"{path}: RocketPy's solver-state header (export_data with no variables) needs rows of "
                             f"{len(SOLVER_COLUMNS)} values (time, x, y, z, vx, vy, vz, e0..e3, w1..w3); these have "
                             f"{data.shape[1]}")
        units = dict(zip(SOLVER_COLUMNS, ("s", "m", "m", "m", "m/s", "m/s", "m/s", "", "", "", "", "rad/s", "rad/s",
                                          "rad/s")))
        return ({name: data[:, i] for i, name in enumerate(SOLVER_COLUMNS)}, units,
                {name: name for name in SOLVER_COLUMNS}, _data_lines(path))
    columns, units, texts, lines = read_csv_rows(path)
    if is_rocketpy(texts):
        rename = {name: name.lower() for name in columns if name in ("E0", "E1", "E2", "E3")}
        columns = {rename.get(n, n): v for n, v in columns.items()}
        units = {rename.get(n, n): u for n, u in units.items()}
        texts = {rename.get(n, n): t for n, t in texts.items()}
    return columns, units, texts, lines


def is_rocketpy(texts: dict) -> bool:
    """Whether a header (column name -> header text) is RocketPy's: ``Time (s)``, ``Z (m)`` and ``Vz (m/s)``,
    or the solver-state export's names."""
    headers = set(texts.values())
    return {"Time (s)", "Z (m)", "Vz (m/s)"} <= headers or set(SOLVER_COLUMNS) <= headers


def column_map(vehicle: str = UNNAMED_VEHICLE, names=None) -> dict:
    """RocketPy's columns as this package's (``csv_dialects.parse_column_map``'s form, theirs -> (ours, factor,
    offset)): Z the vehicle's altitude (m; both above the reference surface, sea level), Vx, Vy, Vz its velocity
    east, north and up over the ground (m/s). X and Y (from the launch site; ours run from the start point) are
    kept under their own names. Only the columns in ``names`` (all four if None)."""
    ours = {theirs: column(template, vehicle) for theirs, template in (
        ("Z", "{owner}_altitude"), ("Vx", "{owner}_velocity_east"), ("Vy", "{owner}_velocity_north"),
        ("Vz", "{owner}_velocity_down"))}
    mapping = {theirs: (name, -1.0 if theirs == "Vz" else 1.0, 0.0) for theirs, name in ours.items()}
    return {theirs: ours for theirs, ours in mapping.items() if names is None or theirs in names}


@dataclass(frozen=True)
class RocketPyStart:
    """The state a RocketPy flight hands over, at its apogee (or its first row if it never climbs).

    Attributes
    ----------
    time : float
        When, in the export's time (s).
    altitude : float
        Altitude above sea level (m).
    ground_elevation : float or None
        The ground's altitude (m): Z - AGL where the export has ``Altitude AGL (m)``; None otherwise.
    latitude_deg, longitude_deg : float or None
        Where (deg), if exported.
    velocity_east, velocity_north, velocity_up : float
        Velocity over the ground (m/s); east and north 0 if not exported.
    nose_pitch_deg, nose_heading_deg : float or None
        The rocket's axis (nose) above the horizontal and clockwise from north (deg), from e0..e3 if exported.
    at_apogee : bool
        True at an apogee found between two rows; False at the first row of a file that only descends.
    """

    time: float
    altitude: float
    ground_elevation: float | None
    latitude_deg: float | None
    longitude_deg: float | None
    velocity_east: float
    velocity_north: float
    velocity_up: float
    nose_pitch_deg: float | None
    nose_heading_deg: float | None
    at_apogee: bool


ROW_KEYS = {"Z": "bodies.rocket.initial.altitude", "Altitude AGL": "bodies.rocket.initial.altitude",
            "Vx": "bodies.rocket.initial.velocity_east", "Vy": "bodies.rocket.initial.velocity_north",
            "Vz": "bodies.rocket.initial.velocity_down"}
"""An export's column -> the case key whose range (``case.plausible.RANGES``, the error bounds) each row's value must
keep: the state a start takes from a row becomes that key."""
QUATERNION_TOLERANCE = 0.01
"""How far (-) the norm of a row's e0..e3 may be from 1: RocketPy's are unit quaternions, written to 6 decimals; a
norm farther off (an all-zero row) is no attitude."""


GROUND_TOLERANCE = 1.0
"""How far (m) a row's Z - Altitude AGL (the launch site's elevation) may be from the first row's; also how far below
the ground (Altitude AGL < 0) a row may be: RocketPy writes both to 6 decimals from one state."""
STEP_TOLERANCE = (10.0, 0.2)
"""(m, -): a step's altitude change ΔZ may differ from the trapezoid of its Vz, (Vz_i + Vz_i+1) Δt / 2, by at most
10 m + 0.2 |ΔZ|; RocketPy's own exports (0.5 s rows) stay within 0.6 m, a twentieth of that."""


def check_rows(path, columns: dict, texts: dict, lines: list) -> None:
    """InputError, one line naming the file, the row's line number and the column, for the first row of a RocketPy
    export that is not a state: a value that is not finite, a time not strictly after the row before, a position or
    velocity outside the case reader's range for it (ROW_KEYS), a latitude or longitude outside the start's (or one
    without the other), an attitude quaternion missing a component or not of unit norm (QUATERNION_TOLERANCE), an
    altitude change its vertical velocity does not give (STEP_TOLERANCE), a ground elevation (Z - AGL) that changes
    or an AGL below 0 (GROUND_TOLERANCE)."""
    from ..authoring.choice_checks import SITE_RANGES
    from ..case.plausible import check_value

    def refuse(row: int, name: str, what: str) -> None:
        raise InputError(f"{path}: line {lines[row]}, {texts.get(name, name)} = {columns[name][row]:g}: {what}")

    if ("Latitude" in columns) != ("Longitude" in columns):
        given, absent = ("Latitude", "Longitude") if "Latitude" in columns else ("Longitude", "Latitude")
        raise InputError(f"{path}: {texts[given]} without {absent}: a position needs both columns or neither (export "
                         "'latitude' and 'longitude' together)")
    for name, values in columns.items():
        bad = np.flatnonzero(~np.isfinite(values))
        if len(bad):
            refuse(int(bad[0]), name, "must be a finite number")
    fault = time_fault(columns["time"])
    if fault is not None:
        refuse(fault[0], "time", f"{fault[1]} {fault[2]}")
    for name, key in ROW_KEYS.items():
        for row, value in enumerate(columns.get(name, ())):
            error, _ = check_value(key, float(value))
            if error is not None:
                refuse(row, name, f"{error} (the case reader's range of {key.rpartition('.')[2]})")
    for name, (_, low, high, unit) in zip(("Latitude", "Longitude"), SITE_RANGES):
        bad = np.flatnonzero((columns[name] < low) | (columns[name] > high)) if name in columns else ()
        if len(bad):
            refuse(int(bad[0]), name, f"must be from {low:g} to {high:g} ({unit})")
    present = [f"e{k}" for k in range(4) if f"e{k}" in columns]
    if 0 < len(present) < 4:
        absent = ", ".join(f"e{k}" for k in range(4) if f"e{k}" not in columns)
        raise InputError(f"{path}: {', '.join(present)} without {absent}: an attitude quaternion needs all four "
                         "columns or none")
    if len(present) == 4:
        norm = np.sqrt(sum(columns[f"e{k}"] ** 2 for k in range(4)))
        bad = np.flatnonzero(np.abs(norm - 1.0) > QUATERNION_TOLERANCE)
        if len(bad):
            refuse(int(bad[0]), "e0", f"with e1..e3 a quaternion of norm {norm[bad[0]]:.4g}: an attitude needs norm 1 "
                   f"(within {QUATERNION_TOLERANCE:g})")
    _check_altitudes(columns, texts, lines, refuse)


def _check_altitudes(columns: dict, texts: dict, lines: list, refuse) -> None:
    """``check_rows``'s altitudes: each step's Z change against its Vz (STEP_TOLERANCE), then Altitude AGL against
    Z (GROUND_TOLERANCE); ``refuse(row, column, what)`` raises."""
    step = np.diff(columns["time"])
    rise = np.diff(columns["Z"])
    by_speed = 0.5 * (columns["Vz"][:-1] + columns["Vz"][1:]) * step
    absolute, relative = STEP_TOLERANCE
    bad = np.flatnonzero(np.abs(rise - by_speed) > absolute + relative * np.abs(rise))
    if len(bad):
        i = int(bad[0])
        refuse(i + 1, "Z", f"{rise[i]:+.6g} m from line {lines[i]} in {step[i]:g} s, where {texts.get('Vz', 'Vz')} "
               f"gives {by_speed[i]:+.6g} m (its trapezoid); allowed: within {absolute:g} m + {relative:.0%} of the "
               "change")
    if "Altitude AGL" not in columns:
        return
    agl, name = columns["Altitude AGL"], texts.get("Altitude AGL", "Altitude AGL")
    ground = columns["Z"] - agl
    bad = np.flatnonzero(np.abs(ground - ground[0]) > GROUND_TOLERANCE)
    if len(bad):
        refuse(int(bad[0]), "Altitude AGL", f"{texts.get('Z', 'Z')} - {name} = {ground[bad[0]]:g} m here, "
               f"{ground[0]:g} m on line {lines[0]}: the launch site's elevation must be the same on every row (within "
               f"{GROUND_TOLERANCE:g} m)")
    bad = np.flatnonzero(agl < -GROUND_TOLERANCE)
    if len(bad):
        refuse(int(bad[0]), "Altitude AGL", f"below the ground; allowed: >= 0 m (within {GROUND_TOLERANCE:g} m)")


def apogee_index(path, time, vertical) -> tuple[int, float]:
    """(row i, fraction f in [0, 1]) of the apogee between rows i and i + 1: the first row where the vertical
    velocity (m/s, up) goes from > 0 to <= 0, interpolated linearly to its zero; (0, 0.0) when it never climbs;
    InputError when it still climbs at its last row."""
    climbing = vertical > 0.0
    if not climbing.any():
        return 0, 0.0
    turns = np.flatnonzero(climbing[:-1] & ~climbing[1:])
    if not len(turns):
        raise InputError(f"{path}: Vz = {vertical[-1]:g} m/s at its last row (t = {time[-1]:g} s): no apogee; the "
                         "export must run past apogee (Vz from > 0 to <= 0), or only descend (the first row is the "
                         "start then)")
    i = int(turns[0])
    return i, float(vertical[i] / (vertical[i] - vertical[i + 1]))


def apogee_state(path) -> RocketPyStart:
    """The start state of a RocketPy export (module docstring): its apogee, interpolated between the two rows
    where Vz changes sign (every column linearly, the altitude by the trapezoid of that Vz), or its first row if it
    never climbs. InputError, naming the field, for a missing column, a bad row (``check_rows``: its line named) or a
    file that never reaches apogee."""
    if not Path(path).is_file():
        raise InputError(f"from_rocketpy = {str(path)!r}: no such file (a RocketPy flight export, CSV)")
    columns, _, texts, lines = read_rows(path)
    missing = [name for name in REQUIRED if name not in columns]
    if missing:
        raise InputError(f"{path}: a RocketPy export needs the columns Time (s), Z (m) and Vz (m/s); missing: "
                         f"{', '.join(missing)} (export them: FlightDataExporter(flight).export_data(path, 'z', "
                         "'vz', 'vx', 'vy', 'e0', 'e1', 'e2', 'e3', 'latitude', 'longitude', 'altitude'))")
    if len(columns["time"]) < 1:
        raise InputError(f"{path}: no data rows")
    check_rows(path, columns, texts, lines)
    i, f = apogee_index(path, columns["time"], columns["Vz"])
    at = {name: float(values[i] + f * (values[min(i + 1, len(values) - 1)] - values[i]))
          for name, values in columns.items()}
    pitch = heading = None
    if all(f"e{k}" in at for k in range(4)):
        pitch, heading = nose_angles_deg([at[f"e{k}"] for k in range(4)])
    climbed = bool((columns["Vz"] > 0.0).any())
    if climbed:   # the altitude the interpolated Vz gives (a trapezoid), closer to the top than a chord
        step = columns["time"][i + 1] - columns["time"][i]
        at["Z"] = float(columns["Z"][i] + 0.5 * columns["Vz"][i] * f * step)
    agl = at.get("Altitude AGL")
    ground = None if agl is None else float(columns["Z"][i] - columns["Altitude AGL"][i])
    return RocketPyStart(at["time"], at["Z"], ground, at.get("Latitude"),
                         at.get("Longitude"), at.get("Vx", 0.0), at.get("Vy", 0.0), 0.0 if climbed else at["Vz"],
                         pitch, heading, climbed)


def nose_angles_deg(quaternion) -> tuple[float, float]:
    """The rocket's axis from RocketPy's attitude quaternion e0..e3 (normalized here): (pitch above the horizontal,
    heading clockwise from north) (deg); the axis is the body-to-launch-frame rotation's third column."""
    e0, e1, e2, e3 = np.asarray(quaternion, float) / max(float(np.linalg.norm(quaternion)), 1e-300)
    east, north, up = 2.0 * (e1 * e3 + e0 * e2), 2.0 * (e2 * e3 - e0 * e1), 1.0 - 2.0 * (e1**2 + e2**2)
    pitch = math.degrees(math.atan2(up, math.hypot(east, north)))
    heading = math.degrees(math.atan2(east, north)) % 360.0 if math.hypot(east, north) > 1e-9 else 0.0
    return pitch, heading

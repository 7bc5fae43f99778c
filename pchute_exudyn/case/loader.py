"""Load, merge, override and validate case files.

A case file is TOML. ``extends = "base.toml"`` (a path relative to the file, or a list of them) merges the named
files first and the file's own tables on top, so shared parts are written once; ``remove = ["planet", "bodies.vehicle
.aerodynamics.center"]`` (dotted keys) deletes what the bases set before the file's own tables merge, so a child can
drop a key or replace a whole table (a flat planet by an ellipsoid). Overrides (``--set key=value`` on
the command line, ``overrides={...}`` in Python, the varied keys of a study) are dotted keys applied after that:

* ``bodies.vehicle.mass=800``; a body or system name may stand for its table (``vehicle.mass=800``,
  ``main.lines.riser.stiffness=6e4``);
* ``*`` matches every entry of a table (``main.lines.*.damping=0``);
* ``[i]`` indexes an array (``vehicle.inertia[0]=250``).

Everything is validated once, here; an error names the file (or override) the value came from, the dotted field,
the bad value and what is allowed. See ``docs/case-format.md`` for every key and its unit.
"""

from __future__ import annotations

import copy
import difflib
import math
import re
import sys
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

from ..errors import CaseError
from ..physics.aerodynamics import CoefficientTable, CoefficientTableError
from ..physics.apparent_mass import ApparentMass
from ..physics.atmosphere import US76, MarsGRC, Wind
from ..physics.cluster import DEFAULT_DRAG_EFFICIENCY
from ..physics.inflation import Inflation, InflationError, InflationStage
from ..physics.lines import LoadElongation, LoadElongationError
from ..physics.planet import FlatPlanet, Planet, StartFrame
from ..physics.wind import DrydenTurbulence, Gust, PowerLawWind, wind_from_direction
from .method_table import INTEGRATORS, METHODS, OptionError, make_options
from .model import (
    Aerodynamics,
    Body,
    Case,
    Confluence,
    Contact,
    DragAreaSchedule,
    Failures,
    InitialState,
    Line,
    ParachuteSystem,
    SimulationSettings,
    canopy_opening,
)
from .plausible import check_value
from .start import VELOCITY_FRAMES, Release, ground_relative
from .tables import read_atmosphere_table

_REQUIRED = object()
_NO_VALUE = CaseError._NO_VALUE
_TOP_KEYS = ("extends", "remove", "case", "planet", "start", "atmosphere", "bodies", "systems", "failures",
             "simulation")
_KEY_PART = re.compile(r"^([^\[\]]+)((?:\[\d+\])*)$")


# ----------------------------------------------------------------------------------------------------------------
# reading and merging files


_PARSED: dict = {}
"""Parsed TOML files by (path, modification time, size)."""


def read_toml(path: Path, kind: str = "case") -> dict:
    """Parse one TOML file (a ``kind`` file: case, study); a missing file or a syntax error becomes a CaseError
    naming the file."""
    if not path.is_file():
        raise CaseError(str(path), "", f"{kind} file not found" if not path.exists() else "not a file")
    try:
        status = path.stat()
        stamp = (str(path.resolve()), status.st_mtime_ns, status.st_size)
        if stamp not in _PARSED:   # a study's worker loads the same files for every run: parsed once
            if len(_PARSED) > 256:
                _PARSED.clear()
            with path.open("rb") as handle:
                _PARSED[stamp] = tomllib.load(handle)
        return copy.deepcopy(_PARSED[stamp])   # the callers change what they are given
    except tomllib.TOMLDecodeError as exc:
        twice = re.search(r"Cannot declare \(([^)]*)\) twice", str(exc))
        if twice:  # e.g. two systems with the same name
            name = ".".join(part.strip(" '") for part in twice.group(1).split(","))
            raise CaseError(str(path), name, f"defined twice (names of bodies, systems and lines must be unique): "
                                             f"{exc}") from None
        raise CaseError(str(path), "", f"malformed TOML: {exc}") from None
    except UnicodeDecodeError:
        raise CaseError(str(path), "", "malformed TOML: the file is not UTF-8 text") from None
    except ValueError as exc:   # an integer beyond Python's 4300 digits for str to int
        raise CaseError(str(path), "", f"malformed TOML: {str(exc).split(';')[0]}") from None
    except RecursionError:   # tomllib and deepcopy recurse once per level of [[[...]]] or {a = {b = ...}}
        raise CaseError(str(path), "", "malformed TOML: arrays or tables nested too deeply (at most a few hundred "
                                       "levels)") from None


def _record(origins: dict, path: tuple, value: Any, source: str) -> None:
    origins[path] = source
    if isinstance(value, dict):
        for key, sub in value.items():
            _record(origins, path + (key,), sub, source)


def _merge(target: dict, data: Mapping, origins: dict, source: str, prefix: tuple = ()) -> None:
    """Deep-merge ``data`` into ``target``: tables merge key by key, every other value replaces."""
    for key, value in data.items():
        path = prefix + (key,)
        if isinstance(value, dict) and isinstance(target.get(key), dict):
            origins[path] = source
            _merge(target[key], value, origins, source, path)
        else:
            target[key] = copy.deepcopy(value)
            _record(origins, path, value, source)


def _load_merged(path: Path, origins: dict, chain: tuple = ()) -> dict:
    path = path.resolve() if path.exists() else path
    if path in chain:
        chain_text = " -> ".join(str(p) for p in (*chain, path))
        raise CaseError(str(path), "extends", f"circular 'extends' chain: {chain_text}")
    data = read_toml(path)
    label = _display(path)
    merged: dict = {}
    extends = data.pop("extends", [])
    if isinstance(extends, str):
        extends = [extends]
    if not isinstance(extends, list) or not all(isinstance(e, str) for e in extends):
        raise CaseError(label, "extends", "must be a file path or a list of file paths", value=extends)
    for base in extends:
        base_path = (path.parent / base)
        if not base_path.is_file():
            raise CaseError(label, "extends", f"base case file not found: {base_path}", value=base)
        _merge(merged, _load_merged(base_path, origins, chain + (path,)), origins, _display(base_path))
    _remove_keys(merged, origins, data.pop("remove", []), label)
    _merge(merged, data, origins, label)
    _resolve_file_keys(merged, path.parent)
    return merged


def _remove_keys(merged: dict, origins: dict, keys, label: str) -> None:
    """Delete the dotted ``keys`` (``remove = [...]``) from what the base files set."""
    if not isinstance(keys, list) or not all(isinstance(k, str) and k.strip() for k in keys):
        raise CaseError(label, "remove", "must be a list of dotted keys the base files set, e.g. "
                        "[\"planet.gravity\"]", value=keys)
    for key in keys:
        parts = key.strip().split(".")
        table = merged
        for part in parts[:-1]:
            table = table.get(part) if isinstance(table, dict) else None
        if not isinstance(table, dict) or parts[-1] not in table:
            raise CaseError(label, "remove", f"{key!r} is not set by the base files ('extends'); nothing to remove",
                            value=key)
        del table[parts[-1]]
        prefix = tuple(parts)
        for path in [p for p in origins if p[:len(prefix)] == prefix]:
            del origins[path]


def _resolve_file_keys(data: dict, directory: Path) -> None:
    """Make file paths inside the data absolute, relative to the file that named them."""
    atmosphere = data.get("atmosphere")
    if isinstance(atmosphere, dict) and isinstance(atmosphere.get("file"), str):
        file = Path(atmosphere["file"])
        if not file.is_absolute():
            atmosphere["file"] = str((directory / file).resolve())


def _display(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(Path.cwd()))
    except ValueError:
        return str(path)


# ----------------------------------------------------------------------------------------------------------------
# overrides


class Scale:
    """An override value that multiplies the value already in the case (a relative dispersion: stiffness x 1.1)."""

    def __init__(self, factor: float):
        self.factor = float(factor)

    def __repr__(self) -> str:
        return f"x{self.factor:g}"


def parse_override(text: str) -> tuple[str, Any]:
    """Split ``key=value``; the value is read as TOML (``800``, ``true``, ``[1, 2]``, ``"x"``) or else as a string."""
    if "=" not in text:
        raise CaseError(f"--set {text}", "", "an override must look like key=value, e.g. vehicle.mass=800")
    key, raw = text.split("=", 1)
    key, raw = key.strip(), raw.strip()
    if not key:
        raise CaseError(f"--set {text}", "", "the key before '=' is empty")
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw
    except RecursionError:
        raise CaseError(f"--set {key}=...", key, "the value's arrays or tables are nested too deeply") from None
    return key, value


def _split_key(key: str, source: str) -> list:
    parts: list = []
    for piece in key.split("."):
        match = _KEY_PART.match(piece)
        if not match:
            raise CaseError(source, key, "malformed key: use dotted names with optional [index], "
                                         "e.g. bodies.vehicle.inertia[0]")
        parts.append(match.group(1))
        parts.extend(int(i) for i in re.findall(r"\[(\d+)\]", match.group(2)))
    return parts


def _expand(data: Any, parts: list, done: tuple, source: str, key: str) -> list:
    """Concrete paths of ``parts`` in ``data``, with ``*`` expanded over existing table entries."""
    if not parts:
        return [done]
    head, rest = parts[0], parts[1:]
    if head == "*":
        if not isinstance(data, dict) or not data:
            raise CaseError(source, ".".join(map(str, done)) or key, "'*' needs an existing table to match in")
        return [p for name in data for p in _expand(data[name], rest, done + (name,), source, key)]
    child = data.get(head) if isinstance(data, dict) else None
    if isinstance(head, int):
        child = data[head] if isinstance(data, list) and head < len(data) else None
    return _expand(child, rest, done + (head,), source, key)


def _scaled(base: Any, factor: float) -> Any:
    """``base`` times ``factor``: a number, every number of a (nested) list, or a coefficient table's ``value``
    (its breakpoints kept); None when ``base`` holds nothing to scale."""
    if isinstance(base, bool):
        return None
    if isinstance(base, (int, float)):
        return base * factor
    if isinstance(base, list) and base:
        items = [_scaled(item, factor) for item in base]
        return None if any(item is None for item in items) else items
    if isinstance(base, dict) and "value" in base:
        values = _scaled(base["value"], factor)
        return None if values is None else {**base, "value": values}
    return None


def apply_override(data: dict, origins: dict, key: str, value: Any, source: str | None = None) -> None:
    """Set the dotted ``key`` to ``value`` in merged case ``data`` (see the module docstring for the key syntax)."""
    source = source or f"--set {key}={value}"
    parts = _split_key(key, source)
    if parts[0] in ("extends", "remove"):   # the files are merged before overrides apply: it would do nothing
        raise CaseError(source, parts[0], "cannot be overridden: it is read when the case file is "
                                          "merged; write a case file that extends this one instead")
    if parts[0] not in _TOP_KEYS:
        sections = [section for section in ("bodies", "systems")
                    if isinstance(data.get(section), dict) and parts[0] in data[section]]
        if len(sections) > 1:
            raise CaseError(source, key, f"'{parts[0]}' names both a body and a system: write bodies.{key} or "
                                         f"systems.{key}")
        if sections:
            parts = [sections[0]] + parts
    for path in _expand(data, parts, (), source, key):
        node = data
        for i, part in enumerate(path[:-1]):
            if isinstance(part, int):
                if not isinstance(node, list) or part >= len(node):
                    raise CaseError(source, _dotted(path[:i + 1]), "index out of range or not an array")
                node = node[part]
                continue
            if not isinstance(node, dict):
                raise CaseError(source, _dotted(path[:i]), "is not a table, so it has no key "
                                                          f"'{part}'")
            if part not in node:  # a table the override creates belongs to the override
                node[part] = {}
                origins[tuple(p for p in path[:i + 1] if not isinstance(p, int))] = source
            node = node[part]
        last = path[-1]
        if isinstance(last, int):
            if not isinstance(node, list) or last >= len(node):
                raise CaseError(source, _dotted(path), "index out of range or not an array")
        elif not isinstance(node, dict):
            raise CaseError(source, _dotted(path[:-1]), f"is not a table, so it has no key '{last}'")
        new = value
        if isinstance(value, Scale):   # relative: multiply what the case holds there
            base = node[last] if isinstance(last, int) else node.get(last)
            new = _scaled(base, value.factor)
            if new is None:
                raise CaseError(source, _dotted(path), "a relative value needs a number in the case to scale (or "
                                                       "numbers: a list, a coefficient table's values), found "
                                                       f"{base!r}")
        node[last] = copy.deepcopy(new)
        _record(origins, tuple(p for p in path if not isinstance(p, int)), value, source)


def _dotted(path: Iterable) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


# ----------------------------------------------------------------------------------------------------------------
# validation


class _Context:
    def __init__(self, top_source: str, origins: dict):
        self.top_source = top_source
        self.origins = origins
        self.units: dict = {}   # dotted key -> unit of every number the case was asked for (Case.key_units)
        self.paths: dict = {}   # dotted key -> its path, for the plausibility check of every key read

    def source(self, path: tuple) -> str:
        for n in range(len(path), 0, -1):
            if path[:n] in self.origins:
                return self.origins[path[:n]]
        return self.top_source

    def error(self, path: tuple, message: str, value: Any = _NO_VALUE) -> CaseError:
        return CaseError(self.source(path), _dotted(path), message, value)


class _Table:
    """Typed, validating access to one table of the case; ``finish()`` rejects keys nobody asked for."""

    def __init__(self, data: Any, path: tuple, ctx: _Context):
        if not isinstance(data, dict):
            raise ctx.error(path, "must be a table", data)
        self.data, self.path, self.ctx = data, path, ctx
        self.allowed: list[str] = []

    def _get(self, key: str, default: Any, unit: str):
        self.allowed.append(key)
        if unit != "table":
            self.ctx.units[_dotted(self.path + (key,))] = unit
            self.ctx.paths[_dotted(self.path + (key,))] = self.path + (key,)
        if key in self.data:
            return self.data[key]
        if default is _REQUIRED:
            raise self.ctx.error(self.path + (key,), f"required{f' ({unit})' if unit else ''} but missing")
        return default

    def error(self, key: str | None, message: str, value: Any = _NO_VALUE) -> CaseError:
        """The error of ``key`` (a dotted key below this table names a key of a sub-table: ``cutaway.main2``)."""
        return self.ctx.error(self.path + (tuple(key.split(".")) if key else ()), message, value)

    def number(self, key: str, unit: str, default: Any = _REQUIRED, *, minimum: float | None = None,
               above: float | None = None, maximum: float | None = None) -> float:
        value = self._get(key, default, unit)
        if value is default and default is not _REQUIRED:
            return value
        return _check_number(value, unit, minimum, above, maximum, lambda m: self.error(key, m, value))

    def string(self, key: str, default: Any = _REQUIRED, choices: Iterable[str] | None = None) -> str:
        value = self._get(key, default, "")
        if value is default and default is not _REQUIRED:
            return value
        if not isinstance(value, str):
            raise self.error(key, "must be a string", value)
        if choices is not None and value not in choices:
            raise self.error(key, f"must be one of: {', '.join(choices)}", value)
        return value

    def boolean(self, key: str, default: Any = _REQUIRED) -> bool:
        value = self._get(key, default, "")
        if not isinstance(value, bool):
            raise self.error(key, "must be true or false", value)
        return value

    def vector(self, key: str, unit: str, length: int = 3, default: Any = _REQUIRED) -> tuple:
        value = self._get(key, default, unit)
        if value is default and default is not _REQUIRED:
            return value
        return _check_vector(value, unit, length, lambda m: self.error(key, m, value))

    def sequence(self, key: str, unit: str, min_length: int = 1) -> tuple:
        value = self._get(key, _REQUIRED, unit)
        if not isinstance(value, list) or len(value) < min_length:
            raise self.error(key, f"must be a list of at least {min_length} numbers{f' ({unit})' if unit else ''}",
                             value)
        return _check_vector(value, unit, len(value), lambda m: self.error(key, m, value))

    def table(self, key: str, default: Any = _REQUIRED) -> _Table | None:
        value = self._get(key, default, "table")
        if value is None:
            return None
        return _Table(value, self.path + (key,), self.ctx)

    def named_tables(self, key: str, default: Any = _REQUIRED) -> dict:
        outer = self.table(key, default)
        if outer is None:
            return {}
        outer.allowed = list(outer.data)
        return {name: _Table(sub, outer.path + (name,), self.ctx) for name, sub in outer.data.items()}

    def finish(self) -> None:
        for key in self.data:
            if key not in self.allowed:
                hint = difflib.get_close_matches(key, self.allowed, n=1)
                raise self.ctx.error(self.path + (key,), "unknown key; allowed here: " + ", ".join(self.allowed)
                                     + (f" (did you mean '{hint[0]}'?)" if hint else ""))


def _check_number(value, unit, minimum, above, maximum, error) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise error(f"must be a number{f' ({unit})' if unit else ''}")
    try:
        value = float(value)
    except OverflowError:   # an integer of hundreds of digits
        value = math.inf
    if not math.isfinite(value):
        raise error("must be a finite number")
    if above is not None and not value > above:
        raise error(f"must be > {above:g}{f' ({unit})' if unit else ''}")
    if minimum is not None and not value >= minimum:
        raise error(f"must be >= {minimum:g}{f' ({unit})' if unit else ''}")
    if maximum is not None and not value <= maximum:
        raise error(f"must be <= {maximum:g}{f' ({unit})' if unit else ''}")
    return value


def _check_vector(value, unit, length, error) -> tuple:
    if not isinstance(value, list) or len(value) != length:
        raise error(f"must be a list of {length} numbers{f' ({unit})' if unit else ''}")
    return tuple(_check_number(v, unit, None, None, None, error) for v in value)


def _read_initial(t: _Table, *, attitude: bool) -> InitialState:
    values = {"altitude": t.number("altitude", "m")}
    for key in ("east", "north"):
        values[key] = t.number(key, "m", 0.0)
    for key in ("velocity_north", "velocity_east", "velocity_down"):
        values[key] = t.number(key, "m/s", 0.0)
    if attitude:
        values["yaw_deg"] = t.number("yaw_deg", "deg", 0.0, minimum=-180.0, maximum=180.0)
        values["pitch_deg"] = t.number("pitch_deg", "deg", 0.0, minimum=-90.0, maximum=90.0)
        values["roll_deg"] = t.number("roll_deg", "deg", 0.0, minimum=-180.0, maximum=180.0)
        for key in ("rate_x", "rate_y", "rate_z"):
            values[key] = t.number(key, "rad/s", 0.0)
    t.finish()
    return InitialState(**values)


def _read_inertia(t: _Table) -> np.ndarray:
    value = t._get("inertia", _REQUIRED, "kg m^2")
    error = lambda m: t.error("inertia", m, value)  # noqa: E731
    if isinstance(value, list) and len(value) == 3 and all(isinstance(v, list) for v in value):
        matrix = np.array([_check_vector(row, "kg m^2", 3, error) for row in value])
        if not np.allclose(matrix, matrix.T, rtol=1e-9, atol=1e-9 * np.abs(matrix).max()):
            raise error("an inertia matrix must be symmetric")
    elif isinstance(value, list) and len(value) == 3:
        matrix = np.diag(_check_vector(value, "kg m^2", 3, error))
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


def _read_aerodynamics(t: _Table) -> Aerodynamics:
    area = t.number("reference_area", "m^2", above=0.0)
    center = t.vector("center", "m")
    enabled = t.boolean("enabled", True)
    axial = _read_coefficient(t, "axial_coefficient", minimum=0.0)
    normal = _read_coefficient(t, "normal_coefficient", default=0.0)
    moments = {key: _read_coefficient(t, key, default=None) for key in MOMENTS}
    length = t.number("reference_length", "m", None, above=0.0)
    given = [key for key, value in moments.items() if value is not None]
    if given and length is None:
        raise t.error("reference_length", f"required (m): the {given[0]} is per unit of it")
    t.finish()
    return Aerodynamics(area, axial, normal, center, enabled, *moments.values(), length)


def _read_coefficient(t: _Table, key: str, default=_REQUIRED, minimum: float | None = None):
    """A coefficient (-): a number (at least ``minimum``) or a table ``{ alpha_deg = [...], value = [...] }`` over the
    angle of attack (deg), ``{ mach = [...], value = [...] }`` over Mach number, or both with ``value`` one row per
    Mach number (``physics.aerodynamics.CoefficientTable``); ``default`` (a number, or None for none) when absent."""
    if key not in t.data:
        t._get(key, default, "")
        return None if default is None else CoefficientTable.constant(default)
    raw = t.data[key]
    if not isinstance(raw, dict):
        return CoefficientTable.constant(t.number(key, "", minimum=minimum))
    table = t.table(key)
    mach = table._get("mach", [], "")
    angles = table._get("alpha_deg", [], "deg")
    value = table._get("value", _REQUIRED, "")
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


def _read_body(name: str, t: _Table) -> Body:
    fixed = t.boolean("fixed", False)
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
    initial = _read_initial(initial_table, attitude=True) if initial_table is not None else None
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
    return Body(name, mass, inertia, points, initial, aero, fixed, apparent)


def _read_apparent_mass(t: _Table) -> ApparentMass | None:
    """``[bodies.<name>.apparent_mass]``; None when switched off (``enabled = false``)."""
    enabled = t.boolean("enabled", True)
    values = (t.number("projected_radius", "m", above=0.0), t.number("axial", "", minimum=0.0),
              t.number("lateral", "", minimum=0.0), t.number("rotational", "", minimum=0.0))
    t.finish()
    return ApparentMass(*values) if enabled else None


def _read_load_elongation(t: _Table) -> LoadElongation:
    """``load_elongation = { strain = [...], tension = [...] }`` of a line."""
    strain = t.sequence("strain", "", min_length=2)
    tension = t.vector("tension", "N", length=len(strain))
    t.finish()
    try:
        return LoadElongation(strain, tension)
    except LoadElongationError as exc:
        raise t.error(exc.field, str(exc), exc.value) from None


def _read_inflation(t: _Table) -> Inflation:
    """``[systems.<name>.inflation]``: the fill-constant opening (stage columns as equal-length lists)."""
    starts = t.sequence("stage_start", "s")
    columns = {key: t.vector(key, "", length=len(starts)) for key in ("fraction", "fill_constant", "exponent")}
    fractions = columns["fraction"]
    if any(b < a for a, b in zip(fractions, fractions[1:])):
        raise t.error("fraction", "must not decrease from stage to stage: a disreef opens the canopy further",
                      list(fractions))
    stages = tuple(InflationStage(start, *values) for start, *values in
                   zip(starts, columns["fraction"], columns["fill_constant"], columns["exponent"]))
    scalars = {key: t.number(key, unit, default) for key, unit, default in
               (("initial_fraction", "", 0.0), ("overinflation", "", 1.0), ("overinflation_decay", "s", 0.0))}
    t.finish()
    try:
        return Inflation(stages, **scalars)
    except InflationError as exc:
        raise t.error(exc.field, str(exc), exc.value) from None


def _read_line(name: str, lt: _Table, bodies: dict) -> Line:
    body, point = _read_body_point(lt, "attach", bodies, lt.string("attach"))
    free_length = lt.number("free_length", "m", above=0.0)
    table_data = lt.table("load_elongation", None)
    table = _read_load_elongation(table_data) if table_data is not None else None
    if table is not None and "stiffness" in lt.data:
        raise lt.error("stiffness", "give stiffness or load_elongation, not both", lt.data["stiffness"])
    # with a table, K is the table's initial tangent stiffness (for reports); the table gives the tension
    stiffness = table.slopes()[0] / free_length if table is not None else lt.number("stiffness", "N/m", minimum=0.0)
    line = Line(name, body, point, free_length=free_length, stiffness=stiffness,
                damping=lt.number("damping", "N s/m", minimum=0.0), load_elongation=table)
    lt.finish()
    return line


def _read_body_point(t: _Table, key: str, bodies: dict, text: str) -> tuple:
    body, _, point = text.partition(".")
    if body not in bodies:
        raise t.error(key, f"unknown body '{body}'; bodies are: {', '.join(bodies)}", text)
    if point not in bodies[body].points:
        known = ", ".join(bodies[body].points) or "none"
        raise t.error(key, f"body '{body}' has no point '{point}'; its points are: {known} "
                           "(write \"<body>.<point>\")", text)
    return body, point


def _read_schedule(t: _Table) -> DragAreaSchedule:
    times = t.sequence("time", "s", min_length=1)
    fractions = t.vector("fraction", "", length=len(times))
    t.finish()
    if times[0] < 0.0 or any(b <= a for a, b in zip(times, times[1:])):
        raise t.error("time", "times since deployment must be >= 0 and strictly increasing", list(times))
    if any(not 0.0 <= f <= 1.0 for f in fractions):
        raise t.error("fraction", "fractions of the full drag area must be within [0, 1]", list(fractions))
    return DragAreaSchedule(times, fractions)


def _canopy_key(t: _Table) -> str:
    """The key a system's table names its canopies by: ``canopies`` (a cluster) or ``canopy``."""
    return "canopies" if "canopies" in t.data else "canopy"


def _read_canopies(t: _Table, bodies: dict) -> tuple:
    """``canopy = "<body>"`` or, for a cluster, ``canopies = ["<body>", ...]``: free bodies, each named once."""
    if "canopy" in t.data and "canopies" in t.data:
        raise t.error("canopies", "give canopy (one body) or canopies (a cluster), not both", t.data["canopies"])
    key = _canopy_key(t)
    t.allowed.append("canopies" if key == "canopy" else "canopy")
    raw = t._get(key, None, "")
    if raw is None:
        return ()
    names = [raw] if key == "canopy" else raw
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise t.error(key, "must be a body name" if key == "canopy" else "must be a non-empty list of body names",
                      raw)
    for canopy in names:
        if canopy not in bodies or bodies[canopy].fixed:
            raise t.error(key, f"must name free bodies; '{canopy}' is not one (bodies are: {', '.join(bodies)})",
                          raw)
    if len(set(names)) != len(names):
        raise t.error(key, "names a body twice", raw)
    return tuple(names)


def _read_cluster(t: _Table, canopies: tuple) -> tuple:
    """``[systems.<name>.cluster]`` and ``[systems.<name>.contact]``: (drag efficiency, deploy spread in rad or None,
    Contact or None); both tables only for a system of two or more canopies."""
    cluster_table, contact_table = t.table("cluster", None), t.table("contact", None)
    for table, key in ((cluster_table, "cluster"), (contact_table, "contact")):
        if table is not None and len(canopies) < 2:
            raise t.error(key, "needs a cluster: a system with two or more canopies (canopies = [...])")
    efficiency, spread = DEFAULT_DRAG_EFFICIENCY, None
    if cluster_table is not None:
        if "drag_efficiency" in cluster_table.data:
            efficiency = cluster_table.sequence("drag_efficiency", "")
            if any(not 0.0 < eta <= 1.0 for eta in efficiency):
                raise cluster_table.error("drag_efficiency", "each must be within (0, 1]: eta for 1, 2, ... inflating "
                                                             "canopies", list(efficiency))
        else:
            cluster_table.allowed.append("drag_efficiency")
        spread_deg = cluster_table.number("deploy_spread_deg", "deg", None, minimum=0.0, maximum=90.0)
        spread = None if spread_deg is None else math.radians(spread_deg)
        cluster_table.finish()
    contact = Contact() if len(canopies) > 1 else None
    if contact_table is not None:
        enabled = contact_table.boolean("enabled", True)
        contact = Contact(contact_table.number("stiffness", "N/m", None, above=0.0),
                          contact_table.number("damping", "N s/m", None, minimum=0.0),
                          contact_table.number("projected_diameter_ratio", "", 0.67, above=0.0, maximum=1.0))
        contact_table.finish()
        contact = contact if enabled else None
    return tuple(efficiency), spread, contact


def _read_system(name: str, t: _Table, bodies: dict) -> ParachuteSystem:
    c = t.table("confluence")
    initial_table = c.table("initial", None)
    confluence = Confluence(c.number("mass", "kg", above=0.0),
                            _read_initial(initial_table, attitude=False) if initial_table is not None else None)
    c.finish()
    canopies = _read_canopies(t, bodies)
    canopy_key = _canopy_key(t)
    deploy_time = t.number("deploy_time", "s", None, minimum=0.0)
    cutaway_time = t.number("cutaway_time", "s", None, above=0.0)
    deploy_point = None
    if "deploy_point" in t.data:
        deploy_point = _read_body_point(t, "deploy_point", bodies, t.string("deploy_point"))
    else:
        t.allowed.append("deploy_point")
    schedule_table = t.table("drag_area_schedule", None)
    schedule = _read_schedule(schedule_table) if schedule_table is not None else None
    inflation_table = t.table("inflation", None)
    inflation = _read_inflation(inflation_table) if inflation_table is not None else None
    if schedule is not None and inflation is not None:
        raise t.error("inflation", "a system has a drag_area_schedule or an inflation, not both")
    efficiency, spread, contact = _read_cluster(t, canopies)
    line_tables = t.named_tables("lines")
    if not line_tables:
        raise t.error("lines", "a system needs at least one line")
    lines = [_read_line(line_name, lt, bodies) for line_name, lt in line_tables.items()]
    if deploy_time is not None:
        missing = [key for key, value in ((canopy_key, canopies), ("deploy_point", deploy_point)) if not value]
        if missing:
            raise t.error(missing[0], "required: a system with a deploy_time is placed at line stretch, which needs "
                                      "its canopy body and the vehicle point where its confluence goes")
    if deploy_point is not None and deploy_point[0] in canopies:
        raise t.error("deploy_point", f"is on the system's own canopy '{deploy_point[0]}': a system deploys from "
                                      "the body it hangs from (e.g. \"vehicle.line_stretch\")",
                      ".".join(deploy_point))
    if cutaway_time is not None and cutaway_time <= (deploy_time or 0.0):
        raise t.error("cutaway_time", f"must be after the deployment (deploy_time = {deploy_time or 0.0:g} s)",
                      cutaway_time)
    for key, value in (("drag_area_schedule", schedule), ("inflation", inflation)):
        if value is not None and (not canopies or any(bodies[c].aerodynamics is None for c in canopies)):
            raise t.error(key, "needs canopy bodies with aerodynamics (canopy = \"<body>\")")
    attached = {line.body for line in lines}
    for canopy in canopies:
        if canopy not in attached:
            raise t.error(canopy_key, f"canopy '{canopy}' has no riser: no line of the system attaches to it",
                          canopy if canopy_key == "canopy" else list(canopies))
    if len(canopies) > 1 and any(bodies[c].aerodynamics is None for c in canopies):
        bare = next(c for c in canopies if bodies[c].aerodynamics is None)
        raise t.error("canopies", f"canopy '{bare}' has no aerodynamics: every canopy of a cluster needs them (its "
                                  "drag, its envelope's size and its spread come from them)", list(canopies))
    if contact is not None and any(bodies[c].aerodynamics is None or not bodies[c].aerodynamics.enabled
                                   for c in canopies):
        raise t.error("contact", "needs every canopy's aerodynamics, enabled (the envelope's size comes from the "
                                 "reference area and the drag-area fraction); set contact.enabled = false otherwise")
    t.finish()
    return ParachuteSystem(name, confluence, tuple(lines), canopies, deploy_time, deploy_point, cutaway_time,
                           schedule, inflation, efficiency, spread, contact)


def _read_failures(t: _Table | None, systems: dict, duration: float) -> Failures:
    """``[failures]``: the canopies that fail and how (``case.model.Failures``; docs/case-format.md). Every key names
    canopies of the case's systems."""
    if t is None:
        return Failures()
    owner = {canopy: system for system in systems.values() for canopy in system.canopies}

    def canopy(key: str, name, value=_NO_VALUE):
        if not isinstance(name, str) or name not in owner:
            known = ", ".join(owner) or "none (no system has a canopy)"
            raise t.error(key, f"unknown canopy {name!r}; the canopies are: {known}",
                          name if value is _NO_VALUE else value)
        return name

    raw = t._get("not_inflated", [], "")
    names = ([] if raw == "" else [raw]) if isinstance(raw, str) else raw
    if not isinstance(names, list):
        raise t.error("not_inflated", "must be a canopy name or a list of them", raw)
    not_inflated = tuple(canopy("not_inflated", name, raw) for name in names)
    model = t.string("not_inflated_model", "absent", ("absent", "trailing"))
    trailing = t.number("trailing_fraction", "", 0.0, minimum=0.0, maximum=1.0)
    cutaway = {}
    for name, time in _named_values(t, "cutaway", "s").items():
        system = owner[canopy(f"cutaway.{name}", name, time)]
        if name in not_inflated:
            raise t.error(f"cutaway.{name}", f"canopy '{name}' never inflates (failures.not_inflated): it cannot "
                                             "also be cut away", time)
        earliest, latest = system.deploy_time or 0.0, min(duration, system.cutaway_time or duration)
        cutaway[name] = _check_number(time, "s", None, earliest, None,
                                      lambda m, n=name, v=time: t.error(f"cutaway.{n}", m, v))
        if not cutaway[name] < latest:
            raise t.error(f"cutaway.{name}", f"must be before {latest:g} s (the system's cut-away or the end of the "
                                             "run)", cutaway[name])
    delays, skipped = {}, {}
    for key, unit, out, read in (("disreef_delay", "s", delays, _delays),
                                 ("skipped_stages", "", skipped, _stage_numbers)):
        for name, value in _named_values(t, key, unit).items():
            system = owner[canopy(f"{key}.{name}", name, value)]
            if system.inflation is None or len(system.inflation.stages) < 2:
                raise t.error(f"{key}.{name}", f"canopy '{name}' has no reefed stages: it needs its system's "
                                               "inflation with two or more stages", value)
            out[name] = read(value, lambda m, k=f"{key}.{name}", v=value: t.error(k, m, v),
                             len(system.inflation.stages))
    t.finish()
    failures = Failures(not_inflated, model, trailing, cutaway, delays, skipped)
    for name in sorted(set(delays) | set(skipped)):   # the openings they give must be valid (moot if not inflated)
        try:
            canopy_opening(owner[name], name, failures)
        except InflationError as exc:
            raise t.error(f"{exc.field}.{name}", str(exc), exc.value) from None
    return failures


def _named_values(t: _Table, key: str, unit: str) -> dict:
    """A table of ``canopy = value`` under ``key`` ({} when absent), each value in ``unit``."""
    value = t._get(key, {}, "table")
    if not isinstance(value, dict):
        raise t.error(key, "must be a table of canopy = value", value)
    for name in value:
        t.ctx.units[_dotted(t.path + (key, name))] = unit
    return value


def _delays(value, error, stages: int) -> tuple:
    """A disreef delay: one number (s) for every disreef, or a list of one per disreef."""
    values = [value] * (stages - 1) if not isinstance(value, list) else value
    return tuple(_check_number(v, "s", None, None, None, lambda m: error(f"{m}; give one number (s) or a list of "
                                                                         f"{stages - 1}, one per disreef"))
                 for v in values)


def _stage_numbers(value, error, stages: int) -> tuple:
    """Skipped stages: a stage number (from 1) or a list of them."""
    values = value if isinstance(value, list) else [value]
    if not values or any(isinstance(v, bool) or not isinstance(v, int) for v in values):
        raise error(f"must be a stage number or a list of them (integers from 1 to {stages - 1})")
    return tuple(values)


def _read_method_options(t: _Table) -> dict:
    """``[simulation.<method>]`` tables: each method's options, validated by its Options type."""
    options = {}
    for name, method_class in METHODS.items():
        table = t.table(name, None)
        if table is None:
            continue
        table.allowed = list(table.data)
        try:
            options[name] = make_options(method_class.Options, table.data)
        except OptionError as exc:
            raise table.error(exc.field, exc.allowed, exc.value) from None
    return options


def _read_steps(t: _Table, duration: float) -> dict:
    """``[simulation.steps]``: ``<method>`` (rk4) and ``<method>_<integrator>`` keys, s."""
    steps = {}
    step_table = t.table("steps", None)
    if step_table is None:
        return steps
    keys = [name if integrator == "rk4" else f"{name}_{integrator}"
            for name, method_class in METHODS.items() for integrator in method_class.integrators]
    for key in keys:
        if key in step_table.data:
            steps[key] = step_table.number(key, "s", above=0.0, maximum=duration)
        else:
            step_table.allowed.append(key)
    step_table.finish()
    return steps


def _read_simulation(t: _Table) -> SimulationSettings:
    duration = t.number("duration", "s", above=0.0)
    output_step = t.number("output_step", "s", 0.01, above=0.0, maximum=duration)
    method = t.string("method", "full", tuple(METHODS))
    integrator = t.string("integrator", "rk4", INTEGRATORS)
    if integrator not in METHODS[method].integrators:
        raise t.error("integrator", f"the {method} method runs with: {', '.join(METHODS[method].integrators)}",
                      integrator)
    spectral_radius = t.number("spectral_radius", "", 0.9, minimum=0.0, maximum=1.0)
    options = _read_method_options(t)
    ground_altitude = t.number("ground_altitude", "m", 0.0)
    stop_at_ground = t.boolean("stop_at_ground", True)
    rates = t._get("descent_rate_events", [], "m/s")
    if not isinstance(rates, list):
        raise t.error("descent_rate_events", "must be a list of descent rates > 0 (m/s)", rates)
    descent_rates = [_check_number(r, "m/s", None, 0.0, None, lambda m: t.error("descent_rate_events", m, rates))
                     for r in rates]
    steps = _read_steps(t, duration)
    t.finish()
    return SimulationSettings(duration, output_step, method, integrator, steps, spectral_radius, options,
                              ground_altitude if stop_at_ground else None, tuple(descent_rates))


def _read_atmosphere(t: _Table, ground_altitude: float, heading: tuple):
    """``[atmosphere]``: the model, and the air's motion (``wind``, ``turbulence``, ``gusts``; docs/case-format.md).
    ``ground_altitude`` (m) is the default ground of the power-law wind and the turbulence; ``heading`` orients the
    turbulence where there is no mean wind."""
    model = t.string("model", choices=("mars_grc", "us76", "table"))
    if model == "table":
        sound = {"gamma": t.number("gamma", "", 1.4, above=0.0),
                 "gas_constant": t.number("gas_constant", "J/(kg K)", 287.05287, above=0.0),
                 "speed_of_sound": t.number("speed_of_sound", "m/s", None, above=0.0)}
        atmosphere = read_atmosphere_table(t.string("file"), **sound)
    elif any(key in t.data for key in ("gamma", "gas_constant", "speed_of_sound")):
        key = next(key for key in ("gamma", "gas_constant", "speed_of_sound") if key in t.data)
        raise t.error(key, f"belongs to a table atmosphere (model = \"table\"); the {model} model has its own",
                      t.data[key])
    elif model == "us76":
        atmosphere = US76()
    else:
        atmosphere = MarsGRC()
    w = t.table("wind", None)
    wind = _read_wind(w, ground_altitude) if w is not None else None
    turbulence_table = t.table("turbulence", None)
    turbulence = (_read_turbulence(turbulence_table, ground_altitude, heading) if turbulence_table is not None
                  else None)
    gusts = _read_gusts(t)
    t.finish()
    return atmosphere, wind, turbulence, gusts


def _read_direction_speed(w: _Table, speed_unit: str = "m/s") -> tuple:
    """(east, north) from ``east``/``north`` or from ``speed``/``from_deg`` (the direction the wind comes from)."""
    if "speed" in w.data or "from_deg" in w.data:
        if "east" in w.data or "north" in w.data:
            raise w.error("speed", "give either east and north or speed and from_deg, not both")
        return wind_from_direction(w.number("speed", speed_unit, minimum=0.0), w.number("from_deg", "deg"))
    return w.number("east", "m/s", 0.0), w.number("north", "m/s", 0.0)


def _read_wind(w: _Table, ground_altitude: float):
    profile = w.string("profile", "table" if "altitude" in w.data else "constant", ("constant", "table", "power_law"))
    if profile == "table":
        altitude = w.sequence("altitude", "m", min_length=2)
        if any(b <= a for a, b in zip(altitude, altitude[1:])):
            raise w.error("altitude", "must be strictly increasing", list(altitude))
        wind = Wind(altitude, w.vector("east", "m/s", len(altitude)), w.vector("north", "m/s", len(altitude)))
    elif profile == "constant":
        wind = Wind.constant(*_read_direction_speed(w))
    else:
        east, north = _read_direction_speed(w)
        wind = PowerLawWind(east, north, w.number("reference_height", "m", above=0.0),
                            w.number("exponent", "", minimum=0.0, maximum=1.0),
                            w.number("ground_altitude", "m", ground_altitude))
    w.finish()
    return wind


def _read_integer(t: _Table, key: str, minimum: int = 0) -> int:
    value = t._get(key, _REQUIRED, "")
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise t.error(key, f"must be an integer >= {minimum}", value)
    return value


def _read_turbulence(t: _Table, ground_altitude: float, heading: tuple) -> DrydenTurbulence:
    t.string("model", "dryden", ("dryden",))
    seed = _read_integer(t, "seed")
    ground = t.number("ground_altitude", "m", ground_altitude)
    if "wind_speed_6m" in t.data:
        given = [k for k in ("sigma_u", "sigma_v", "sigma_w", "length_u", "length_v", "length_w") if k in t.data]
        if given:
            raise t.error(given[0], "give either wind_speed_6m (the low-altitude forms) or the intensities and "
                                    "scale lengths, not both")
        turbulence = DrydenTurbulence(seed, ground, wind_speed_6m=t.number("wind_speed_6m", "m/s", minimum=0.0),
                                      heading=heading)
    else:
        sigma = [t.number(f"sigma_{c}", "m/s", minimum=0.0) for c in "uvw"]
        length = [t.number(f"length_{c}", "m", above=0.0) for c in "uvw"]
        turbulence = DrydenTurbulence(seed, ground, sigma, length, heading=heading)
    t.finish()
    return turbulence


def _read_gusts(t: _Table) -> tuple:
    raw = t._get("gusts", [], "")
    if not isinstance(raw, list):
        raise t.error("gusts", "must be an array of tables ([[atmosphere.gusts]])", raw)
    gusts = []
    for i, data in enumerate(raw):
        g = _Table(data, t.path + ("gusts", i), t.ctx)
        amplitude = g.number("amplitude", "m/s")
        start = g.number("start", "s", minimum=0.0)
        length = g.number("length", "s", above=0.0)
        if "direction" in g.data:
            if "from_deg" in g.data:
                raise g.error("from_deg", "give either direction or from_deg, not both")
            direction = np.array(g.vector("direction", ""), float)
            with np.errstate(over="ignore"):
                norm = np.linalg.norm(direction)
            if not norm > 0.0:
                raise g.error("direction", "must be a non-zero [east, north, up] vector", g.data["direction"])
            if not math.isfinite(norm):   # its length overflows: the gust would be dropped
                raise g.error("direction", "its length overflows: give a direction of moderate numbers (only the "
                                           "direction counts), e.g. [1, 1, 0]", g.data["direction"])
            direction = tuple((direction / np.linalg.norm(direction)).tolist())
        else:
            east, north = wind_from_direction(1.0, g.number("from_deg", "deg"))
            direction = (east, north, 0.0)
        g.finish()
        gusts.append(Gust(amplitude, start, length, direction))
    return tuple(gusts)


def _read_planet(p: _Table):
    """The [planet] section: an ellipsoid (its gravitational parameter, radii and rotation) or a flat planet."""
    if p.string("model", "ellipsoid", ("ellipsoid", "flat")) == "flat":
        planet = FlatPlanet(p.number("gravity", "m/s^2", minimum=0.0), p.string("name", "flat"))
    else:
        planet = Planet(
            gravitational_parameter=p.number("gravitational_parameter", "m^3/s^2", above=0.0),
            equatorial_radius=p.number("equatorial_radius", "m", above=0.0),
            polar_radius=p.number("polar_radius", "m", above=0.0),
            rotation_rate=p.number("rotation_rate", "rad/s", 0.0),
            name=p.string("name", "planet"))
        if planet.polar_radius > planet.equatorial_radius:
            raise p.error("polar_radius", f"must be <= equatorial_radius ({planet.equatorial_radius:g} m)",
                          planet.polar_radius)
    p.finish()
    return planet


def build_case(data: dict, origins: dict, source: str) -> Case:
    """Validate merged case ``data`` and build the Case (``origins`` maps key paths to the file they came from)."""
    ctx = _Context(source, origins)
    top = _Table(data, (), ctx)
    info = top.table("case", {})
    name = info.string("name", Path(source.split(" ")[0]).stem)
    description = info.string("description", "")
    vehicle = info.string("vehicle", "vehicle")
    info.finish()

    planet = _read_planet(top.table("planet"))
    start, frame, release = _read_start(top.table("start", {}), planet)
    atmosphere_table = top.table("atmosphere", None)

    body_tables = top.named_tables("bodies")
    if not body_tables:
        raise top.error("bodies", "a case needs at least one body")
    bodies = {body_name: _read_body(body_name, bt) for body_name, bt in body_tables.items()}
    aerodynamic = [name for name, body in bodies.items() if body.aerodynamics is not None]
    if atmosphere_table is None and aerodynamic:
        raise top.error("atmosphere", f"required because body '{aerodynamic[0]}' has aerodynamics")
    if vehicle not in bodies:
        raise info.error("vehicle", f"must name a body; bodies are: {', '.join(bodies)}", vehicle)
    system_tables = top.named_tables("systems", {})
    systems = {sys_name: _read_system(sys_name, st, bodies) for sys_name, st in system_tables.items()}
    _check_vehicle(info, vehicle, systems)
    simulation_table = top.table("simulation")
    simulation = _read_simulation(simulation_table)
    atmosphere, wind, turbulence, gusts = None, None, None, ()
    if atmosphere_table is not None:
        ground = simulation.ground_altitude if simulation.ground_altitude is not None else 0.0
        atmosphere, wind, turbulence, gusts = _read_atmosphere(atmosphere_table, ground,
                                                               _heading(bodies[vehicle], release))
        initial = bodies[vehicle].initial
        _check_grounds(atmosphere_table, wind, turbulence, None if initial is None else initial.altitude)
    _check_mach(body_tables, bodies, atmosphere)
    if release is not None:
        _check_release(body_tables, system_tables, bodies, systems, vehicle)
    _check_events(top, body_tables, system_tables, simulation_table, bodies, systems, simulation, vehicle)
    bodies, systems = ground_relative(bodies, systems, vehicle, wind, frame, release)
    _check_connections(system_tables, bodies, systems, vehicle)
    failures = _read_failures(top.table("failures", None), systems, simulation.duration)
    top.allowed.extend(("extends", "remove"))
    top.finish()
    warnings = _check_plausible(data, ctx)
    _check_escape(body_tables, bodies, planet)
    return Case(name=name, description=description, source=source, planet=planet, start=start,
                atmosphere=atmosphere, bodies=bodies, systems=systems, simulation=simulation, vehicle=vehicle,
                wind=wind, turbulence=turbulence, gusts=gusts, key_units=dict(ctx.units), failures=failures,
                velocities_relative_to=frame, release=release, warnings=warnings)


def _check_plausible(data: dict, ctx: _Context) -> tuple:
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


def _check_escape(body_tables: dict, bodies: dict, planet) -> None:
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


def _check_vehicle(info: _Table, vehicle: str, systems: dict) -> None:
    """The vehicle is the body the parachutes hang from, never one of their canopies (a canopy placed at
    deployment has no initial state to start from)."""
    for name, system in systems.items():
        if vehicle in system.canopies:
            raise info.error("vehicle", f"is a canopy of system '{name}': case.vehicle must name the body the "
                                        "parachutes hang from", vehicle)


def _check_grounds(atmosphere_table: _Table, wind, turbulence, start_altitude: float | None) -> None:
    """A power-law wind or a turbulence field whose ground is at or above the vehicle's start would do nothing
    (no wind below its ground, a field frozen at its ground value)."""
    if start_altitude is None:
        return
    for key, model in (("wind.ground_altitude", wind), ("turbulence.ground_altitude", turbulence)):
        ground = getattr(model, "ground_altitude", None)
        if ground is not None and ground >= start_altitude:
            raise atmosphere_table.error(key, f"must be below the vehicle's start altitude ({start_altitude:g} m): "
                                              "above the flight it does nothing", ground)


def _heading(vehicle: Body, release: Release | None) -> tuple:
    """Unit (east, north) direction of the vehicle's initial horizontal velocity as the case gives it (a release's
    heading; east when it has none): where turbulence's u points without a mean wind."""
    east, north = (release.air_velocity()[:2] if release is not None
                   else (vehicle.initial.velocity_east, vehicle.initial.velocity_north))
    speed = math.hypot(east, north)
    return (east / speed, north / speed) if speed > 0.0 else (1.0, 0.0)


def _read_start(s: _Table, planet) -> tuple:
    """``[start]``: the start frame, what the initial velocities are relative to, and the release (or None)."""
    start = StartFrame(planet, s.number("latitude_deg", "deg", 0.0, minimum=-90.0, maximum=90.0),
                       s.number("longitude_deg", "deg", 0.0, minimum=-180.0, maximum=360.0))
    frame = s.string("velocities_relative_to", "ground", VELOCITY_FRAMES)
    release = _read_release(s.table("release", None))
    s.finish()
    return start, frame, release


def _read_release(t: _Table | None) -> Release | None:
    """``[start.release]``: the aircraft's airspeed (m/s), heading and flight-path angle (deg)."""
    if t is None:
        return None
    release = Release(t.number("airspeed", "m/s", minimum=0.0),
                      t.number("heading_deg", "deg", minimum=-360.0, maximum=360.0),
                      t.number("flight_path_deg", "deg", 0.0, minimum=-90.0, maximum=90.0))
    t.finish()
    return release


RELEASED_KEYS = ("velocity_north", "velocity_east", "velocity_down", "rate_x", "rate_y", "rate_z")
"""Initial-state keys a released vehicle may not have: its motion is the release's."""


def _check_release(body_tables, system_tables, bodies, systems, vehicle: str) -> None:
    """A release gives the vehicle its velocity and deploys every system at line stretch: the vehicle has no
    velocities or rates of its own, every system a deploy_time (the static line's time from the release), and no
    other free body an initial state."""
    given = [key for key in RELEASED_KEYS if key in body_tables[vehicle].data.get("initial", {})]
    if given:
        raise body_tables[vehicle].error(f"initial.{given[0]}", "a vehicle released from an aircraft "
                                         "(start.release) takes its velocity and rates from the release; remove it",
                                         body_tables[vehicle].data["initial"][given[0]])
    for name, system in systems.items():
        if system.deploy_time is None:
            raise system_tables[name].error("deploy_time", "required with start.release (s: the static line's time "
                                                           "from the release to line stretch)")
    for name, body in bodies.items():
        if name != vehicle and not body.fixed and body.initial is not None:
            raise body_tables[name].error("initial", "with start.release only the vehicle starts with a state; its "
                                                     "canopies are placed at line stretch: remove this table")


def _check_mach(body_tables, bodies, atmosphere) -> None:
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


def _check_events(top, body_tables, system_tables, simulation_table, bodies, systems, simulation, vehicle) -> None:
    """Cross-checks of deployments, cut-aways, canopies, initial states and the ground."""
    duration = simulation.duration
    canopies = {}
    for name, system in systems.items():
        st = system_tables[name]
        key = _canopy_key(st)
        if system.deploy_time is not None and system.deploy_time >= duration:
            raise st.error("deploy_time", f"must be before the end of the run (simulation.duration = {duration:g} s)",
                           system.deploy_time)
        if system.cutaway_time is not None and system.cutaway_time >= duration:
            raise st.error("cutaway_time", f"must be before the end of the run (simulation.duration = {duration:g} s)",
                           system.cutaway_time)
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
    for name, body in bodies.items():
        if body.initial is None and name not in canopies or \
                body.initial is None and systems[canopies[name]].deploy_time is None:
            raise body_tables[name].error("initial", "required (only a canopy deployed at line stretch has none)")
    ground = simulation.ground_altitude
    if ground is not None and not bodies[vehicle].fixed and ground >= bodies[vehicle].initial.altitude:
        raise simulation_table.error("ground_altitude", f"must be below the vehicle's start altitude "
                                                        f"({bodies[vehicle].initial.altitude:g} m; the default is the "
                                                        "surface, 0 m; stop_at_ground = false flies on)", ground)


def _check_connections(system_tables, bodies, systems, vehicle) -> None:
    """A system must join different bodies: lines that all end on one free body tie it to itself (its canopy would
    fall free), a system with canopies must hang them from the vehicle, and no line may run to another system's
    canopy (each canopy hangs on risers to its own system's confluence)."""
    owner = {canopy: name for name, system in systems.items() for canopy in system.canopies}
    for name, system in systems.items():
        attached = {line.body for line in system.lines}
        if len(attached) == 1 and not bodies[next(iter(attached))].fixed:
            raise system_tables[name].error("lines", f"every line attaches to body '{next(iter(attached))}': the "
                                                     "system would join that body to itself; attach its lines to two "
                                                     "bodies (e.g. bridles to the vehicle, a riser to the canopy)")
        if system.canopies and vehicle not in attached:
            key = _canopy_key(system_tables[name])
            raise system_tables[name].error(key, f"canopy '{system.canopies[0]}' is not connected to the vehicle "
                                                 f"'{vehicle}': no line of the system attaches to it",
                                            system.canopies[0])
        for line in system.lines:
            if owner.get(line.body, name) != name:
                raise system_tables[name].error(f"lines.{line.name}.attach", f"runs to canopy '{line.body}' of system "
                                                                             f"'{owner[line.body]}': a canopy's risers "
                                                                             "run to its own system's confluence",
                                                f"{line.body}.{line.point}")


def load_case(path, overrides: Mapping[str, Any] | Iterable[str] = ()) -> Case:
    """Load and validate a case file.

    Parameters
    ----------
    path : str or Path
        The case TOML file.
    overrides : mapping of dotted key to value, or iterable of ``"key=value"`` strings
        Applied after the file (and its ``extends`` chain) is merged; see the module docstring for the key syntax.

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
    data = _load_merged(path, origins)
    items = overrides.items() if isinstance(overrides, Mapping) else (parse_override(o) for o in overrides)
    applied = []
    for key, value in items:
        apply_override(data, origins, key, value, f"--set {key}={value}")
        applied.append(f"{key}={value}")
    source = _display(path) + (f" with {', '.join(applied)}" if applied else "")
    origins_top = _display(path)
    case = build_case(data, origins, origins_top)
    return _with_source(case, source)


def override_leaves(path, overrides: Mapping[str, Any]) -> dict:
    """The case values ``overrides`` change, as full dotted keys to whole values (an indexed override gives its whole
    array): what a case file extending ``path`` must set to hold them."""
    origins: dict = {}
    before = _load_merged(Path(path), origins)
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


def _with_source(case: Case, source: str) -> Case:
    from dataclasses import replace
    return replace(case, source=source)

"""Typed, validating access to the tables of a TOML input (a case, a study or a fit file).

A ``Table`` reads each key with its unit and range and records it (the case's key units, the plausibility check),
``finish()`` rejects the keys nobody asked for, and every error is a CaseError naming the file the value came from
(``Context``), the dotted field, the bad value and what is allowed.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from collections.abc import Iterable
from typing import Any

from ..errors import CaseError

REQUIRED = object()
"""The default of a key that must be given: its absence is an error."""
NO_VALUE = CaseError._NO_VALUE
"""An error that shows no value (CaseError's marker)."""


def dotted(path: Iterable) -> str:
    """The dotted key of a key path (``("bodies", "vehicle", "inertia", 0)`` -> ``bodies.vehicle.inertia[0]``)."""
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


class Context:
    """What the tables of one input share: the file each key came from (``origins``, else ``top_source``) and the
    units and paths of every key read."""

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

    def error(self, path: tuple, message: str, value: Any = NO_VALUE) -> CaseError:
        return CaseError(self.source(path), dotted(path), message, value)


class Table:
    """Typed, validating access to one table of the case; ``finish()`` rejects keys nobody asked for."""

    def __init__(self, data: Any, path: tuple, ctx: Context):
        if not isinstance(data, dict):
            raise ctx.error(path, "must be a table", data)
        self.data, self.path, self.ctx = data, path, ctx
        self.allowed: list[str] = []

    def raw(self, key: str, default: Any, unit: str):
        """The value of ``key`` as the file gives it (``default`` when absent), recorded as allowed and read (with
        its ``unit``; ``"table"`` for a table)."""
        self.allowed.append(key)
        if unit != "table":
            self.ctx.units[dotted(self.path + (key,))] = unit
            self.ctx.paths[dotted(self.path + (key,))] = self.path + (key,)
        if key in self.data:
            return self.data[key]
        if default is REQUIRED:
            raise self.ctx.error(self.path + (key,), f"required{f' ({unit})' if unit else ''} but missing")
        return default

    def error(self, key: str | None, message: str, value: Any = NO_VALUE) -> CaseError:
        """The error of ``key`` (a dotted key below this table names a key of a sub-table: ``cutaway.main2``)."""
        return self.ctx.error(self.path + (tuple(key.split(".")) if key else ()), message, value)

    def number(self, key: str, unit: str, default: Any = REQUIRED, *, minimum: float | None = None,
               above: float | None = None, maximum: float | None = None) -> float:
        value = self.raw(key, default, unit)
        if value is default and default is not REQUIRED:
            return value
        return check_number(value, unit, minimum, above, maximum, lambda m: self.error(key, m, value))

    def string(self, key: str, default: Any = REQUIRED, choices: Iterable[str] | None = None) -> str:
        value = self.raw(key, default, "")
        if value is default and default is not REQUIRED:
            return value
        if not isinstance(value, str):
            raise self.error(key, "must be a string", value)
        if choices is not None and value not in choices:
            raise self.error(key, f"must be one of: {', '.join(choices)}", value)
        return value

    def boolean(self, key: str, default: Any = REQUIRED) -> bool:
        value = self.raw(key, default, "")
        if not isinstance(value, bool):
            raise self.error(key, "must be true or false", value)
        return value

    def vector(self, key: str, unit: str, length: int = 3, default: Any = REQUIRED) -> tuple:
        value = self.raw(key, default, unit)
        if value is default and default is not REQUIRED:
            return value
        return check_vector(value, unit, length, lambda m: self.error(key, m, value))

    def sequence(self, key: str, unit: str, min_length: int = 1) -> tuple:
        value = self.raw(key, REQUIRED, unit)
        if not isinstance(value, list) or len(value) < min_length:
            raise self.error(key, f"must be a list of at least {min_length} numbers{f' ({unit})' if unit else ''}",
                             value)
        return check_vector(value, unit, len(value), lambda m: self.error(key, m, value))

    def table(self, key: str, default: Any = REQUIRED) -> Table | None:
        value = self.raw(key, default, "table")
        if value is None:
            return None
        return Table(value, self.path + (key,), self.ctx)

    def named_tables(self, key: str, default: Any = REQUIRED) -> dict:
        outer = self.table(key, default)
        if outer is None:
            return {}
        outer.allowed = list(outer.data)
        return {name: Table(sub, outer.path + (name,), self.ctx) for name, sub in outer.data.items()}

    def finish(self) -> None:
        for key in self.data:
            if key not in self.allowed:
                hint = difflib.get_close_matches(key, self.allowed, n=1)
                raise self.ctx.error(self.path + (key,), "unknown key; allowed here: " + ", ".join(self.allowed)
                                     + (f" (did you mean '{hint[0]}'?)" if hint else ""))


def check_number(value, unit, minimum, above, maximum, error) -> float:
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


def check_vector(value, unit, length, error) -> tuple:
    if not isinstance(value, list) or len(value) != length:
        raise error(f"must be a list of {length} numbers{f' ({unit})' if unit else ''}")
    return tuple(check_number(v, unit, None, None, None, error) for v in value)


def default_of(model: type, name: str) -> Any:
    """The default of dataclass ``model``'s field ``name``: what a reader returns for an absent key, so the default
    is written once, on the model."""
    default = model.__dataclass_fields__[name].default
    if default is dataclasses.MISSING:
        raise TypeError(f"{model.__name__}.{name} has no plain default")
    return default

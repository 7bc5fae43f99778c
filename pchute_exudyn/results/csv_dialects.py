"""Other tools' CSV files and the column maps that rename them to this package's names.

Dialects read (docs/tutorial.md, "Cross-checking against another tool"):

* this package's ``timeseries.csv`` and any CSV with one header row of names, then numeric rows;
* a header row that starts with ``#`` (RocketPy's ``Flight`` export: ``# Time (s),Z (m),Vz (m/s)``; its other form
  and its column map: ``rocketpy_export``), after any
  ``#`` comment lines (OpenRocket's export: comment lines, then ``# Time (s),Altitude (m),...``, with
  ``# Event ... occurred at t=...`` lines between the data rows, which are skipped);
* units in parentheses or brackets after a name (``Z (m)``, ``alt [ft]``): the column is named without them
  (``Z``) and the unit kept; a column named ``time`` (any case) or ``t``, in seconds, is the time.

The header is the last non-numeric line before the first numeric row. Cells are split by ``,`` (``;`` or a tab
when the header has no comma).

A column map entry ``THEIRS=OURS``, ``THEIRS=OURS*FACTOR``, ``THEIRS=OURS+OFFSET`` or ``THEIRS=OURS*FACTOR+OFFSET``
(``-OFFSET`` too) reads their column as ours = theirs x FACTOR + OFFSET (feet to metres: ``*0.3048``; height above
the ground to altitude: ``+1200``). THEIRS is a column's name with or without its unit.
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np

from ..errors import InputError

_UNIT = re.compile(r"^(?P<name>.*?)\s*[(\[](?P<unit>[^()\[\]]*)[)\]]\s*$")
_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_TARGET = re.compile(rf"^(?P<ours>[A-Za-z_][\w.-]*?)\s*(?:\*\s*(?P<factor>{_NUMBER}))?"
                     rf"\s*(?:(?P<sign>[+-])\s*(?P<offset>{_NUMBER}))?\s*$")
_LOOSE = re.compile(r"^(?P<ours>[A-Za-z_][\w.]*)\s*(?:\*\s*(?P<factor>[^+\-\s]\S*?|[+-]?[\d.]\S*?))?"
                    r"\s*(?:(?P<sign>[+-])\s*(?P<offset>.+?))?\s*$")


def split_unit(header: str) -> tuple[str, str]:
    """``"Z (m)"`` -> ``("Z", "m")``; a name without a unit -> ``(name, "")``."""
    header = header.strip()
    match = _UNIT.match(header)
    return (match["name"].strip(), match["unit"].strip()) if match and match["name"].strip() else (header, "")


TIME_UNITS = {"": 1.0, "s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0}
"""Units of a time column (to seconds)."""


def _numeric(row) -> bool:
    try:
        [float(cell) for cell in row]
    except ValueError:
        return False
    return bool(row)


def _cells(text: str, delimiter: str) -> list:
    cells = [cell.strip() for cell in next(csv.reader([text], delimiter=delimiter))]
    while len(cells) > 1 and cells[-1] == "":   # a trailing delimiter
        cells.pop()
    return cells


def _is_comment(line: str) -> bool:
    return line.lstrip().startswith("#")


def read_csv_columns(path) -> tuple[dict, dict, dict]:
    """Columns of a CSV file in any dialect above: (columns by name, units by name, header text by name)."""
    return read_csv_rows(path)[:3]


def read_csv_rows(path) -> tuple[dict, dict, dict, list]:
    """``read_csv_columns``, and the file's line number (from 1) of each data row: what a check of the rows names."""
    path = Path(path)
    numbered = [(number, line) for number, line in
                enumerate(path.read_text(encoding="utf-8-sig", errors="replace").splitlines(), start=1)
                if line.strip()]
    lines = [line for _, line in numbered]
    plain = next((line for line in lines if not _is_comment(line)), "")
    delimiter = next((d for d in (",", ";", "\t") if d in plain), ",")
    first = next((i for i, line in enumerate(lines) if not _is_comment(line) and _numeric(_cells(line, delimiter))),
                 None)
    if not first:
        raise InputError(f"{path}: needs a header row and at least one numeric data row")
    header_text = lines[first - 1].lstrip().lstrip("#").strip()
    names, units, texts, scales = _header(path, _cells(header_text, delimiter))
    width = len(_cells(lines[first], delimiter))
    if width != len(names):
        raise InputError(f"{path}: the header (the last line before the data: {header_text[:50]!r}) names "
                         f"{len(names)} columns but the first data row has {width} values")
    data, line_numbers = [], []
    for number, line in enumerate(lines[first:], start=first + 1):
        if _is_comment(line):   # OpenRocket's event lines between the rows
            continue
        row = _cells(line, delimiter)
        if not _numeric(row):
            raise InputError(f"{path}: row {number} is not numeric ({line[:60]!r}); expected numeric rows after the "
                             "header")
        if len(row) != len(names):
            raise InputError(f"{path}: row {number} has {len(row)} values but the header names {len(names)} columns")
        data.append([float(cell) for cell in row])
        line_numbers.append(numbered[number - 1][0])
    array = np.array(data)
    return {name: array[:, i] * scales[name] for i, name in enumerate(names)}, units, texts, line_numbers


def _header(path, headers) -> tuple[list, dict, dict, dict]:
    """Names, units, header texts and scales (a time column to seconds) of a header row."""
    names, units, texts, scales = [], {}, {}, {}
    for header in headers:
        name, unit = split_unit(header)
        scale = 1.0
        if name.lower() == "time" or name == "t":
            if unit not in TIME_UNITS:
                raise InputError(f"{path}: time column {header!r}: its unit must be one of "
                                 f"{', '.join(u for u in TIME_UNITS if u)} (or none, seconds)")
            name, scale, unit = "time", TIME_UNITS[unit], "s"
        if name in texts:
            raise InputError(f"{path}: column {name!r} appears twice in the header")
        names.append(name)
        units[name], texts[name], scales[name] = unit, header, scale
    return names, units, texts, scales


def parse_column_map(entries) -> dict:
    """Parse column map entries (module docstring) into ``{theirs: (ours, factor, offset)}``; a column mapped
    twice, or two columns mapped to one of ours, is an error."""
    mapping: dict = {}
    for entry in entries:
        theirs, sep, target = entry.partition("=")
        theirs = theirs.strip()
        match = (_TARGET.match(target.strip()) or _LOOSE.match(target.strip())) if sep and theirs else None
        if match is None:
            raise InputError(f"column map entry {entry!r}: write THEIRS=OURS, THEIRS=OURS*FACTOR or "
                             "THEIRS=OURS*FACTOR+OFFSET, e.g. alt_ft=vehicle_altitude*0.3048")
        factor = _map_number(entry, "factor", match["factor"], 1.0)
        offset = _map_number(entry, "offset", match["offset"], 0.0) * (-1.0 if match["sign"] == "-" else 1.0)
        ours = match["ours"]
        if theirs in mapping:
            raise InputError(f"column map entry {entry!r}: column {theirs!r} is already mapped "
                             f"(to {mapping[theirs][0]}); map each column once")
        taken = [name for name, (target_name, _, _) in mapping.items() if target_name == ours]
        if taken:
            raise InputError(f"column map entry {entry!r}: {ours!r} is already mapped from {taken[0]!r}; one column "
                             "of theirs per column of ours")
        mapping[theirs] = (ours, factor, offset)
    return mapping


def _map_number(entry: str, what: str, text, default: float) -> float:
    if text is None:
        return default
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"column map entry {entry!r}: the {what} {text.strip()!r} is not a number") from None
    if not math.isfinite(value) or (what == "factor" and value == 0.0):
        kind = "finite, non-zero number" if what == "factor" else "finite number"
        raise InputError(f"column map entry {entry!r}: the {what} must be a {kind}, not {text.strip()}")
    return value


def _resolve(columns: dict, mapping: dict, source, headers: dict | None) -> dict:
    """``mapping`` keyed by the columns' names (theirs given by name or by header text); a column mapped twice or
    a target that another, unmapped column already has is an error."""
    by_text = {text: name for name, text in (headers or {}).items()}
    resolved = {}
    for theirs, target in mapping.items():
        name = theirs if theirs in columns else by_text.get(theirs)
        if name is None:
            raise InputError(f"{source}: column map names column {theirs!r} that the file does not have; it has: "
                             f"{', '.join(columns)}")
        if name in resolved:
            raise InputError(f"{source}: column {name!r} is mapped twice (as {theirs!r} too); map each column once")
        resolved[name] = target
    for name, (ours, _, _) in resolved.items():
        if ours in columns and ours not in resolved and ours != name:
            raise InputError(f"{source}: the map of {name!r} to {ours!r} collides with the file's own column "
                             f"{ours!r}; map that one to another name too")
    return resolved


def map_columns(columns: dict, mapping: dict, source="", headers: dict | None = None,
                units: dict | None = None) -> tuple[dict, dict]:
    """Columns renamed and rescaled by ``mapping`` ``{theirs: (ours, factor, offset)}`` (theirs: a column's name or
    its header text with the unit, ``headers``), the others kept as they are; and their ``units`` by the new names
    (a rescaled column's unit is unknown, '')."""
    resolved = _resolve(columns, mapping, source, headers)
    mapped, mapped_units = {}, {}
    for name, values in columns.items():
        ours, factor, offset = resolved.get(name, (name, 1.0, 0.0))
        same = (factor, offset) == (1.0, 0.0)
        mapped[ours] = values if same else values * factor + offset
        mapped_units[ours] = (units or {}).get(name, "") if same else ""
    return mapped, mapped_units


def time_fault(time) -> tuple[int, str, str] | None:
    """The first sample of a time column (s) that is not finite or does not come strictly after the one before:
    (its index, what is wrong, its value in words), or None."""
    time = np.asarray(time, dtype=float)
    bad = np.flatnonzero(~np.isfinite(time))
    if len(bad):
        return int(bad[0]), "time is not a finite number", f"({float(time[bad[0]])})"
    steps = np.flatnonzero(np.diff(time) <= 0.0)
    if len(steps):
        i = steps[0]
        kind = "repeats" if time[i + 1] == time[i] else "goes back"
        return int(i + 1), f"time {kind}", f"({time[i + 1]:g} s after {time[i]:g} s); times must increase strictly"
    return None


def time_problem(time) -> str | None:
    """What is wrong with a time column (s), or None: every sample's time finite and strictly increasing."""
    fault = time_fault(time)
    return None if fault is None else f"{fault[1]} at sample {fault[0] + 1} {fault[2]}"

"""Compare two trajectories: ours against ours (full mass against SP) or another tool's against ours.

Result B is interpolated onto the times of result A inside their common time span. Another tool's columns are renamed
(and scaled, e.g. feet to metres) when it is loaded, with a column map (``results.parse_column_map``). Differences
are B - A.

Metrics (units of the compared columns):

* final vehicle altitude difference (m) and final lateral (horizontal east/north) position difference (m);
* per line: maximum and RMS absolute tension difference (N), overall and after a settling time;
* confluence lateral velocity: maximum and RMS of the horizontal velocity difference |dv_east, dv_north| (m/s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import InputError
from .results import Result


@dataclass
class Comparison:
    """Differences B - A between two results on A's times within the common span."""

    label_a: str
    label_b: str
    time: np.ndarray
    settle_time: float
    final: dict = field(default_factory=dict)        # name -> difference at the end of the common span
    lines: dict = field(default_factory=dict)        # line -> {max, rms, max_settled, rms_settled} (N)
    confluence_velocity: dict = field(default_factory=dict)  # {max, rms} of the horizontal difference (m/s)
    common: list = field(default_factory=list)       # column names compared

    def table(self) -> str:
        """Markdown table of the metrics."""
        rows = [f"Comparison: B = {self.label_b} against A = {self.label_a}, "
                f"{self.time[0]:g} to {self.time[-1]:g} s ({len(self.time)} samples); differences are B - A.", "",
                "| quantity | difference |", "|---|---|"]
        for name, value in self.final.items():
            rows.append(f"| final {name} | {value:+.4g} m |")
        for line, m in self.lines.items():
            rows.append(f"| tension {line}: max / RMS | {m['max']:.4g} / {m['rms']:.4g} N |")
            rows.append(f"| tension {line} after {self.settle_time:g} s: max / RMS | "
                        f"{m['max_settled']:.4g} / {m['rms_settled']:.4g} N |")
        if self.confluence_velocity:
            c = self.confluence_velocity
            rows.append(f"| confluence lateral velocity: max / RMS | {c['max']:.4g} / {c['rms']:.4g} m/s |")
        return "\n".join(rows) + "\n"

    def to_dict(self) -> dict:
        """The metrics as plain data (for JSON)."""
        return {"a": self.label_a, "b": self.label_b, "start": float(self.time[0]), "end": float(self.time[-1]),
                "settle_time": self.settle_time, "final": self.final, "lines": self.lines,
                "confluence_lateral_velocity": self.confluence_velocity, "columns": self.common}


def _rms(values) -> float:
    values = np.asarray(values)[np.isfinite(values)]
    return float(np.sqrt(np.mean(np.square(values)))) if len(values) else math.nan


def _max(values) -> float:
    values = np.asarray(values)[np.isfinite(values)]
    return float(values.max()) if len(values) else math.nan


def aligned(a: Result, b: Result, name: str, time: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Column ``name`` of A and of B (interpolated) on ``time``; NaN where a result has no value (a system not yet
    deployed or cut away), including across such gaps."""
    def on(result):
        values = result[name]
        finite = np.isfinite(values)
        if finite.all():
            return np.interp(time, result.time, values)
        out = np.interp(time, result.time, np.where(finite, values, 0.0))
        nearest = np.clip(np.searchsorted(result.time, time), 1, len(result.time) - 1)
        out[~(finite[nearest] & finite[nearest - 1])] = np.nan
        return out
    return on(a), on(b)


def check_times(result: Result, label: str) -> None:
    """Refuse a result whose time is not finite and strictly increasing."""
    time = result.time
    bad = np.flatnonzero(~np.isfinite(time))
    if len(bad):
        raise InputError(f"{label}: time is not a finite number at sample {bad[0] + 1} ({float(time[bad[0]])})")
    steps = np.flatnonzero(np.diff(time) <= 0.0)
    if len(steps):
        i = steps[0]
        kind = "repeats" if time[i + 1] == time[i] else "goes back"
        raise InputError(f"{label}: time {kind} at sample {i + 2} ({time[i + 1]:g} s after {time[i]:g} s); times "
                         "must increase strictly")


def check_values(result: Result, label: str, columns) -> None:
    """Refuse infinite values in ``columns``, and NaN unless the result is this package's own (a summary), where
    NaN marks a system not present."""
    for name in columns:
        values = result[name]
        wrong = np.isinf(values) if result.summary else ~np.isfinite(values)
        if wrong.any():
            i = int(np.argmax(wrong))
            raise InputError(f"{label}: column {name} is {float(values[i])} at t = {result.time[i]:g} s; compared "
                             "values must be finite numbers")


def compare_results(a: Result, b: Result, label_a: str = "A", label_b: str = "B", settle_time: float = 2.0,
                    vehicle: str = "vehicle", confluence: str = "confluence") -> Comparison:
    """Compare result ``b`` against result ``a`` (see the module docstring).

    Raises
    ------
    InputError
        When the results share no time span or no column besides ``time``, or a time or compared column is bad
        (``check_times``, ``check_values``).
    """
    for result, label in ((a, label_a), (b, label_b)):
        check_times(result, label)
    start, end = max(a.time[0], b.time[0]), min(a.time[-1], b.time[-1])
    if not end > start:
        raise InputError(f"{label_a} ({a.time[0]:g} to {a.time[-1]:g} s) and {label_b} ({b.time[0]:g} to "
                         f"{b.time[-1]:g} s) share no time span")
    common = [n for n in a.names if n != "time" and n in b]
    if not common:
        raise InputError(f"{label_a} and {label_b} share no column besides 'time' ({label_a}: "
                         f"{', '.join(a.names[1:6])}...; {label_b}: {', '.join(b.names[1:6])}...); "
                         "rename columns with a column map (--map THEIRS=OURS)")
    for result, label in ((a, label_a), (b, label_b)):
        check_values(result, label, common)
    inside = (a.time >= start - 1e-9) & (a.time <= end + 1e-9)
    time = a.time[inside]
    comparison = Comparison(label_a, label_b, time, settle_time, common=common)
    for suffix in ("altitude", "east", "north"):
        name = f"{vehicle}_{suffix}"
        if name in common:
            va, vb = aligned(a, b, name, time[-1:])   # at the end of the common span
            comparison.final[f"{vehicle} {suffix}"] = float(vb[0] - va[0])
    if f"{vehicle} east" in comparison.final and f"{vehicle} north" in comparison.final:
        comparison.final[f"{vehicle} lateral position"] = math.hypot(comparison.final[f"{vehicle} east"],
                                                                     comparison.final[f"{vehicle} north"])
    settled = time >= settle_time
    for name in common:
        if name.startswith("tension_"):
            va, vb = aligned(a, b, name, time)
            diff = np.abs(vb - va)   # NaN where either run lacks the line (a system not deployed): left out
            comparison.lines[name.removeprefix("tension_")] = {
                "max": _max(diff), "rms": _rms(diff), "max_settled": _max(diff[settled]),
                "rms_settled": _rms(diff[settled])}
    east, north = f"{confluence}_velocity_east", f"{confluence}_velocity_north"
    if east in common and north in common:
        ea, eb = aligned(a, b, east, time)
        na, nb = aligned(a, b, north, time)
        horizontal = np.hypot(eb - ea, nb - na)
        comparison.confluence_velocity = {"max": _max(horizontal), "rms": _rms(horizontal)}
    return comparison

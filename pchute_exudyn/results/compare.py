"""Compare two trajectories: ours against ours (full mass against SP) or another tool's against ours.

Result B is interpolated onto the times of result A inside their common time span. Another tool's columns are renamed
(and rescaled, e.g. feet to metres, height above the ground to altitude) when it is loaded, with a column map
(``csv_dialects.parse_column_map``). Differences are B - A.

Metrics (units of the compared columns):

* per compared column (every column the two share, or the ``columns`` asked for): the largest |B - A|, the time it
  happens and the RMS difference, on A's samples in the common span;
* for a descent (the vehicle's altitude on both sides): each side's rate of descent at chosen altitudes, time to the
  ground and rate at the ground (``descent_metrics``), each from that side's whole history;
* final vehicle altitude difference (m) and final lateral (horizontal east/north) position difference (m);
* per line: maximum and RMS absolute tension difference (N), overall and after a settling time;
* confluence lateral velocity: maximum and RMS of the horizontal velocity difference |dv_east, dv_north| (m/s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..registries.columns import UNNAMED_VEHICLE, column, owner
from .csv_dialects import time_problem
from .result import Result
from .summary import first_fall_through


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
    columns: dict = field(default_factory=dict)      # name -> {max, time, rms, unit}: |B - A| per compared column
    descent: dict = field(default_factory=dict)      # descent_metrics: {ground, altitudes, a, b}; {} without
    missing_descent: str = ""                        # why there are no descent figures, when one side has a height

    def column_table(self) -> list:
        """Markdown rows: per compared column its largest and RMS difference and where."""
        rows = ["| column | largest abs(B - A) | at t (s) | RMS | unit |", "|---|---|---|---|---|"]
        for name, m in self.columns.items():
            rows.append(f"| {name} | {m['max']:.4g} | {m['time']:.4g} | {m['rms']:.4g} | {m['unit']} |")
        return rows

    def descent_table(self) -> list:
        """Markdown rows: the descent figures of each side and their difference."""
        d = self.descent
        rows = [f"Descent (the vehicle's centre of mass; ground at {d['ground']:g} m):", "",
                "| quantity | A | B | B - A | (B - A) / A |", "|---|---|---|---|---|"]
        a, b = d["a"], d["b"]
        named = [(f"rate of descent at {h:g} m (m/s)", a["rates"][i], b["rates"][i])
                 for i, h in enumerate(d["altitudes"])]
        named += [("time to ground (s)", a["ground_time"], b["ground_time"]),
                  ("rate of descent at the ground (m/s)", a["ground_rate"], b["ground_rate"])]
        for label, va, vb in named:
            rel = (vb - va) / va if va else math.nan
            rows.append(f"| {label} | {va:.4f} | {vb:.4f} | {vb - va:+.4f} | {rel:+.2e} |")
        notes = [f"{side}: {d[side.lower()]['note']}" for side in ("A", "B") if d[side.lower()]["note"]]
        return rows + ([""] + notes if notes else [])

    def table(self) -> str:
        """Markdown table of the metrics."""
        rows = [f"Comparison: B = {self.label_b} against A = {self.label_a}, "
                f"{self.time[0]:g} to {self.time[-1]:g} s ({len(self.time)} samples); differences are B - A.", ""]
        if self.descent:
            rows += self.descent_table() + [""]
        elif self.missing_descent:
            rows += [f"No descent figures: {self.missing_descent}.", ""]
        if self.columns:
            rows += self.column_table() + [""]
        rows += ["| quantity | difference |", "|---|---|"]
        for name, value in self.final.items():
            rows.append(f"| final {name} | {value:+.4g} m |")
        settled = bool((self.time >= self.settle_time).any())
        for line, m in self.lines.items():
            rows.append(f"| tension {line}: max / RMS | {m['max']:.4g} / {m['rms']:.4g} N |")
            if settled:
                rows.append(f"| tension {line} after {self.settle_time:g} s: max / RMS | "
                            f"{m['max_settled']:.4g} / {m['rms_settled']:.4g} N |")
        if self.lines and not settled:   # say why, rather than rows of nan
            rows.append(f"| tensions after {self.settle_time:g} s | none: the common span ends at "
                        f"{self.time[-1]:g} s |")
        if self.confluence_velocity:
            c = self.confluence_velocity
            rows.append(f"| confluence lateral velocity: max / RMS | {c['max']:.4g} / {c['rms']:.4g} m/s |")
        return "\n".join(rows) + "\n"

    def to_dict(self) -> dict:
        """The metrics as plain data (for JSON)."""
        return {"a": self.label_a, "b": self.label_b, "start": float(self.time[0]), "end": float(self.time[-1]),
                "settle_time": self.settle_time, "final": self.final, "lines": self.lines,
                "confluence_lateral_velocity": self.confluence_velocity, "compared": self.common,
                "columns": self.columns, "descent": self.descent}


def _finite_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


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
    problem = time_problem(result.time)
    if problem is not None:
        raise InputError(f"{label}: {problem}")


# Largest magnitude a compared value may have (m, m/s, N, Pa, kg, ...): far beyond any quantity of a descent (the
# Earth's radius is 6.4e6 m, a line load above 1e9 N breaks any line), so a larger one is a broken file, and below
# it every difference squared (< 4e30) and its mean stay far from the float overflow at 1.8e308.
LARGEST_VALUE = 1e15


def check_values(result: Result, label: str, columns) -> None:
    """Refuse infinite values in ``columns`` and magnitudes beyond ``LARGEST_VALUE``, and NaN unless the result is
    this package's own (a summary), where NaN marks a system not present."""
    for name in columns:
        values = result[name]
        wrong = np.isinf(values) if result.summary is not None else ~np.isfinite(values)
        if wrong.any():
            i = int(np.argmax(wrong))
            raise InputError(f"{label}: column {name} is {float(values[i])} at t = {result.time[i]:g} s; compared "
                             "values must be finite numbers")
        huge = np.abs(np.where(np.isnan(values), 0.0, values)) > LARGEST_VALUE
        if huge.any():
            i = int(np.argmax(huge))
            raise InputError(f"{label}: column {name} is {float(values[i]):g} at t = {result.time[i]:g} s (sample "
                             f"{i + 1}); compared values must be within +-{LARGEST_VALUE:g}")


def column_differences(a: Result, b: Result, names, time) -> dict:
    """Per column: the largest |B - A| on ``time`` (s), when it happens and the RMS difference; NaN samples (a
    system not present on one side) are left out, and a column without a common finite sample is left out too."""
    found = {}
    for name in names:
        va, vb = aligned(a, b, name, time)
        diff = np.abs(vb - va)
        finite = np.isfinite(diff)
        if not finite.any():
            continue
        i = int(np.argmax(np.where(finite, diff, -1.0)))
        found[name] = {"max": float(diff[i]), "time": float(time[i]), "rms": _rms(diff),
                       "unit": a.units.get(name) or b.units.get(name) or ""}
    return found


def descent_profile(result: Result, vehicle: str = UNNAMED_VEHICLE) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time s, altitude m, rate of descent m/s) of a side: its ``<vehicle>_velocity_down`` where it has one, else
    -d(altitude)/dt; samples without an altitude left out."""
    time, altitude = result.time, result[column("{owner}_altitude", vehicle)]
    keep = np.isfinite(altitude)
    velocity = column("{owner}_velocity_down", vehicle)
    with np.errstate(all="ignore"):   # times too close for the altitude's change: refused by _check_rates
        rate = result[velocity][keep] if velocity in result else -np.gradient(altitude[keep], time[keep])
    return time[keep], altitude[keep], rate


def _check_rates(sides, vehicle: str) -> None:
    """Refuse a side whose rate of descent (m/s, ``descent_profile``) is no number or beyond ``LARGEST_VALUE``: its
    ``<vehicle>_velocity_down`` as ``check_values`` does, else -d(altitude)/dt (``sides``: (result, label) pairs)."""
    altitude, velocity = column("{owner}_altitude", vehicle), column("{owner}_velocity_down", vehicle)
    for result, label in sides:
        if altitude in result and velocity in result:
            check_values(result, label, [velocity])
        elif altitude in result:
            time, _, rate = descent_profile(result, vehicle)
            wrong = ~(np.abs(rate) <= LARGEST_VALUE)   # NaN and inf too
            if wrong.any():
                i = int(np.argmax(wrong))
                raise InputError(f"{label}: rate of descent -d({altitude})/dt is {float(rate[i]):g} m/s at t = "
                                 f"{time[i]:g} s; it must be within +-{LARGEST_VALUE:g} (are the times too close?)")


def descent_side(result: Result, vehicle: str, altitudes, ground: float) -> dict:
    """One side's descent: rate of descent (m/s) at each altitude (m) on the way down, time to ``ground`` (s) and
    the rate there. The rate is the side's ``<vehicle>_velocity_down`` where it has one, else -d(altitude)/dt. A
    history that ends above the ground while descending reaches it by extrapolation at its last rate (noted)."""
    time, altitude, rate = descent_profile(result, vehicle)
    rates = []
    for level in altitudes:
        when = first_fall_through(time, altitude, level)
        rates.append(float(np.interp(when, time, rate)) if when is not None else math.nan)
    when, note = first_fall_through(time, altitude, ground), ""
    with np.errstate(over="ignore"):   # a last rate near 0: no time to extrapolate to
        remaining = (altitude[-1] - ground) / rate[-1] if rate[-1] > 0.0 else math.inf
    if when is None and altitude[-1] > ground and math.isfinite(remaining):
        when = float(time[-1] + remaining)
        note = (f"ends {altitude[-1] - ground:.3g} m above the ground at {time[-1]:g} s; time to ground extrapolated "
                f"at its last rate, {rate[-1]:.4g} m/s")
    elif when is None:
        note = f"does not reach the ground (lowest {altitude.min():.4g} m)"
    ground_rate = (math.nan if when is None else float(np.interp(when, time, rate)) if when <= time[-1]
                   else float(rate[-1]))
    return {"rates": rates, "ground_time": math.nan if when is None else when, "ground_rate": ground_rate,
            "note": note}


def descent_metrics(a: Result, b: Result, vehicle: str = UNNAMED_VEHICLE, altitudes=None, ground: float = 0.0) -> dict:
    """Both sides' descent figures (``descent_side``) at ``altitudes`` (m; default: a quarter, half and three
    quarters of the way down the altitudes both sides cover, above the ground); {} when a side has no altitude."""
    name = column("{owner}_altitude", vehicle)
    if name not in a or name not in b:
        return {}
    if altitudes is None:
        tops = [np.nanmax(r[name]) for r in (a, b)]
        bottoms = [max(np.nanmin(r[name]), ground) for r in (a, b)]
        top, bottom = min(tops), max(bottoms)
        altitudes = [float(top - f * (top - bottom)) for f in (0.25, 0.5, 0.75)] if top > bottom else []
    altitudes = [float(h) for h in altitudes]
    return {"ground": ground, "altitudes": altitudes, "a": descent_side(a, vehicle, altitudes, ground),
            "b": descent_side(b, vehicle, altitudes, ground)}


def _check_altitudes(sides, vehicle: str, altitudes) -> None:
    """Refuse an altitude (m) of ``altitudes`` that a side's vehicle never descends through: its rate of descent
    there would be no number (``sides``: (result, label) pairs)."""
    name = column("{owner}_altitude", vehicle)
    for result, label in sides:
        if name not in result:
            return
        time, altitude, _ = descent_profile(result, vehicle)
        for level in altitudes:
            if first_fall_through(time, altitude, level) is None:
                raise InputError(f"altitudes (--altitudes) = {level:g}: {label} never descends through {level:g} m "
                                 f"(its {name} spans {np.nanmin(altitude):.6g} to {np.nanmax(altitude):.6g} m): "
                                 "each must be an altitude both sides descend through")


def _ground(sides, vehicle: str, ground: float | None) -> float:
    """The ground altitude (m): ``ground`` when given, refused when not finite, outside a case's ground range or not
    below a side's highest vehicle altitude (its time to the ground would be no number); else the first side's
    summary's, else 0 (``sides``: (result, label) pairs)."""
    if ground is None:   # a summary's ground that is not a finite number (a file edited by hand) is not used
        grounds = (getattr(result.summary, "ground_altitude", None) for result, _ in sides)
        return next((float(value) for value in grounds if _finite_number(value)), 0.0)
    from ..case.plausible import check_value

    if not _finite_number(ground):
        raise InputError(f"ground (--ground) = {ground!r}: must be a finite altitude (m)")
    refusal, _ = check_value("simulation.ground_altitude", float(ground))   # a case's ground: the same range
    if refusal is not None:
        raise InputError(f"ground (--ground) = {ground:g}: {refusal}")
    name = column("{owner}_altitude", vehicle)
    if not all(name in result and np.isfinite(result[name]).any() for result, _ in sides):
        return ground   # no descent figures: no time to the ground to refuse
    for result, label in sides:
        top = np.nanmax(result[name])
        if not ground < top:   # at the top itself there is no fall to it either
            raise InputError(f"ground (--ground) = {ground:g}: {label} never descends to {ground:g} m (its {name} "
                             f"is at most {top:.6g} m): must be below the highest altitude of both sides")
    return ground


def _missing_descent(a: Result, b: Result, vehicle: str) -> str:
    """Why a comparison has no descent figures when a side has the vehicle's height but not its altitude (a log's
    height mapped to ``<vehicle>_height``): say so rather than drop the table silently."""
    altitude, height = column("{owner}_altitude", vehicle), column("{owner}_height", vehicle)
    sides = [label for label, r in (("A", a), ("B", b)) if altitude not in r and height in r]
    if not sides:
        return ""
    return (f"they are read from {altitude} on both sides, and {' and '.join(sides)} has {height} only: map its "
            f"height to {altitude} with the ground's altitude added (--map 'h=" + altitude + "+<ground m>'), or "
            "compare a flight log with a run folder without a map (docs/flight-logs.md)")


def _final_differences(a: Result, b: Result, vehicle: str, common: list, end) -> dict:
    """The vehicle's altitude, east and north differences (m, b - a) at ``end`` (the common span's last time, as a
    one-element array), and its lateral position difference where both east and north are compared."""
    final = {}
    for template, suffix in (("{owner}_altitude", "altitude"), ("{owner}_east", "east"), ("{owner}_north", "north")):
        name = column(template, vehicle)
        if name in common:
            va, vb = aligned(a, b, name, end)
            final[f"{vehicle} {suffix}"] = float(vb[0] - va[0])
    if f"{vehicle} east" in final and f"{vehicle} north" in final:
        final[f"{vehicle} lateral position"] = math.hypot(final[f"{vehicle} east"], final[f"{vehicle} north"])
    return final


def compare_results(a: Result, b: Result, label_a: str = "A", label_b: str = "B", settle_time: float = 2.0,
                    vehicle: str = UNNAMED_VEHICLE, confluence: str = "confluence", columns=None, altitudes=None,
                    ground: float | None = None) -> Comparison:
    """Compare result ``b`` against result ``a`` (see the module docstring): ``columns`` (default every shared
    one) column by column; a descent at ``altitudes`` (m) with the ground at ``ground`` (m; default the ground of
    either side's summary, else 0).

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
    comparison.columns = column_differences(a, b, common if columns is None else columns, time)
    _check_rates(((a, label_a), (b, label_b)), vehicle)
    ground = _ground(((a, label_a), (b, label_b)), vehicle, ground)
    if altitudes is not None:
        _check_altitudes(((a, label_a), (b, label_b)), vehicle, altitudes)
    comparison.descent = descent_metrics(a, b, vehicle, altitudes, ground)
    comparison.missing_descent = _missing_descent(a, b, vehicle) if not comparison.descent else ""
    comparison.final = _final_differences(a, b, vehicle, common, time[-1:])
    settled = time >= settle_time
    for name in common:
        line = owner(name, "tension_{owner}")
        if line is not None:
            va, vb = aligned(a, b, name, time)
            diff = np.abs(vb - va)   # NaN where either run lacks the line (a system not deployed): left out
            comparison.lines[line] = {
                "max": _max(diff), "rms": _rms(diff), "max_settled": _max(diff[settled]),
                "rms_settled": _rms(diff[settled])}
    east, north = column("{owner}_velocity_east", confluence), column("{owner}_velocity_north", confluence)
    if east in common and north in common:
        ea, eb = aligned(a, b, east, time)
        na, nb = aligned(a, b, north, time)
        horizontal = np.hypot(eb - ea, nb - na)
        comparison.confluence_velocity = {"max": _max(horizontal), "rms": _rms(horizontal)}
    return comparison

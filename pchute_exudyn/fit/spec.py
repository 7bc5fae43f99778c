"""Fit files (``pchute fit FIT.toml``): the base case, how each run integrates, the free keys with their bounds and
the targets, validated into a ``FitSpec``. Paths in a fit file are relative to it.

    [fit]
    name = "PA1 calibration"
    case = "../cases/cev_pa1.toml"
    method = "sp"                 # and integrator, step, and the method's options, as a study configuration

    [free."main_canopy.aerodynamics.axial_coefficient"]   # a --set key
    low = 0.6
    high = 1.0
    initial = 0.76                # default: the case's value

    [[targets]]                   # an event's time (s): start, deploy <system>, cutaway <system>, descent_rate,
    event = "touchdown"           # touchdown, separation <body> (as the run's summary names them)
    time = 78.87
    std = 0.1                     # or weight = 10 (1 / std)

    [[targets]]                   # a column's final value
    final = "capsule_altitude"
    value = 1200.0
    std = 0.5

    [[targets]]                   # a measured time history: every sample of one column of a CSV file
    history = "flight.csv"
    column = "tension_main_riser" # this package's column name (after map)
    map = ["T_lbf=tension_main_riser*4.44822"]   # their=ours[*factor], as pchute compare --map
    std = 2000.0
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..boundary import check_path
from ..case.fields import Context, Table
from ..case.files import load_merged, read_toml
from ..case.loader import load_case, override_leaves
from ..errors import CaseError, InputError
from ..results.csv_dialects import map_columns, parse_column_map, read_csv_columns, time_problem
from ..study.spec import Configuration, read_configuration

MAX_RUNS = 200
"""The default budget of runs (``[fit] max_runs``; Jacobian runs included) after which the fit stops and reports
the best point it reached."""
STD_RANGE = (1e-9, 1e6)
"""A target's std (or 1 / weight) must lie within these multiples of its scale: its largest measured magnitude, at
least 1 in the target's unit (a target measured near 0 keeps a usable range). Below, the residuals overflow; above,
the target weighs nothing and the fit would report its starting values as the answer."""


@dataclass(frozen=True)
class Free:
    """A free case key: ``--set`` syntax, bounds and starting value (in the key's unit)."""

    key: str
    low: float
    high: float
    initial: float


@dataclass(frozen=True)
class Target:
    """One measured quantity: ``kind`` "event" (an event's time, s), "final" (a column's last value), "history" (a
    column at ``times``) or "log" (a flight log's descent: the vehicle's height above the ground at ``times``, s
    after the apogee); ``name`` the event label or column; ``measured`` the value(s); ``std`` the standard deviation
    (same unit), ``weighted`` when given as a weight (1 / std) instead."""

    kind: str
    name: str
    measured: tuple
    std: float
    weighted: bool
    times: tuple = ()

    @property
    def size(self) -> int:
        return len(self.measured)

    def label(self) -> str:
        return {"event": f"event {self.name} (s)", "final": f"final {self.name}",
                "history": f"history {self.name}", "log": f"log {self.name} (m)"}[self.kind]


@dataclass(frozen=True)
class FitSpec:
    """A validated fit file."""

    name: str
    source: Path
    case: Path
    configuration: Configuration
    free: tuple
    targets: tuple
    text: str
    max_runs: int = MAX_RUNS

    def overrides(self, values) -> dict:
        """The case overrides for free-key ``values`` (one per free key, in order)."""
        return {f.key: float(v) for f, v in zip(self.free, values)}

    def measured(self) -> np.ndarray:
        return np.concatenate([np.asarray(t.measured, float) for t in self.targets])

    def scales(self) -> np.ndarray:
        """Each residual's standard deviation (the residual is (model - measured) / scale)."""
        return np.concatenate([np.full(t.size, t.std) for t in self.targets])

    def fingerprint(self) -> str:
        """The fit file, the case file and every target's data: a resumed fit must match it."""
        digest = hashlib.sha256(self.text.encode())
        digest.update(Path(self.case).read_bytes())
        for t in self.targets:
            digest.update(repr((t.kind, t.name, t.measured, t.times, t.std)).encode())
        return digest.hexdigest()

    def source_files(self) -> list:
        """Every file the fit reads: the fit file, its case with its ``extends`` chain and data tables, and the
        targets' history CSV files (their contents' digests are kept in the fit folder: a resume after one changed
        is refused)."""
        import tomllib

        from ..results.journal import case_files

        files = [Path(self.source).resolve()] + case_files(self.case)
        for target in tomllib.loads(self.text).get("targets", []):
            for kind in ("history", "log"):
                if isinstance(target, dict) and isinstance(target.get(kind), str):
                    files.append((Path(self.source).parent / target[kind]).resolve())
        return files


def load_fit(path) -> FitSpec:
    """Read and validate fit file ``path`` (CaseError or InputError naming the key)."""
    path = check_path(path, "path", "fit file (TOML)")
    if not path.is_file():
        raise InputError(f"fit file not found: {path}")
    data = read_toml(path, kind="fit")
    ctx = Context(str(path), {})
    top = Table(data, (), ctx)
    f = top.table("fit")
    name = f.string("name", path.stem)
    case_path = (path.parent / f.string("case")).resolve()
    if not case_path.is_file():
        raise f.error("case", f"case file not found: {case_path}", f.data["case"])
    max_runs = _read_max_runs(f)
    configuration = read_configuration(f, single_step=True)[0]
    case = load_case(case_path)   # the base case must load before its keys are checked
    free_tables = top.named_tables("free")
    if not free_tables:
        raise top.error("free", "a fit needs at least one free key: [free.\"<key>\"] with low and high")
    free = tuple(_read_free(key, t, case_path) for key, t in free_tables.items())
    raw_targets = top.raw("targets", None, "")
    if not isinstance(raw_targets, list) or not raw_targets:
        raise top.error("targets", "a fit needs at least one [[targets]] table (event, final or history)")
    targets = tuple(_read_target(Table(t, ("targets", i), ctx), path.parent, case)
                    for i, t in enumerate(raw_targets))
    _check_separations(ctx, targets, sorted(case.separations))
    top.finish()
    if max_runs < len(free) + 2:
        raise f.error("max_runs", f"must be >= {len(free) + 2}: the starting run and one Jacobian ({len(free)} runs, "
                                  "one per free key) plus a step", max_runs)
    return FitSpec(name, path, case_path, configuration, free, targets, path.read_text(), max_runs)


def _check_separations(ctx: Context, targets: tuple, bodies: list) -> None:
    """Event "separation" names one body's only when one body separates: else the choices ("separation <body>")."""
    for i, target in enumerate(targets):
        if target.kind == "event" and target.name == "separation" and len(bodies) > 1:
            choices = " or ".join(f"'separation {body}'" for body in bodies)
            raise ctx.error(("targets", i, "event"), f"{len(bodies)} bodies separate in the case "
                                                     f"({', '.join(bodies)}): name one: {choices}", target.name)


def _read_max_runs(f: Table) -> int:
    value = f.raw("max_runs", MAX_RUNS, "")
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 1_000_000:
        raise f.error("max_runs", "must be an integer from 1 to 1000000 (the fit's budget of runs)", value)
    return value


def _read_free(key: str, t: Table, case_path: Path) -> Free:
    low, high = t.number("low", ""), t.number("high", "")
    if not low < high:
        raise t.error("high", f"must be > low ({low:g})", high)
    if "initial" in t.data:
        initial = t.number("initial", "", minimum=low, maximum=high)
    else:
        try:
            case_value = _case_value(case_path, key)
        except CaseError as exc:
            raise t.error(None, f"does not apply to the case: {exc.detail}") from None
        if not low <= case_value <= high:
            raise t.error("initial", f"the case's value {case_value:g} lies outside [low, high] = [{low:g}, {high:g}]: "
                                     "give initial or widen the bounds")
        initial = case_value
    t.finish()
    try:
        load_case(case_path, {key: initial})
    except CaseError as exc:
        raise t.error(None, f"does not apply to the case: {exc.detail}") from None
    return Free(key, low, high, float(initial))


def _case_value(case_path: Path, key: str) -> float:
    """The case's own value of ``key`` (a --set key): where overriding it with a marker changes the case."""
    marker = 987654321.125
    merged = load_merged(case_path, {})
    for full, value in override_leaves(case_path, {key: marker}).items():
        node = merged
        try:
            for part in full.split("."):
                node = node[part]
            return float(node[value.index(marker)] if isinstance(value, list) else node)
        except (KeyError, TypeError, ValueError):
            break
    raise CaseError(str(case_path), key, "the case does not set it: give initial")


def _read_target(t: Table, folder: Path, case) -> Target:
    kinds = [k for k in ("event", "final", "history", "log") if k in t.data]
    if len(kinds) != 1:
        raise t.error(None, "give exactly one of: event = \"...\" (with time), final = \"<column>\" (with value), "
                            "history = \"<file.csv>\" (with column) or log = \"<flight log>\"")
    kind = kinds[0]
    if "std" in t.data and "weight" in t.data:
        raise t.error("weight", "give std or weight, not both")
    if "weight" in t.data:
        std, weighted = 1.0 / t.number("weight", "", above=0.0), True
    else:
        std, weighted = t.number("std", "same unit as the target", above=0.0), False
    if kind == "event":
        target = Target("event", t.string("event"), (t.number("time", "s"),), std, weighted)
    elif kind == "final":
        target = Target("final", t.string("final"), (t.number("value", ""),), std, weighted)
    elif kind == "log":
        target = _log_target(t, folder, case, std, weighted)
    else:
        file = (folder / t.string("history")).resolve()
        if not file.is_file():
            raise t.error("history", f"file not found: {file}", t.data["history"])
        column = t.string("column")
        entries = t.raw("map", [], "")
        if not isinstance(entries, list):
            raise t.error("map", "must be a list of \"theirs=ours[*factor]\" entries", entries)
        try:
            raw, _, headers = read_csv_columns(file)
            columns, _ = map_columns(raw, parse_column_map(entries), file, headers)
        except InputError as exc:
            raise t.error("map", str(exc)) from None
        if "time" not in columns:
            raise t.error("history", f"{file.name} has no 'time' column (map one: map = [\"t=time\"])")
        if column not in columns:
            raise t.error("column", f"{file.name} has no column {column!r} (after the map); it has: "
                                    f"{', '.join(c for c in columns if c != 'time')}", column)
        values = columns[column]
        problem = time_problem(columns["time"])
        if problem is not None:
            raise t.error("history", f"{file.name}: {problem} (every sample needs its time, s)", t.data["history"])
        keep = np.isfinite(values)
        target = Target("history", column, tuple(values[keep].tolist()), std, weighted,
                        tuple(columns["time"][keep].tolist()))
    t.finish()
    if not all(math.isfinite(v) for v in target.measured):
        raise t.error(None, "measured values must be finite")
    _check_std(t, target)
    return target


def _log_target(t: Table, folder: Path, case, std: float, weighted: bool) -> Target:
    """A flight log's descent (``results.flight_log``): its heights above the pad from the apogee to the touchdown,
    barometric ones read through the case's air (``physics.barometric``), spikes (samples SPIKE from the running
    median) left out; times after the apogee. The model's value: its vehicle's height above the ground that long
    after its own highest point."""
    from ..physics.atmosphere import OutsideAtmosphereError
    from ..physics.flight_phases import APOGEE_WINDOW, SPIKE, running_median
    from ..registries.columns import column
    from ..results.flight_log import read_flight_log
    from ..results.log_compare import log_descent

    file = (folder / t.string("log")).resolve()
    if not file.is_file():
        raise t.error("log", f"file not found: {file}", t.data["log"])
    log = read_flight_log(file)
    ground = case.simulation.ground_altitude
    air = None if case.atmosphere is None else (lambda z: case.atmosphere.states(z + ground)[0])
    try:
        _, times, heights = log_descent(log, air, ground)
    except OutsideAtmosphereError as exc:
        raise t.error("log", f"its heights are read through the case's air, which does not reach them: {exc}",
                      t.data["log"]) from None
    keep = np.abs(heights - running_median(times, heights, APOGEE_WINDOW)) <= SPIKE
    return Target("log", column("{owner}_height", case.vehicle), tuple(heights[keep].tolist()), std, weighted,
                  tuple(times[keep].tolist()))


def _check_std(t: Table, target: Target) -> None:
    """The std within STD_RANGE times the target's scale (see STD_RANGE)."""
    scale = max(max((abs(v) for v in target.measured), default=0.0), 1.0)
    low, high = STD_RANGE[0] * scale, STD_RANGE[1] * scale
    if not low <= target.std <= high:
        key, value = ("weight", 1.0 / target.std) if target.weighted else ("std", target.std)
        raise t.error(key, f"the std must be within {low:.3g}..{high:.3g} ({STD_RANGE[0]:g} to {STD_RANGE[1]:g} "
                           f"times the largest measured magnitude or 1, {scale:.6g}): outside, the target overflows or "
                           "weighs nothing", value)

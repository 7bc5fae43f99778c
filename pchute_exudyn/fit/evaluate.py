"""One evaluation of a fit: a run at given free-key values and the model's value of every target (in a worker)."""

from __future__ import annotations

import time
from dataclasses import dataclass, fields, replace

import numpy as np

from ..errors import PchuteError
from ..results.summary import RunSummary


def event_times(summary: RunSummary) -> dict:
    """Event label -> time (s) of a run's summary: 'deploy main', 'cutaway drogue', 'descent_rate', 'touchdown'
    (the first of each), 'separation <body>'; a cluster's canopy events name the canopy too ('disreef main main2')."""
    times = {}
    for event in summary.events:
        names = (getattr(event, key, None) for key in ("system", "canopy"))
        label = " ".join([event.kind, *(str(name) for name in names if name is not None)])
        times.setdefault(label, event.time)
        body = getattr(event, "body", None)
        if body is not None:   # 'separation heat_shield'; 'separation' alone is the only separating body's
            times.setdefault(f"{label} {body}", event.time)
    return times


def predictions(result, targets) -> tuple[list, list]:
    """The model's value of each target's measured value(s), and the event targets that never happened (their
    model time is the run's end: a continuous stand-in that pulls the fit back towards the event). A column target
    the run does not have gives NaN values and is listed too."""
    events = event_times(result.summary)
    end = float(result.time[-1])
    values, missing = [], []
    for target in targets:
        if target.kind != "event" and target.name not in result:
            missing.append(target.name)
            values.extend([float("nan")] * target.size)
            continue
        if target.kind == "event":
            if target.name not in events:
                missing.append(target.name)
            values.append(float(events.get(target.name, end)))
        elif target.kind == "final":
            column = result[target.name]
            finite = column[np.isfinite(column)]
            values.append(float(finite[-1]) if len(finite) else float("nan"))
        else:
            column = result[target.name]
            keep = np.isfinite(column)
            times = np.asarray(target.times)
            if target.kind == "log":   # the log's times count from its apogee: the run's from its highest point
                top = result.time[int(np.nanargmax(np.where(keep, column, -np.inf)))]
                values.extend(aligned_to_log(result.time[keep], column[keep], times + top, target.measured).tolist())
            else:
                values.extend(np.interp(times, result.time[keep], column[keep]).tolist())
    return values, missing


ALIGN_STEPS = 4
"""Gauss-Newton steps of a run's alignment to a log (``aligned_to_log``): the shifts are linear to 1e-6 in two."""


def aligned_to_log(time, height, times, measured) -> np.ndarray:
    """A run's ``height`` (m, at its ``time`` s) at a log's sample ``times`` (s on the run's clock), shifted by the
    time and the height that best match the log's ``measured`` heights (least squares): the log's apogee time and pad
    level are known only to its noise, a few hundredths of a second and tenths of a metre, which would otherwise bias
    every fitted value by more than its standard error. The two shifts are profiled out of each run (its residuals
    are those left after them), so the fit's standard errors include their uncertainty."""
    rate = np.gradient(height, time)
    measured = np.asarray(measured, float)
    delay = offset = 0.0
    for _ in range(ALIGN_STEPS):
        values = np.interp(times + delay, time, height) + offset
        jacobian = np.column_stack([np.interp(times + delay, time, rate), np.ones(len(times))])
        step, *_ = np.linalg.lstsq(jacobian, measured - values, rcond=None)
        delay, offset = delay + step[0], offset + step[1]
    return np.interp(times + delay, time, height) + offset


@dataclass(frozen=True)
class Evaluation:
    """One run of a fit: a line of ``evaluations.jsonl`` (``to_dict``; ``from_dict`` reads it back).

    Attributes
    ----------
    status : str
        "ok" or "failed".
    error : str
        Why the run failed ("" for an ok run).
    values : list of float
        The free keys' values the run was made at (in the keys' units, ``FitSpec.free`` order).
    predictions : list of float or None
        The model's value of each target's measured value(s) (``predictions``; the targets' units); None: failed.
    missing_events : list of str or None
        The targets the run did not have (events that never happened, columns it lacks).
    columns : list of str or None
        The run's columns (``registries.columns``), for the message naming a mistyped target column.
    events : dict or None
        The run's event labels and times (s, ``event_times``).
    end_time : float or None
        The run's last sample (s).
    wall_time : float or None
        The whole evaluation in its worker (s).
    evaluation : int or None
        Its number in the fit folder (``FitStore.add``), None until recorded.
    """

    status: str
    error: str
    values: list
    predictions: list | None = None
    missing_events: list | None = None
    columns: list | None = None
    events: dict | None = None
    end_time: float | None = None
    wall_time: float | None = None
    evaluation: int | None = None

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def to_dict(self) -> dict:
        """The evaluation's line of ``evaluations.jsonl``: its fields in order, each only when set."""
        return {f.name: getattr(self, f.name) for f in fields(self)
                if getattr(self, f.name) is not None or f.name in ("status", "error", "values")}

    @classmethod
    def from_dict(cls, data: dict) -> Evaluation:
        """A line of ``evaluations.jsonl`` (checked by ``FitStore``), of this version or an earlier one."""
        return cls(**{f.name: data.get(f.name, "" if f.name == "error" else None) for f in fields(cls)})


def evaluate(case_file: str, overrides: dict, configuration, targets) -> Evaluation:
    """Run the case with ``overrides``; never raises: a failure is a record with its error text."""
    from ..case import load_case
    from ..run.simulation import simulate

    started = time.perf_counter()
    values = list(overrides.values())
    try:
        case = load_case(case_file, overrides)
        c = configuration
        result = simulate(case, c.method, c.integrator, c.step, **dict(c.options))
        predicted, missing = predictions(result, targets)
        record = Evaluation("ok", "", values, predicted, missing, list(result.names), event_times(result.summary),
                            float(result.time[-1]))
    except PchuteError as exc:
        record = Evaluation("failed", str(exc), values)
    except Exception as exc:  # a bug, not a user mistake: still recorded
        record = Evaluation("failed", f"internal error: {exc!r}", values)
    return replace(record, wall_time=time.perf_counter() - started)

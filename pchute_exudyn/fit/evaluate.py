"""One evaluation of a fit: a run at given free-key values and the model's value of every target (in a worker)."""

from __future__ import annotations

import time

import numpy as np

from ..errors import PchuteError


def event_times(summary: dict) -> dict:
    """Event label -> time (s) of a run's summary: 'deploy main', 'cutaway drogue', 'descent_rate', 'touchdown'
    (the first of each), 'separation <body>'; a cluster's canopy events name the canopy too ('disreef main main2')."""
    times = {}
    for e in summary.get("events", []):
        label = " ".join(str(e[key]) for key in ("event", "system", "canopy") if key in e)
        times.setdefault(label, e["time"])
        if "body" in e:   # 'separation heat_shield'; 'separation' alone is the only separating body's
            times.setdefault(f"{label} {e['body']}", e["time"])
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
            values.extend(np.interp(target.times, result.time[keep], column[keep]).tolist())
    return values, missing


def evaluate(case_file: str, overrides: dict, configuration, targets) -> dict:
    """Run the case with ``overrides``; never raises: a failure is a record with its error text."""
    from ..case import load_case
    from ..run.simulation import simulate

    started = time.perf_counter()
    record = {"status": "ok", "error": "", "values": list(overrides.values())}
    try:
        case = load_case(case_file, overrides)
        c = configuration
        result = simulate(case, c.method, c.integrator, c.step, **dict(c.options))
        record["predictions"], record["missing_events"] = predictions(result, targets)
        record["columns"] = [name for name in result.names]
        record["events"] = event_times(result.summary)
        record["end_time"] = float(result.time[-1])
    except PchuteError as exc:
        record.update(status="failed", error=str(exc))
    except Exception as exc:  # a bug, not a user mistake: still recorded
        record.update(status="failed", error=f"internal error: {exc!r}")
    record["wall_time"] = time.perf_counter() - started
    return record

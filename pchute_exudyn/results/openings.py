"""A run's canopy openings in its summary: each stage's events (start or disreef, fill end), the warnings of a
supersonic opening outside its law's validity, and each stage's peak line loads."""

from __future__ import annotations

import numpy as np

from ..registries.columns import column
from .summary import DisreefEvent, FillEndEvent, StageStartEvent


def opening_events(case, openings: dict, end: float) -> list:
    """Stage starts, disreefs and fill ends (at or before ``end``, s) of each canopy's opening (``openings``: by
    (system, canopy))."""
    events = []
    for (system, canopy), progress in openings.items():
        named = {"canopy": canopy} if case.systems[system].cluster else {}
        flies_to = case.systems[system].end(canopy, case.failures, end)   # no fill ends once the canopy has left
        for flown, (stage, fill_end, speed, fill) in enumerate(progress.fill_ends()):
            start = fill_end - fill
            kind = StageStartEvent if flown == 0 else DisreefEvent   # the first flown (stage 1 unless skipped)
            supersonic = {"mach": progress.stretch_mach, "load_factor": progress.load_factor} \
                if progress.load_factor is not None and flown == len(progress.inflation.stages) - 1 else {}
            events.append(kind(start, system, stage, speed, fill, **named, **supersonic))
            if fill_end <= flies_to:
                events.append(FillEndEvent(fill_end, system, stage, **named))
    return events


def opening_warnings(case, events, openings: dict | None = None) -> tuple:
    """A supersonic opening whose line stretch fell outside its ``mach_range``: its load factor was held at the
    range's end (the constants were not fitted there); one (of ``openings``, by (system, canopy)) whose load-factor
    law gave C_k below 1 there: held at 1, the law outside its validity (no peak above the filled drag area)."""
    warned = []
    for (system, _), progress in (openings or {}).items():
        law = None if progress.load_factor is None else progress.supersonic.law_at(progress.stretch_mach,
                                                                                    progress.diameter)
        if law is not None and law < 1.0:
            warned.append(f"systems.{system}.inflation.supersonic: its load-factor law gives C_k = {law:.4g} at the "
                          f"line-stretch Mach {progress.stretch_mach:.3g}, below 1 (no peak above the filled drag "
                          "area: load_factor, mach_slope and wake_coefficient outside the law's validity): the run "
                          "held it at 1")
    for event in events:
        if isinstance(event, StageStartEvent) and event.mach is not None:
            low, high = case.systems[event.system].inflation.supersonic.mach_range
            if not low <= event.mach <= high:
                warned.append(f"systems.{event.system}: line stretch at Mach {event.mach:.3g}, outside the supersonic "
                              f"opening's mach_range [{low:g}, {high:g}]: its load factor was held at the range's "
                              f"end (C_k = {event.load_factor:.4g})")
    return tuple(warned)


def opening_loads(case, openings: dict, columns: dict) -> dict:
    """Per opening (by its label: the system, or the canopy in a cluster), per stage: its window (s: from the stage
    start to the next one, the cut-away or the run's end) and the peak tension (N) in it and when (s) of each line
    of the system (of the canopy's own risers, in a cluster), from the sampled histories (resolution: the output
    step)."""
    time = columns["time"]
    loads = {}
    for (name, canopy), progress in openings.items():
        system = case.systems[name]
        stages = []
        end = system.end(canopy, case.failures, float(time[-1]) + 1e-9)
        lines = system.risers(canopy) if system.cluster else system.lines
        for stage, start, stop in progress.windows(end):
            inside = (time >= start - 1e-9) & (time < stop)
            peaks = {}
            for line in lines:
                values = columns[column("tension_{owner}", case.line_label(system, line))][inside]
                if len(values) and np.isfinite(values).any():
                    k = int(np.nanargmax(values))
                    peaks[line.name] = {"tension": float(values[k]), "time": float(time[inside][k])}
            stages.append({"stage": stage, "start": start, "end": min(stop, float(time[-1])), "peaks": peaks})
        loads[case.opening_label(system, canopy)] = stages
    return loads

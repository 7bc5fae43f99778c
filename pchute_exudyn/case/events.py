"""A case's events by name, their times, and the case with triggered events placed at their firing times.

Names: ``<system>.deploy``, ``<system>.cutaway``, ``<system>.disreef<k>`` (stage k >= 2 of its inflation),
``<canopy>.cutaway`` (one canopy alone, ``failures``), ``<body>.separation``. An event fired by a trigger
(``Case.triggers``) stands in the case at ``math.inf`` until it fires (pending: never reached); the run replaces it
with its firing time (``with_event_times``) and builds the phases from that case as from one with fixed times.
"""

from __future__ import annotations

import math
from dataclasses import replace

from .model import Case

DISREEF = "disreef"


def known_times(systems: dict, failures, separations: dict) -> dict:
    """event -> run time (s) of every event whose time is known (fixed, or already fired): not pending. Takes a
    case's parts (``systems``, ``failures``, ``separations``), so the reader checks the event graph with it before
    the Case exists; a disreef counts from line stretch (the start of the run for a system present from it)."""
    times = {}
    for name, system in systems.items():
        for key, value in (("deploy", system.deploy_time), ("cutaway", system.cutaway_time)):
            if value is not None and math.isfinite(value):
                times[f"{name}.{key}"] = value
        stretch = system.deploy_time if system.deploy_time is not None else 0.0
        if system.inflation is not None and math.isfinite(stretch):
            for k, stage in enumerate(system.inflation.stages[1:], start=2):
                if math.isfinite(stage.start):
                    times[f"{name}.{DISREEF}{k}"] = stretch + stage.start
    times.update({f"{c}.cutaway": t for c, t in failures.cutaway.items() if math.isfinite(t)})
    times.update({f"{b}.separation": s.time for b, s in separations.items() if math.isfinite(s.time)})
    return times


def armed_by(case: Case, event: str) -> str | None:
    """The event that must have happened before ``event``'s trigger senses: a system's deployment for its cut-away,
    disreefs and canopies' cut-aways, the disreef before for a later one; None: armed from the start."""
    owner, kind = event.rsplit(".", 1)
    system = case.systems.get(owner) if kind != "cutaway" or owner in case.systems else case.canopy_system(owner)
    if system is None or kind == "separation":
        return None
    if kind.startswith(DISREEF) and int(kind[len(DISREEF):]) > 2:
        return f"{system.name}.{DISREEF}{int(kind[len(DISREEF):]) - 1}"
    if kind == "deploy" or system.deploy_time is None:
        return None
    return f"{system.name}.deploy"


def with_event_times(case: Case, times: dict) -> Case:
    """``case`` with events ``times`` (event -> run time, s) placed: what a fixed-time case of that sequence is."""
    systems, cutaway, separations = dict(case.systems), dict(case.failures.cutaway), dict(case.separations)
    for event, time in sorted(times.items(), key=lambda item: ("deploy" not in item[0], item[1])):
        owner, kind = event.rsplit(".", 1)
        if kind == "deploy":
            systems[owner] = replace(systems[owner], deploy_time=time)
        elif kind == "cutaway" and owner in systems:
            systems[owner] = replace(systems[owner], cutaway_time=time)
        elif kind == "cutaway":
            cutaway[owner] = time
        elif kind == "separation":
            separations[owner] = replace(separations[owner], time=time)
        else:
            system = systems[owner]
            index = int(kind[len(DISREEF):]) - 1
            stages = list(system.inflation.stages)
            stages[index] = replace(stages[index], start=time - system.deploy_time)
            systems[owner] = replace(system, inflation=replace(system.inflation, stages=tuple(stages)))
    return replace(case, systems=systems, failures=replace(case.failures, cutaway=cutaway), separations=separations)

"""Deployment loads as a run goes: each parachute system's line tensions at every solver step while its loads may
peak (``results.deployments`` turns them into the summary's ``deployments``; docs/models/deployment_loads.md).

A snatch lasts tens of milliseconds and an opening's peak a fraction of a second: the output samples (0.05 s and
more) miss them. So after every step inside a system's watch windows its lines' tensions are read and kept: from its
line stretch, and from each stage start of its opening, until that stage's fill ends, its overshoot has decayed and
SETTLE has passed; a system that opens by a time table, until the table's end plus SETTLE; one fully open at line
stretch, for SETTLE (``results.deployments.watch_windows``). Between windows the loads are quasi-steady and the
samples hold them. Reading only, the watch changes no result."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..case.model import Case
from ..engine.phase_model import Model
from ..engine.state import TensionChannel
from ..engine.tethers import tether_channel
from ..results.deployments import watch_windows


@dataclass
class LoadTrace:
    """A system's line tensions (N, by line name: a phase may fly fewer of its lines, a canopy cut away) at the ends
    of the steps (s) inside its watch windows."""

    times: list = field(default_factory=list)
    tensions: list = field(default_factory=list)


class _Watched:
    """One system under watch: its windows, made again only when its opening has started another stage (a step's
    check then costs a comparison or two)."""

    def __init__(self, case: Case, system, progress, trace: LoadTrace, readers: dict):
        self.case, self.system, self.progress, self.trace, self.readers = case, system, progress, trace, readers
        self.started, self.windows = None, []

    def due(self, t: float) -> bool:
        started = None if self.progress is None else (len(self.progress.speeds), self.progress.line_stretch)
        if started != self.started or not self.windows:
            self.started, self.windows = started, watch_windows(self.case, self.system, self.progress)
        for start, end in self.windows:   # a loop, not any() over a generator: after every step
            if start <= t <= end:
                return True
        return False

    def keep(self, t: float) -> None:
        self.trace.times.append(t)
        self.trace.tensions.append({name: float(read()) for name, read in self.readers.items()})


def watch_deployments(model: Model, case: Case, traces: dict, openings: dict) -> None:
    """Keep each of the model's systems' line tensions in ``traces`` (system name -> LoadTrace, made when first
    needed: a run's traces live through its phases) after every step inside its watch windows, and each acting
    tether's tension after every step (key ("tether", name)). ``openings``: the run's ``InflationProgress`` by
    (system, canopy)."""
    watched = []
    for system in model.systems:
        trace = traces.setdefault(system.name, LoadTrace())
        readers = {line.name: model.channels[TensionChannel(system.name, line.name)] for line in system.lines}
        progress = next((openings[(system.name, c)] for c in system.canopies if (system.name, c) in openings), None)
        watched.append(_Watched(case, system, progress, trace, readers))
    tethers = []   # a tether is read after every step it acts: an engine read, and it may snatch at any time
    for tether in case.tethers.values():
        channel = tether_channel(tether.name)
        if channel in model.channels:
            trace = traces.setdefault(("tether", tether.name), LoadTrace())
            tethers.append((trace, tether.name, model.channels[channel]))
    if not watched and not tethers:
        return

    def after_step(mbs, t):
        for system in watched:
            if system.due(t):
                system.keep(t)
        for trace, name, read in tethers:
            trace.times.append(t)
            trace.tensions.append({name: float(read())})
    model.add_post_step(after_step)

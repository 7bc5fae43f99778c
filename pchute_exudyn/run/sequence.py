"""A run's sequence of events as it unfolds: the times known so far (fixed ones, and each trigger's once it fires),
the sensed triggers still watching (``triggers.watch.Watch``), and the case with the fired events in place
(``case.events.with_event_times``), from which the phases are built.

A sensed trigger that fires stops its phase after the step that decided (``engine.trigger_monitor.TriggerMonitor``).
The event then happens exactly at the firing time t_f = sample time + lag: the run goes on to t_f in a new phase
when t_f lies ahead, or integrates the phase again from its start to t_f when the firing time falls inside the step
just taken (a lag shorter than that step, ``run.simulation.run``). Either way the phase boundary lands on t_f.
"""

from __future__ import annotations

import copy
import math
from dataclasses import replace

from ..case.events import DISREEF, armed_by, known_times, with_event_times
from ..case.model import Case
from ..case.sensing import true_values
from ..errors import SimulationError
from ..registries.quantities import RECORDED
from ..triggers.definition import After
from ..triggers.watch import Watch


class Sequence:
    """The events of one run of ``case`` (see the module docstring)."""

    def __init__(self, case: Case):
        self.base = case
        # event -> run time (s): fixed, resolved or fired
        self.times = known_times(case.systems, case.failures, case.separations)
        self.records: dict = {}          # event -> its trigger's record (summary.json ``trigger``)
        self.watches = [Watch(event, trigger, case.simulation.seed, armed_by(case, event))
                        for event, trigger in case.triggers.items() if not trigger.timed]
        self.case = case
        self._resolve()

    @property
    def triggered(self) -> bool:
        return bool(self.base.triggers)

    def pending_watches(self) -> list:
        return [watch for watch in self.watches if watch.event not in self.times]

    def fire(self, firings: list, earliest: float) -> float:
        """Record ``firings`` (``triggers.watch.Firing``; none before ``earliest``, s); returns the earliest event
        time among them."""
        for firing in firings:
            self.times[firing.event] = max(firing.time, earliest)
            self.records[firing.event] = firing.record
        self._resolve()
        for event, time in self.times.items():
            if event.endswith(".deploy") and event in self.base.triggers:
                self._check_after_deployment(event.removesuffix(".deploy"), time)
        return min(self.times[firing.event] for firing in firings)

    def _check_after_deployment(self, system_name: str, time: float) -> None:
        """A fixed-time cut-away of a system (or of one of its canopies) that comes before the deployment its trigger
        placed at ``time`` (s) is an error of the case: nothing can be cut away before it is out."""
        system = self.base.systems[system_name]
        fixed = [(f"systems.{system_name}.cutaway_time", system.cutaway_time)]
        fixed += [(f"failures.cutaway.{c}", self.base.failures.cutaway.get(c)) for c in system.canopies]
        for key, cut in fixed:
            if cut is not None and math.isfinite(cut) and cut <= time:
                raise SimulationError(f"{key} = {cut:g} s comes before the deployment its trigger fired at "
                                      f"{time:g} s ({self.base.triggers[system_name + '.deploy'].key}): cut it away "
                                      "by a trigger after the deployment (after = \"" + system_name + ".deploy\")",
                                      time)

    def _resolve(self) -> None:
        """Place every ``after`` trigger whose event is known, then rebuild the case with the triggered times."""
        changed = True
        while changed:
            changed = False
            for event, trigger in self.base.triggers.items():
                condition = trigger.condition
                if event in self.times or not isinstance(condition, After) or condition.event not in self.times:
                    continue
                stage_before = _stage_before(self.base, event)
                if stage_before is not None and stage_before not in self.times:
                    continue   # a disreef is armed by the stage before it, a timed one too
                reference = self.times[condition.event]
                self.times[event] = reference + condition.delay
                self._check_stage_order(event, stage_before)
                self.records[event] = {"quantity": "after", "threshold": condition.delay, "measured": None,
                                       "true": None, "time": reference + condition.delay, "lag": 0.0,
                                       "event": condition.event}
                changed = True
        placed = {event: time for event, time in self.times.items() if event in self.base.triggers}
        self.case = with_event_times(self.base, placed) if placed else self.base

    def _check_stage_order(self, event: str, stage_before: str | None) -> None:
        """A disreef placed at or before the stage before it (its deployment, the disreef before) stops the run
        naming its trigger: the stages of an inflation start in order."""
        if stage_before is not None and self.times[event] <= self.times[stage_before]:
            raise SimulationError(f"{self.base.triggers[event].key}: places {event} at {self.times[event]:g} s, not "
                                  f"after {stage_before} at {self.times[stage_before]:g} s: the stages of an "
                                  "inflation start in order, each after the one before", self.times[event])

    def boundaries(self, duration: float) -> set:
        """The run times (s) of the triggered events placed so far within the run: each is a phase boundary, so that
        every triggered event (a disreef too) starts a phase and its conditions are read there."""
        return {t for event, t in self.times.items() if event in self.base.triggers and 0.0 < t < duration}

    def snapshot(self):
        """What a phase integrated again from its start needs restored (the watches' samples and noise)."""
        return copy.deepcopy(self.watches)

    def restore(self, snapshot) -> None:
        self.watches = snapshot

    def note_conditions(self, time: float, body_states: dict) -> None:
        """Add the vehicle's true altitude, Mach number, dynamic pressure and air speed to the record of each event
        fired at ``time`` (s), from the phase's start states."""
        state = body_states.get(self.base.vehicle)
        if state is None or self.base.atmosphere is None:
            return
        for event, record in self.records.items():
            if self.times.get(event) == time and "conditions" not in record:
                truth = true_values(self.case, state.position, state.velocity, time)
                record["conditions"] = {key: float(truth[key]) for key in RECORDED if math.isfinite(truth[key])}

    def attach(self, events: list) -> list:
        """``events`` with each triggered one's record (``trigger``)."""
        if not self.records:
            return events
        return [replace(e, trigger=self.records[e.name]) if getattr(e, "name", None) in self.records
                and hasattr(e, "trigger") else e for e in events]

    def warnings(self, end: float) -> list:
        """One line per trigger that never fired before ``end`` (s)."""
        return [f"{trigger.key} never fired ({trigger.describe()}) in the {end:g} s run"
                for event, trigger in self.base.triggers.items()
                if self.times.get(event, math.inf) > end]

    def with_unfired(self, error: SimulationError) -> SimulationError:
        """``error`` (the run died at ``error.time``) with the triggers that had not fired by then named: a vehicle
        whose drogue never deployed fails later for a reason its message alone would not show."""
        time = math.inf if error.time is None else error.time
        waiting = [f"{trigger.key} ({trigger.describe()})" for event, trigger in self.base.triggers.items()
                   if self.times.get(event, math.inf) > time]
        if not waiting:
            return error
        note = f"; by then {'this trigger had' if len(waiting) == 1 else 'these triggers had'} not fired: "
        return SimulationError(str(error) + note + ", ".join(waiting), error.time)


def _stage_before(case: Case, event: str) -> str | None:
    """The event that starts the stage before disreef ``event`` (the disreef before it, or its system's deployment;
    ``case.events.armed_by``); None for any other event, and for the first disreef of a system present from the
    start (its first stage starts with the run)."""
    kind = event.rsplit(".", 1)[1]
    if not kind.startswith(DISREEF) or not kind[len(DISREEF):].isdigit():
        return None
    return armed_by(case, event)

"""The sensed triggers of a phase as a stop condition: after every accepted step, each trigger that is armed and due
samples the true state of its body (``triggers.watch.Watch``); the first firing stops the phase after that step,
and the run places the event at its firing time (``run.simulation``)."""

from __future__ import annotations

import math

import numpy as np

from ..case.model import Case
from ..case.sensing import pressure_function, true_values
from ..errors import SimulationError
from ..triggers.definition import LineStretch
from ..triggers.watch import TIME_TOLERANCE, TriggerFailed, TriggerInterrupted
from .bodies import MAX_DESCENT_ACCELERATION
from .phase_model import Model
from .state import BodyChannel


class TriggerMonitor:
    """Stop condition of the sensed triggers of a phase (``watches``: ``triggers.watch.Watch``; ``fired``: event ->
    time of the events fired so far, updated by the run). ``firings`` holds what fired at the step that stopped."""

    def __init__(self, model: Model, case: Case, watches: list, fired: dict):
        self.case, self.watches, self.fired = case, watches, fired
        self.model = model
        self.start = model.phase.start
        self.pressure_at = pressure_function(case) if case.atmosphere is not None else None
        self.air_motion = case.air_motion()
        self.readers = {}
        self.reads = {watch.event: _bodies_read(watch, case.vehicle) for watch in watches}   # (sensed, anchor or None)
        for watch in watches:   # a body not in this phase (not deployed yet, cut away) cannot be sensed in it
            for body in self.reads[watch.event]:
                if body is not None and BodyChannel(body, "position") in model.channels:
                    self.readers[body] = (model.channels[BodyChannel(body, "position")],
                                          model.channels[BodyChannel(body, "velocity")])
        self.firings: list = []
        self.next_check: dict = {}   # adaptive steps: event -> the time of its next look (s)
        self.window: set = set()     # adaptive steps: the events that can fire now, sampled at their sample times
        self.horizon = math.inf      # adaptive steps: the longest step (s; set by the run)
        self.step = None             # s: the phase's fixed step, None for adaptive steps (``warm_up``)
        self.previous = self.start   # s: the end of the last step seen (adaptive steps)
        for watch in watches:        # a user function's wait ends on Ctrl-C or SIGTERM (``triggers.user_calls``)
            watch.calls.stopped = self._stopped

    def _stopped(self) -> bool:
        """Whether the run was asked to stop (``engine.solver``'s progress)."""
        return bool(self.model.progress.get("interrupted"))

    def warm_up(self, step: float | None) -> None:
        """The step the engine takes (s; None for adaptive steps), before the solve."""
        self.step = step

    def __call__(self, t: float) -> bool:
        step = self.step
        if step is None:
            return self._adaptive(t)
        if t <= self.start:   # the start state was sampled at the end of the phase before
            return False
        truths = {}
        for watch in self.watches:
            if watch.armed_by is not None and self.fired.get(watch.armed_by, math.inf) >= t - TIME_TOLERANCE:
                continue   # its arming event has not happened before this sample (a known future time counts then)
            if not self._readable(watch) or not watch.due(t, step):
                continue
            self._observe(watch, t, self._watch_truth(watch, t, truths))
            if self._stopped():
                return True
        return bool(self.firings)

    def _truth(self, body: str, t: float, truths: dict):
        """The true values of ``body`` at ``t`` (s), read once per sample time (``truths``: those read so far)."""
        if body not in truths:
            position, velocity = self.readers[body]
            truths[body] = true_values(self.case, position(), velocity(), t, self.air_motion)
        return truths[body]

    def _readable(self, watch) -> bool:
        """Whether every body ``watch`` reads flies in this phase (a pilot chute still carried cannot pull)."""
        sensed, anchor = self.reads[watch.event]
        return sensed in self.readers and (anchor is None or anchor in self.readers)

    def _watch_truth(self, watch, t: float, truths: dict) -> dict:
        """The true values ``watch`` samples at ``t`` (s): its sensed body's, with a pilot chute's line stretch
        the pilot chute's centre of mass as ``anchor_position`` (m, start frame)."""
        sensed, anchor = self.reads[watch.event]
        truth = self._truth(sensed, t, truths)
        if anchor is None:
            return truth
        return dict(truth, anchor_position=np.array(self.readers[anchor][0](), float))

    def _observe(self, watch, t: float, truth) -> None:
        """A sample of ``watch`` at ``t`` (s): its firing, if any, recorded."""
        try:
            firing = watch.observe(t, truth, self.fired, self.pressure_at)
        except TriggerFailed as exc:
            raise SimulationError(str(exc), exc.time) from None
        except TriggerInterrupted as exc:   # the solver stops after this step and raises errors.Interrupted
            self.model.progress.update(interrupted=True, cause=self.model.progress.get("cause") or exc.cause)
            return
        if firing is not None:
            self.firings.append(firing)

    def _adaptive(self, t: float) -> bool:
        """Adaptive steps (the model has no fixed step; ``run.step_control``): a trigger samples only at its own
        sample times k / rate, on which the step control lands the steps (``landing``) while the trigger can fire.
        A noise-free altitude threshold cannot fire before ``Watch.earliest`` (the touchdown check's bound on the
        body's acceleration towards it, MAX_DESCENT_ACCELERATION): while that is more than ``horizon`` (the longest
        step, s) away its samples are skipped (no step can reach it), and its next look is halfway to it less the
        horizon (the step that passes that time still ends before it)."""
        if t <= self.start:
            return False
        truths = {}
        previous, self.previous = self.previous, t
        for watch in self.watches:
            if watch.armed_by is not None and self.fired.get(watch.armed_by, math.inf) >= t - TIME_TOLERANCE:
                continue
            looked = watch.event in self.window   # it could fire at the last step's end too
            if not self._readable(watch) or t < self.next_check.get(watch.event, -math.inf):
                continue
            truth = self._watch_truth(watch, t, truths)
            earliest = watch.earliest(t, truth, MAX_DESCENT_ACCELERATION)
            if earliest > t + self.horizon:   # the coming steps end before it: its next look halfway there
                self.window.discard(watch.event)
                self.next_check[watch.event] = t + 0.5 * (earliest - t - self.horizon)
                continue
            self.window.add(watch.event)
            if watch.on_sample(t) or (looked and watch.passed(previous, t)):
                self._observe(watch, t, truth)
                if self._stopped():
                    return True
        return bool(self.firings)

    def landing(self, t: float) -> float:
        """The next sample time (s) after ``t`` of a trigger that can fire now: adaptive steps end there, so that
        each sample is taken at its own time (inf: none)."""
        return min((w.next_sample(t) for w in self.watches if w.event in self.window), default=math.inf)


def _bodies_read(watch, vehicle: str) -> tuple:
    """(sensed body, anchor body or None): the body ``watch`` senses (default ``vehicle``), and the body a line
    stretch's bag hangs from (a pilot chute's; None for any other trigger and a static line)."""
    condition = watch.trigger.condition
    return watch.trigger.sensor.body or vehicle, condition.line.body if isinstance(condition, LineStretch) else None

"""Canopy inflation and reefing from line stretch by the fill-constant law (``docs/models/canopy.md``, "Inflation and
reefing").

A system's drag-area fraction f (multiplying its canopy's C_A and C_N table) against the time s since line stretch,
in stages i = 1..n (reefed stages, then the full canopy). Stage i starts at s_i (s_1 = 0) from the previous stage's
fraction f_(i-1) (f_0, the initial fraction, for the first)::

    t_f,i = n_i D_0 / V_i                          fill time: n_i the fill constant, D_0 = sqrt(4 S / pi) the nominal
                                                   diameter, V_i the canopy's air speed at s_i (measured in the run)
    f(s)  = f_(i-1) + (C_i f_i - f_(i-1)) ((s - s_i) / t_f,i)^e_i      during the fill (e_i the opening exponent)
    f(s)  = f_i                                    after it; C_i = 1 but for the last stage, C_n = C_x >= 1
                                                   (overinflation), where f then falls linearly from C_x f_n to f_n
                                                   over the decay time t_k

A stage that starts before the previous fill has ended starts from f_(i-1) all the same (the law's definition).
With a supersonic opening (``physics.supersonic_opening``) the last stage's C_x and n come from the conditions at its
start, and the filled canopy breathes once its overinflation has decayed. Plain floats: the fraction is evaluated
at every solver stage.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from .invalid import InvalidField
from .supersonic_opening import SupersonicOpening


class InflationError(InvalidField):
    """Invalid inflation input; ``field`` names its key (a stage column such as ``fill_constant`` for a stage)."""


@dataclass(frozen=True)
class InflationStage:
    """One stage of an opening.

    Attributes
    ----------
    start : float
        Time since line stretch at which the stage starts (s): 0 for the first, the disreef time for the others.
    fraction : float
        f_i, the stage's drag-area fraction once filled (-), in (0, 1].
    fill_constant : float
        n_i (-), > 0: the fill time is n_i D_0 / V_i.
    exponent : float
        e_i (-), > 0: the opening exponent.
    """

    start: float
    fraction: float
    fill_constant: float
    exponent: float


def _check(condition: bool, field: str, value, message: str) -> None:
    if not condition:
        raise InflationError(field, value, message)


@dataclass(frozen=True)
class Inflation:
    """An opening by the fill-constant law (see the module docstring).

    Attributes
    ----------
    stages : tuple of InflationStage
        In order of their start times (the first at 0).
    initial_fraction : float
        f_0 (-), in [0, f_1): the fraction at line stretch.
    overinflation : float
        C_x (-), >= 1: the last stage fills to C_x f_n.
    overinflation_decay : float
        t_k (s), >= 0 (> 0 when C_x > 1): the time over which f falls back to f_n.
    numbers : tuple of int
        Each stage's number as the case counts them (empty: 1, 2, ...): an opening that skips stages keeps the others'
        numbers (``skipping``), so that reports name the same stage the same way.
    supersonic : SupersonicOpening or None
        The last stage's C_x, fill constant and breathing from the conditions at its start (then ``overinflation``
        stays 1 and ``overinflation_decay`` > 0).
    """

    stages: tuple
    initial_fraction: float = 0.0
    overinflation: float = 1.0
    overinflation_decay: float = 0.0
    numbers: tuple = ()
    supersonic: SupersonicOpening | None = None

    def __post_init__(self):
        stages = self.stages
        _check(len(stages) >= 1, "stages", [], "an inflation needs at least one stage")
        starts = [stage.start for stage in stages]
        _check(starts[0] == 0.0, "stage_start", starts, "the first stage starts at line stretch: 0 s")
        # a disreef fired by a trigger that has not fired yet starts at inf (pending; ``case.events``)
        _check(all(b > a or b == math.inf for a, b in zip(starts, starts[1:])), "stage_start", starts,
               "stages must start in order: strictly increasing times since line stretch (s)")
        for key, name, test, allowed in (("fraction", "fraction", lambda v: 0.0 < v <= 1.0, "within (0, 1]"),
                                         ("fill_constant", "fill_constant", lambda v: v > 0.0, "> 0"),
                                         ("exponent", "exponent", lambda v: v > 0.0, "> 0")):
            values = [getattr(stage, key) for stage in stages]
            _check(all(math.isfinite(v) and test(v) for v in values), name, values, f"each must be {allowed}")
        _check(0.0 <= self.initial_fraction < stages[0].fraction, "initial_fraction", self.initial_fraction,
               f"must be >= 0 and below the first stage's fraction ({stages[0].fraction:g})")
        _check(math.isfinite(self.overinflation) and self.overinflation >= 1.0, "overinflation",
               self.overinflation, "must be >= 1 (C_x: 1 = no overinflation)")
        decay = self.overinflation_decay
        _check(math.isfinite(decay) and decay >= 0.0, "overinflation_decay", decay, "must be >= 0 (s)")
        _check(self.overinflation == 1.0 or decay > 0.0, "overinflation_decay", decay,
               "must be > 0 (s) when overinflation > 1")
        if self.supersonic is not None:
            _check(self.overinflation == 1.0, "overinflation", self.overinflation,
                   "must be left out (or 1) with a supersonic opening: its load factor is the overinflation")
            _check(decay > 0.0, "overinflation_decay", decay, "must be > 0 (s) with a supersonic opening")

    def number(self, stage: int) -> int:
        """The number (from 1, as the case counts them) of stage ``stage`` (0-based here)."""
        return self.numbers[stage] if self.numbers else stage + 1

    def fill_time(self, stage: int, speed: float, nominal_diameter: float, fill_constant: float | None = None) -> float:
        """t_f = n_i D_0 / V_i (s) of stage ``stage`` (0-based) at air speed ``speed`` (m/s), D_0 in m; with
        ``fill_constant`` (-), that n instead of the stage's (a supersonic opening's n at its Mach number)."""
        n = self.stages[stage].fill_constant if fill_constant is None else fill_constant
        return n * nominal_diameter / max(speed, 1e-9)

    def stage_at(self, since: float) -> int:
        """The stage (0-based) running at ``since`` (s since line stretch)."""
        current = 0
        for i, stage in enumerate(self.stages):
            if stage.start <= since:
                current = i
        return current

    def fraction(self, since: float, fill_times, overinflation: float | None = None, breathing=None) -> float:
        """f at ``since`` (s since line stretch) given each started stage's fill time (s; ``fill_times[i]``; a stage
        without one yet holds f_(i-1), its value at its start); ``overinflation`` (-) replaces C_x (a supersonic
        opening's load factor) and ``breathing(elapsed)`` (-) multiplies the last stage's f_n once the overinflation
        has decayed (``elapsed`` s before)."""
        if since < 0.0:
            return self.initial_fraction
        i = self.stage_at(since)
        stage = self.stages[i]
        before = self.initial_fraction if i == 0 else self.stages[i - 1].fraction
        last = i == len(self.stages) - 1
        peak = stage.fraction * ((self.overinflation if overinflation is None else overinflation) if last else 1.0)
        if i >= len(fill_times):   # the stage's speed is not measured yet (the engine's start-up call): f_(i-1)
            return before
        elapsed, fill = since - stage.start, fill_times[i]
        if elapsed < fill:
            return before + (peak - before) * (elapsed / fill) ** stage.exponent
        decay = elapsed - fill
        if last and decay < self.overinflation_decay:
            return peak - (peak - stage.fraction) * decay / self.overinflation_decay
        if last and breathing is not None:
            return stage.fraction * breathing(decay - self.overinflation_decay)
        return stage.fraction


def with_disreef_delays(inflation: Inflation, delays) -> Inflation:
    """The opening with each disreef (the start of stages 2..n) moved by ``delays`` (s, one per disreef: negative when
    the reefing-line cutter fires early). InflationError (field ``disreef_delay``) when the stages fall out of
    order or before line stretch."""
    delays = tuple(float(d) for d in delays)
    _check(len(delays) == len(inflation.stages) - 1, "disreef_delay", list(delays),
           f"needs one delay (s) per disreef: {len(inflation.stages) - 1} for {len(inflation.stages)} stages")
    stages = (inflation.stages[0],) + tuple(replace(stage, start=stage.start + delay)
                                            for stage, delay in zip(inflation.stages[1:], delays))
    starts = [stage.start for stage in stages]
    _check(all(b > a for a, b in zip(starts, starts[1:])), "disreef_delay", list(delays),
           f"moves the disreefs out of order or to line stretch: stage starts {starts} s must stay strictly "
           "increasing after 0")
    return replace(inflation, stages=stages)


def skipping(inflation: Inflation, skipped) -> Inflation:
    """The opening with the stages ``skipped`` (numbers from 1) left out: the canopy fills from the stage before a
    skipped one straight to the stage after it, starting at the skipped stage's start (both reefing cutters fire
    together). The last stage, the full canopy, cannot be skipped (a canopy that never opens is a failure to
    inflate). InflationError (field ``skipped_stages``) otherwise."""
    skipped = sorted(set(int(k) for k in skipped))
    count = len(inflation.stages)
    _check(all(1 <= k < count for k in skipped), "skipped_stages", skipped,
           f"each must be a reefed stage, 1 to {count - 1} (the last, stage {count}, is the full canopy)")
    stages, numbers, pending = [], [], None
    for index, stage in enumerate(inflation.stages):
        if inflation.number(index) in skipped:
            pending = stage.start if pending is None else pending
            continue
        stages.append(stage if pending is None else replace(stage, start=pending))
        numbers.append(inflation.number(index))
        pending = None
    return replace(inflation, stages=tuple(stages), numbers=tuple(numbers))


def nominal_diameter(reference_area: float) -> float:
    """D_0 = sqrt(4 S / pi) (m) from the canopy's reference area S (m^2)."""
    return math.sqrt(4.0 * reference_area / math.pi)


class InflationProgress:
    """An opening as a run goes: the air speed measured at each stage start and the fill times it gives.

    The engine measures the speed V_i at a stage start s_i from the states around it: ``begin`` at the start of the
    step in which s_i falls (provisionally, V at the step start) and ``complete`` at its end (V_i interpolated
    linearly to s_i). A supersonic opening also takes the speed of sound there (its Mach number sets the last
    stage's C_x and n) and, for its breathing, the canopy's Mach number after every step (``observe``). Pure floats,
    no engine: it outlives the models of a run's phases.

    Parameters
    ----------
    inflation : Inflation
    diameter : float
        D_0 (m).
    line_stretch : float
        Run time (s) of line stretch (the system's deployment).
    """

    def __init__(self, inflation: Inflation, diameter: float, line_stretch: float):
        self.inflation, self.diameter, self.line_stretch = inflation, diameter, line_stretch
        self.speeds: list = []           # V_i (m/s) per started stage
        self.fill_times: list = []       # t_f,i (s) per started stage
        self.pending = None              # (run time, speed, speed of sound) at the start of the step of a stage start
        self.load_factor = None          # C_k (-) of a supersonic opening, once its last stage has started
        self.stretch_mach = None         # the Mach number (-) at that start
        self.mach = 0.0                  # the canopy's Mach number (-) at the last step's end (breathing)

    @property
    def supersonic(self):
        """The opening's ``SupersonicOpening`` (None: a subsonic fill-constant law)."""
        return self.inflation.supersonic

    def __call__(self, since: float) -> float:
        """The drag-area fraction at ``since`` (s since line stretch)."""
        if self.load_factor is None:
            return self.inflation.fraction(since, self.fill_times)
        return self.inflation.fraction(since, self.fill_times, self.load_factor, self._breathing)

    def _breathing(self, elapsed: float) -> float:
        return self.supersonic.breathing(elapsed, self.mach, self.speeds[-1], self.diameter)

    def supersonic_flight(self) -> bool:
        """Whether a supersonic opening's canopy still flies faster than sound (at its last measured Mach number):
        the unsteady flight in which it breathes and its lines swing."""
        return self.load_factor is not None and self.mach > 1.0

    def observe(self, mach: float) -> None:
        """The canopy's Mach number (-) at a step's end: the breathing's amplitude over the next step."""
        self.mach = mach

    def due(self, step_end: float) -> bool:
        """Whether a stage not yet measured starts by ``step_end`` (run time, s)."""
        started = len(self.speeds)
        return started < len(self.inflation.stages) and \
            self.line_stretch + self.inflation.stages[started].start <= step_end

    def begin(self, time: float, speed: float, sound: float | None = None) -> None:
        """At the start ``time`` (s) of the step in which the next stage starts, with the air speed (m/s) and, for a
        supersonic opening, the speed of sound (m/s) then."""
        self.pending = (time, speed, sound)
        self._set(speed, sound)

    def complete(self, time: float, speed: float, sound: float | None = None) -> None:
        """At the end ``time`` (s) of that step: V_i (and the speed of sound) interpolated to the stage start."""
        if self.pending is None:
            return
        start_time, start_speed, start_sound = self.pending
        stage_time = self.line_stretch + self.inflation.stages[len(self.speeds) - 1].start
        w = (stage_time - start_time) / (time - start_time) if time > start_time else 1.0
        w = min(max(w, 0.0), 1.0)
        self.speeds.pop()
        self.fill_times.pop()
        self._set(start_speed + w * (speed - start_speed),
                  None if sound is None else start_sound + w * (sound - start_sound))
        self.pending = None

    def _set(self, speed: float, sound: float | None = None) -> None:
        stage = len(self.speeds)
        self.speeds.append(speed)
        if self.supersonic is None or stage < len(self.inflation.stages) - 1 or sound is None:
            self.fill_times.append(self.inflation.fill_time(stage, speed, self.diameter))
            return
        mach = speed / sound
        self.stretch_mach, self.mach = mach, mach
        self.load_factor = self.supersonic.load_factor_at(mach, self.diameter)
        fill_constant = self.supersonic.fill_constant_at(mach, self.inflation.stages[stage].fill_constant)
        self.fill_times.append(self.inflation.fill_time(stage, speed, self.diameter, fill_constant))

    def windows(self, end: float) -> list:
        """(stage number from 1, start, end) in run time (s) of each stage started before ``end`` (s)."""
        starts = [self.line_stretch + stage.start for stage in self.inflation.stages[:len(self.speeds)]]
        return [(self.inflation.number(i), start, min(stop, end))
                for i, (start, stop) in enumerate(zip(starts, starts[1:] + [end])) if start < end]

    def fill_ends(self) -> list:
        """(stage number from 1, run time of the fill's end (s), V_i (m/s), t_f,i (s)) of each started stage."""
        return [(self.inflation.number(i), self.line_stretch + self.inflation.stages[i].start + fill, speed, fill)
                for i, (speed, fill) in enumerate(zip(self.speeds, self.fill_times))]

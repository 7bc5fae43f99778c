"""A trigger through a run (``Watch``): fed the true values at each accepted step, it samples, senses
(``triggers.sensors``) and decides, calling a user's function in a thread of its own (``triggers.user_calls``). The
engine layer feeds it (``engine.trigger_monitor``); the run places the event it fires (``run.sequence``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..physics.atmosphere import OutsideAtmosphereError
from ..registries.quantities import QUANTITY, SENSED
from .crossing import crossing
from .definition import After, AllOf, AnyOf, Apogee, At, LineStretch, Threshold, Trigger, UserFunction, leaves
from .sensors import NoiseStream, sense, stream_seed
from .user_calls import CallInterrupted, CallTimedOut, UserCalls

TIME_TOLERANCE = 1e-9
"""s: a sample is due at the first step end no earlier than its time minus half a step, less this round-off."""


@dataclass
class Firing:
    """A trigger that fired: the event happens at ``time`` (s) = ``sample_time`` + lag."""

    event: str
    time: float
    sample_time: float
    record: dict


class TriggerFailed(Exception):
    """A user trigger function raised, returned no bool, called sys.exit or overran its time limit: ``key`` names
    the trigger."""

    def __init__(self, key: str, message: str, time: float):
        super().__init__(f"{key}: {message} at t = {time:.4f} s")
        self.key, self.time = key, time


class TriggerInterrupted(Exception):
    """The run was interrupted while a user trigger function ran (Ctrl-C, SIGTERM; ``cause`` empty) or the function
    raised KeyboardInterrupt (``cause`` says so): the run stops as interrupted."""

    def __init__(self, key: str, time: float, cause: str = ""):
        super().__init__(f"{key}: interrupted at t = {time:.4f} s")
        self.key, self.time, self.cause = key, time, cause


class Watch:
    """One sensed trigger through a run (see the module docstring).

    Parameters
    ----------
    event : str
        The event's name ("main.deploy").
    trigger : Trigger
    seed : int
        The case's ``simulation.seed``.
    armed_by : str or None
        The event that must have fired before this trigger samples (its system's deployment, the previous disreef).
    """

    def __init__(self, event: str, trigger: Trigger, seed: int, armed_by: str | None = None):
        self.event, self.trigger, self.armed_by = event, trigger, armed_by
        sensor = trigger.sensor
        period = 1.0 / sensor.rate if sensor.rate else None
        self.period = period
        self.pressure_noise = NoiseStream(stream_seed(seed, event, 0), sensor.pressure_noise, period,
                                          sensor.correlation_time)
        self.speed_noise = NoiseStream(stream_seed(seed, event, 1), sensor.speed_noise, period, 0.0)
        self.index = 0            # the next sample's number (its time: index * period)
        self.previous = None      # (time, sensed, truth) of the last sample
        self.calls = UserCalls()  # runs a user function (its ``stopped`` set by who feeds the watch)

    def due(self, time: float, step: float) -> bool:
        """Whether a sample is due at the step end ``time`` (s) of a step ``step`` (s)."""
        return self.period is None or time >= self.index * self.period - 0.5 * step - TIME_TOLERANCE

    def earliest(self, time: float, truth: dict, acceleration: float) -> float:
        """The earliest run time (s) at which this trigger can fire, from the true values ``truth`` at ``time`` (s):
        a noise-free altitude threshold cannot be crossed before the body, at its vertical velocity now and at most
        ``acceleration`` (m/s^2) towards it, has covered the distance; any other trigger can fire at its next sample
        (``time`` itself)."""
        condition, sensor = self.trigger.condition, self.trigger.sensor
        if not isinstance(condition, Threshold) or condition.quantity != "altitude" or sensor.noisy or \
                sensor.pressure_bias != 0.0 or sensor.speed_bias != 0.0:
            return time
        distance = truth[condition.sensed_name] - condition.value
        speed = -truth["vertical_velocity"]   # towards the threshold
        if not condition.below:
            distance, speed = -distance, -speed
        if distance <= 0.0:
            return time
        return time + (math.sqrt(speed * speed + 2.0 * acceleration * distance) - speed) / acceleration

    def next_sample(self, time: float) -> float:
        """The first sample time (s) after ``time`` (s) not taken yet (inf for a trigger sampled every step)."""
        if self.period is None:
            return math.inf
        return max(self.index, math.floor(time / self.period + TIME_TOLERANCE) + 1) * self.period

    def on_sample(self, time: float) -> bool:
        """Whether ``time`` (s) is a sample time not taken yet (every step end for a trigger without a rate)."""
        if self.period is None:
            return True
        k = round(time / self.period)
        return k >= self.index and abs(time - k * self.period) <= TIME_TOLERANCE

    def passed(self, previous: float, time: float) -> bool:
        """Whether the step from ``previous`` to ``time`` (s) passed a sample time not taken: adaptive steps land on
        each sample time, but the engine may merge a short step with the next (seen in a full-mass run of the
        rocket: a step of 2 h where h was asked). That sample is then taken at ``time``, late by less than a step,
        rather than never."""
        return self.period is not None and self.next_sample(previous) < time - TIME_TOLERANCE

    def observe(self, time: float, truth: dict, fired: dict, pressure_at) -> Firing | None:
        """Take the sample due at ``time`` (s) from the true values ``truth`` (a pilot chute's line stretch: with its
        body's ``anchor_position``, m); ``fired``: event -> time of the events fired so far. Returns the Firing when
        the trigger fires."""
        if self.period is not None:   # samples missed (a rate above the step's) are skipped with their noise
            noisy = self.trigger.sensor.noisy   # (a noise-free sensor draws none: ten thousand samples skipped
            while (self.index + 1) * self.period <= time + TIME_TOLERANCE:   # at once cost nothing)
                if noisy:
                    self._errors()
                self.index += 1
            self.index += 1
        sensed = self._sense(time, truth, pressure_at)
        condition = self.trigger.condition
        if isinstance(condition, LineStretch):   # the line's own geometry, true in both
            distance = {condition.sensed_name: condition.distance(time, truth["position"],
                                                                  truth.get("anchor_position"))}
            sensed, truth = dict(sensed, **distance), dict(truth, **distance)
        holds = self._holds(condition, time, sensed, truth, fired)
        previous, self.previous = self.previous, (time, sensed, truth)
        if not holds:
            return None
        sample_time, record = time, self._record(condition, time, sensed, truth, fired)
        if self.period is None and previous is not None and isinstance(condition, (Threshold, Apogee, LineStretch)):
            sample_time, record = crossing(condition, previous, (time, sensed, truth))
        record.update(time=sample_time, lag=self.trigger.sensor.lag)
        return Firing(self.event, sample_time + self.trigger.sensor.lag, sample_time, record)

    def _sense(self, time: float, truth: dict, pressure_at) -> dict:
        """The sensed values of the sample at ``time`` (s). A sensor setting that gives a value the quantity cannot
        take stops the run naming the trigger and the setting (TriggerFailed): a noisy or biased pressure with no
        altitude in the atmosphere, a speed bias that makes a magnitude the trigger reads negative (noise alone may,
        for a sample, and is kept as drawn)."""
        sensor = self.trigger.sensor
        pressure_error, speed_error = self._errors()
        try:
            sensed = sense(truth, sensor, pressure_error, speed_error, pressure_at)
        except OutsideAtmosphereError as exc:
            raise TriggerFailed(self.trigger.key, f"the sensed pressure {truth['pressure'] + pressure_error:.6g} Pa "
                                f"(true {truth['pressure']:.6g} Pa, pressure_noise = {sensor.pressure_noise:g} Pa, "
                                f"pressure_bias = {sensor.pressure_bias:g} Pa) has no barometric altitude: {exc}",
                                time) from None
        if sensor.speed_bias < 0.0:
            for name in _read_by(self.trigger.condition):
                if QUANTITY[name].error == "speed" and truth[name] + sensor.speed_bias < QUANTITY[name].limits[0]:
                    raise TriggerFailed(self.trigger.key, f"speed_bias = {sensor.speed_bias:g} m/s makes the sensed "
                                        f"{name} negative (true {truth[name]:.4g} m/s; a {name} is a magnitude: the "
                                        f"bias must stay above minus the run's lowest {name})", time)
        return sensed

    def _errors(self) -> tuple:
        sensor = self.trigger.sensor
        pressure = self.pressure_noise.next() + sensor.pressure_bias
        speed = self.speed_noise.next() + sensor.speed_bias
        return pressure, speed

    def _holds(self, condition, time: float, sensed: dict, truth: dict, fired: dict) -> bool:
        if isinstance(condition, At):
            return time >= condition.time - TIME_TOLERANCE
        if isinstance(condition, After):
            return condition.event in fired and time >= fired[condition.event] + condition.delay - TIME_TOLERANCE
        if isinstance(condition, (Threshold, LineStretch)):
            return condition.holds(sensed)
        if isinstance(condition, Apogee):
            return condition.holds(sensed, None if self.previous is None else self.previous[1])
        if isinstance(condition, UserFunction):
            return self._call(condition, time, sensed, truth)
        results = [self._holds(part, time, sensed, truth, fired) for part in condition.parts]
        return all(results) if isinstance(condition, AllOf) else any(results)

    def _call(self, condition: UserFunction, time: float, sensed: dict, truth: dict) -> bool:
        state = {name: truth[name] for name in SENSED}
        state.update(position=truth["position"].copy(), velocity=truth["velocity"].copy())
        key, name = self.trigger.key, condition.name
        try:
            answer = self.calls.call(condition.function, (time, dict(sensed), state), condition.time_limit)
        except CallTimedOut:
            raise TriggerFailed(key, f"the function {name} took longer than its time limit of "
                                f"{condition.time_limit:g} s per call (time_limit)", time) from None
        except CallInterrupted:
            raise TriggerInterrupted(key, time) from None
        except KeyboardInterrupt:
            raise TriggerInterrupted(key, time, f"{key}: the function {name} raised KeyboardInterrupt") from None
        except SystemExit as exc:
            raise TriggerFailed(key, f"the function {name} called sys.exit({exc.code!r}) instead of returning "
                                "True or False", time) from None
        except Exception as exc:   # the user's code: its message, with the trigger's key and the time
            raise TriggerFailed(key, f"the function {name} raised {type(exc).__name__}: {exc}", time) from None
        if not isinstance(answer, (bool, np.bool_)):
            raise TriggerFailed(key, f"the function {name} returned {type(answer).__name__}, not a bool", time)
        return bool(answer)

    def _record(self, condition, time: float, sensed: dict, truth: dict, fired: dict) -> dict:
        if isinstance(condition, (Threshold, Apogee, LineStretch)):
            name = condition.sensed_name
            return {"quantity": condition.quantity, "threshold": condition.value, "measured": sensed[name],
                    "true": truth[name]}
        if isinstance(condition, (AllOf, AnyOf)):
            parts = [self._record(p, time, sensed, truth, fired) for p in condition.parts]
            return {"quantity": "all" if isinstance(condition, AllOf) else "any", "threshold": None,
                    "measured": None, "true": None, "parts": parts}
        if isinstance(condition, UserFunction):
            return {"quantity": "function", "threshold": condition.name, "measured": None, "true": None}
        if isinstance(condition, At):
            return {"quantity": "time", "threshold": condition.time, "measured": time, "true": time}
        return {"quantity": "after", "threshold": condition.delay, "measured": time - fired.get(condition.event, time),
                "true": time - fired.get(condition.event, time), "event": condition.event}


def _read_by(condition) -> set:
    """The sensed values (``SENSED``) a condition reads: a threshold's quantity (Mach number and dynamic pressure
    through the airspeed), every value for a user function."""
    names = set()
    for leaf in leaves(condition):
        if isinstance(leaf, UserFunction):
            names.update(SENSED)
        elif isinstance(leaf, Threshold):
            names.add("airspeed" if QUANTITY[leaf.quantity].derive is not None else leaf.sensed_name)
    return names

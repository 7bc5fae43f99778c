"""Triggers: when an event of a sequence happens, from what avionics sense (docs/case-format.md, "Triggers").

A trigger is a condition and a sensor. The condition is one of: a run time (``At``), a delay after another event
(``After``), a sensed quantity crossing a value (``Threshold``), apogee (``Apogee``), a user's flight-computer
function (``UserFunction``) or ``all``/``any`` of several (``AllOf``, ``AnyOf``). The sensor samples at a rate (Hz;
none: at every accepted step), fires after a lag (s) and adds seeded noise and a bias: a barometric altitude from a
pressure with noise in Pa (white or AR(1) correlated), a navigated speed with noise in m/s.

``Watch`` runs one trigger through a run: fed the true values at each accepted step, it samples, senses and decides.
Pure Python and numpy: the engine layer feeds it (``engine.triggers``).

Conventions: ``vertical_velocity`` is up-positive (m/s); ``altitude`` is geodetic (above the reference ellipsoid,
"geoid" in the case), ``altitude_ground`` above the case's ground; speeds are magnitudes (m/s).
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .aerodynamics import dynamic_pressure_of_speed, mach_number
from .atmosphere import OutsideAtmosphereError
from .user_calls import CallInterrupted, CallTimedOut, UserCalls


@dataclass(frozen=True)
class Quantity:
    """A quantity a trigger's sensor reads.

    Attributes
    ----------
    name, unit : str
        Its name in a case file's trigger and in a user function's ``sensed`` and ``state``; its SI unit.
    meaning : str
        One line (the docs' table).
    error : {"pressure", "speed", "none"}
        The sensor error that reaches it directly: the barometric pressure error (the altitudes), the navigated speed
        error (the speeds), none (a value derived from others).
    derive : callable, optional
        ``derive(values, truth)``: its value from the other ``values`` (true or sensed) and the ``truth`` (density,
        speed of sound); None for a value the sampling supplies (``case.sensing.true_values``).
    needs_speed_of_sound : bool
        Whether it needs an atmosphere with a temperature.
    threshold : bool
        Whether a ``Threshold`` may watch it.
    recorded : bool
        Whether a triggered deployment's record keeps the vehicle's true value (``run.sequence``).
    studied : bool
        Whether a study keeps that recorded value as a column (``deploy_<name>_<system>``, ``registries.columns``).
    limits : (float, float)
        The range (its unit) the quantity can take in a run of this tool: a threshold outside it cannot mean
        anything, and a sensed magnitude below it (a speed bias that makes a speed negative) stops the run.
    """

    name: str
    unit: str
    meaning: str
    error: str = "none"
    derive: Callable | None = None
    needs_speed_of_sound: bool = False
    threshold: bool = False
    recorded: bool = False
    studied: bool = False
    limits: tuple = (-math.inf, math.inf)


ALTITUDES = (-5e4, 1e7)
"""m: the altitudes of this tool (``case.plausible``'s impossible range of an initial altitude)."""
SPEEDS = (0.0, 1e5)
"""m/s: a speed magnitude (the tool's initial speeds are within 2e4 m/s per axis)."""
QUANTITIES = (
    Quantity("altitude", "m", "geodetic altitude (barometric when the sensor has a pressure error)", "pressure",
             threshold=True, recorded=True, studied=True, limits=ALTITUDES),
    Quantity("altitude_ground", "m", "the same above the case's ground", "pressure", limits=ALTITUDES),
    Quantity("pressure", "Pa", "static pressure", "pressure", limits=(0.0, 1e8)),
    Quantity("vertical_velocity", "m/s", "up-positive vertical velocity", "speed", limits=(-SPEEDS[1], SPEEDS[1])),
    Quantity("speed", "m/s", "speed relative to the ground", "speed", threshold=True, limits=SPEEDS),
    Quantity("airspeed", "m/s", "speed relative to the air", "speed", threshold=True, recorded=True, limits=SPEEDS),
    Quantity("mach", "-", "airspeed over the speed of sound", derive=lambda v, t: mach_number(
        v["airspeed"], t["speed_of_sound"]), needs_speed_of_sound=True, threshold=True, recorded=True, studied=True,
             limits=(0.0, 1e3)),
    Quantity("dynamic_pressure", "Pa", "1/2 rho airspeed^2", derive=lambda v, t: dynamic_pressure_of_speed(
        t["density"], v["airspeed"]), needs_speed_of_sound=True, threshold=True, recorded=True, studied=True,
             limits=(0.0, 1e10)),
)
"""Every quantity a sensor reads, in the order a user function's ``sensed`` lists them."""
QUANTITY = {quantity.name: quantity for quantity in QUANTITIES}
THRESHOLD_QUANTITIES = {q.name: q.unit for q in QUANTITIES if q.threshold}
"""What a ``Threshold`` can watch, with units."""
SENSED = tuple(QUANTITY)
"""The values a sensor gives a user function (``sensed``), each also in ``state`` as its true value."""
RECORDED = tuple(q.name for q in QUANTITIES if q.recorded)
"""The vehicle's true values a triggered deployment's record keeps (``run.sequence``)."""


def derive_quantities(values: dict, truth: dict) -> None:
    """Fill the derived quantities (those with ``derive``) of ``values`` from its others and ``truth``."""
    for quantity in QUANTITIES:
        if quantity.derive is not None:
            values[quantity.name] = quantity.derive(values, truth)
TIME_TOLERANCE = 1e-9
"""s: a sample is due at the first step end no earlier than its time minus half a step, less this round-off."""


@dataclass(frozen=True)
class At:
    """At run time ``time`` (s)."""

    time: float

    def describe(self) -> str:
        return f"time {self.time:g} s"


@dataclass(frozen=True)
class After:
    """``delay`` (s) after event ``event`` fires."""

    event: str
    delay: float = 0.0

    def describe(self) -> str:
        return f"{self.delay:g} s after {self.event}"


@dataclass(frozen=True)
class Threshold:
    """A sensed ``quantity`` (``THRESHOLD_QUANTITIES``) at or below (``below``) or at or above ``value``. An altitude
    fires on its descending crossing (``below``, the sensed vertical velocity < 0) or ascending one (``above``, > 0);
    ``reference`` "geoid" or "ground"."""

    quantity: str
    below: bool
    value: float
    reference: str = "geoid"

    @property
    def sensed_name(self) -> str:
        return "altitude_ground" if self.quantity == "altitude" and self.reference == "ground" else self.quantity

    def holds(self, sensed: dict) -> bool:
        value = sensed[self.sensed_name]
        if self.quantity == "altitude":
            rising = sensed["vertical_velocity"]
            return value <= self.value and rising < 0.0 if self.below else value >= self.value and rising > 0.0
        return value <= self.value if self.below else value >= self.value

    def describe(self) -> str:
        where = " above the ground" if self.sensed_name == "altitude_ground" else ""
        return f"{self.quantity}{where} {'below' if self.below else 'above'} {self.value:g}"


@dataclass(frozen=True)
class Apogee:
    """The sensed vertical velocity goes from > 0 to <= 0; a first sample that already descends (a start at or past
    apogee, the state another tool hands over) fires too."""

    quantity = "apogee"
    value = 0.0
    sensed_name = "vertical_velocity"

    def holds(self, sensed: dict, previous: dict | None) -> bool:
        descending = sensed["vertical_velocity"] <= 0.0
        return descending and (previous is None or previous["vertical_velocity"] > 0.0)

    def describe(self) -> str:
        return "apogee"


FUNCTION_TIME_LIMIT = 10.0
"""s: the default longest a user trigger function may take per call (``UserFunction.time_limit``)."""


@dataclass(frozen=True)
class UserFunction:
    """``function(time, sensed, state) -> bool`` (``name``: its "module:function", or the callable's name), called
    in a thread of its own (``user_calls``); a call that takes longer than ``time_limit`` (s) stops the run."""

    name: str
    function: object = field(compare=False, repr=False)
    time_limit: float = FUNCTION_TIME_LIMIT

    def describe(self) -> str:
        return f"function {self.name}"


@dataclass(frozen=True)
class AllOf:
    parts: tuple

    def describe(self) -> str:
        return "all of (" + "; ".join(p.describe() for p in self.parts) + ")"


@dataclass(frozen=True)
class AnyOf:
    parts: tuple

    def describe(self) -> str:
        return "any of (" + "; ".join(p.describe() for p in self.parts) + ")"


@dataclass(frozen=True)
class Sensor:
    """How a trigger senses.

    Attributes
    ----------
    rate : float or None
        Samples per second (Hz); None: at every accepted step.
    lag : float
        Firing delay after the sample that decides (s).
    pressure_noise, pressure_bias : float
        1-sigma noise and bias of the barometric pressure (Pa).
    correlation_time : float
        Time constant of the AR(1) pressure noise (s); 0: white.
    speed_noise, speed_bias : float
        1-sigma noise and bias of the navigated speeds and vertical velocity (m/s).
    body : str or None
        The body sensed; None: the vehicle.
    """

    rate: float | None = None
    lag: float = 0.0
    pressure_noise: float = 0.0
    pressure_bias: float = 0.0
    correlation_time: float = 0.0
    speed_noise: float = 0.0
    speed_bias: float = 0.0
    body: str | None = None

    @property
    def noisy(self) -> bool:
        return self.pressure_noise > 0.0 or self.speed_noise > 0.0


@dataclass(frozen=True)
class Trigger:
    """A condition with its sensor; ``key`` is where the case set it (for messages)."""

    condition: object
    sensor: Sensor = Sensor()
    key: str = ""

    @property
    def timed(self) -> bool:
        """Whether it fires at a time known without sensing (``At``, ``After``)."""
        return isinstance(self.condition, (At, After))

    def describe(self) -> str:
        return self.condition.describe()

    def references(self) -> list:
        """The events whose firing this trigger needs (``After`` anywhere in it)."""
        return [c.event for c in leaves(self.condition) if isinstance(c, After)]


def leaves(condition) -> list:
    """The simple conditions of ``condition`` (itself, or the parts of ``all``/``any``, recursively)."""
    if isinstance(condition, (AllOf, AnyOf)):
        return [leaf for part in condition.parts for leaf in leaves(part)]
    return [condition]


def stream_seed(seed: int, event: str, stream: int) -> np.random.SeedSequence:
    """The seed of noise ``stream`` (0: pressure, 1: speed) of the trigger of ``event``: from the case's seed and the
    event's name alone (CRC-32, the same in every Python process), so any machine, method and step draws the same."""
    return np.random.SeedSequence([int(seed), zlib.crc32(event.encode()), stream])


class NoiseStream:
    """Gaussian noise of standard deviation ``sigma``, one value per sample in order, AR(1) with coefficient
    exp(-period / correlation_time) (stationary from the first sample), white when ``correlation_time`` is 0."""

    def __init__(self, seed: np.random.SeedSequence, sigma: float, period: float | None, correlation_time: float):
        self.rng = np.random.Generator(np.random.PCG64(seed))
        self.sigma = sigma
        self.phi = math.exp(-period / correlation_time) if correlation_time > 0.0 and period else 0.0
        self.value = None

    def next(self) -> float:
        if self.sigma == 0.0:
            return 0.0
        e = float(self.rng.standard_normal())
        if self.value is None:
            self.value = self.sigma * e
        else:
            self.value = self.phi * self.value + self.sigma * math.sqrt(1.0 - self.phi * self.phi) * e
        return self.value


def barometric_altitude(truth: dict, pressure: float, pressure_at) -> float:
    """The altitude (m) whose pressure is ``pressure`` (Pa), by Newton's method on ``pressure_at(h) -> (p, rho)``
    from the true state (hydrostatic slope dp/dh = -rho g)."""
    if not pressure > 0.0:   # a reading at or below zero: above the atmosphere as far as the altimeter knows
        return math.inf
    h, gravity = truth["altitude"], truth["gravity"]
    p, rho = truth["pressure"], truth["density"]
    for _ in range(50):   # converges in 2-4 iterations for errors of 1 % of p, in under 10 for 90 %
        step = (p - pressure) / (rho * gravity)
        step = max(min(step, 5.0 * p / (rho * gravity)), -5.0 * p / (rho * gravity))   # at most 5 scale heights
        h += step
        if abs(step) < 1e-6:
            break
        p, rho = pressure_at(h)
    return h


def sense(truth: dict, sensor: Sensor, pressure_error: float, speed_error: float, pressure_at) -> dict:
    """The sensed values (``SENSED``) from the true ones, with the sample's pressure error (Pa) and speed error (m/s),
    biases included."""
    sensed = {name: truth[name] for name in SENSED}
    if pressure_error != 0.0:
        sensed["pressure"] = truth["pressure"] + pressure_error
        altitude = barometric_altitude(truth, sensed["pressure"], pressure_at)
        sensed["altitude_ground"] += altitude - truth["altitude"]
        sensed["altitude"] = altitude
    if speed_error != 0.0:
        for quantity in QUANTITIES:
            if quantity.error == "speed":
                sensed[quantity.name] = truth[quantity.name] + speed_error
        derive_quantities(sensed, truth)
    return sensed


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

    def observe(self, time: float, truth: dict, fired: dict, pressure_at) -> Firing | None:
        """Take the sample due at ``time`` (s) from the true values ``truth``; ``fired``: event -> time of the events
        fired so far. Returns the Firing when the trigger fires."""
        if self.period is not None:   # samples missed (a rate above the step's) are skipped with their noise
            while (self.index + 1) * self.period <= time + TIME_TOLERANCE:
                self._errors()
                self.index += 1
            self.index += 1
        sensed = self._sense(time, truth, pressure_at)
        condition = self.trigger.condition
        holds = self._holds(condition, time, sensed, truth, fired)
        previous, self.previous = self.previous, (time, sensed, truth)
        if not holds:
            return None
        sample_time, record = time, self._record(condition, time, sensed, truth, fired)
        if self.period is None and previous is not None and isinstance(condition, (Threshold, Apogee)):
            sample_time, record = _crossing(condition, previous, (time, sensed, truth))
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
        if isinstance(condition, Threshold):
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
        if isinstance(condition, (Threshold, Apogee)):
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


def _crossing(condition, before: tuple, after: tuple) -> tuple:
    """(time, record) of a continuously sampled crossing, interpolated linearly between two samples
    (time, sensed, truth)."""
    name = condition.sensed_name
    (t0, sensed0, truth0), (t1, sensed1, truth1) = before, after
    m0, m1 = sensed0[name], sensed1[name]
    w = (condition.value - m0) / (m1 - m0) if m1 != m0 else 1.0
    w = min(max(w, 0.0), 1.0)
    rates = None
    if condition.quantity == "altitude":   # the altitude's rate is known: cubic Hermite, exact for constant g
        rates = [(t1 - t0) * s["vertical_velocity"] for s in (sensed0, sensed1)]
        w = _hermite_root(m0, m1, *rates, condition.value, w)
    time = t0 + w * (t1 - t0)
    measured = condition.value if rates is not None else m0 + w * (m1 - m0)
    true = truth0[name] + w * (truth1[name] - truth0[name])
    if rates is not None:
        true = _hermite(truth0[name], truth1[name], *[(t1 - t0) * s["vertical_velocity"] for s in (truth0, truth1)],
                        w)
    return time, {"quantity": condition.quantity, "threshold": condition.value, "measured": measured, "true": true}


def _hermite(y0: float, y1: float, d0: float, d1: float, w: float) -> float:
    """The cubic Hermite interpolant at ``w`` in [0, 1] of end values y and end slopes d (per unit w)."""
    w2, w3 = w * w, w * w * w
    return ((2 * w3 - 3 * w2 + 1) * y0 + (w3 - 2 * w2 + w) * d0 + (-2 * w3 + 3 * w2) * y1 + (w3 - w2) * d1)


def _hermite_root(y0: float, y1: float, d0: float, d1: float, value: float, guess: float) -> float:
    """w in [0, 1] where the Hermite interpolant equals ``value``, by Newton's method from ``guess``."""
    w = guess
    for _ in range(20):
        w2 = w * w
        slope = (6 * w2 - 6 * w) * y0 + (3 * w2 - 4 * w + 1) * d0 + (-6 * w2 + 6 * w) * y1 + (3 * w2 - 2 * w) * d1
        if slope == 0.0:
            break
        change = (_hermite(y0, y1, d0, d1, w) - value) / slope
        w = min(max(w - change, 0.0), 1.0)
        if abs(change) < 1e-15:
            break
    return w


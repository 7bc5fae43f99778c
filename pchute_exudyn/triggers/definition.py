"""What a trigger is, as the case reader builds it (docs/case-format.md, "Triggers"): a condition and a sensor.

The condition is one of: a run time (``At``), a delay after another event (``After``), a sensed quantity crossing a
value (``Threshold``, the quantities of ``registries.quantities``), a static line's or pilot chute's line stretch
(``LineStretch``, made by the case reader from ``[systems.<name>.static_line]`` or ``.pilot_chute``), apogee
(``Apogee``), a user's flight-computer function (``UserFunction``) or ``all``/``any`` of several (``AllOf``,
``AnyOf``). The sensor (``Sensor``) samples at a rate (Hz; none: at every accepted step), fires after a lag (s) and
adds seeded noise and a bias. Frozen data: what a sensor reads is ``triggers.sensors``, a trigger through a run
``triggers.watch``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..physics.deployment import PilotChute, StaticLine


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
class LineStretch:
    """A static line's or pilot chute's system at line stretch: the sensed body's centre of mass ``value`` (m, its
    reach: ``physics.deployment.bag_reach``) from the bag's anchor (``line``: a ``StaticLine``, whose anchor
    flies on with the aircraft, or a ``PilotChute``, whose anchor is its body's centre of mass as the run reads it).
    Read from the true positions (a line coming taut, not a sensor), at every step, its crossing interpolated."""

    line: StaticLine | PilotChute
    value: float

    @property
    def quantity(self) -> str:
        return self.line.key

    @property
    def sensed_name(self) -> str:
        return f"{self.line.key}_distance"

    def distance(self, time: float, position, anchor_position=None) -> float:
        """m: from the anchor at run time ``time`` (s) to the start-frame ``position`` (m); ``anchor_position``: the
        anchor body's centre of mass (m; a pilot chute's), None for a static line's."""
        return float(np.linalg.norm(np.asarray(position, float) - self.line.anchor_at(time, anchor_position)))

    def holds(self, sensed: dict) -> bool:
        return sensed[self.sensed_name] >= self.value

    def describe(self) -> str:
        return f"{self.line.described} and lines out ({self.value:g} m from {self.line.describe()})"


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
    in a thread of its own (``triggers.user_calls``); a call that takes longer than ``time_limit`` (s) stops the run."""

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

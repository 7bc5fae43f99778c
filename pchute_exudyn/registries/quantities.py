"""The quantities a trigger's sensor reads, one record each (``Quantity``: name, unit, meaning, the sensor error that
reaches it, how it is derived from the others, whether a threshold may watch it and a record keeps it, the range it
can take), and the tables the case reader, the sensing (``triggers.sensors``), the run's records and the study
columns read from them (docs/case-format.md, "Triggers").

Conventions: ``vertical_velocity`` is up-positive (m/s); ``altitude`` is geodetic (above the reference ellipsoid,
"geoid" in the case), ``altitude_ground`` above the case's ground; speeds are magnitudes (m/s).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from ..physics.aerodynamics import dynamic_pressure_of_speed, mach_number


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

"""Unit slips a user really makes, caught where each value alone is plausible: a warning when the case loads
(``Case.warnings``: the run line and summary.json show it) naming the likely mistake (docs/case-format.md, "Unit
slips").

* The vehicle's mass against its size: its ballistic coefficient m / (C_A A) (with aerodynamics) above
  BALLISTIC_RANGE, as a mass given in grams gives.
* Its inertia against its mass and size: the largest radius of gyration sqrt(I / m) outside GYRATION_RANGE times its
  size (the larger of the aerodynamic reference diameter and twice its farthest named point), as an inertia in
  g cm^2 (1e7 times kg m^2), or a mass in grams with the inertia in kg m^2, gives.
* A start rate above SPIN_RATE rad/s: a rate in deg/s where rad/s is asked.

Each warns only when the slip it names explains the value (the value corrected lies in the range): a body made
immovable on purpose (tests/cases/pivot_wind.toml, 1e12 kg) is not a slip. A value already outside its
plausibility range (``case.plausible``) has that warning alone.
"""

from __future__ import annotations

import math

import numpy as np

from .plausible import check_value

BALLISTIC_RANGE = (0.05, 5e4)
"""kg/m^2: m / (C_A A) of real descending vehicles, from a parachute payload of a few grams per m^2 of canopy area
to a dense re-entry body (the shipped cases: 84 to 303; a slender rocket: a few 1000)."""
GYRATION_RANGE = (0.03, 10.0)
"""The largest radius of gyration over the size (-): a solid sphere 0.32, a capsule 0.2 to 0.4, a slender rocket's
pitch axis about 0.3 of its length, a long rod 0.29 (the shipped cases: 0.07 to 0.41)."""
SPIN_RATE = 10.0
"""rad/s (1.6 revolutions per second): a faster start rate is far more often a rate in deg/s."""


def unit_slips(body) -> tuple:
    """One warning line per likely unit mistake of vehicle ``body`` (``model.Body``); () for none."""
    if body.mass is None or body.fixed or check_value(f"bodies.{body.name}.mass", body.mass)[1] is not None:
        return ()
    key = f"bodies.{body.name}"
    lines = []
    aero = body.aerodynamics
    axial = max((abs(v) for v in np.ravel(aero.axial_coefficient.value)), default=0.0) if aero is not None else 0.0
    if axial > 0.0:
        beta = body.mass / (axial * aero.reference_area)
        if beta > BALLISTIC_RANGE[1] and _within(beta / 1e3, BALLISTIC_RANGE):
            lines.append(f"{key}.mass = {body.mass:g} kg gives a ballistic coefficient m / (C_A A) of {beta:.3g} "
                         f"kg/m^2, above every real vehicle's ({BALLISTIC_RANGE[1]:g}): if it is in grams, give "
                         f"{body.mass / 1e3:.6g} kg")
    lines += _gyration(body, key, _size(body))
    for axis in "xyz":
        rate = getattr(body.initial, f"rate_{axis}", 0.0) if body.initial is not None else 0.0
        if SPIN_RATE < abs(rate) and check_value(f"{key}.initial.rate_{axis}", rate)[1] is None:
            lines.append(f"{key}.initial.rate_{axis} = {rate:g} rad/s ({abs(rate) / (2 * math.pi):.3g} revolutions "
                         f"per second): if it is in deg/s, give {math.radians(rate):.6g} rad/s")
    return tuple(lines)


def _within(value: float, bounds: tuple) -> bool:
    return bounds[0] <= value <= bounds[1]


def _size(body) -> float:
    """m: the larger of the aerodynamic reference diameter and twice the farthest named point (0: neither)."""
    reach = max((float(np.linalg.norm(point)) for point in body.points.values()), default=0.0)
    diameter = math.sqrt(4.0 * body.aerodynamics.reference_area / math.pi) if body.aerodynamics is not None else 0.0
    return max(diameter, 2.0 * reach)


def _gyration(body, key: str, size: float) -> list:
    if body.inertia is None or size <= 0.0 or check_value(f"{key}.inertia", np.ravel(body.inertia).tolist())[1]:
        return []
    moments = np.abs(np.linalg.eigvalsh(np.asarray(body.inertia, dtype=float)))
    ratio = math.sqrt(float(moments.max()) / body.mass) / size
    if ratio > GYRATION_RANGE[1] and _within(ratio / math.sqrt(1e7), GYRATION_RANGE):
        hint = "if the inertia is in g cm^2, give it divided by 1e7 (kg m^2)"
    elif ratio < GYRATION_RANGE[0] and _within(ratio * math.sqrt(1e3), GYRATION_RANGE):
        hint = f"if the mass is in grams (the inertia in kg m^2), give {body.mass / 1e3:.6g} kg"
    else:   # no unit slip explains it (a body made immovable on purpose)
        return []
    return [f"{key}.inertia: its largest radius of gyration sqrt(I / m) is {ratio:.3g} times the body's size "
            f"({size:.3g} m), outside {GYRATION_RANGE[0]:g}..{GYRATION_RANGE[1]:g}: {hint}"]

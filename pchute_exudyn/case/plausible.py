"""Plausibility ranges of a case's physical keys: the one table the case reader checks every number against, and
the source of the table in docs/case-format.md ("Plausibility ranges"; a test compares the two).

Each range names a key pattern (dotted, ``*`` standing for a body, system, line or gust), its unit, the values that
are *impossible* for this tool (outside them: a CaseError, "key = value: must be within A..B (unit)") and the values
that are *plausible* (outside them but possible: a warning the run carries in ``Case.warnings``, its run line and
``summary.json``). The readers' own checks (a mass > 0, a fraction within [0, 1]) come first; these catch what passes
them but cannot be meant: a line table of 1e307 N, an initial speed of 3e7 m/s, a turbulence scale length of 1 mm.

Time scales that need the integration step (a gust's length, the time a turbulence scale length takes to pass) are
checked when the run is planned: ``check_time_scales``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

from ..errors import CaseError, short_repr


@dataclass(frozen=True)
class Range:
    """The plausibility range of the keys matching ``pattern`` (every number of a list or table counts).

    Attributes
    ----------
    pattern : str
        Dotted key, ``*`` for any name (``systems.*.lines.*.stiffness``).
    unit : str
        The key's unit ("" for a pure number).
    impossible : tuple of 2 float
        (low, high): a value outside is an error.
    plausible : tuple of 2 float
        (low, high): a value outside (but possible) is a warning.
    """

    pattern: str
    unit: str
    impossible: tuple
    plausible: tuple


def _speeds(pattern: str, impossible: float, plausible: float) -> Range:
    return Range(pattern, "m/s", (-impossible, impossible), (-plausible, plausible))


_COEFFICIENTS = ("axial_coefficient", "normal_coefficient", "moment_coefficient", "pitch_damping", "roll_damping")
_INITIAL = ("bodies.*.initial.", "systems.*.confluence.initial.")

RANGES: tuple = (
    # masses and inertias
    Range("bodies.*.mass", "kg", (1e-6, 1e15), (1e-2, 1e12)),
    Range("systems.*.confluence.mass", "kg", (1e-9, 1e9), (1e-4, 1e4)),
    Range("bodies.*.inertia", "kg m^2", (-1e18, 1e18), (-1e14, 1e14)),
    # lengths and areas
    Range("bodies.*.points.*", "m", (-1e5, 1e5), (-1e3, 1e3)),
    Range("bodies.*.aerodynamics.center", "m", (-1e5, 1e5), (-1e3, 1e3)),
    Range("bodies.*.aerodynamics.reference_length", "m", (1e-6, 1e5), (1e-3, 1e3)),
    Range("bodies.*.aerodynamics.reference_area", "m^2", (1e-9, 1e8), (1e-4, 1e5)),
    Range("bodies.*.apparent_mass.projected_radius", "m", (1e-6, 1e5), (1e-3, 1e3)),
    Range("systems.*.lines.*.free_length", "m", (1e-6, 1e5), (1e-2, 1e3)),
    # coefficients
    *(Range(f"bodies.*.aerodynamics.{key}{tail}", "", (-1e4, 1e4), (-100.0, 100.0))
      for key in _COEFFICIENTS for tail in ("", ".value")),
    *(Range(f"bodies.*.aerodynamics.{key}.mach", "", (0.0, 1e3), (0.0, 50.0)) for key in _COEFFICIENTS),
    *(Range(f"bodies.*.apparent_mass.{key}", "", (0.0, 1e3), (0.0, 10.0)) for key in ("axial", "lateral",
                                                                                       "rotational")),
    # lines, contact
    Range("systems.*.lines.*.stiffness", "N/m", (0.0, 1e15), (0.0, 1e10)),
    Range("systems.*.lines.*.damping", "N s/m", (0.0, 1e12), (0.0, 1e8)),
    Range("systems.*.lines.*.load_elongation.tension", "N", (0.0, 1e12), (0.0, 1e8)),
    Range("systems.*.lines.*.load_elongation.strain", "", (0.0, 10.0), (0.0, 2.0)),
    Range("systems.*.lines.*.breaking_strength", "N", (0.0, 1e12), (1.0, 1e8)),
    Range("systems.*.contact.stiffness", "N/m", (0.0, 1e15), (0.0, 1e10)),
    Range("systems.*.contact.damping", "N s/m", (0.0, 1e12), (0.0, 1e8)),
    # initial states: speeds, rates, altitudes, positions
    *(_speeds(f"{prefix}velocity_{axis}", 2e4, 3e3) for prefix in _INITIAL for axis in ("north", "east", "down")),
    *(Range(f"bodies.*.initial.rate_{axis}", "rad/s", (-1e4, 1e4), (-100.0, 100.0)) for axis in "xyz"),
    *(Range(f"{prefix}altitude", "m", (-5e4, 1e7), (-1.2e4, 2e5)) for prefix in _INITIAL),
    *(Range(f"{prefix}{axis}", "m", (-1e7, 1e7), (-1e5, 1e5)) for prefix in _INITIAL for axis in ("east", "north")),
    Range("start.release.airspeed", "m/s", (0.0, 2e4), (0.0, 1e3)),
    # the run
    Range("simulation.duration", "s", (1e-9, 1e8), (1e-3, 1e5)),
    Range("simulation.ground_altitude", "m", (-5e4, 1e7), (-1.2e4, 2e4)),
    Range("simulation.descent_rate_events", "m/s", (0.0, 2e4), (0.0, 1e3)),
    Range("simulation.step_control.relative", "", (1e-15, 1.0), (1e-8, 0.1)),
    Range("simulation.step_control.absolute", "m/s", (1e-15, 1e4), (1e-9, 10.0)),
    # a step over 1 s skips a trigger's samples and a deployment's snatch (the default largest is 0.25 s)
    *(Range(f"simulation.step_control.{key}", "s", (1e-12, 1e6), (1e-9, 1.0))
      for key in ("first", "largest", "smallest")),
    # inflation
    Range("systems.*.inflation.fill_constant", "", (1e-6, 1e4), (1e-2, 100.0)),
    Range("systems.*.inflation.exponent", "", (0.0, 100.0), (0.1, 10.0)),
    Range("systems.*.inflation.overinflation", "", (1.0, 100.0), (1.0, 5.0)),
    Range("systems.*.inflation.overinflation_decay", "s", (0.0, 1e5), (0.0, 100.0)),
    # a drag area schedule: a canopy fills in seconds (PA1's reefed main: 18 s); minutes are a typo or a unit slip
    Range("systems.*.drag_area_schedule.time", "s", (0.0, 1e8), (0.0, 100.0)),
    # a supersonic opening's law: C_ref fitted from 1.3 to 2 (SR01, SR02, MSL); the largest entry forebodies ~ 10 m
    Range("systems.*.inflation.supersonic.load_factor", "", (1.0, 1e6), (1.0, 5.0)),
    Range("systems.*.inflation.supersonic.forebody_diameter", "m", (0.0, 1e6), (0.0, 30.0)),
    Range("systems.*.inflation.supersonic.mach_slope", "", (-1e6, 1e6), (-10.0, 10.0)),   # MSL's: 1.254
    # planet and atmosphere
    Range("planet.gravity", "m/s^2", (0.0, 1e3), (0.0, 100.0)),
    Range("planet.gravitational_parameter", "m^3/s^2", (1.0, 1e22), (1e9, 1e18)),
    Range("planet.equatorial_radius", "m", (1.0, 1e10), (1e4, 1e8)),
    Range("planet.polar_radius", "m", (1.0, 1e10), (1e4, 1e8)),
    Range("planet.rotation_rate", "rad/s", (-1.0, 1.0), (-1e-3, 1e-3)),
    Range("planet.spin_rate", "rad/s", (0.0, 1.0), (0.0, 1e-3)),
    Range("atmosphere.speed_of_sound", "m/s", (1.0, 1e5), (100.0, 2e3)),
    Range("atmosphere.gamma", "", (1.0, 10.0), (1.0, 1.7)),
    Range("atmosphere.gas_constant", "J/(kg K)", (1.0, 1e6), (100.0, 5e3)),
    # wind, turbulence, gusts
    *(_speeds(f"atmosphere.wind.{key}", 1e3, 150.0) for key in ("east", "north", "speed")),
    Range("atmosphere.wind.altitude", "m", (-5e4, 1e7), (-1.2e4, 2e5)),
    Range("atmosphere.wind.from_deg", "deg", (-1e6, 1e6), (-360.0, 360.0)),   # a direction: one turn either way
    Range("atmosphere.wind.reference_height", "m", (1e-3, 1e5), (0.1, 1e3)),
    Range("atmosphere.wind.ground_altitude", "m", (-5e4, 1e7), (-1.2e4, 2e4)),
    *(Range(f"atmosphere.turbulence.sigma_{c}", "m/s", (0.0, 1e3), (0.0, 30.0)) for c in "uvw"),
    *(Range(f"atmosphere.turbulence.length_{c}", "m", (0.1, 1e6), (1.0, 1e4)) for c in "uvw"),
    Range("atmosphere.turbulence.wind_speed_6m", "m/s", (0.0, 1e3), (0.0, 100.0)),
    Range("atmosphere.turbulence.ground_altitude", "m", (-5e4, 1e7), (-1.2e4, 2e4)),
    _speeds("atmosphere.gusts[*].amplitude", 1e3, 100.0),
    Range("atmosphere.gusts[*].length", "s", (1e-9, 1e8), (1e-2, 1e4)),
    Range("atmosphere.density_scale", "", (1e-6, 1e6), (0.5, 2.0)),
    # triggers, sensors and separations
    Range("*trigger*.rate", "Hz", (1e-6, 1e9), (0.1, 1e4)),
    Range("*trigger*.lag", "s", (0.0, 1e7), (0.0, 60.0)),
    Range("*trigger*.delay", "s", (0.0, 1e9), (0.0, 1e5)),
    Range("*trigger*.pressure_noise", "Pa", (0.0, 1e6), (0.0, 1e4)),
    Range("*trigger*.pressure_bias", "Pa", (-1e6, 1e6), (-1e4, 1e4)),
    Range("*trigger*.correlation_time", "s", (0.0, 1e9), (0.0, 1e4)),
    Range("*trigger*.speed_noise", "m/s", (0.0, 1e4), (0.0, 100.0)),
    Range("*trigger*.speed_bias", "m/s", (-1e4, 1e4), (-100.0, 100.0)),
    Range("*trigger*.time_limit", "s", (1e-6, 1e7), (1e-3, 3600.0)),
    Range("separations.*.speed", "m/s", (0.0, 1e4), (0.0, 50.0)),
)
"""Every plausibility range; the first whose pattern matches a key applies."""


IMPLAUSIBLE = " is implausible: "
"""What joins a key and its value to the range in an implausibility warning (``check_value``; ``implausible_settings``
reads it back)."""


def implausible_settings(warnings) -> list:
    """The "key = value" of each implausibility warning among ``warnings`` (one-line texts)."""
    return [line.partition(IMPLAUSIBLE)[0] for line in warnings if IMPLAUSIBLE in line]


@functools.lru_cache(maxsize=4096)
def range_of(key: str) -> Range | None:
    """The range of the full dotted ``key`` (gusts indexed: ``atmosphere.gusts[0].amplitude``), None for none;
    remembered per key (a study's worker loads the same keys in every run: 0.1 ms each through the patterns)."""
    for entry in RANGES:
        if _matches(key, entry.pattern):
            return entry
    return None


def _matches(key: str, pattern: str) -> bool:
    """Whether ``key`` matches ``pattern``, whose ``*`` stands for any run of characters (dots and brackets
    included) and every other character for itself (``[*]`` a bracketed index): fnmatch's rule for such patterns,
    without compiling 100 regular expressions at a run's start (20 ms)."""
    parts = pattern.split("*")
    head, tail = parts[0], parts[-1]
    if len(parts) == 1:
        return key == pattern
    if len(key) < len(head) + len(tail) or not key.startswith(head) or not key.endswith(tail):
        return False
    position, end = len(head), len(key) - len(tail)
    for part in parts[1:-1]:   # each middle piece at its leftmost place after the last (greedy is exact for *)
        found = key.find(part, position, end)
        if found < 0:
            return False
        position = found + len(part)
    return True


def numbers(value) -> list:
    """Every number in ``value``: a number, a (nested) list, or a coefficient table's values; booleans and text
    are none (the readers refuse them)."""
    if isinstance(value, bool):
        return []
    if isinstance(value, (int, float)):
        return [value]
    if isinstance(value, list):
        return [number for item in value for number in numbers(item)]
    return []


def _within(value: float, bounds: tuple) -> bool:
    return bounds[0] <= value <= bounds[1]


def _describe(value, entry: Range, bounds: tuple) -> str:
    unit = f" ({entry.unit})" if entry.unit else ""
    return f"{'each ' if isinstance(value, list) else ''}must be within {bounds[0]:g}..{bounds[1]:g}{unit}"


def check_value(key: str, value) -> tuple:
    """(error, warning) for ``value`` of ``key``: what is allowed, for an impossible value (or None), and the
    one-line warning of an implausible one (or None)."""
    entry = range_of(key)
    if entry is None:
        return None, None
    for number in numbers(value):
        number = float(number) if not isinstance(number, float) else number
        if not math.isfinite(number):
            return None, None   # the reader's own check names it
        if not _within(number, entry.impossible):
            return _describe(value, entry, entry.impossible) + " for this tool", None
    for number in numbers(value):
        if not _within(float(number), entry.plausible):
            unit = f" ({entry.unit})" if entry.unit else ""
            return None, (f"{key} = {short_repr(value)}{IMPLAUSIBLE}outside {entry.plausible[0]:g}.."
                          f"{entry.plausible[1]:g}{unit}")
    return None, None


def check_time_scales(case, step: float) -> None:
    """Refuse, when the run is planned with its ``step`` (s), time scales the integration cannot resolve: a gust
    shorter than the step, and a turbulence scale length the vehicle crosses in less than a step (at its start
    speed, in the air at rest; none when it starts at rest). Raises CaseError naming the key, its value and the
    smallest allowed."""
    for i, gust in enumerate(case.gusts):
        if gust.length < step:
            raise CaseError(case.source, f"atmosphere.gusts[{i}].length", f"must be >= the integration step "
                            f"({step:g} s): a shorter pulse falls between the steps", gust.length)
    turbulence = case.turbulence
    if turbulence is None or turbulence.length is None:
        return
    speed = _start_speed(case)
    for component, length in zip("uvw", turbulence.length):
        if speed > 0.0 and length / speed < step:
            raise CaseError(case.source, f"atmosphere.turbulence.length_{component}",
                            f"must be >= {speed * step:.3g} m: the vehicle at {speed:.3g} m/s crosses it in less "
                            f"than the integration step ({step:g} s)", length)


def _start_speed(case) -> float:
    """The vehicle's speed (m/s) at the start: what sweeps it through the turbulence field."""
    vehicle = case.bodies[case.vehicle]
    if vehicle.initial is None or vehicle.fixed:
        return 0.0
    return float(math.hypot(*vehicle.initial.velocity_enu))


def markdown_table() -> str:
    """RANGES as the Markdown table of docs/case-format.md ("Plausibility ranges"; a test keeps the two equal)."""
    rows = ["| key | unit | impossible outside (error) | implausible outside (warning) |", "|---|---|---|---|"]
    for entry in RANGES:
        rows.append(f"| `{entry.pattern}` | {entry.unit or '-'} | {entry.impossible[0]:g} .. {entry.impossible[1]:g} | "
                    f"{entry.plausible[0]:g} .. {entry.plausible[1]:g} |")
    return "\n".join(rows)

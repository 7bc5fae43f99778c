"""Flight conditions as a start: the altitude and speed at which an atmosphere gives a Mach number and a dynamic
pressure (line stretch or mortar fire as flight reconstructions state it; docs/case-format.md).

With V = M a(h) the dynamic pressure is q = rho(h) a(h)^2 M^2 / 2, so the altitude solves

    rho(h) a(h)^2 M^2 / 2 = q        (rho kg/m^3, a m/s, q Pa; rho a^2 = gamma p for an ideal gas)

over the atmosphere's altitude range, and the speed is V = M a(h). rho a^2 falls with altitude in a hydrostatic
atmosphere, so there is one root; in a table where it does not, the lowest is taken. No Exudyn, no files.
"""

from __future__ import annotations

import numpy as np

OPEN_RANGE = (-10000.0, 100000.0)
"""m: where the root is sought in a model without a range of its own (the Mars model; its temperature stays above
0 K to about 112 km)."""
SCAN_POINTS = 2001
"""Altitudes the range is scanned at for the bracket before the root is refined."""


class ConditionsError(ValueError):
    """No altitude of the atmosphere gives the Mach number and dynamic pressure, or it has no speed of sound;
    ``field`` names the input at fault ("mach" or "dynamic_pressure")."""

    def __init__(self, message: str, field: str = "dynamic_pressure"):
        super().__init__(message)
        self.field = field


def slowest_sound(atmosphere) -> float:
    """The smallest speed of sound (m/s) of ``atmosphere`` over its altitude range (``altitude_range``, at the
    SCAN_POINTS altitudes the solve scans): a Mach number M gives at least M times it."""
    low, high = altitude_range(atmosphere)
    return float(np.nanmin(atmosphere.states(np.linspace(low, high, SCAN_POINTS))[1]))


def altitude_range(atmosphere) -> tuple:
    """(low, high) (m): the geodetic altitudes ``atmosphere`` covers, ``OPEN_RANGE`` when it covers every one."""
    try:
        outside = atmosphere.outside(0.0)
    except NotImplementedError:
        return OPEN_RANGE
    return float(outside.low), float(outside.high)


def altitude_and_speed(atmosphere, mach: float, dynamic_pressure: float) -> tuple:
    """The geodetic altitude (m) and airspeed (m/s) at which ``atmosphere`` gives Mach number ``mach`` (-, > 0) and
    dynamic pressure ``dynamic_pressure`` (Pa, > 0): the root of rho(h) a(h)^2 mach^2 / 2 = q, and V = mach a(h).

    Raises
    ------
    ConditionsError
        When the atmosphere has no speed of sound, or no altitude in its range gives that pair (the message gives
        the dynamic pressures it spans at that Mach number).
    """
    if not atmosphere.has_speed_of_sound:
        raise ConditionsError(f"the {atmosphere.name} atmosphere has no speed of sound, so a Mach number cannot be "
                              "turned into a speed")
    low, high = altitude_range(atmosphere)
    heights = np.linspace(low, high, SCAN_POINTS)
    density, sound = atmosphere.states(heights)
    try:
        square = mach ** 2
    except OverflowError:   # a float past 1e154
        square = np.inf
    with np.errstate(over="ignore"):
        pressures = 0.5 * density * sound ** 2 * square
    if not np.isfinite(pressures).any():
        raise ConditionsError(f"Mach {mach:g} overflows the dynamic pressure rho a^2 M^2 / 2 at every altitude of "
                              f"the {atmosphere.name} atmosphere", "mach")
    excess = np.where(np.isfinite(pressures), pressures - dynamic_pressure, np.nan)
    crossings = np.flatnonzero((excess[:-1] >= 0.0) & (excess[1:] <= 0.0) | (excess[:-1] <= 0.0) & (excess[1:] >= 0.0))
    if crossings.size == 0:
        spanned = pressures[np.isfinite(pressures)]
        raise ConditionsError(f"no altitude of the {atmosphere.name} atmosphere ({low:g} to {high:g} m) gives "
                              f"{dynamic_pressure:g} Pa at Mach {mach:g}: it spans {spanned.min():.4g} to "
                              f"{spanned.max():.4g} Pa there")
    i = int(crossings[0])

    def excess_at(h):
        rho, a = atmosphere.state(h)
        return 0.5 * rho * a * a * mach * mach - dynamic_pressure

    if excess[i] == 0.0:
        return float(heights[i]), float(mach * atmosphere.speed_of_sound(heights[i]))
    from scipy.optimize import brentq  # here, not at import: a case load must not pay for scipy.optimize

    altitude = brentq(excess_at, heights[i], heights[i + 1], xtol=1e-10, rtol=4 * np.finfo(float).eps, maxiter=200)
    return float(altitude), float(mach * atmosphere.speed_of_sound(altitude))

"""Piecewise-linear interpolation in tables with sorted breakpoints: in plain floats (``bracket``,
``interpolate_held``: drag-area schedules, wind profiles) and compiled on packed arrays (``bracket_packed``: the
per-stage coefficient tables and atmosphere tables)."""

from __future__ import annotations

import bisect

from .compiled import kernel


def bracket(breakpoints, x: float) -> tuple[int, float]:
    """(i, w) with x = (1 - w) breakpoints[i - 1] + w breakpoints[i]; held at the end points beyond them
    (w = 0 at the first, w = 1 at the last). ``breakpoints``: strictly increasing, at least two."""
    if x <= breakpoints[0]:
        return 1, 0.0
    if x >= breakpoints[-1]:
        return len(breakpoints) - 1, 1.0
    i = bisect.bisect_right(breakpoints, x)
    return i, (x - breakpoints[i - 1]) / (breakpoints[i] - breakpoints[i - 1])


def interpolate_held(breakpoints, values, x: float) -> float:
    """``values`` at ``x``, linear between the breakpoints and held constant beyond the ends."""
    i, w = bracket(breakpoints, x)
    return values[i - 1] + w * (values[i] - values[i - 1])


@kernel
def bracket_packed(values, start, n, x):
    """``bracket`` for the n breakpoints at values[start:start + n] of a packed array (the same arithmetic)."""
    if x <= values[start]:
        return 1, 0.0
    if x >= values[start + n - 1]:
        return n - 1, 1.0
    i = 1
    while values[start + i] <= x:   # bisect_right
        i += 1
    return i, (x - values[start + i - 1]) / (values[start + i] - values[start + i - 1])

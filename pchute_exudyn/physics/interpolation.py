"""Piecewise-linear interpolation in tables with sorted breakpoints, in plain floats (it runs in per-stage user
functions): aerodynamic coefficient tables, drag-area schedules, wind and atmosphere profiles."""

from __future__ import annotations

import bisect


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

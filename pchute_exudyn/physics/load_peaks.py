"""The peaks of a deployment's load history: the snatch (the first peak) and the opening load (the largest), as a
recovery designer reads them off a load-cell trace (docs/models/deployment_loads.md)."""

from __future__ import annotations

import math

import numpy as np

SNATCH_DROP = 0.1
"""A peak counts as the snatch once the load has fallen this share below it (-): a load cell's first peak, not a
ripple on a rising load."""


SNATCH_FLOOR = 0.1
"""A first peak counts only from this share of the largest load on (-): the ripples of a slack line's first
centimetres are not a snatch."""


def first_peak(times, loads, drop: float = SNATCH_DROP, floor: float = 0.0) -> tuple[float, float]:
    """The first peak (N) of ``loads`` (N, at ``times`` in s) and its time (s): the running maximum at the first
    sample where the load has fallen a share ``drop`` (-) below it, once that maximum exceeds ``floor`` (N); the
    largest load when it never falls that far (a load that only rises has its first peak at its end). (nan, nan) for
    no samples."""
    peak, when = -math.inf, math.nan
    for t, load in zip(times, loads):
        if load > peak:
            peak, when = load, t
        elif load < (1.0 - drop) * peak and peak > max(floor, 0.0):
            return peak, when
    return (peak, when) if when == when else (math.nan, math.nan)


def largest(times, loads) -> tuple[float, float]:
    """The largest load (N) and its time (s), the first when it repeats; (nan, nan) for no samples."""
    peak, when = -math.inf, math.nan
    for t, load in zip(times, loads):
        if load > peak:
            peak, when = load, t
    return (peak, when) if when == when else (math.nan, math.nan)


def averaged_peak(times, loads, start: float, span: float, window: float, spacing: float = 1e-4) -> float:
    """N: the largest load averaged over ``window`` (s) within ``span`` (s) from ``start`` (s), the history (N at
    ``times`` in s) resampled every ``spacing`` (s): the peak a load cell of that averaging time reads. A full-mass
    confluence's own chatter between its bridles (hundreds of hertz under a held canopy's snatch) averages out; the
    snatch's hump, a few tenths of a second long, does not."""
    grid = np.arange(start, start + span, spacing)
    resampled = np.interp(grid, np.asarray(times, float), np.asarray(loads, float))
    count = max(int(round(window / spacing)), 1)
    return float(np.max(np.convolve(resampled, np.full(count, 1.0 / count), mode="valid")))

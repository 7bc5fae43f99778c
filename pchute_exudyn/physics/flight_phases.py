"""A flight's phases from a height history: the pad level and the launch, the apogee, and robust descent rates over
height bands, for reading a flight log. Pure functions on arrays: heights in m, times in s.

The descent rate over a band is the Theil-Sen slope of the samples within it, the median of the slopes between every
pair of them: a barometric spike at an ejection charge or a dropout moves it only when it covers more than about
three tenths of the band's samples, where a single-sample derivative follows every one of them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LAUNCH_RISE = 10.0
"""m above the pad level that counts as off the pad (a gust or a door slam moves a barometer by a few metres)."""
PAD_TOLERANCE = 1.0
"""m: the launch is the last sample this close to the pad level before the rise."""
APOGEE_WINDOW = 1.0
"""s: the running median the apogee is read on (an ejection charge's pressure spike lasts a few samples)."""
SPIKE = 5.0
"""m from the running median beyond which a sample is a spike, left out of the apogee's parabola."""
MOST_PAIRS = 400
"""Samples at most in one Theil-Sen fit (evenly thinned): 80,000 pairs, milliseconds."""
TOUCHDOWN_WINDOW = 2.0
"""s: the running median the touchdown is read on (a landing's bounce and the wind on the port last a second)."""
LANDED_BAND = 5.0
"""m: on the ground is within this of the pad level, or still to within this (a landing site off the pad's level)."""
LANDED_HOLD = 5.0
"""s the height must stay so (and over LANDED_SAMPLES samples at least): a canopy descends at 3 m/s or more, 15 m
in this time, so no descent passes for it, nor a telemetry record's repeated last value over a gap."""
LANDED_SAMPLES = 3
"""Samples at least in the LANDED_HOLD window."""
REST_CEILING = 100.0
"""m above the pad level below which a log at rest is on the ground (above it, a stuck sensor, not a landing)."""


class FlightPhaseError(ValueError):
    """The history has no launch, no apogee or no descent: the message says which."""


@dataclass(frozen=True)
class Phases:
    """Indices and times of a flight: the pad level (m), launch and apogee (index, time in s), and whether it
    descends after the apogee."""

    pad_level: float
    launch_index: int
    launch_time: float
    apogee_index: int
    apogee_time: float
    apogee_height: float


def running_median(times, values, window: float) -> np.ndarray:
    """``values`` replaced by their median over a centred window of ``window`` (s)."""
    times, values = np.asarray(times, float), np.asarray(values, float)
    left = np.searchsorted(times, times - 0.5 * window, side="left")
    right = np.searchsorted(times, times + 0.5 * window, side="right")
    return np.array([np.median(values[a:b]) for a, b in zip(left, right)])


def flight_phases(times, heights) -> Phases:
    """The pad level (median of the samples before the rise), the launch (the last sample within PAD_TOLERANCE of it
    before the height first rises LAUNCH_RISE above it) and the apogee (the highest point of the running median,
    APOGEE_WINDOW). FlightPhaseError when the height never rises or never falls after its highest point."""
    times, heights = np.asarray(times, float), np.asarray(heights, float)
    if len(times) < 3 or np.any(np.diff(times) <= 0.0):
        raise FlightPhaseError("times must increase from sample to sample (at least three samples)")
    start = np.median(heights[: max(3, len(heights) // 100)])
    risen = np.nonzero(heights > start + LAUNCH_RISE)[0]
    if len(risen) == 0:
        raise FlightPhaseError(f"the height never rises {LAUNCH_RISE:g} m above the pad level ({start:.1f} m): no "
                               "launch")
    pad = float(np.median(heights[: risen[0]])) if risen[0] > 0 else float(start)
    near = np.nonzero(np.abs(heights[: risen[0]] - pad) <= PAD_TOLERANCE)[0]
    launch = int(near[-1]) if len(near) else 0
    smooth = running_median(times, heights, APOGEE_WINDOW)
    coarse = launch + int(np.argmax(smooth[launch:]))
    if times[-1] - times[coarse] <= APOGEE_WINDOW:
        raise FlightPhaseError(f"the height still rises at the log's end (its highest, {smooth[coarse]:.1f} m, at "
                               f"{times[coarse]:.2f} s of {times[-1]:.2f} s): no apogee; the log must run past it")
    if smooth[coarse:].min() > smooth[coarse] - LAUNCH_RISE:
        raise FlightPhaseError(f"the height never falls {LAUNCH_RISE:g} m below its highest point "
                               f"({smooth[coarse]:.1f} m at {times[coarse]:.2f} s): no descent")
    time, height = _vertex(times, heights, smooth, times[coarse])
    apogee = int(np.searchsorted(times, time))
    return Phases(pad, launch, float(times[launch]), min(apogee, len(times) - 1), time, height)


def touchdown_index(times, heights, phases: Phases) -> int | None:
    """Index of the touchdown: the first sample after the apogee from which the running median (TOUCHDOWN_WINDOW)
    stays within LANDED_BAND of the pad level for LANDED_HOLD and LANDED_SAMPLES (or to the log's end), or stays
    within LANDED_BAND of itself for them below REST_CEILING (a field above or below the pad). None when the log
    ends in the air."""
    times, heights = np.asarray(times, float), np.asarray(heights, float)
    smooth = running_median(times, heights, TOUCHDOWN_WINDOW)
    ends = np.maximum(np.searchsorted(times, times + LANDED_HOLD, side="right"),
                      np.arange(len(times)) + LANDED_SAMPLES)
    for i in range(phases.apogee_index, len(times)):
        window = smooth[i:ends[i]]
        if len(window) >= min(LANDED_SAMPLES, len(times) - i) and np.all(np.abs(window - phases.pad_level)
                                                                         <= LANDED_BAND):
            return i
        whole = times[i] + LANDED_HOLD <= times[-1] and ends[i] <= len(times)
        if whole and np.ptp(window) <= LANDED_BAND and smooth[i] - phases.pad_level <= REST_CEILING:
            return i
    return None


def _vertex(times, heights, smooth, near: float) -> tuple[float, float]:
    """(time in s, height in m) of the top of a parabola fitted by least squares to the samples within
    APOGEE_WINDOW of ``near`` (s) that stay within SPIKE of the running median ``smooth``: the running median's own
    peak leans toward the flank that curves less; the parabola's does not. The running median's peak when the fit
    has no top inside the window."""
    inside = (np.abs(times - near) <= APOGEE_WINDOW) & (np.abs(heights - smooth) <= SPIKE)
    if np.count_nonzero(inside) >= 5:
        a, b, c = np.polyfit(times[inside] - near, heights[inside], 2)
        if a < 0.0 and abs(b / (2.0 * a)) <= APOGEE_WINDOW:
            top = -b / (2.0 * a)
            return float(near + top), float(c - b * b / (4.0 * a))
    index = int(np.searchsorted(times, near))
    return float(near), float(smooth[index])


def theil_sen_slope(times, values) -> float:
    """The median of the slopes between every pair of samples (at most MOST_PAIRS samples, evenly thinned)."""
    times, values = np.asarray(times, float), np.asarray(values, float)
    if len(times) > MOST_PAIRS:
        keep = np.linspace(0, len(times) - 1, MOST_PAIRS).round().astype(int)
        times, values = times[keep], values[keep]
    i, j = np.triu_indices(len(times), k=1)
    spans = times[j] - times[i]
    return float(np.median((values[j] - values[i])[spans > 0.0] / spans[spans > 0.0]))


def band_rate(times, heights, low: float, high: float) -> tuple[float, int]:
    """(descent rate in m/s, positive down; samples used): the Theil-Sen slope of the samples whose height lies
    between ``low`` and ``high`` (m). (nan, n) with fewer than five samples in the band."""
    times, heights = np.asarray(times, float), np.asarray(heights, float)
    inside = (heights >= low) & (heights <= high)
    count = int(np.count_nonzero(inside))
    if count < 5:
        return float("nan"), count
    return -theil_sen_slope(times[inside], heights[inside]), count


def band_descent_rate(times, heights, phases: Phases, low: float, high: float) -> tuple[float, int]:
    """``band_rate`` of the samples after the apogee (heights ``low`` and ``high`` in m, the log's heights)."""
    after = slice(phases.apogee_index, None)
    return band_rate(np.asarray(times, float)[after], np.asarray(heights, float)[after], low, high)

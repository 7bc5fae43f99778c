"""Adaptive RK4 steps: the error indicator and the step rule (``docs/models/step_control.md``).

A run that sets no step (neither ``[simulation.steps]`` nor ``--dt``) integrates with RK4 at steps chosen as it
goes: small where the motion changes quickly (a deployment's snatch and opening), large where it is smooth (a steady
descent), never beyond the stability limits of the model's fastest modes (``run.step_control``).

The indicator. After each step the velocity coordinates of every body (translational velocity, m/s, and body-axis
angular velocity, rad/s) at the last four step ends t_0 < t_1 < t_2 < t_3 are known. The quadratic through the
first three, extrapolated to t_3, misses the new value by about (t_3 - t_0)(t_3 - t_1)(t_3 - t_2) u'''/6, h^3 u''' for
equal steps: the velocity's third derivative on the scale of the step. Per component it is weighed against
``absolute + relative |u|``; the indicator is the largest ratio. A steady descent (u''' = 0) gives 0, an opening
a large value, and a mode that RK4 cannot follow at the step (near or past its stability limit) a growing one.

The rule. The next step is h (safety / e)^(1/3), at most GROWTH times and at least SHRINK times the last, within
the caps (the stability limits and the largest step). No step is taken again: a step whose indicator is large
shortens the steps after it (the indicator is a smoothness measure, not a local error to reject on); a phase
starts at a small step and grows into its motion.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .compiled import kernel

ORDER = 3
"""Order of the indicator in the step (h^3 u''')."""


@dataclass(frozen=True)
class StepRule:
    """Settings of the adaptive step (``[simulation.step_control]`` in a case).

    Attributes
    ----------
    relative : float
        Relative tolerance (-) on each velocity coordinate's change beyond a quadratic over three steps.
    absolute : float
        Absolute tolerance of the same, in m/s for velocities and rad/s for angular velocities.
    first : float
        A phase's first step (s), before any cap.
    largest : float
        The largest step (s).
    smallest : float
        The smallest step (s) the rule takes; a stability limit below it stops the run with its cause.
    """

    relative: float = 1e-3
    absolute: float = 1e-3
    first: float = 1e-3
    largest: float = 0.25
    smallest: float = 1e-6


SAFETY = 0.8
"""Fraction (-) of the step the indicator allows that the rule takes."""
GROWTH = 2.0
"""Largest factor (-) from one step to the next."""
SHRINK = 0.2
"""Smallest factor (-) from one step to the next."""
CAP_FRACTION = 0.8
"""Fraction (-) of a stability limit the steps may reach."""


@kernel
def extrapolation_error(history, times, count, velocities, weights, masses, t, absolute, relative):
    """The indicator (see the module docstring) of the step that ended at ``t`` (s) with the velocity coordinates
    ``velocities`` (m/s and rad/s), against the ``count`` (0-3) step ends before it in ``history`` (rows: oldest
    first) at ``times`` (s); then ``velocities`` and ``t`` join the record (the oldest leaves). The misses are
    weighed in the kinetic-energy norm (``weights``: sqrt of each coordinate's mass or moment of inertia) against
    ``absolute`` (m/s) times sqrt(``masses``, the moving mass in kg) plus ``relative`` times the same norm of the
    velocities (sqrt of twice the kinetic energy). Returns (indicator, new count); the indicator is -1 while fewer
    than three earlier step ends are known."""
    n = velocities.shape[0]
    error = -1.0
    if count >= 3:
        t0, t1, t2 = times[0], times[1], times[2]
        w0 = (t - t1) * (t - t2) / ((t0 - t1) * (t0 - t2))
        w1 = (t - t0) * (t - t2) / ((t1 - t0) * (t1 - t2))
        w2 = (t - t0) * (t - t1) / ((t2 - t0) * (t2 - t1))
        miss = 0.0
        energy = 0.0
        for i in range(n):
            predicted = w0 * history[0, i] + w1 * history[1, i] + w2 * history[2, i]
            weighted = weights[i] * (velocities[i] - predicted)
            miss += weighted * weighted
            energy += weights[i] * weights[i] * velocities[i] * velocities[i]
        scale = absolute * math.sqrt(masses) + relative * math.sqrt(energy)
        error = math.sqrt(miss) / scale if scale > 0.0 else 0.0   # nothing moves: nothing to measure
    if count >= 3:
        for row in range(2):
            times[row] = times[row + 1]
            for i in range(n):
                history[row, i] = history[row + 1, i]
        row = 2
    else:
        row = count
        count += 1
    times[row] = t
    for i in range(n):
        history[row, i] = velocities[i]
    return error, count


def next_step(step: float, error: float, cap: float, largest: float) -> float:
    """The step (s) after a step of ``step`` (s) with indicator ``error`` (-1: none yet, the step may grow by
    GROWTH), within ``cap`` (s, from the stability limits) and ``largest`` (s)."""
    if error < 0.0 or error == 0.0:
        factor = GROWTH
    elif not math.isfinite(error):
        factor = SHRINK
    else:
        factor = min(GROWTH, max(SHRINK, (SAFETY / error) ** (1.0 / ORDER)))
    return min(step * factor, cap, largest)


def merge_summaries(parts: list) -> dict:
    """One record of the steps of several phases (``AdaptiveSteps.summary``)."""
    parts = [p for p in parts if p]
    if not parts:
        return {}
    count = sum(p["count"] for p in parts)
    return {"smallest": min(p["smallest"] for p in parts), "largest": max(p["largest"] for p in parts),
            "mean": sum(p["mean"] * p["count"] for p in parts) / count, "count": count}

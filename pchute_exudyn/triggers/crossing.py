"""Where a continuously sampled threshold or apogee was crossed between two samples (``crossing``): linear in the
sensed value, a cubic Hermite in the altitude, whose rate (the vertical velocity) is known."""

from __future__ import annotations


def crossing(condition, before: tuple, after: tuple) -> tuple:
    """(time, record) of a continuously sampled crossing, interpolated linearly between two samples
    (time, sensed, truth)."""
    name = condition.sensed_name
    (t0, sensed0, truth0), (t1, sensed1, truth1) = before, after
    m0, m1 = sensed0[name], sensed1[name]
    w = (condition.value - m0) / (m1 - m0) if m1 != m0 else 1.0
    w = min(max(w, 0.0), 1.0)
    rates = None
    if condition.quantity == "altitude":   # the altitude's rate is known: cubic Hermite, exact for constant g
        rates = [(t1 - t0) * s["vertical_velocity"] for s in (sensed0, sensed1)]
        w = hermite_root(m0, m1, *rates, condition.value, w)
    time = t0 + w * (t1 - t0)
    measured = condition.value if rates is not None else m0 + w * (m1 - m0)
    true = truth0[name] + w * (truth1[name] - truth0[name])
    if rates is not None:
        true = hermite(truth0[name], truth1[name], *[(t1 - t0) * s["vertical_velocity"] for s in (truth0, truth1)],
                       w)
    return time, {"quantity": condition.quantity, "threshold": condition.value, "measured": measured, "true": true}


def hermite(y0: float, y1: float, d0: float, d1: float, w: float) -> float:
    """The cubic Hermite interpolant at ``w`` in [0, 1] of end values y and end slopes d (per unit w)."""
    w2, w3 = w * w, w * w * w
    return ((2 * w3 - 3 * w2 + 1) * y0 + (w3 - 2 * w2 + w) * d0 + (-2 * w3 + 3 * w2) * y1 + (w3 - w2) * d1)


def hermite_root(y0: float, y1: float, d0: float, d1: float, value: float, guess: float) -> float:
    """w in [0, 1] where the Hermite interpolant equals ``value``, by Newton's method from ``guess``."""
    w = guess
    for _ in range(20):
        w2 = w * w
        slope = (6 * w2 - 6 * w) * y0 + (3 * w2 - 4 * w + 1) * d0 + (-6 * w2 + 6 * w) * y1 + (3 * w2 - 2 * w) * d1
        if slope == 0.0:
            break
        change = (hermite(y0, y1, d0, d1, w) - value) / slope
        w = min(max(w - change, 0.0), 1.0)
        if abs(change) < 1e-15:
            break
    return w


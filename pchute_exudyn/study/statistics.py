"""How sure a study's numbers are: bootstrap confidence intervals on percentiles, the smallest run count a
percentile means something at, and the rank correlation of each output with each input."""

from __future__ import annotations

import math

import numpy as np

BOOTSTRAP_RESAMPLES = 2000
BOOTSTRAP_SEED = 20261123
"""Fixed, so a report is the same every time it is written."""
CONFIDENCE = 0.95
ROUND_OFF = 1e-9
"""An output's spread over the runs at or below ROUND_OFF x max(largest |value|, 1 SI unit) is round-off, not a
response to the inputs: its rank correlations would rank noise (a final east position spanning 1e-14..3e-13 m
ranks as +1.00), so ``at_round_off`` outputs get none."""


def bootstrap_interval(values: np.ndarray, percentile: float) -> tuple[float, float]:
    """The 95 % percentile-bootstrap interval of the ``percentile``-th percentile (%) of ``values``: the 2.5th and
    97.5th percentiles of that percentile over BOOTSTRAP_RESAMPLES resamples with replacement. For extreme
    percentiles of few runs it cannot reach beyond the largest (smallest) run: ``enough_runs`` says when to worry."""
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    resamples = rng.choice(values, size=(BOOTSTRAP_RESAMPLES, len(values)), replace=True)
    estimates = np.percentile(resamples, percentile, axis=1)
    tail = 100.0 * (1.0 - CONFIDENCE) / 2.0
    return float(np.percentile(estimates, tail)), float(np.percentile(estimates, 100.0 - tail))


def percentile_table(reference: dict, candidate: dict, outcomes, percentiles) -> tuple[list, bool]:
    """Markdown rows ``| outcome | percentile | reference's | its 95 % bootstrap interval | candidate's | inside |`` of
    each outcome's (a key of both: sample arrays) percentiles (%), the candidate's against the reference's interval
    (``bootstrap_interval``); and whether every one lies inside. An outcome either side lacks is left out."""
    rows, inside_all = [], True
    for key in outcomes:
        ref, cand = np.asarray(reference[key], float), np.asarray(candidate[key], float)
        if not len(ref) or not len(cand):
            continue
        for p in percentiles:
            low, high = bootstrap_interval(ref, p)
            value = float(np.percentile(cand, p))
            inside = bool(low <= value <= high)
            inside_all &= inside
            rows.append(f"| {key} | {p:g} | {np.percentile(ref, p):.4f} | {low:.4f} .. {high:.4f} | {value:.4f} | "
                        f"{'yes' if inside else 'NO'} |")
    return rows, inside_all


def bootstrap_mean_interval(points: np.ndarray) -> np.ndarray:
    """The 95 % percentile-bootstrap interval of the mean of ``points`` (n, d), per column: (d, 2) lower and upper
    bounds, from the means of BOOTSTRAP_RESAMPLES resamples of whole rows with replacement (a landing footprint's
    centre: east and north drawn together)."""
    points = np.asarray(points, float)
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    rows = rng.integers(0, len(points), size=(BOOTSTRAP_RESAMPLES, len(points)))
    means = points[rows].mean(axis=1)
    tail = 100.0 * (1.0 - CONFIDENCE) / 2.0
    return np.percentile(means, [tail, 100.0 - tail], axis=0).T


def runs_needed(percentile: float) -> int:
    """Runs for the ``percentile``-th percentile to have at least ten runs beyond it (100 for the median's
    neighbours, 1000 for the 1st and 99th): with fewer it is set by a handful of extreme runs."""
    return math.ceil(10.0 * 100.0 / min(percentile, 100.0 - percentile))


def at_round_off(values: np.ndarray) -> bool:
    """Whether the finite ``values`` (one output over the runs, SI units) spread no more than ROUND_OFF x
    max(largest |value|, 1): double-precision round-off of the run's own scale, not a response."""
    finite = values[np.isfinite(values)]
    if len(finite) < 2:
        return False
    return bool(np.ptp(finite) <= ROUND_OFF * max(float(np.max(np.abs(finite))), 1.0))


def rank_correlations(inputs: dict, output: np.ndarray) -> list:
    """(input name, Spearman rank correlation with ``output``) for each input (name -> values), largest magnitude
    first; an input or output that does not vary gives no entry."""
    from scipy.stats import spearmanr

    ranked = []
    for name, values in inputs.items():
        keep = np.isfinite(values) & np.isfinite(output)
        if keep.sum() > 2 and np.ptp(values[keep]) > 0 and np.ptp(output[keep]) > 0:
            rho = float(spearmanr(values[keep], output[keep]).statistic)
            ranked.append((name, rho))
    return sorted(ranked, key=lambda item: -abs(item[1]))

"""Parachute clusters: several canopies, each its own body with its own riser(s), on one confluence
(``docs/models/cluster.md``). The cluster's drag efficiency, the spread of its canopies at line stretch, and the
quantities analysts read from a run: each canopy's flyout angle and the load share between risers.
"""

from __future__ import annotations

import math

import numpy as np

DEFAULT_DRAG_EFFICIENCY = (1.0, 0.97, 0.95, 0.93, 0.91, 0.90, 0.89, 0.88)
"""eta(n), n = 1, 2, ...: the drag coefficient of each canopy of a cluster of n inflating canopies as a fraction of
the same canopy's alone (held beyond the last entry). Clustered canopies crowd each other and lose a few per cent of
drag for each canopy added (Knacke, Parachute Recovery Systems Design Manual, NWC TP 6575, March 1991, chapter 5 on
clusters; the values follow that trend and are assumed, not digitised: override them per system)."""


def drag_efficiency(table, count: int) -> float:
    """eta for ``count`` inflating canopies (>= 1) from ``table`` (eta for 1, 2, ... canopies, held beyond its end)."""
    return float(table[min(max(count, 1), len(table)) - 1])


def touching_spread(radius: float, reach: float, count: int) -> float:
    """The half-angle (rad) of the cone on which ``count`` canopies of envelope radius ``radius`` (m), their centres
    ``reach`` (m) from the confluence and evenly spread around the cone's axis, just touch: the centres sit on a
    circle of radius rho = r / sin(pi / n) (rho = r for two), at sin(theta) = rho / reach. 0 for a single canopy."""
    if count < 2:
        return 0.0
    circle = radius if count == 2 else radius / math.sin(math.pi / count)
    return math.asin(min(circle / reach, 1.0))


def spread_directions(axis, across, spread: float, count: int) -> list:
    """The unit directions from each of ``count`` canopies toward the confluence (each canopy's +x at line stretch):
    ``spread`` (rad) off ``axis`` (unit: the vehicle's air-relative velocity, which the canopies trail behind), at
    azimuths 2 pi i / n around it from ``across`` (unit, perpendicular to ``axis``)."""
    axis, across = np.asarray(axis, float), np.asarray(across, float)
    third = np.cross(axis, across)
    return [math.cos(spread) * axis + math.sin(spread) * (math.cos(2.0 * math.pi * i / count) * across
                                                          + math.sin(2.0 * math.pi * i / count) * third)
            for i in range(count)]


def flyout_angles(confluence, centres) -> np.ndarray:
    """Each canopy's flyout angle (deg) for arrays of the confluence (n, 3) and the canopies' envelope centres
    (n, k, 3; NaN where a canopy is absent): the angle at the confluence between the canopy's centre and the cluster
    axis, the line from the confluence to the mean of the present canopies' centres. NaN where absent."""
    arms = np.asarray(centres, float) - np.asarray(confluence, float)[:, None, :]
    present = np.isfinite(arms).all(axis=-1)
    counts = present.sum(axis=1)
    axis = np.where(present[..., None], arms, 0.0).sum(axis=1) / np.maximum(counts, 1)[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):   # no axis (canopies evenly round the confluence): NaN
        cosine = np.einsum("nkj,nj->nk", arms, axis) / (np.linalg.norm(arms, axis=-1)
                                                         * np.linalg.norm(axis, axis=-1)[:, None])
        return np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))


def present_mean(values) -> np.ndarray:
    """The mean over axis 1 of ``values`` (n, k) of the entries present (finite); 0 where none is."""
    values = np.asarray(values, float)
    present = np.isfinite(values)
    return np.where(present, values, 0.0).sum(axis=1) / np.maximum(present.sum(axis=1), 1)


def load_share(riser_tensions) -> np.ndarray:
    """The load share max_i T_i / mean_i T_i (-) of the canopies' riser tensions (n, k) (N; a canopy's summed over its
    risers, NaN where absent): 1 when the risers share the load evenly, k when one carries it all. NaN where no
    riser pulls."""
    tensions = np.asarray(riser_tensions, float)
    present = np.isfinite(tensions)
    counts = present.sum(axis=1)
    mean = present_mean(tensions)
    peak = np.where(present, tensions, -np.inf).max(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where((counts > 0) & (mean > 0.0), peak / mean, np.nan)

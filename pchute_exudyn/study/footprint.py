"""The landing footprint of a study whose runs touch down: statistics of the touchdown points (its figures:
``views.study_figures``).

The touchdown point is the vehicle's east and north position (m, start frame) when the run stops at the ground
(``final_east``, ``final_north`` of runs with a ``touchdown_time``: the end of the step that reached the ground,
within a step's horizontal travel of the interpolated crossing). Dispersion ellipses are those of a bivariate normal
with the sample mean and covariance: k sigma holds 1 - exp(-k^2 / 2) of it (39.3 % for 1 sigma, 98.9 % for 3 sigma)
and the 99 % ellipse is k = sqrt(-2 ln 0.01) = 3.035.
"""

from __future__ import annotations

import math

import numpy as np

from ..registries.columns import column, owner

ELLIPSES = (("1 sigma", 1.0), ("3 sigma", 3.0), ("99 %", math.sqrt(-2.0 * math.log(0.01))))
"""(label, k): dispersion ellipses drawn and tabulated, k in standard deviations along the principal axes."""
MINIMUM_RUNS = 3
"""Touchdowns needed for a covariance (and a footprint)."""


def touchdown_points(rows: list) -> np.ndarray:
    """(n, 2) east, north (m) of the ok runs that touched down."""
    east, north, landed = column("final_east"), column("final_north"), column("touchdown_time")
    return np.array([(r[east], r[north]) for r in rows if isinstance(r.get(landed), float)
                     and isinstance(r.get(east), float) and isinstance(r.get(north), float)], float).reshape(-1, 2)


def footprint_statistics(points: np.ndarray) -> dict:
    """Mean (m), covariance (m^2), principal standard deviations (m), the major axis's azimuth (deg clockwise
    from north), and per ellipse its semi-axes (m), the normal model's share and the share of runs inside;
    radial miss distances from the mean (m): median (CEP), 90th and 99th percentiles and the largest."""
    mean = points.mean(axis=0)
    covariance = np.cov(points.T, ddof=1)
    variances, vectors = np.linalg.eigh(covariance)          # ascending
    major, minor = math.sqrt(max(variances[1], 0.0)), math.sqrt(max(variances[0], 0.0))
    east, north = vectors[:, 1]
    azimuth = math.degrees(math.atan2(east, north)) % 180.0  # an axis, not a direction
    offsets = points - mean
    # Mahalanobis radius of each point (the ellipse k through it); a degenerate spread gives none
    inverse = np.linalg.pinv(covariance)
    radius = np.sqrt(np.einsum("ij,jk,ik->i", offsets, inverse, offsets))
    distance = np.hypot(offsets[:, 0], offsets[:, 1])
    return {"count": int(len(points)), "mean_east": float(mean[0]), "mean_north": float(mean[1]),
            "covariance": covariance.tolist(), "sigma_major": major, "sigma_minor": minor,
            "major_axis_azimuth_deg": azimuth,
            "ellipses": {label: {"k": k, "semi_major": k * major, "semi_minor": k * minor,
                                 "normal_share": 1.0 - math.exp(-0.5 * k * k),
                                 "share_inside": float(np.mean(radius <= k))} for label, k in ELLIPSES},
            "miss_distance": {"p50": float(np.percentile(distance, 50)), "p90": float(np.percentile(distance, 90)),
                              "p99": float(np.percentile(distance, 99)), "max": float(distance.max())}}


TOUCHDOWN_PANELS = {column("touchdown_speed"): "touchdown speed, total over the ground (m/s)",
                    column("touchdown_descent_rate"): "touchdown descent rate, down the local vertical (m/s)"}
"""The touchdown histograms of a study's report (runs.csv columns and their x labels) before its peak loads'."""


def touchdown_histogram_panels(rows: list, loads: list) -> list:
    """``views.study_figures.percentile_histograms_figure``'s panels of the touchdown's total speed and descent rate
    (m/s; ``TOUCHDOWN_PANELS``, a study recorded before the descent rate has none of it) and of the peak line loads
    ``loads`` (runs.csv columns, N, drawn in kN) of the ``rows`` that touched down, with their 1st, 50th and 99th
    percentiles."""
    panels = []
    for name in list(TOUCHDOWN_PANELS) + list(loads):
        values = np.array([r[name] for r in rows if isinstance(r.get(name), float)
                           and isinstance(r.get(column("touchdown_time")), float)])
        if name in TOUCHDOWN_PANELS:
            if name != column("touchdown_speed") and not len(values):
                continue
            label, scale = TOUCHDOWN_PANELS[name], 1.0
        else:
            line = owner(name, "peak_tension_{owner}") or name
            label, scale = f"{line.replace('_', ' ')}: peak load (kN)", 1e-3
        panels.append((values * scale, label, {p: np.percentile(values, p) * scale for p in (1, 50, 99)}))
    return panels


def footprint_markdown(stats: dict, percentile_rows: list) -> list:
    """Report lines: the footprint table and the touchdown percentiles (``percentile_rows``: (label, unit,
    percentiles dict))."""
    lines = ["", "## Landing footprint", "",
             f"{stats['count']} touchdowns. Mean touchdown point: {stats['mean_east']:.1f} m east, "
             f"{stats['mean_north']:.1f} m north of the start point. Principal standard deviations "
             f"{stats['sigma_major']:.1f} m and {stats['sigma_minor']:.1f} m, the major axis at "
             f"{stats['major_axis_azimuth_deg']:.0f} deg from north.", "",
             "| ellipse | semi-major (m) | semi-minor (m) | normal model holds | runs inside |",
             "|---|---|---|---|---|"]
    for label, e in stats["ellipses"].items():
        lines.append(f"| {label} | {e['semi_major']:.1f} | {e['semi_minor']:.1f} | {100 * e['normal_share']:.1f} % "
                     f"| {100 * e['share_inside']:.1f} % |")
    miss = stats["miss_distance"]
    lines += ["", f"Miss distance from the mean point: median (CEP) {miss['p50']:.1f} m, 90th percentile "
                  f"{miss['p90']:.1f} m, 99th percentile {miss['p99']:.1f} m, largest {miss['max']:.1f} m.", "",
              "| touchdown output | p1 | p5 | p50 | p95 | p99 | max |", "|---|---|---|---|---|---|---|"]
    for label, unit, p in percentile_rows:
        lines.append(f"| {label} ({unit}) | " + " | ".join(f"{p[k]:.4g}" for k in ("p1", "p5", "p50", "p95", "p99",
                                                                                      "max")) + " |")
    return lines

"""The landing footprint of a study whose runs touch down: statistics of the touchdown points and their figure.

The touchdown point is the vehicle's east and north position (m, start frame) when the run stops at the ground
(``final_east``, ``final_north`` of runs with a ``touchdown_time``: the end of the step that reached the ground,
within a step's horizontal travel of the interpolated crossing). Dispersion ellipses are those of a bivariate normal
with the sample mean and covariance: k sigma holds 1 - exp(-k^2 / 2) of it (39.3 % for 1 sigma, 98.9 % for 3 sigma)
and the 99 % ellipse is k = sqrt(-2 ln 0.01) = 3.035.
"""

from __future__ import annotations

import math

import numpy as np

from ..views.plotting import new_figure, save_figure

ELLIPSES = (("1 sigma", 1.0), ("3 sigma", 3.0), ("99 %", math.sqrt(-2.0 * math.log(0.01))))
"""(label, k): dispersion ellipses drawn and tabulated, k in standard deviations along the principal axes."""
MINIMUM_RUNS = 3
"""Touchdowns needed for a covariance (and a footprint)."""


def touchdown_points(rows: list) -> np.ndarray:
    """(n, 2) east, north (m) of the ok runs that touched down."""
    return np.array([(r["final_east"], r["final_north"]) for r in rows
                     if isinstance(r.get("touchdown_time"), float) and isinstance(r.get("final_east"), float)
                     and isinstance(r.get("final_north"), float)], float).reshape(-1, 2)


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


def ellipse(stats: dict, k: float, count: int = 181) -> np.ndarray:
    """(count, 2) east, north (m) of the k-sigma ellipse of ``footprint_statistics``."""
    variances, vectors = np.linalg.eigh(np.array(stats["covariance"]))
    angle = np.linspace(0.0, 2.0 * np.pi, count)
    unit = np.stack([np.cos(angle), np.sin(angle)], axis=1) * np.sqrt(np.maximum(variances, 0.0))
    return np.array([stats["mean_east"], stats["mean_north"]]) + k * unit @ vectors.T


def plot_footprint(points: np.ndarray, stats: dict, title: str, path, failed: int = 0) -> None:
    """Save ``footprint_figure`` at ``path``."""
    save_figure(footprint_figure(points, stats, title, failed), path)


def footprint_figure(points: np.ndarray, stats: dict, title: str, failed: int = 0):
    """Touchdown points, their mean and the 1- and 3-sigma dispersion ellipses, east against north in metres on
    equal axes; ``failed`` runs (no touchdown recorded: a failed run keeps no position) are counted in the title
    and the legend, so a footprint never looks complete when runs are missing from it."""
    figure, axes = new_figure(1, 1, size=(7.0, 7.0))
    ax = axes[0, 0]
    ax.plot(points[:, 0], points[:, 1], ".", color="tab:blue", markersize=4, alpha=0.7,
            label=f"touchdown ({len(points)} runs)")
    ax.plot([stats["mean_east"]], [stats["mean_north"]], "k+", markersize=12, markeredgewidth=2, label="mean")
    for (label, k), style in zip(ELLIPSES[:2], ("-", "--")):   # the 99 % ellipse lies on the 3-sigma one
        e = stats["ellipses"][label]
        curve = ellipse(stats, k)
        ax.plot(curve[:, 0], curve[:, 1], style, color="tab:red", linewidth=1.2,
                label=f"{label} ellipse: {e['semi_major']:.0f} x {e['semi_minor']:.0f} m "
                      f"({100 * e['share_inside']:.0f} % of runs inside)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("touchdown east of the start point (m)")
    ax.set_ylabel("touchdown north of the start point (m)")
    ax.grid(True, alpha=0.3)
    if failed:   # an empty red x in the legend: the runs that are not on the map
        ax.plot([], [], "x", color="red", label=f"{failed} failed runs not shown: no touchdown")
        title = f"{title}\n({failed} failed runs not shown: no touchdown)"
    ax.legend(fontsize="x-small", loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2)
    figure.suptitle(title)
    return figure


def plot_touchdown_histograms(rows: list, loads: list, title: str, path) -> None:
    """Histograms of touchdown speed (m/s) and of the peak line loads ``loads`` (runs.csv columns, N), with the
    1st, 50th and 99th percentiles marked."""
    shown = ["touchdown_speed"] + list(loads)
    figure, axes = new_figure(math.ceil(len(shown) / 2), 2, size=(10.0, 2.8 * math.ceil(len(shown) / 2) + 0.6))
    for ax, name in zip(axes.ravel(), shown):
        values = np.array([r[name] for r in rows if isinstance(r.get(name), float)
                           and isinstance(r.get("touchdown_time"), float)])
        if name == "touchdown_speed":
            label, scale = "touchdown speed, relative to the ground (m/s)", 1.0
        else:
            label, scale = f"{name.removeprefix('peak_tension_').replace('_', ' ')}: peak load (kN)", 1e-3
        ax.hist(values * scale, bins=min(30, max(5, len(values) // 5)), color="tab:blue", alpha=0.8)
        for p in (1, 50, 99):
            ax.axvline(np.percentile(values, p) * scale, color="k", linewidth=0.8, linestyle="-" if p == 50 else ":")
        ax.set_xlabel(label)
        ax.set_ylabel("runs")
    for ax in axes.ravel()[len(shown):]:
        ax.set_visible(False)
    figure.suptitle(f"{title} (dotted: 1st and 99th percentile, solid: median)")
    save_figure(figure, path)


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

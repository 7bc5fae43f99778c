"""Figures of a study's report (``study.report``, ``study.footprint``): histograms, outputs against inputs, errors
against the reference, the deployment box and the landing footprint.

The callers read the study folder and pass the data with its labels (strings); nothing here knows a study's files.
Every function returns the figure; the caller saves it (``plotting.save_figure``).
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

from .plotting import new_figure

FAILED_MARK = {"marker": "x", "color": "red", "linestyle": "none", "markersize": 7, "clip_on": False}
"""How a figure marks the failed runs: a red x."""


def percentile_histograms_figure(panels: list, title: str, panel_height: float) -> Figure:
    """Histograms two to a row, ``panel_height`` (inch) each; ``panels``: (values, x label, {percentile: value})
    per histogram, a vertical line at each percentile (the median solid, the others dotted)."""
    figure, axes = new_figure(math.ceil(len(panels) / 2), 2,
                              size=(10.0, panel_height * math.ceil(len(panels) / 2) + 0.6))
    for ax, (values, label, marks) in zip(axes.ravel(), panels):
        ax.hist(values, bins=min(30, max(5, len(values) // 5)), color="tab:blue", alpha=0.8)
        for p, value in marks.items():
            ax.axvline(value, color="k", linewidth=0.8, linestyle=":" if p != 50 else "-")
        ax.set_xlabel(label)
        ax.set_ylabel("runs")
    for ax in axes.ravel()[len(panels):]:
        ax.set_visible(False)
    figure.suptitle(f"{title} (dotted: 1st and 99th percentile, solid: median)")
    return figure


def outputs_against_input_figure(ok: list, failed: list, key: str, label: str, targets: list,
                                 output_labels: list) -> Figure:
    """Outputs ``targets`` (runs.csv columns, y labels ``output_labels``) against drawn input ``key`` (x label
    ``label``), one point per ok run; each failed run a red x at its drawn value on the bottom edge of every panel
    (it has no outputs)."""
    figure, axes = new_figure(1, len(targets), size=(3.6 * len(targets), 3.4))
    drawn = [r[key] for r in failed if isinstance(r.get(key), float)]
    for ax, name, output_label in zip(axes[0], targets, output_labels):
        ax.plot([r[key] for r in ok], [r.get(name) for r in ok], ".", markersize=4, label=f"ok ({len(ok)} runs)")
        if drawn:   # x in data units, y in axes units: on the bottom edge whatever the output's scale
            ax.plot(drawn, [0.0] * len(drawn), transform=ax.get_xaxis_transform(), **FAILED_MARK,
                    label=f"failed ({len(drawn)} runs, at their drawn value)")
        ax.set_xlabel(label)
        ax.set_ylabel(output_label)
        ax.grid(True, alpha=0.3)
    note = f"; red x: {len(drawn)} failed runs" if drawn else ""
    figure.suptitle(f"outputs against {key}{note}")
    if drawn:
        axes[0, 0].legend(fontsize="x-small")
    return figure


def outputs_against_grid_figure(key: str, label: str, panels: list) -> Figure:
    """Outputs against grid parameter ``key`` (x label ``label``); ``panels``: (y label, [(curve label, sorted
    (x, y) points)]) per output, one line per curve."""
    figure, axes = new_figure(1, len(panels), size=(3.8 * len(panels), 3.4))
    for ax, (output_label, curves) in zip(axes[0], panels):
        for curve_label, points in curves:
            ax.plot(*zip(*points), "o-", label=curve_label, markersize=3)
        ax.set_xlabel(label)
        ax.set_ylabel(output_label)
        ax.grid(True, alpha=0.3)
    return _finish(figure, axes[0, 0], f"outputs against {key}")


def error_against_cost_figure(errors: list) -> Figure:
    """Error against wall time (``errors``: ``study.report.reference_errors``): one colour per configuration family,
    its steps joined by a line; one marker per case."""
    families = sorted({e["family"] for e in errors})
    cases = sorted({e["case"] for e in errors})
    markers = "osD^v<>ph*"
    figure, axes = new_figure(1, 2, size=(12.0, 5.0))
    for ax, metric, unit in zip(axes[0], ("altitude_error", "max_tension_error"), ("m", "N")):
        labelled = set()
        for i, family in enumerate(families):
            for j, case in enumerate(cases):
                points = sorted((e["step"], e["wall_time"], e[metric]) for e in errors
                                if e["family"] == family and e["case"] == case and e[metric] > 0
                                and isinstance(e.get("step"), float))
                if points:
                    # ten colours, then the same colours dashed, dotted, ...
                    ax.loglog([p[1] for p in points], [p[2] for p in points], ("-", "--", ":", "-.")[i // 10 % 4],
                              color=f"C{i % 10}",
                              marker=markers[j % len(markers)], markersize=5, linewidth=0.8,
                              label=None if family in labelled else family)
                    labelled.add(family)
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel(f"{metric.replace('_', ' ')} against the reference ({unit})")
        ax.grid(True, which="both", alpha=0.3)
    axes[0, 1].legend(fontsize="x-small", title="configuration (line joins its steps)", title_fontsize="x-small")
    if len(cases) > 1:
        handles = [axes[0, 0].plot([], [], linestyle="none", color="0.3", marker=markers[j % len(markers)])[0]
                   for j in range(len(cases))]
        axes[0, 0].legend(handles, cases, fontsize="x-small", title="case", title_fontsize="x-small")
    figure.suptitle("accuracy against cost: each run against its reference")
    return figure


def error_against_parameter_figure(errors: list, key: str, label: str) -> Figure:
    """Errors against the reference (``errors``: ``study.report.reference_errors``) over grid parameter ``key``
    (x label ``label``), one line per case and configuration."""
    figure, axes = new_figure(1, 2, size=(12.0, 4.6))
    positive = all(isinstance(e.get(key), float) and e[key] > 0 for e in errors)
    for ax, metric, unit in zip(axes[0], ("altitude_error", "max_tension_error"), ("m", "N")):
        for group in sorted({(e["case"], e["configuration"]) for e in errors}):
            points = sorted((e[key], e[metric]) for e in errors if (e["case"], e["configuration"]) == group
                            and isinstance(e.get(key), float) and e[metric] > 0)
            if points:
                ax.plot(*zip(*points), "o-", label=" ".join(group), markersize=4)
        ax.set_xscale("log" if positive else "linear")
        ax.set_yscale("log")
        ax.set_xlabel(label)
        ax.set_ylabel(f"{metric.replace('_', ' ')} against the reference ({unit})")
        ax.grid(True, which="both", alpha=0.3)
    return _finish(figure, axes[0, 1], f"error against {key}")


def _finish(figure: Figure, legend_axis, title: str) -> Figure:
    """A legend on ``legend_axis`` when it has labelled lines, and the title."""
    if legend_axis is not None and legend_axis.get_legend_handles_labels()[0]:
        legend_axis.legend(fontsize="x-small")
    figure.suptitle(title)
    return figure


def ellipse(stats: dict, k: float, count: int = 181) -> np.ndarray:
    """(count, 2) east, north (m) of the k-sigma ellipse of ``study.footprint.footprint_statistics``."""
    variances, vectors = np.linalg.eigh(np.array(stats["covariance"]))
    angle = np.linspace(0.0, 2.0 * np.pi, count)
    unit = np.stack([np.cos(angle), np.sin(angle)], axis=1) * np.sqrt(np.maximum(variances, 0.0))
    return np.array([stats["mean_east"], stats["mean_north"]]) + k * unit @ vectors.T


def footprint_figure(points: np.ndarray, stats: dict, title: str, failed: int = 0) -> Figure:
    """Touchdown points, their mean and the first two dispersion ellipses of ``stats``
    (``study.footprint.footprint_statistics``: 1 and 3 sigma), east against north in metres on equal axes;
    ``failed`` runs (no touchdown recorded: a failed run keeps no position) are counted in the title and the legend,
    so a footprint never looks complete when runs are missing from it."""
    figure, axes = new_figure(1, 1, size=(7.0, 7.0))
    ax = axes[0, 0]
    ax.plot(points[:, 0], points[:, 1], ".", color="tab:blue", markersize=4, alpha=0.7,
            label=f"touchdown ({len(points)} runs)")
    ax.plot([stats["mean_east"]], [stats["mean_north"]], "k+", markersize=12, markeredgewidth=2, label="mean")
    for (label, e), style in zip(list(stats["ellipses"].items())[:2], ("-", "--")):   # the 99 % lies on 3 sigma
        curve = ellipse(stats, e["k"])
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


def deployment_box_figure(points: np.ndarray, box: dict, title: str, failed: int = 0) -> Figure:
    """A triggered deployment's conditions over the ok runs: the vehicle's Mach number (x, -) against its dynamic
    pressure (y, Pa), one point per run (``points``: (runs, 2)), and the box of ``box`` (``{"mach": (p1, p99),
    "dynamic_pressure": (p1, p99)}``: the 1st-99th percentile of each, taken separately); ``failed`` runs (no
    deployment values) are counted in the legend, not drawn."""
    from matplotlib.patches import Rectangle

    figure, axes = new_figure(1, 1, size=(6.4, 5.8))
    ax = axes[0, 0]
    ax.plot(points[:, 0], points[:, 1], ".", color="tab:blue", markersize=5, alpha=0.8,
            label=f"deployment ({len(points)} runs)")
    (m1, m99), (q1, q99) = box["mach"], box["dynamic_pressure"]
    ax.add_patch(Rectangle((m1, q1), m99 - m1, q99 - q1, fill=False, edgecolor="tab:red", linestyle="--",
                           linewidth=1.2, label=f"1st-99th percentile box (each axis): Mach {m1:.3g}..{m99:.3g}, "
                                            f"{q1:.4g}..{q99:.4g} Pa"))
    ax.plot([float(np.median(points[:, 0]))], [float(np.median(points[:, 1]))], "k+", markersize=12,
            markeredgewidth=2, label="medians")
    if failed:   # an empty red x in the legend: the runs that are not in the figure
        ax.plot([], [], "x", color="red", label=f"{failed} failed runs not shown: no deployment values")
    ax.margins(0.15)
    ax.set_xlabel("Mach number at deployment (-)")
    ax.set_ylabel("dynamic pressure at deployment (Pa)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="x-small", loc="upper center", bbox_to_anchor=(0.5, -0.13))
    figure.suptitle(title)
    return figure

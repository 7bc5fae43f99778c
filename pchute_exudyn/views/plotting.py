"""Figures of results. Object-oriented matplotlib (no pyplot state, no display needed); functions return figures.

Rules every figure here follows: axis labels carry their units; curves that are identical are drawn once with their
labels merged ("bridle1 = bridle2"), and the others cycle through line styles so that one lying on another stays
visible; an overlay of several results has a difference panel under each quantity (each result minus the first, on
the first's times), so a 0.4 N difference shows even on a 3 kN scale.
"""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..registries.columns import UNNAMED_VEHICLE, column
from ..results.io import atomic_writer


def new_figure(rows: int = 1, cols: int = 1, size=(9.0, 6.0), layout="constrained", **kwargs):
    """A figure with an Agg canvas and its axes (``layout``: matplotlib's, or None for fixed margins)."""
    figure = Figure(figsize=size, layout=layout)
    FigureCanvasAgg(figure)
    axes = figure.subplots(rows, cols, squeeze=False, **kwargs)
    return figure, axes


def plot_overview(result, title: str | None = None) -> Figure:
    """Line tensions (top left), the vehicle's altitude and, when the run has them, its Mach number and dynamic
    pressure (below) against time, with the run's events (``event_marks``) as vertical lines, and the vehicle's rate
    of descent against its altitude (right, altitude up). Fixed margins: every run draws it, and a layout engine would
    double the time to save it."""
    vehicle = result.vehicle
    extra = [(name, label) for name, label in ((column("{owner}_mach", vehicle), f"{vehicle} Mach number (-)"),
                                               (column("{owner}_dynamic_pressure", vehicle),
                                                f"{vehicle} dynamic pressure (Pa)"))
             if name in result and np.isfinite(result[name]).any()]
    rows, height = 2 + len(extra), 6.5 + 1.6 * len(extra)   # in: the events' labels over the top panel
    figure = Figure(figsize=(12.0, height))
    FigureCanvasAgg(figure)
    grid = figure.add_gridspec(rows, 2, width_ratios=(3.0, 1.0), left=0.075, right=0.985, bottom=0.5 / height,
                               top=1.0 - 0.85 / height, hspace=0.08, wspace=0.18)
    top = figure.add_subplot(grid[0, 0])
    panels = [top] + [figure.add_subplot(grid[row, 0], sharex=top) for row in range(1, rows)]
    time = result.time
    draw_curves(top, [(line, time, result[name]) for line, name in result.tensions().items()])
    top.set_ylabel("line tension (N)")
    if result.tension_names():
        top.legend(loc="best", fontsize="small")
    altitude = column("{owner}_altitude", vehicle)
    if altitude in result:
        panels[1].plot(time, result[altitude], color="k")
    panels[1].set_ylabel(f"{vehicle} altitude (m)")
    for ax, (name, label) in zip(panels[2:], extra):
        ax.plot(time, result[name], color="tab:red", linewidth=0.9)
        ax.set_ylabel(label)
    for ax in panels:
        ax.grid(True, alpha=0.3)
        if ax is not panels[-1]:
            ax.tick_params(labelbottom=False)
    panels[-1].set_xlabel("time (s)")
    mark_events(panels, event_marks(result.summary))
    _descent_panel(figure.add_subplot(grid[:, 1]), result, vehicle)
    case, method, integrator, step = (_text(result.summary, key) for key in ("case", "method", "integrator", "step"))
    figure.suptitle(title or f"{case}: {method} / {integrator}, step {step} s")
    return figure


def _text(summary, name: str):
    """Entry ``name`` of a run's summary for a title ('' without a summary, or one without it)."""
    value = getattr(summary, name, None)
    return "" if value is None else value


MARKED_EVENTS = ("deploy", "separation", "cutaway", "disreef", "touchdown")
"""The events (``summary.json``'s kinds, ``results.summary``) the figures of a run mark."""


def event_marks(summary) -> list:
    """(time in s, label) of each event of a run's summary (``results.summary.RunSummary``; None: no events) that
    its figures mark (``MARKED_EVENTS``)."""
    marks = []
    for event in () if summary is None else summary.events:
        kind = event.kind
        if kind not in MARKED_EVENTS or event.time is None:
            continue
        who = next((name for name in (getattr(event, key, None) for key in ("canopy", "system", "body")) if name), "")
        words = {"deploy": "deployment", "separation": "separation", "cutaway": "cut-away",
                 "disreef": f"disreef {getattr(event, 'stage', '')}".strip(), "touchdown": "touchdown"}[kind]
        marks.append((float(event.time), f"{who} {words}".strip()))
    return marks


def mark_events(panels: list, marks: list) -> None:
    """Each mark (time in s, label) as a vertical line across every time panel, labelled over the first (three rows
    of labels, so that events close in time stay readable)."""
    low, high = panels[0].get_xlim()
    for index, (time, label) in enumerate(marks):
        for ax in panels:
            ax.axvline(time, color="0.45", linestyle=":", linewidth=0.8)
        right = time > low + 0.8 * (high - low)   # a label near the right end goes left of its line
        panels[0].annotate(label, (time, 1.0), xycoords=("data", "axes fraction"),
                           xytext=(-2 if right else 2, 2 + 9 * (index % 3)), textcoords="offset points",
                           fontsize="x-small", color="0.3", va="bottom", ha="right" if right else "left",
                           arrowprops={"arrowstyle": "-", "color": "0.6", "linewidth": 0.5, "shrinkA": 0,
                                       "shrinkB": 0})


def plot_ground_track(result, title: str | None = None) -> Figure:
    """The vehicle's track over the ground: north against east (m, relative to the ground, from the start point along
    its axes), equal scales, with its start and the run's events (``event_marks``) marked."""
    vehicle = result.vehicle
    east, north = column("{owner}_east", vehicle), column("{owner}_north", vehicle)
    figure, axes = new_figure(1, 1, size=(7.0, 6.5))
    ax = axes[0, 0]
    if east in result and north in result:
        ax.plot(result[east], result[north], color="k", linewidth=0.9, label=f"{vehicle} centre of mass")
        ax.plot(result[east][:1], result[north][:1], "o", color="k", label="start")
        for index, (time, label) in enumerate(event_marks(result.summary)):
            x = np.interp(time, result.time, result[east])
            y = np.interp(time, result.time, result[north])
            ax.plot([x], [y], "s" if label == "touchdown" else STYLES_OF_MARKS[index % len(STYLES_OF_MARKS)],
                    color=f"C{index % 10}", label=label)
        ax.legend(loc="best", fontsize="small")
    ax.set_xlabel(f"{vehicle} east of the start point (m)")
    ax.set_ylabel(f"{vehicle} north of the start point (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    figure.suptitle(title or f"{_text(result.summary, 'case')}: ground track")
    return figure


def _descent_panel(ax, result, vehicle: str) -> None:
    """The vehicle's rate of descent (m/s, its downward velocity in the start frame) against its altitude (m)."""
    altitude, down = column("{owner}_altitude", vehicle), column("{owner}_velocity_down", vehicle)
    if altitude in result and down in result:
        ax.plot(result[down], result[altitude], color="tab:blue", linewidth=0.9)
    ax.set_xlabel("rate of descent (m/s)")
    ax.set_ylabel(f"{vehicle} altitude (m)")
    ax.set_title("rate of descent", fontsize="medium")
    ax.grid(True, alpha=0.3)


def plot_deployment_loads(result, title: str | None = None) -> Figure:
    """One panel per deployment (``result.loads``, its ``summary.deployments``): the load (N) against time (s) at every
    step kept (a system's risers, a tether), its snatch and opening load marked, Knacke's estimate and a rated line's
    breaking strength as horizontal lines (docs/models/deployment_loads.md)."""
    deployments = {d.system: d for d in (result.summary.deployments if result.summary is not None else ())}
    names = [name for name in result.loads if name in deployments] or list(result.loads)
    fig, axes = new_figure(len(names), 1, size=(9.0, 2.6 * max(len(names), 1)))
    for ax, name in zip(axes[:, 0], names):
        times, loads = result.loads[name]
        d = deployments.get(name)
        start = d.line_stretch_time if d is not None else float(times[0])
        end = max(d.opening_time, d.snatch_time) if d is not None else float(times[-1])
        span = max(end - start, 1e-3)
        shown = (times >= start - 0.2 * span) & (times <= end + 0.6 * span)
        ax.plot(times[shown], loads[shown], lw=1.0, color="C0", label="load")
        if d is not None:
            ax.plot([d.snatch_time], [d.snatch_load], "o", color="C1", label=f"snatch {d.snatch_load:.4g} N")
            ax.plot([d.opening_time], [d.opening_load], "s", color="C3", label=f"opening {d.opening_load:.4g} N")
            if d.knacke_opening_load is not None:
                ax.axhline(d.knacke_opening_load, ls="--", color="C2", lw=0.8,
                           label=f"Knacke {d.knacke_opening_load:.4g} N")
            strengths = [p["breaking_strength"] for p in d.lines.values() if p.get("breaking_strength")]
            if strengths:
                ax.axhline(min(strengths), ls=":", color="k", lw=0.8, label=f"breaking {min(strengths):.4g} N")
        ax.set_title(f"{name}{' (tether)' if d is not None and d.kind == 'tether' else ''}", fontsize=9)
        ax.set_ylabel("load (N)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    axes[-1, 0].set_xlabel("time (s)")
    if title or result.summary is not None:
        fig.suptitle(title or f"{result.summary.case}: deployment loads", fontsize=10)
    return fig


def save_figure(figure: Figure, path, dpi: int = 120) -> None:
    """Save ``figure`` as a PNG atomically (the fastest deflate: a tenth of the time, a slightly larger file)."""
    with atomic_writer(path, "wb") as handle:
        figure.savefig(handle, format="png", dpi=dpi, pil_kwargs={"compress_level": 1})


def plot_tension_overlay(results: dict, lines=None, title: str = "", t_max: float | None = None) -> Figure:
    """One panel per line, the tension of each labelled result overlaid (``results``: label -> Result)."""
    first = next(iter(results.values()))
    lines = lines or list(first.tensions())
    return _overlay(results, [(column("tension_{owner}", line), f"{line} (N)") for line in lines],
                    title or "line tensions",
                    (9.0, 2.2 * len(lines) + 0.8), t_max)


def plot_confluence_velocity_overlay(results: dict, prefix: str = "confluence", title: str = "",
                                     t_max: float | None = None) -> Figure:
    """Confluence east and north (lateral) velocity of each labelled result overlaid."""
    panels = [(column(template, prefix), f"{axis} velocity (m/s)")
              for template, axis in (("{owner}_velocity_east", "east"), ("{owner}_velocity_north", "north"))]
    return _overlay(results, panels, title or "confluence lateral velocity", (9.0, 5.5), t_max)


def plot_column_overlay(results: dict, name: str, unit: str = "", title: str = "") -> Figure:
    """One column of each labelled result overlaid, with the difference panel under it."""
    return _overlay(results, [(name, f"{name} ({unit})" if unit else name)], title or name, (9.0, 5.0), None)


def plot_descent_rates(sides: dict, vehicle: str = UNNAMED_VEHICLE) -> Figure:
    """Rate of descent (m/s) against altitude (m) of each labelled side (``compare.descent_side``'s inputs):
    ``sides`` label -> (altitude array, rate array)."""
    figure, axes = new_figure(1, 1, size=(7.0, 6.0))
    ax = axes[0, 0]
    draw_curves(ax, [(label, rate, altitude, i) for i, (label, (altitude, rate)) in enumerate(sides.items())])
    ax.set_xlabel("rate of descent (m/s)")
    ax.set_ylabel(f"{vehicle} altitude (m)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="x-small")
    figure.suptitle("rate of descent against altitude")
    return figure


def _overlay(results: dict, panels: list, title: str, size, t_max: float | None) -> Figure:
    """Per (column, y label) a panel with every labelled result that has the column overlaid, up to ``t_max`` (s),
    and, with two results or more, a difference panel under it: each result minus the first, in its own colour and
    line style (the legend of the first panel names them)."""
    rows = [(name, ylabel, kind) for name, ylabel in panels for kind in (("value", "difference")
                                                                         if len(results) > 1 else ("value",))]
    ratios = [2.0 if kind == "value" else 1.0 for _, _, kind in rows]
    figure, axes = new_figure(len(rows), 1, size=(size[0], size[1] * sum(ratios) / (2.0 * len(panels))),
                              sharex=True, gridspec_kw={"height_ratios": ratios})
    labels = list(results)
    reference = results[labels[0]]

    def end(time):   # samples up to t_max
        return time <= (t_max if t_max is not None else time[-1])
    for ax, (name, ylabel, kind) in zip(axes[:, 0], rows):
        curves = []
        for index, (label, result) in enumerate(results.items()):
            if name not in result:
                continue
            if kind == "value":
                mask = end(result.time)
                curves.append((label, result.time[mask], result[name][mask], index))
            elif index > 0 and name in reference:
                keep = end(reference.time)
                curves.append((label, reference.time[keep],
                               difference_on(reference.time[keep], reference[name][keep], result.time, result[name]),
                               index))
        draw_curves(ax, curves)
        unit = ylabel[ylabel.rfind("(") + 1:ylabel.rfind(")")] if "(" in ylabel else ""
        ax.set_ylabel(ylabel if kind == "value" else f"difference ({unit})" if unit else "difference")
        ax.grid(True, alpha=0.3)
    axes[0, 0].legend(loc="best", fontsize="x-small" if len(results) > 1 else "small")
    axes[-1, 0].set_xlabel("time (s)")
    figure.suptitle(title if len(results) == 1 else f"{title}\n(narrow panels: each run minus {labels[0]})")
    return figure


STYLES = ("-", "--", "-.", ":")
STYLES_OF_MARKS = ("x", "^", "v", "D", "+", "*")


def draw_curves(ax, curves: list) -> None:
    """Plot (label, x, y) or (label, x, y, index) curves on ``ax``: identical curves once, their labels joined by
    " = "; curve ``index`` (default its position) in colour C<index> and the index-th of solid, dashed, dash-dotted
    and dotted, so one lying on another stays visible and a quantity keeps its look from panel to panel."""
    groups: list = []
    for position, (label, x, y, *rest) in enumerate(curves):
        index = rest[0] if rest else position
        for group in groups:
            if np.array_equal(group[1], x) and np.array_equal(group[2], y, equal_nan=True):
                group[0].append(label)
                break
        else:
            groups.append(([label], x, y, index))
    for group_labels, x, y, index in groups:
        ax.plot(x, y, STYLES[index % len(STYLES)], color=f"C{index % 10}", label=" = ".join(group_labels),
                linewidth=0.9)


def difference_on(time, reference, other_time, other) -> np.ndarray:
    """``other`` (sampled at ``other_time``) minus ``reference`` on the reference's ``time`` (s); NaN outside the
    other's time span or where either is absent."""
    values = np.interp(time, other_time, other, left=np.nan, right=np.nan)
    values[(time < other_time[0]) | (time > other_time[-1])] = np.nan
    return values - reference

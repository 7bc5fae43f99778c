"""Figures of results. Object-oriented matplotlib (no pyplot state, no display needed); functions return figures."""

from __future__ import annotations

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from .io import atomic_writer


def new_figure(rows: int = 1, cols: int = 1, size=(9.0, 6.0), **kwargs):
    """A figure with an Agg canvas and its axes."""
    figure = Figure(figsize=size, layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(rows, cols, squeeze=False, **kwargs)
    return figure, axes


def plot_overview(result, title: str | None = None) -> Figure:
    """Line tensions (top) and vehicle altitude (bottom) against time."""
    figure, axes = new_figure(2, 1, sharex=True)
    top, bottom = axes[0, 0], axes[1, 0]
    time = result.time
    for name in result.tension_names():
        top.plot(time, result[name], label=name.removeprefix("tension_"), linewidth=0.9)
    top.set_ylabel("line tension (N)")
    if result.tension_names():
        top.legend(loc="best", fontsize="small")
    top.grid(True, alpha=0.3)
    vehicle = result.summary.get("vehicle", "vehicle")
    if f"{vehicle}_altitude" in result:
        bottom.plot(time, result[f"{vehicle}_altitude"], color="k")
    bottom.set_ylabel(f"{vehicle} altitude (m)")
    bottom.set_xlabel("time (s)")
    bottom.grid(True, alpha=0.3)
    s = result.summary
    figure.suptitle(title or f"{s.get('case', '')}: {s.get('method', '')} / {s.get('integrator', '')}, "
                             f"step {s.get('step', '')} s")
    return figure


def save_figure(figure: Figure, path, dpi: int = 120) -> None:
    """Save ``figure`` as a PNG atomically."""
    with atomic_writer(path, "wb") as handle:
        figure.savefig(handle, format="png", dpi=dpi)


def plot_tension_overlay(results: dict, lines=None, title: str = "", t_max: float | None = None) -> Figure:
    """One panel per line, the tension of each labelled result overlaid (``results``: label -> Result)."""
    first = next(iter(results.values()))
    lines = lines or [n.removeprefix("tension_") for n in first.tension_names()]
    return _overlay(results, [(f"tension_{line}", f"{line} (N)") for line in lines], title or "line tensions",
                    (9.0, 2.2 * len(lines) + 0.8), t_max)


def plot_confluence_velocity_overlay(results: dict, prefix: str = "confluence", title: str = "",
                                     t_max: float | None = None) -> Figure:
    """Confluence east and north (lateral) velocity of each labelled result overlaid."""
    panels = [(f"{prefix}_velocity_{c}", f"{c} velocity (m/s)") for c in ("east", "north")]
    return _overlay(results, panels, title or "confluence lateral velocity", (9.0, 5.5), t_max)


def _overlay(results: dict, panels: list, title: str, size, t_max: float | None) -> Figure:
    """One panel per (column, y label), every labelled result that has the column overlaid, up to ``t_max`` (s)."""
    figure, axes = new_figure(len(panels), 1, size=size, sharex=True)
    for ax, (name, ylabel) in zip(axes[:, 0], panels):
        for label, result in results.items():
            if name in result:
                mask = result.time <= (t_max if t_max is not None else result.time[-1])
                ax.plot(result.time[mask], result[name][mask], label=label, linewidth=0.8)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
    axes[0, 0].legend(loc="best", fontsize="small")
    axes[-1, 0].set_xlabel("time (s)")
    figure.suptitle(title)
    return figure

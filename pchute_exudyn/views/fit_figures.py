"""The figure of a fit's report (``fit.report``): every target measured, at the start and fitted."""

from __future__ import annotations

from matplotlib.figure import Figure

from .plotting import new_figure


def fit_targets_figure(name: str, panels: list) -> Figure:
    """One panel per target of fit ``name``; ``panels``: (times, y label, std, measured, initial, fitted) per target:
    a history's ``times`` (s) draw three curves, None (a single value) draws three points, the measured one with its
    ``std`` as error bar."""
    figure, axes = new_figure(len(panels), 1, size=(8.0, 2.6 * len(panels) + 0.6))
    for ax, (times, label, std, measured, initial, fitted) in zip(axes[:, 0], panels):
        if times is not None:
            ax.plot(times, measured, ".", color="k", markersize=3, label="target")
            ax.plot(times, initial, "--", color="tab:blue", label="start")
            ax.plot(times, fitted, "-", color="tab:red", label="fitted")
            ax.set_xlabel("time (s)")
            ax.set_ylabel(label)
        else:
            ax.errorbar([0], measured, yerr=[std], fmt="o", color="k", capsize=4, label="target +- std")
            ax.plot([1], initial, "s", color="tab:blue", label="start")
            ax.plot([2], fitted, "D", color="tab:red", label="fitted")
            ax.set_xticks([0, 1, 2], ["target", "start", "fitted"])
            ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="x-small")
    figure.suptitle(f"{name}\ntargets: measured, at the start and fitted")
    return figure

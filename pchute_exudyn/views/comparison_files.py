"""The files of ``pchute compare --out DIR``: the report (``comparison.md``), its figures as data
(``comparison.json``, strict) and, for two trajectories, the figures."""

from __future__ import annotations

from ..registries import columns
from ..results.io import atomic_write_text, ensure_writable_dir, json_text


def write_comparison(comparison, labelled: dict, folder, vehicle: str = "", shown: tuple = (),
                     most: int = 0) -> list:
    """comparison.md and comparison.json of ``comparison`` (a ``results.compare.Comparison`` or a
    ``results.log_compare.LogComparison``) in ``folder``; for two trajectories (``labelled``: label -> Result) also
    the figures: tensions, the confluence's velocity, the descent rates and one per column of ``shown`` (at most
    ``most``; tensions and the confluence's velocity have their own). Returns the paths written."""
    out = ensure_writable_dir(folder)
    written = [out / "comparison.md", out / "comparison.json"]
    atomic_write_text(written[0], comparison.table())
    atomic_write_text(written[1], json_text(comparison.to_dict(), indent=2) + "\n")
    if labelled:
        written += _figures(comparison, labelled, out, vehicle, shown, most)
    return written


def _figures(comparison, labelled: dict, out, vehicle: str, shown, most: int) -> list:
    from ..results.compare import descent_profile
    from .plotting import (
        plot_column_overlay,
        plot_confluence_velocity_overlay,
        plot_descent_rates,
        plot_tension_overlay,
        save_figure,
    )

    written = []
    if comparison.lines:
        written.append(out / "tensions.png")
        save_figure(plot_tension_overlay(labelled, list(comparison.lines)), written[-1])
    if comparison.confluence_velocity:
        written.append(out / "confluence_velocity.png")
        save_figure(plot_confluence_velocity_overlay(labelled), written[-1])
    if comparison.descent:
        written.append(out / "descent_rate.png")
        profiles = {label: descent_profile(result, vehicle)[1:] for label, result in labelled.items()}
        save_figure(plot_descent_rates(profiles, vehicle), written[-1])
    shown = [n for n in shown if n in comparison.columns and columns.owner(n, "tension_{owner}") is None
             and "confluence_velocity" not in n]
    for name in shown[:most]:
        written.append(out / f"{name}.png")
        save_figure(plot_column_overlay(labelled, name, comparison.columns[name]["unit"]), written[-1])
    return written

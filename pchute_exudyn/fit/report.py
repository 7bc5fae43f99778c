"""The fit's report in its folder: ``fit.json`` (strict), ``fit_report.md``, ``targets.png`` (every target's value,
at the start and fitted) and ``calibrated.toml`` (a case file extending the base case with the fitted values)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..case.loader import extending_case_text
from ..results.io import atomic_write_text, json_text
from ..views.fit_figures import fit_targets_figure
from ..views.plotting import save_figure
from .solve import FitOutcome
from .spec import FitSpec


def write_report(spec: FitSpec, result: FitOutcome, folder) -> dict:
    """Write the report files of ``result`` (``fit.solve.run_fit``; a ``fit.json`` read back:
    ``FitOutcome.from_dict``) into ``folder``; returns their paths."""
    folder = Path(folder)
    paths = {"json": folder / "fit.json", "report": folder / "fit_report.md", "plot": folder / "targets.png",
             "case": folder / "calibrated.toml"}
    atomic_write_text(paths["json"], json_text(result.to_dict(), indent=2) + "\n")
    atomic_write_text(paths["case"], calibrated_case(spec, result.fitted, folder))
    _plot_targets(spec, result, paths["plot"])
    atomic_write_text(paths["report"], _markdown(spec, result, paths))
    return paths


def calibrated_case(spec: FitSpec, fitted: list, folder: Path) -> str:
    """A case file extending the base case with the fitted values (whole arrays where a key indexed one)."""
    return extending_case_text(spec.case, spec.overrides(fitted), folder,
                               f"{spec.name}: the fitted values of `pchute fit {spec.source.name}`")


def _rows(spec: FitSpec, result: FitOutcome):
    """(target, measured, initial, fitted) per target, arrays for histories."""
    start = 0
    for target in spec.targets:
        stop = start + target.size
        yield (target, np.asarray(target.measured), np.asarray(result.predictions_initial[start:stop]),
               np.asarray(result.predictions_fitted[start:stop]))
        start = stop


def _plot_targets(spec: FitSpec, result: FitOutcome, path: Path) -> None:
    """``targets.png``: each target's history against time (y label its column) or single value (its label)."""
    series = ("history", "log")   # drawn against their times (a log's: after its apogee)
    panels = [(target.times if target.kind in series else None,
               target.name if target.kind in series else target.label(), target.std, measured, initial, fitted)
              for target, measured, initial, fitted in _rows(spec, result)]
    save_figure(fit_targets_figure(spec.name, panels), path)


def _markdown(spec: FitSpec, result: FitOutcome, paths: dict) -> str:
    lines = [f"# Fit: {spec.name}", "",
             f"`pchute fit {spec.source.name}`: case `{spec.case.name}`, {spec.configuration.label or 'the case'}; "
             f"{result.runs} runs recorded ({result.runs_this_time} run now, {result.reused} read back). "
             f"Least squares: {result.message} (status {result.status}).", "",
             "| free key | bounds | start | fitted | standard error |", "|---|---|---|---|---|"]
    for key, (low, high), start, fitted, error, bound in zip(result.keys, result.bounds, result.initial,
                                                             result.fitted, result.standard_error, result.at_bound):
        lines.append(f"| {key} | [{low:g}, {high:g}] | {start:.6g} | {fitted:.6g}{' (at a bound)' if bound else ''}"
                     f" | {error:.3g} |")
    scaled = "scaled by the residuals' variance" if result.covariance_scaled_by_residuals else \
        "from the targets' standard deviations"
    lines += ["", f"Standard errors from the Jacobian at the fit, (J^T J)^-1 {scaled}.", "",
              "| target | target value | std | start | fitted | fitted - target |", "|---|---|---|---|---|---|"]
    for target, measured, initial, fitted in _rows(spec, result):
        if target.kind in ("history", "log"):
            start_rms, fitted_rms = (float(np.sqrt(np.mean((v - measured) ** 2))) for v in (initial, fitted))
            lines.append(f"| {target.label()} ({target.size} samples, RMS difference) | - | {target.std:g} | "
                         f"{start_rms:.4g} | {fitted_rms:.4g} | {fitted_rms:.4g} |")
        else:
            lines.append(f"| {target.label()} | {measured[0]:.6g} | {target.std:g} | {initial[0]:.6g} | "
                         f"{fitted[0]:.6g} | {fitted[0] - measured[0]:+.4g} |")
    lines += ["", "Files: `fit.json`, `targets.png`, `calibrated.toml` (the base case with the fitted values), "
                  "`evaluations.jsonl` (every run)."]
    return "\n".join(lines) + "\n"

"""Summaries and plots of a study folder (``pchute study-report DIR``).

Writes into ``DIR/report/``: ``report.md`` (counts, percentiles, failed runs and their errors, errors against the
reference), ``percentiles.json``, ``histograms.png``, ``scatter_<parameter>.png`` (outputs against each drawn input),
``grid_<parameter>.png`` (outputs against each grid parameter, one line per configuration), when runs deploy a
system on a trigger ``deployment_box_<system>.png`` (Mach number against dynamic pressure at the deployment, with the
1st-99th percentile box), when runs touch down the landing footprint (``footprint.json``, ``footprint.png``,
``touchdown.png``: ``study.footprint``) and, when the study has a reference, ``errors.csv`` and
``error_vs_wall_time.png``.
"""

from __future__ import annotations

import csv
import json
import math
import sys
from pathlib import Path

import numpy as np

from ..boundary import check_path
from ..errors import InputError
from ..registries.columns import DEPLOY_CONDITIONS, column
from ..registries.columns import owner as column_owner
from ..registries.columns import unit as column_unit
from ..registries.methods import METHODS, option_names
from ..results.compare import compare_results
from ..results.io import atomic_write_text, ensure_writable_dir, json_text
from ..results.result import Result
from ..views.plotting import save_figure
from ..views.study_figures import (
    deployment_box_figure,
    error_against_cost_figure,
    error_against_parameter_figure,
    footprint_figure,
    outputs_against_grid_figure,
    outputs_against_input_figure,
    percentile_histograms_figure,
)
from .failures import (
    choice_markdown,
    counts_markdown,
    failed_runs_markdown,
    failure_counts,
    never_fired_counts,
    never_fired_markdown,
    separation,
    separation_markdown,
)
from .footprint import (
    MINIMUM_RUNS,
    footprint_markdown,
    footprint_statistics,
    touchdown_histogram_panels,
    touchdown_points,
)
from .statistics import ROUND_OFF, at_round_off, bootstrap_interval, rank_correlations, runs_needed

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

PERCENTILES = (1, 50, 99)
BOOTSTRAP_NOTE = "2000 resamples, fixed seed"
def _is_peak_tension(name: str) -> bool:
    return column_owner(name, "peak_tension_{owner}") is not None


def output_label(name: str) -> str:
    """An output column with its unit (``registries.columns``): 'peak_tension_riser (N)'."""
    found = column_unit(name)
    return f"{name} ({found})" if found else name


def parameter_label(key: str, units: dict, relative: bool) -> str:
    """A study parameter's axis label: its last name with its unit, or saying it multiplies the case's value (the
    figure's title gives the whole key)."""
    name = key.split(".")[-1]
    if relative:
        return f"{name} (multiplier of the case's value)"
    unit = units.get(key)
    return f"{name} ({unit or '-'})" if unit is not None else name
MAIN_OUTPUTS = tuple(column(name) for name in (
    "final_east", "final_north", "final_lateral", "final_altitude", "touchdown_time", "touchdown_speed",
    "touchdown_descent_rate", "touchdown_horizontal_speed", "descent_rate", "pendulum_max_deg"))
CLUSTER_OUTPUTS = ("peak_load_share_{owner}", "max_flyout_{owner}", "mean_flyout_{owner}")
"""Per-cluster outputs the report's percentile table shows (``runner.cluster_outputs``), by template."""
DEPLOY_TIME, SEPARATION_TIME = "deploy_time_{owner}", "separation_time_{owner}"
DEPLOY_OUTPUTS = (DEPLOY_CONDITIONS["mach"], DEPLOY_CONDITIONS["dynamic_pressure"], DEPLOY_CONDITIONS["altitude"],
                  DEPLOY_TIME)
SEPARATION_OUTPUTS = (SEPARATION_TIME, "separation_clearance_{owner}")
"""Per triggered deployment and per separation outputs (``runner.sequence_outputs``), by template: the report's
percentile table shows them right after the main outputs, each system (body) in the order of its median time."""


def _number(text):
    if text in ("", None):
        return None
    try:
        return float(text)
    except ValueError:
        return text


def load_table(folder) -> list:
    """Rows of ``runs.csv`` with numbers as floats."""
    path = Path(folder) / "runs.csv"
    if not path.is_file():
        raise InputError(f"{folder}: no runs.csv: not a study folder (run `pchute study` into it first)")
    rewrite = "rerun `pchute study` into the folder to rewrite it from runs.jsonl"
    try:
        with path.open(newline="", encoding="utf-8") as handle:
            reader = csv.DictReader(handle)
            rows = [{k: _number(v) for k, v in row.items()} for row in reader]
            columns = reader.fieldnames or []
    except (UnicodeDecodeError, csv.Error) as exc:
        raise InputError(f"{path}: not a runs table pchute wrote ({type(exc).__name__}); {rewrite}") from None
    missing = [name for name in ("run", "status") if name not in columns]
    if missing:
        raise InputError(f"{path}: no {' or '.join(missing)} column: not a runs table pchute wrote; {rewrite}")
    bad = next((r for r in rows if not (isinstance(r.get("run"), float) and r["run"].is_integer())), None)
    if bad is not None:
        raise InputError(f"{path}: run = {bad.get('run')!r}: must be a run number (an integer); {rewrite}")
    return rows


def _study_files(folder: Path) -> tuple[dict, dict]:
    """The study's copy of its file (``study.toml``) and the parameters' units of ``manifest.json``; each {} when
    absent, an InputError when unreadable."""
    study, units = {}, {}
    try:
        if (folder / "study.toml").is_file():
            study = tomllib.loads((folder / "study.toml").read_text(encoding="utf-8"))
        if (folder / "manifest.json").is_file():
            manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
            units = manifest.get("parameter_units", {}) if isinstance(manifest, dict) else None
    except (OSError, UnicodeDecodeError, ValueError, RecursionError) as exc:   # TOML and JSON errors are ValueErrors
        raise InputError(f"{folder}: its study.toml or manifest.json cannot be read ({type(exc).__name__}: "
                         f"{str(exc).splitlines()[0] if str(exc) else ''}): not a study folder pchute wrote") from None
    if not isinstance(units, dict):
        raise InputError(f"{folder / 'manifest.json'}: not a JSON object with the study's fingerprint: not a "
                         "study folder pchute wrote")
    if not isinstance(study.get("study", {}), dict) or not isinstance(study.get("parameters", {}), dict) or \
            not all(isinstance(p, dict) for p in study.get("parameters", {}).values()):
        raise InputError(f"{folder / 'study.toml'}: [study] and each [parameters.\"<key>\"] must be tables")
    return study, units


def planned_runs(folder: Path) -> int | None:
    """The number of runs ``inputs.csv`` plans (None without a readable one)."""
    try:
        with (folder / "inputs.csv").open(newline="", encoding="utf-8") as handle:
            return sum(1 for _ in csv.DictReader(handle))
    except (OSError, UnicodeDecodeError, csv.Error):
        return None


def _configuration(row, with_step: bool = True) -> str:
    """'method integrator step option value ...' of a run (without the step: its family, one curve in a plot); the
    options are those of the row's method (the method table says which columns they are)."""
    step = f"{row['step']:g}" if with_step and isinstance(row.get("step"), float) else ""
    method = row.get("method") or ""
    parts = [str(method or "case"), str(row.get("integrator") or ""), step]
    names = option_names(METHODS[method].Options) if method in METHODS else ()
    for name in names:
        value = row.get(name)
        if isinstance(value, str) and value:
            parts.append(value)
        elif isinstance(value, (int, float)) and math.isfinite(value):   # absent: NaN or "" in other rows
            parts.append(f"{name} {value:g}")
    return " ".join(p for p in parts if p)


def percentiles(rows: list, outputs: list) -> dict:
    """Per output: the PERCENTILES with their 95 % bootstrap intervals (``p99_ci``) and whether the runs are enough
    for each (``p99_enough``: ``statistics.runs_needed``), mean, std, min, max and count."""
    table = {}
    for name in outputs:
        values = np.array([r[name] for r in rows if isinstance(r.get(name), float)])
        if len(values):
            entry = {}
            for p in PERCENTILES:
                entry[f"p{p}"] = float(np.percentile(values, p))
                entry[f"p{p}_ci"] = list(bootstrap_interval(values, p)) if len(values) > 1 else [entry[f"p{p}"]] * 2
                entry[f"p{p}_enough"] = len(values) >= runs_needed(p)
            table[name] = {**entry, "mean": float(values.mean()),
                           "std": float(values.std(ddof=1)) if len(values) > 1 else 0.0,
                           "min": float(values.min()), "max": float(values.max()), "count": int(len(values))}
    return table


def sensitivity(ok: list, drawn: list, outputs: list) -> tuple[dict, list]:
    """Per output, the drawn inputs ranked by their Spearman rank correlation with it (``statistics``), and the
    outputs skipped because their spread over the runs is round-off (``statistics.at_round_off``)."""
    inputs = {key: np.array([r.get(key) if isinstance(r.get(key), float) else np.nan for r in ok]) for key in drawn}
    table, skipped = {}, []
    for name in outputs:
        output = np.array([r.get(name) if isinstance(r.get(name), float) else np.nan for r in ok])
        if at_round_off(output):
            skipped.append(name)
            continue
        ranked = rank_correlations(inputs, output)
        if ranked:
            table[name] = ranked
    return table, skipped


def reference_errors(folder: Path, rows: list, grid: list) -> list:
    """Each run's differences from its reference run (from the saved histories)."""
    references = {r["run"]: r for r in rows if r.get("reference") == "True" and r.get("status") == "ok"}
    errors = []
    cache = {}

    def history(run):
        if run not in cache:
            cache[run] = Result.load(folder / "histories" / f"run_{int(run):05d}")
        return cache[run]
    for row in rows:
        ref = references.get(row.get("reference_run"))
        if row.get("reference") == "True" or ref is None or row.get("status") != "ok":
            continue
        try:
            a, b = history(ref["run"]), history(row["run"])
        except InputError:
            continue
        settle = min(2.0, 0.2 * float(a.time[-1]))   # the start-up transient, shorter for short runs
        c = compare_results(a, b, settle_time=settle, vehicle=a.vehicle)
        tension = [m["max_settled"] for m in c.lines.values() if np.isfinite(m["max_settled"])]
        errors.append({"run": int(row["run"]), "case": row["case"], "configuration": _configuration(row),
                       "family": _configuration(row, with_step=False), "step": row.get("step"),
                       "wall_time": row.get("wall_time"), "reference_wall_time": ref.get("wall_time"),
                       "altitude_error": abs(c.final.get(f"{a.vehicle} altitude", math.nan)),
                       "lateral_error": c.final.get(f"{a.vehicle} lateral position", math.nan),
                       "max_tension_error": max(tension) if tension else math.nan,
                       **{key: row.get(key) for key in grid}})
    return errors


def study_report(folder) -> dict:
    """Write the report of study folder ``folder``; returns the paths written."""
    folder = check_path(folder, "folder", "study folder")
    rows = load_table(folder)
    study, units = _study_files(folder)
    title = str(study.get("study", {}).get("name", folder.name))
    parameters = study.get("parameters", {})
    drawn = [k for k, p in parameters.items() if "distribution" in p and p["distribution"] not in ("seed", "choice")]
    categorical = [k for k, p in parameters.items() if p.get("distribution") == "choice"]
    grid = [k for k, p in parameters.items() if "distribution" not in p]
    labels = {k: parameter_label(k, units, bool(p.get("relative"))) for k, p in parameters.items()}
    out = ensure_writable_dir(folder / "report")
    ok = [r for r in rows if r.get("status") == "ok" and r.get("reference") != "True"]
    failed = [r for r in rows if r.get("status") != "ok"]
    outputs = _outputs(ok)
    stats = percentiles(ok, outputs)
    atomic_write_text(out / "percentiles.json", json_text(stats, indent=2) + "\n")
    ranking, skipped = sensitivity(ok, drawn, outputs) if drawn and len(ok) > 2 else ({}, [])
    paths = {"percentiles": out / "percentiles.json"}
    if ok and outputs:
        paths["histograms"] = _plot_histograms(ok, outputs[:12], stats, f"{title}: {len(ok)} ok runs"
                                               + (f" ({len(failed)} failed not shown)" if failed else ""), out)
    _input_figures(ok, failed, drawn, grid, outputs, labels, out, paths)
    boxes = _deployment_boxes(ok, stats, title, out, paths, len(failed))
    footprint = _footprint(ok, outputs, title, out, paths, len(failed))
    errors = _errors(folder, rows, grid, labels, out, paths)
    counts = failure_counts(rows, planned_runs(folder))
    found = separation(ok, [r for r in failed if r.get("reference") != "True"], drawn + grid + ["step"]) \
        if failed and ok else []
    unfired = never_fired_counts(rows)
    atomic_write_text(out / "failures.json", json_text({**counts, "failed_runs": [int(r["run"]) for r in failed],
                                                        "separation": found,
                                                        **({"never_fired": unfired} if unfired else {})},
                                                       indent=2) + "\n")
    paths["failures"] = out / "failures.json"
    first = _failure_section(counts, rows, failed, found, parameters) + never_fired_markdown(unfired, counts["ok"])
    first += choice_markdown([r for r in rows if r.get("reference") != "True"], categorical) if failed else []
    extra = boxes + footprint + _by_category(ok, categorical, outputs) + _ranking(ranking, skipped)
    atomic_write_text(out / "report.md", _markdown(title, first, ok, failed, stats, errors, grid, paths, extra))
    paths["report"] = out / "report.md"
    return paths


def _outputs(ok: list) -> list:
    """The outputs the ok runs hold, in the report's order: the main ones, per triggered deployment and per
    separation (in the order they happen), per cluster, then every peak tension."""
    systems = {column_owner(k, CLUSTER_OUTPUTS[0]) for r in ok for k in r} - {None}
    clustered = [column(template, system) for system in sorted(systems) for template in CLUSTER_OUTPUTS]
    deployed = [column(template, system) for system in _in_time_order(ok, DEPLOY_TIME) for template in DEPLOY_OUTPUTS]
    separated = [column(template, body) for body in _in_time_order(ok, SEPARATION_TIME)
                 for template in SEPARATION_OUTPUTS]
    return [o for o in MAIN_OUTPUTS + tuple(deployed + separated + clustered)
            if any(isinstance(r.get(o), float) for r in ok)] + \
        sorted({k for r in ok for k in r if _is_peak_tension(k) and isinstance(r[k], float)})


def _in_time_order(ok: list, template: str) -> list:
    """The owners of the ok runs' columns of ``template`` (``deploy_time_{owner}``: systems,
    ``separation_time_{owner}``: bodies), by their median time over the runs that have one (then by name; those
    without a time last)."""
    names = {column_owner(k, template) for r in ok for k in r} - {None}
    times = {name: [r[column(template, name)] for r in ok if isinstance(r.get(column(template, name)), float)]
             for name in names}
    return sorted(names, key=lambda name: (0, float(np.median(times[name])), name) if times[name] else (1, 0.0, name))


def _deployment_boxes(ok: list, stats: dict, title: str, out: Path, paths: dict, failed: int) -> list:
    """``deployment_box_<system>.png`` for each system whose triggered deployment the ok runs record with its Mach
    number and dynamic pressure (``failed`` runs have no values: counted, not drawn); returns the report lines."""
    rows = []
    for system in _in_time_order(ok, DEPLOY_TIME):
        mach, pressure = (column(DEPLOY_CONDITIONS[quantity], system) for quantity in ("mach", "dynamic_pressure"))
        points = [(r[mach], r[pressure]) for r in ok if isinstance(r.get(mach), float)
                  and isinstance(r.get(pressure), float)]
        if not points or mach not in stats or pressure not in stats:
            continue
        box = {"mach": (stats[mach]["p1"], stats[mach]["p99"]),
               "dynamic_pressure": (stats[pressure]["p1"], stats[pressure]["p99"])}
        missing = f" ({failed} failed runs not shown)" if failed else ""
        path = out / f"deployment_box_{_safe(system)}.png"
        save_figure(deployment_box_figure(np.array(points), box, f"{title}: {system} deployment, {len(points)} ok "
                                          f"runs{missing}", failed), path)
        paths[f"deployment box {system}"] = path
        rows.append(f"| {system} | {len(points)} | {box['mach'][0]:.4g} .. {box['mach'][1]:.4g} | "
                    f"{box['dynamic_pressure'][0]:.5g} .. {box['dynamic_pressure'][1]:.5g} | "
                    f"{stats[mach]['p50']:.4g} | {stats[pressure]['p50']:.5g} | `{path.name}` |")
    if not rows:
        return []
    machs = [column(DEPLOY_CONDITIONS["mach"], system) for system in _in_time_order(ok, DEPLOY_TIME)]
    few = any(not stats[mach]["p1_enough"] for mach in machs if mach in stats)
    return ["", "## Deployment box", "",
            "The vehicle's Mach number and dynamic pressure when each system's trigger deployed it (`trigger."
            "conditions` in each run's summary), over the ok runs: the 1st to 99th percentile of each, and the medians."
            + (" With fewer than 1000 runs the box's edges are set by the few most extreme runs (the percentile "
               "table's *)." if few else ""), "",
            "| system | runs | Mach p1 .. p99 (-) | dynamic pressure p1 .. p99 (Pa) | Mach p50 (-) | "
            "dynamic pressure p50 (Pa) | figure |", "|---|---|---|---|---|---|---|", *rows]


def _input_figures(ok: list, failed: list, drawn: list, grid: list, outputs: list, labels: dict, out: Path,
                   paths: dict) -> None:
    """Outputs against each drawn input (failed runs marked at their drawn value) and each grid parameter."""
    tensions = [o for o in outputs if _is_peak_tension(o)][:2]
    for key in drawn:
        targets = [column(o) for o in ("final_lateral", "final_altitude", "touchdown_speed") if column(o) in outputs]
        path = out / f"scatter_{_safe(key)}.png"
        save_figure(scatter_figure(ok, failed, key, labels[key], targets + tensions or [column("final_altitude")]),
                    path)
        paths[f"scatter {key}"] = path
    for key in grid:
        targets = [column(o) for o in ("final_altitude", "final_lateral") if column(o) in outputs] + tensions
        if targets:
            paths[f"grid {key}"] = _plot_grid(ok, key, labels[key], targets, out / f"grid_{_safe(key)}.png")


def _errors(folder: Path, rows: list, grid: list, labels: dict, out: Path, paths: dict) -> list:
    """Each run's errors against its reference, with their table and figures (none without a reference)."""
    errors = reference_errors(folder, rows, grid) if any(r.get("reference") == "True" for r in rows) else []
    if errors:
        paths["errors"] = _write_errors(errors, out / "errors.csv")
        save_figure(error_against_cost_figure(errors), out / "error_vs_wall_time.png")
        paths["error_vs_wall_time"] = out / "error_vs_wall_time.png"
        for key in grid:
            paths[f"error vs {key}"] = out / f"error_vs_{_safe(key)}.png"
            save_figure(error_against_parameter_figure(errors, key, labels[key]), paths[f"error vs {key}"])
    return errors


def _failure_section(counts: dict, rows: list, failed: list, found: list, parameters: dict) -> list:
    """The report's first lines: the counts and failure rate, the failed runs with their inputs and errors, and
    which inputs separate them from the ok runs (``found``: ``failures.separation``)."""
    references = sum(r.get("reference") == "True" for r in rows)
    lines = counts_markdown(counts, references)
    lines += failed_runs_markdown(failed, list(parameters), _configuration)
    return lines + separation_markdown(found)


def _footprint(ok: list, outputs: list, title: str, out: Path, paths: dict, failed: int) -> list:
    """The landing footprint's files when at least MINIMUM_RUNS runs touched down (``failed`` runs counted as not
    shown); returns its report lines."""
    points = touchdown_points(ok)
    if len(points) < MINIMUM_RUNS:
        return []
    stats = footprint_statistics(points)
    loads = [o for o in outputs if _is_peak_tension(o)]
    landed = [r for r in ok if isinstance(r.get(column("touchdown_time")), float)]
    rows = []
    touchdown = ("touchdown_speed", "touchdown_descent_rate", "touchdown_horizontal_speed", "touchdown_time")
    for name in [column(name) for name in touchdown] + loads:
        values = np.array([r[name] for r in landed if isinstance(r.get(name), float)])
        if len(values):
            unit = column_unit(name)
            rows.append((name, unit, {**{f"p{q}": float(np.percentile(values, q)) for q in (1, 5, 50, 95, 99)},
                                      "max": float(values.max())}))
    stats["percentiles"] = {name: {"unit": unit, **p} for name, unit, p in rows}
    atomic_write_text(out / "footprint.json", json_text(stats, indent=2) + "\n")
    paths["footprint data"] = out / "footprint.json"
    save_figure(footprint_figure(points, stats, f"{title}: touchdown points and dispersion ellipses", failed),
                out / "footprint.png")
    paths["footprint"] = out / "footprint.png"
    landed_loads = [name for name in loads if name in stats["percentiles"]]   # lines of the runs that landed
    heaviest = sorted(landed_loads, key=lambda name: -stats["percentiles"][name]["p50"])[:5]   # largest median peaks
    missing = f" ({failed} failed runs not shown)" if failed else ""
    save_figure(percentile_histograms_figure(touchdown_histogram_panels(landed, heaviest),
                                             f"{title}: {len(landed)} touchdowns{missing}", 2.8), out / "touchdown.png")
    paths["touchdown"] = out / "touchdown.png"
    lines = footprint_markdown(stats, rows)
    return lines + (["", f"{failed} failed runs are not in the footprint: a failed run records no touchdown."]
                    if failed else [])


def _plot_histograms(ok: list, shown: list, stats: dict, title: str, out: Path) -> Path:
    """``histograms.png``: each output in ``shown`` over the ok runs, with its PERCENTILES of ``stats``."""
    panels = [([r[name] for r in ok if isinstance(r.get(name), float)], output_label(name),
               {p: stats[name][f"p{p}"] for p in PERCENTILES}) for name in shown]
    save_figure(percentile_histograms_figure(panels, title, 2.6), out / "histograms.png")
    return out / "histograms.png"


def scatter_figure(ok: list, failed: list, key: str, label: str, targets: list):
    """Outputs against a drawn input (``views.study_figures.outputs_against_input_figure``), with their units."""
    return outputs_against_input_figure(ok, failed, key, label, targets, [output_label(name) for name in targets])


def _plot_grid(ok: list, key: str, label: str, targets: list, path: Path) -> Path:
    """Outputs against a grid parameter, one line per case and configuration."""
    panels = []
    for name in targets:
        curves = []
        for case, configuration in sorted({(r["case"], _configuration(r)) for r in ok}):
            points = sorted((r[key], r[name]) for r in ok if r["case"] == case and _configuration(r) == configuration
                            and isinstance(r.get(name), float) and isinstance(r.get(key), float))
            if points:
                curves.append((f"{case} {configuration}", points))
        panels.append((output_label(name), curves))
    save_figure(outputs_against_grid_figure(key, label, panels), path)
    return path


def _write_errors(errors: list, path: Path) -> Path:
    keys = list(errors[0])

    def cell(value):
        return f"{value:.6g}" if isinstance(value, float) else ("" if value is None else str(value))
    atomic_write_text(path, ",".join(keys) + "\n" + "".join(",".join(cell(e[k]) for k in keys) + "\n" for e in errors))
    return path


def _markdown(title: str, first: list, ok: list, failed: list, stats: dict, errors: list, grid: list, paths: dict,
              footprint: list) -> str:
    lines = [f"# Study report: {title}", "", *first, "", "## Outputs", ""]
    lines += _percentile_table(ok, failed, stats) if stats else [f"No outputs: no run ended ok ({len(failed)} failed)."]
    lines += loads_section(ok)
    lines += footprint
    if errors:
        lines += ["", "Errors against the reference (each run against its reference run):", "",
                  "| case | configuration | " + "".join(f"{k} | " for k in grid) + "wall time (s) | final altitude "
                  "error (m) | final lateral error (m) | max tension error after min(2 s, 20% of the run) (N) |",
                  "|---|---|" + "---|" * len(grid) + "---|---|---|---|"]
        for e in sorted(errors, key=lambda e: (e["case"], e["family"], e["step"] or 0.0,
                                               *[_sort_key(e.get(k)) for k in grid])):
            lines.append(f"| {e['case']} | {e['configuration']} | " + "".join(f"{e.get(k)} | " for k in grid)
                         + f"{e['wall_time']:.3g} | {e['altitude_error']:.3g} | {e['lateral_error']:.3g} | "
                           f"{e['max_tension_error']:.3g} |")
    lines += ["", "Figures: " + ", ".join(f"`{Path(p).name}`" for p in paths.values() if str(p).endswith(".png"))]
    return "\n".join(lines) + "\n"


DESIGN_PERCENTILES = (50, 99, 99.87)
"""The percentiles of the deployment loads the report gives: the median, the 99th and the 99.87th (three standard
deviations of a normal distribution: a design limit load teams take)."""


def loads_section(ok: list) -> list:
    """Report lines: per deployment (a system or a tether), the DESIGN_PERCENTILES of its snatch and opening loads
    over the ok runs, Knacke's median estimate, its lines' lowest breaking strength and the margin to the 99.87th
    percentile of its opening load (strength / load - 1); none without deployments."""
    names = sorted({column_owner(key, "opening_load_{owner}") for row in ok for key in row} - {None})
    if not names:
        return []
    head = " | ".join(f"p{p:g}" for p in DESIGN_PERCENTILES)
    lines = ["", "## Deployment loads", "",
             f"Over {len(ok)} ok runs (N; docs/models/deployment_loads.md). A percentile rests on at least ten runs "
             f"beyond it only with {runs_needed(99.87)} runs for the 99.87th, {runs_needed(99)} for the 99th: with "
             "fewer it is set by the few most extreme runs.", "",
             f"| deployment | load | {head} | Knacke (median) | breaking strength | margin at p99.87 |",
             "|---|---|" + "---|" * len(DESIGN_PERCENTILES) + "---|---|---|"]
    for name in names:
        def values(template):
            return np.array([r[template] for r in ok if isinstance(r.get(template), float)])
        knacke, strength = values(f"knacke_opening_load_{name}"), values(f"breaking_strength_{name}")
        for kind in ("snatch", "opening"):
            loads = values(f"{kind}_load_{name}")
            if not len(loads):
                continue
            cells = " | ".join(f"{np.percentile(loads, p):.4g}" for p in DESIGN_PERCENTILES)
            design = float(np.percentile(loads, 99.87))
            rated = float(np.median(strength)) if len(strength) else None
            margin = f"{rated / design - 1.0:.3g}" if rated and design > 0.0 and kind == "opening" else ""
            lines.append(f"| {name} | {kind} | {cells} | "
                         f"{f'{np.median(knacke):.4g}' if len(knacke) and kind == 'opening' else ''} | "
                         f"{f'{rated:.4g}' if rated else ''} | {margin} |")
    return lines


def _percentile_table(ok: list, failed: list, stats: dict) -> list:
    """Report lines: the percentiles of every output over the ok runs, with their bootstrap intervals."""
    lines = [f"Percentiles of {len(ok)} ok runs ({len(failed)} failed excluded: they have no outputs), with their "
             "95 % bootstrap intervals in brackets (percentile bootstrap, "
             f"{BOOTSTRAP_NOTE}); a percentile marked * rests on fewer runs than it needs to mean much (ten runs "
             "beyond it: 1000 for the 1st and 99th, 20 for the median).", "",
             "| output | p1 | p50 | p99 | mean | std | min | max | runs |", "|---|---|---|---|---|---|---|---|---|"]
    for name, s in stats.items():
        cells = [f"{s[f'p{p}']:.6g} [{s[f'p{p}_ci'][0]:.6g}, {s[f'p{p}_ci'][1]:.6g}]"
                 f"{'' if s[f'p{p}_enough'] else '*'}" for p in PERCENTILES]
        cells += [f"{s[k]:.6g}" for k in ("mean", "std", "min", "max")]
        lines.append(f"| {output_label(name)} | " + " | ".join(cells) + f" | {s['count']} |")
    short = [f"p{p}" for p in PERCENTILES if any(not s[f"p{p}_enough"] for s in stats.values())]
    if short:
        lines += ["", f"Warning: {', '.join(short)} rest on too few runs here (*): their intervals show how little "
                      "the runs pin them down; run more samples before quoting them."]
    return lines


def _by_category(ok: list, categorical: list, outputs: list) -> list:
    """Report lines: for each drawn choice (e.g. which canopy fails), the median of each output per value drawn."""
    lines = []
    for key in categorical:
        def label(row, key=key) -> str:
            value = row.get(key)
            return "(none)" if value in (None, "") else str(value)
        values = sorted({label(r) for r in ok})
        lines += ["", f"## By {key}", "", "Median of each output over the runs that drew each value (runs in "
                  "brackets).", "", "| output | " + " | ".join(f"{v} ({sum(label(r) == v for r in ok)})"
                                                              for v in values) + " |",
                  "|---|" + "---|" * len(values)]
        for name in outputs:
            cells = []
            for value in values:
                numbers = [r[name] for r in ok if label(r) == value and isinstance(r.get(name), float)]
                cells.append(f"{np.median(numbers):.6g}" if numbers else "-")
            lines.append(f"| {output_label(name)} | " + " | ".join(cells) + " |")
    return lines


def _ranking(ranking: dict, skipped: list) -> list:
    """Report lines: per output, the drawn inputs by rank correlation (strongest first), and the outputs skipped
    as round-off."""
    if not ranking and not skipped:
        return []
    lines = ["", "## Sensitivity: which inputs move which outputs", "",
             "Spearman rank correlation of each output with each drawn input over the ok runs (+1: the output rises "
             "with the input), strongest first.", "", "| output | inputs, strongest first |", "|---|---|"]
    for name, ranked in ranking.items():
        lines.append(f"| {output_label(name)} | " + ", ".join(f"{key} ({rho:+.2f})" for key, rho in ranked) + " |")
    for name in skipped:
        lines.append(f"| {output_label(name)} | skipped: its spread over the runs is round-off (at most "
                     f"{ROUND_OFF:g} x max(largest value, 1)), not a response to the inputs |")
    return lines


def _sort_key(value):
    return (0, value, "") if isinstance(value, float) else (1, 0.0, str(value))


def _safe(key: str) -> str:
    return "_".join("".join(c if c.isalnum() else " " for c in key).split())

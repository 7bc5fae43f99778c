"""Command line: ``pchute run ...``. Thin over the Python API; user mistakes print one line and exit non-zero."""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
from dataclasses import fields, replace
from pathlib import Path

from . import __version__, _interrupt
from ._interrupt import signals_interrupt as _signals_interrupt
from .errors import InputError, PchuteError
from .kernels import dataclass_code, lock, selection
from .registries.methods import INTEGRATORS, METHODS
from .views.command_parser import EXIT_USAGE
from .views.command_parser import CommandParser as _Parser

EXIT_ERROR = 1
EXIT_INTERRUPTED = 130   # 128 + SIGINT, as shells report an interrupted command
EXIT_TERMINATED = 143    # 128 + SIGTERM
DEFAULT_SETTLE = 2.0     # s: pchute compare's settling time without --settle
FIGURE_COLUMNS = 12      # pchute compare draws at most this many single-column figures (the first compared)
ADAPTIVE_STEP_ESTIMATE = 1e-2   # s: an adaptive run's steps counted at the thesis's step when deciding on a build


def _add_run(subparsers) -> None:
    subparsers.add_parser(
        "run", help="simulate a case and write its result files",
        description="Simulate a case file and write timeseries.csv, result.npz, summary.json, overview.png and "
                    "ground_track.png into the output folder. Prints a one-line summary.", arguments=_run_arguments)


def _run_arguments(run) -> None:
    run.add_argument("case", help="case file (TOML), e.g. cases/mer/case1.toml")
    run.add_argument("--method", choices=tuple(METHODS), default=None,
                     help="confluence method: " + "; ".join(f"{name} = {cls.summary}" + (
                         "" if cls.integrators == tuple(INTEGRATORS) else f" ({', '.join(cls.integrators)} only)")
                         for name, cls in METHODS.items()) + "; default: the case's simulation.method")
    run.add_argument("--integrator", choices=tuple(INTEGRATORS), default=None,
                     help="rk4 = explicit Runge-Kutta 4, fixed step (the thesis's); implicit = Exudyn's "
                          "generalized-alpha; default: the case's simulation.integrator")
    run.add_argument("--dt", type=_step, default=None, metavar="S",
                     help="integration step in s, or auto (adaptive RK4 steps); default: the case's "
                          "simulation.steps entry for the method, else adaptive steps with RK4, else half the step's "
                          "stability limit, rounded down (printed in the run line)")
    run.add_argument("--t-end", type=float, default=None, metavar="S",
                     help="simulated duration in s; default: the case's simulation.duration")
    run.add_argument("--out", default=None, metavar="DIR",
                     help="output folder (created if needed); default: results/<case>_<method>_<integrator>")
    run.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                     help="override a case field, validated like the file; repeatable. Keys are dotted "
                          "(bodies.vehicle.mass=800); a body or system name may lead (vehicle.mass=800); '*' "
                          "matches every entry (main.lines.*.damping=0); [i] indexes arrays (vehicle.inertia[0]=250)")
    _add_method_options(run)
    run.add_argument("--no-plot", action="store_true", help="do not write overview.png and ground_track.png")
    run.add_argument("--exudyn-solution", action="store_true",
                     help="also write Exudyn's own solution file of each phase (exudyn_solution_phase<k>.txt, every "
                          "output step) for scripts that open Exudyn's viewer on the phase model; `pchute view` and "
                          "`pchute animate` need neither")
    run.add_argument("--overwrite", action="store_true",
                     help="replace the result already in --out (by default an earlier result is not replaced)")
    run.add_argument("--quiet", action="store_true",
                     help="no progress line (it is shown only on a terminal anyway); the one-line summary remains")
    run.set_defaults(func=_run)


def _step(text: str):
    """--dt: a step in s, or 'auto' (adaptive steps); checked with the run's other inputs (``resolve_run``)."""
    try:
        return float(text)
    except ValueError:
        return text


def _option_flags():
    """(method name, option name, flag, field) of every method option that has a command-line flag."""
    for name, method_class in METHODS.items():
        for f in fields(method_class.Options):
            if f.metadata.get("flag"):
                yield name, f.name, f.metadata["flag"], f


def _add_method_options(parser) -> None:
    """One flag per method option that declares one (``methods.base.option``), from the method table."""
    seen = {}
    for method, _, flag, f in _option_flags():
        if flag in seen:   # two methods sharing a flag share its meaning
            continue
        seen[flag] = method
        parser.add_argument(flag, type=f.metadata["parse"], choices=f.metadata["choices"], default=None,
                            dest=f"option_{method}_{f.name}", metavar=None if f.metadata["choices"] else "X",
                            help=f"{method}: {f.metadata['help']}; default: the case's simulation.{method}.{f.name}"
                                 + ("" if f.default is None else f" ({f.default})"))


def _method_options(args, method_class) -> dict:
    """The options of ``method_class`` given on the command line; a flag of another method's option is an error."""
    own = {f.metadata.get("flag"): f.name for f in fields(method_class.Options)}
    given = {}
    for owner, option, flag, _ in _option_flags():
        value = getattr(args, f"option_{owner}_{option}", None)
        if value is None:
            continue
        if flag not in own:
            raise InputError(f"{flag} is an option of the {owner} method, not of --method {method_class.name}")
        given[own[flag]] = value
    return given


def _run(args) -> int:
    figure = None
    if not args.no_plot:   # imports matplotlib on another core while the run goes on (started by ``command``)
        from .views.figure_process import FigureProcess
        figure = _entry.pop("figure", None) or FigureProcess()
    try:
        with _signals_interrupt():
            return _run_case(args, figure)
    finally:
        if figure is not None:
            figure.close()


def _run_case(args, figure) -> int:
    from .boundary import load_case
    from .results.io import check_result_folder
    from .results.run_line import run_line
    from .run.simulation import method_class_of, resolve_run, simulate
    from .views.progress import TerminalProgress

    case = load_case(args.case, args.overrides)
    method_class = method_class_of(case, args.method)
    plan = resolve_run(case, method_class, args.integrator, args.dt, args.t_end, _method_options(args, method_class))
    method, integrator = method_class.name, plan.integrator
    out = Path(args.out) if args.out else Path("results") / f"{Path(args.case).stem}_{method}_{integrator}"
    check_result_folder(out, args.overwrite)  # fail before a long run, not after it; nothing is created yet
    for warning in case.warnings + plan.warnings:   # implausible values (case.plausible), idle settings: it goes on
        print(f"pchute run: warning: {warning}", file=sys.stderr)
    progress = TerminalProgress(plan.duration) if TerminalProgress.wanted(args.quiet) else None
    steps = plan.duration / (plan.step if plan.control is None else ADAPTIVE_STEP_ESTIMATE)
    if _entry["process"] and lock.worth_building_first(steps):
        lock.build_then_restart(steps, args.quiet)
    if lock.start_background_build() and not args.quiet:
        print(lock.BACKGROUND_NOTE, file=sys.stderr)
    try:
        result = simulate(case, plan=plan, progress=progress, engine_solution=args.exudyn_solution)
    finally:
        if progress is not None:
            progress.close()
    for warning in result.summary.warnings[len(case.warnings):len(result.summary.warnings) - len(plan.warnings)]:
        print(f"pchute run: warning: {warning}", file=sys.stderr)   # the run's own (a trigger unfired), not again
    result.save(out, plot=not args.no_plot, overwrite=args.overwrite, draw=figure.draw if figure else None)
    print(run_line(result.summary, out, plan.stability_limit))
    return 0


def _add_new(subparsers) -> None:
    subparsers.add_parser(
        "new", help="write a new, runnable case file from a few choices",
        description="Write a complete, commented case file: a vehicle under one canopy (or a cluster) on bridles "
                    "and a riser per canopy, in steady descent (every line stretched by its steady load, moving with "
                    "the air and down at the steady rate), released from an aircraft (--release-airspeed) or at line "
                    "stretch at flight conditions (--mach, --dynamic-pressure); or a rocket's dual deploy from a "
                    "state over the ground (--dual-deploy, --from-rocketpy). Edit it or run it as it is (`pchute run "
                    "FILE`). The same from Python: pchute_exudyn.new_case(...).", arguments=_new_arguments)


def _new_arguments(new) -> None:
    from .authoring.command_help import choice_fields, command_help
    from .authoring.planets import PLANETS
    from .authoring.rocket_start import WORDS
    from .registries.canopy_types import CANOPY_TYPES

    new.add_argument("file", help="the case file to write (TOML), e.g. my_case.toml")
    choices = {"planet": tuple(PLANETS), "canopy_type": tuple(CANOPY_TYPES), **WORDS}
    helps = command_help()
    for name, default in choice_fields():
        metavar, text = helps[name]
        if isinstance(default, bool):
            new.add_argument("--" + name.replace("_", "-"), dest=f"new_{name}", action="store_true", default=None,
                             help=text)
            continue
        kind = str if isinstance(default, str) else int if isinstance(default, int) else float
        kind = str if name == "from_rocketpy" else kind
        new.add_argument("--" + name.replace("_", "-"), dest=f"new_{name}", type=kind, default=None,
                         choices=choices.get(name), metavar="CSV" if name == "from_rocketpy" else metavar,
                         help=text + ("" if default is None else f" (default {default})"))
    new.add_argument("--overwrite", action="store_true", help="replace an existing file")
    new.set_defaults(func=_new)


def _new(args) -> int:
    from .authoring.layout import layout
    from .authoring.write import new_choices
    from .results.io import atomic_write_text
    from .run.dry_run import dry_run

    given = {key.removeprefix("new_"): value for key, value in vars(args).items()
             if key.startswith("new_") and value is not None}
    given.setdefault("name", Path(args.file).stem)
    choices = new_choices(given)
    if choices.from_rocketpy is not None:
        from .authoring.rocket_start import no_ground_warning, started_from
        from .results.rocketpy_export import apogee_state

        source = choices.from_rocketpy
        state = apogee_state(source)
        choices = started_from(replace(choices, from_rocketpy=None), state, source)
        print(f"{source}: start at t = {state.time:.3f} s, "
              + ("its apogee" if state.at_apogee else "its first row (it only descends)") + f", {state.altitude:.2f} m")
        if choices.ground_elevation is None:   # neither the export (no AGL column) nor the command line gave one
            print(f"pchute new: warning: {no_ground_warning(source)}", file=sys.stderr)
    path = Path(args.file)
    if path.exists() and not args.overwrite:
        raise InputError(f"{path} exists; pass --overwrite to replace it")
    if not path.parent.is_dir():
        raise InputError(f"{path}: the folder {path.parent} does not exist")
    text, warnings = dry_run(choices)
    for warning in warnings:
        print(f"pchute new: warning: {warning}", file=sys.stderr)
    atomic_write_text(path, text)
    if choices.dual_deploy:
        from .authoring.rocket_start import start_height
        print(f"wrote {path}: {choices.mass:g} kg rocket, dual deploy from {start_height(choices):.1f} m above the "
              f"ground, main at {choices.main_height:g} m; run it with `pchute run {path}`")
        return 0
    plan = layout(choices)
    print(f"wrote {path}: {choices.mass:g} kg vehicle on {choices.planet}, suspended mass {plan.total_mass:.2f} kg, "
          f"{plan.conditions_words}steady descent {plan.steady_rate(plan.altitude):.2f} m/s at {plan.altitude:g} m; "
          f"run it with `pchute run {path}`")
    return 0


def _add_compare(subparsers) -> None:
    compare = subparsers.add_parser(
        "compare", help="cross-check two results (folders or CSV files, another tool's included)",
        description="Align result B with result A on their common time span and report B - A: per compared column "
                    "(the mapped ones, or every shared one) the largest and RMS difference and when; for a descent, "
                    "each side's rate of descent at chosen altitudes, time to the ground and rate there; the final "
                    "vehicle position, line tensions and confluence lateral velocity. Prints the report; with --out "
                    "also writes comparison.md, comparison.json and figures (overlays with a difference panel). "
                    "CSV dialects: docs/tutorial.md. A run against a flight log (an altimeter's or flight computer's "
                    "export, read as it comes: docs/flight-logs.md) gives each side's apogee, deployments, descent "
                    "rates under each canopy, apogee-to-touchdown time and drift, read the same way from both.")
    compare.add_argument("a", help="reference result: a result folder or a CSV file with a time column (s)")
    compare.add_argument("b", help="result to check: a result folder, a CSV file with a time column (s) or, against a "
                                   "run folder, a flight log")
    compare.add_argument("--out", default=None, metavar="DIR", help="folder for the report and the figures")
    compare.add_argument("--settle", type=float, default=None, metavar="S",
                         help="settling time in s after which tension differences are also reported (default 2)")
    compare.add_argument("--altitudes", default=None, metavar="H1,H2,...",
                         help="altitudes in m of the vehicle at which to report each side's rate of descent "
                              "(default: a quarter, half and three quarters of the way down)")
    compare.add_argument("--ground", type=float, default=None, metavar="M",
                         help="ground altitude in m for the time to ground (default: the runs' own, else 0)")
    compare.add_argument("--map", action="append", default=[], metavar="THEIRS=OURS[*F][+C]", dest="column_map",
                         help="read a column of B as one of this package's: OURS = THEIRS x F + C, e.g. "
                              "--map alt_ft=vehicle_altitude*0.3048 --map 'Z (m)=vehicle_altitude+1200'; THEIRS "
                              "with or without its unit; repeatable, each column once")
    compare.add_argument("--map-a", action="append", default=[], metavar="THEIRS=OURS[*F][+C]",
                         help="the same for A")
    compare.set_defaults(func=_compare)


def _altitudes(text):
    """--altitudes H1,H2,... (m)."""
    if text is None:
        return None
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise InputError(f"--altitudes = {text!r}: must be altitudes in m separated by commas, e.g. 2000,1000,500") \
            from None
    if not values or not all(math.isfinite(v) for v in values):
        raise InputError(f"--altitudes = {text!r}: must be finite altitudes in m separated by commas")
    return values


def _compare(args) -> int:
    from .registries import columns
    from .results.compare import compare_results
    from .results.log_files import flight_log_side
    from .results.result import Result, parse_column_map
    from .views.comparison_files import write_comparison

    if args.out is not None and (not args.out.strip() or Path(args.out).is_file()):   # "": the working folder
        raise InputError(f"--out = {args.out!r}: must name a folder for the report (or leave --out out to print it)")
    settle = DEFAULT_SETTLE if args.settle is None else args.settle
    if not (math.isfinite(settle) and settle >= 0.0):
        raise InputError(f"--settle = {settle!r}: must be >= 0 (s) and finite")
    if args.ground is not None and not math.isfinite(args.ground):
        raise InputError(f"--ground = {args.ground!r}: must be a finite altitude (m)")
    altitudes = _altitudes(args.altitudes)
    maps = {"--map-a": parse_column_map(args.map_a), "--map": parse_column_map(args.column_map)}
    log_side = flight_log_side(args.a, args.b, bool(maps["--map-a"]), bool(maps["--map"]))
    if log_side is not None:
        return _compare_log(args, *log_side)
    a = Result.load(args.a, maps["--map-a"])
    b = Result.load(args.b, maps["--map"])
    for flag, mapping, other, label in (("--map", maps["--map"], a, "A"), ("--map-a", maps["--map-a"], b, "B")):
        for theirs, (ours, _, _) in mapping.items():
            if ours not in other:   # a mistyped name of ours would silently drop that quantity from the comparison
                raise InputError(f"{flag} {theirs}={ours}: {label} has no column {ours!r}; its columns are: "
                                 f"{', '.join(other.names)}")
    mapped = [ours for mapping in maps.values() for ours, _, _ in mapping.values() if ours != "time"]
    vehicle = next((r.vehicle for r in (a, b) if r.vehicle_named), columns.UNNAMED_VEHICLE)   # the first named
    if vehicle != columns.UNNAMED_VEHICLE:   # a RocketPy export read without a map: its columns as the named vehicle's
        a, b = (Result.load(path, mapping, vehicle) if not mapping and not Path(path).is_dir() else result
                for path, mapping, result in ((args.a, maps["--map-a"], a), (args.b, maps["--map"], b)))
    comparison = compare_results(a, b, args.a, args.b, settle, vehicle=vehicle, columns=mapped or None,
                                 altitudes=altitudes, ground=args.ground)
    if args.settle is not None and not settle < comparison.time[-1]:   # no settled sample: nothing to report
        raise InputError(f"--settle = {settle:g}: must be before the end of the common time span "
                         f"({comparison.time[0]:g} to {comparison.time[-1]:g} s)")
    for flag, mapping in maps.items():
        for theirs, (ours, _, _) in mapping.items():
            if ours != "time" and ours not in comparison.columns:
                raise InputError(f"{flag} {theirs}={ours}: no time in the common span where both sides have a value "
                                 f"of {ours}: nothing to compare")
    print(comparison.table(), end="")
    if args.out is not None:
        shown = mapped or [columns.column("{owner}_altitude", vehicle),
                           columns.column("{owner}_velocity_down", vehicle)]
        written = write_comparison(comparison, {f"A: {args.a}": a, f"B: {args.b}": b}, args.out, vehicle, shown,
                                   FIGURE_COLUMNS)
        print(f"wrote {', '.join(path.name for path in written)} in {args.out}")
    return 0


def _compare_log(args, run_path: str, log_path: str, run) -> int:
    """``pchute compare RUN LOG``: the run against a flight log (``results.log_files``)."""
    from .results.log_files import compare_files
    from .views.comparison_files import write_comparison

    for flag in ("settle", "altitudes", "ground"):
        if getattr(args, flag) is not None:
            raise InputError(f"--{flag}: not for a run against a flight log (its figures: docs/flight-logs.md)")
    comparison = compare_files(run_path, log_path, run)
    print(comparison.table(), end="")
    if args.out is not None:
        written = write_comparison(comparison, {}, args.out)
        print(f"wrote {', '.join(path.name for path in written)} in {args.out}")
    return 0


def _add_linearize(subparsers) -> None:
    lin = subparsers.add_parser(
        "linearize", help="equilibrium point, linearised confluence modes and stable step sizes",
        description="Solve the confluence equilibrium point (thesis Eq. 2.9), linearise the confluence about it "
                    "(Eq. 2.6: C_bar, K_bar), solve its modes and report the largest stable RK4 step of the full-mass "
                    "and singular-perturbation models. Fixed attach points are used as they are; for a flight case "
                    "the bodies' state at --time comes from a full-mass (implicit) run.")
    lin.add_argument("case", help="case file (TOML)")
    lin.add_argument("--time", type=float, default=0.0, metavar="T", help="time in s of the state (default 0)")
    lin.add_argument("--system", default=None, help="parachute system (default: the first)")
    lin.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    lin.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                     help="override a case field (as for pchute run); repeatable")
    lin.set_defaults(func=_linearize)


def _linearize(args) -> int:
    from .boundary import load_case
    from .results.io import json_text
    from .run.linear_report import format_report, linearization_report

    report = linearization_report(load_case(args.case, args.overrides), args.system, args.time)
    print(json_text(report) if args.json else format_report(report))
    return 0


def _add_study(subparsers) -> None:
    study = subparsers.add_parser(
        "study", help="run a parameter study or Monte Carlo dispersion",
        description="Run every run of a study file (grids, distributions, method and step configurations) and "
                    "record each as it finishes into the study folder; rerunning the same command resumes, skipping "
                    "finished runs. A failed run is recorded with its error and the study goes on.")
    study.add_argument("study_file", metavar="STUDY", help="study file (TOML), see docs/study-format.md")
    _add_executor_arguments(study, "local worker processes (default: every core)")
    study.add_argument("--out", default=None, metavar="DIR", help="study folder; default: studies/<study file name>")
    study.add_argument("--retry-failed", action="store_true", help="run again the runs recorded as failed")
    study.add_argument("--no-progress", action="store_true", help="no progress bar")
    study.add_argument("--allow-failures", type=float, default=0.0, metavar="F",
                       help="fraction 0..1 of the finished runs that may fail with exit status 0 (default 0: any "
                            "failed run makes the exit status 1)")
    study.set_defaults(func=_study)
    report = subparsers.add_parser(
        "study-report", help="summaries and plots of a study folder",
        description="Write DIR/report/: percentiles, histograms, scatter plots against the drawn inputs, line plots "
                    "for grids, and errors against the study's reference runs.")
    report.add_argument("folder", metavar="DIR", help="a study folder written by pchute study")
    report.set_defaults(func=_study_report)


def _add_executor_arguments(parser, workers_help: str) -> None:
    """Where a study's or a fit's runs execute: local processes, an existing Dask cluster or a local one."""
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=None, metavar="N", help=workers_help)
    where.add_argument("--dask-scheduler", default=None, metavar="ADDRESS",
                       help="run on an existing Dask cluster, e.g. tcp://10.0.0.5:8786 (install the dask extra)")
    where.add_argument("--dask-local", type=int, default=None, metavar="N",
                       help="start a local Dask cluster of N worker processes")
    parser.add_argument("--dask-timeout", type=_timeout_seconds, default=10.0, metavar="S",
                        help="seconds to wait for the Dask scheduler (default 10)")


def _timeout_seconds(text: str) -> float:
    """--dask-timeout S: a finite number of seconds > 0, checked as the command line is read (before any folder is
    made or cluster started)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"{text!r}: must be a finite number of seconds > 0")
    return value


def _interrupted_status(exc: KeyboardInterrupt) -> int:
    terminated = isinstance(exc, _interrupt.Terminated) or getattr(exc, "terminated", False)
    return EXIT_TERMINATED if terminated else EXIT_INTERRUPTED


def _interruptible(args, out: Path, kept: str, work) -> tuple:
    """``work(executor)`` on the executor the arguments ask for, SIGTERM taken as Ctrl-C: (its result, None), or
    (None, the exit status) when interrupted, after one line saying what is ``kept`` in ``out``."""
    from .results.io import ensure_writable_dir
    from .study.executors import executor_for

    ensure_writable_dir(out)   # before a Dask cluster starts
    with _signals_interrupt():
        close = None
        try:
            executor, close = executor_for(args.dask_scheduler, args.dask_local, args.dask_timeout)
            return work(executor), None
        except KeyboardInterrupt as exc:
            print(f"pchute {args.command}: interrupted; {kept} {out}: rerun the same command to resume",
                  file=sys.stderr)
            return None, _interrupted_status(exc)
        finally:
            if close is not None:
                close()


def _study(args) -> int:
    from .study import load_study, run_study
    from .study.executors import check_worker_counts

    if not 0.0 <= args.allow_failures <= 1.0:
        raise InputError(f"--allow-failures = {args.allow_failures}: must be a fraction of the runs from 0 to 1")
    check_worker_counts(args.workers, args.dask_local)
    spec = load_study(args.study_file)
    out = Path(args.out) if args.out else Path("studies") / Path(args.study_file).stem
    lock.start_background_build()   # the runs after this command's get the compiled module
    outcome, stopped = _interruptible(args, out, "finished runs are recorded in", lambda executor: run_study(
        spec, out, executor, args.workers, progress=not args.no_progress, retry_failed=args.retry_failed))
    if stopped is not None:
        return stopped
    print(f"{spec.name}: {outcome.executed} runs in {outcome.wall_time:.1f} s ({outcome.skipped} already done, "
          f"{outcome.failed} failed of {outcome.planned}{_rate(outcome)}) -> {out}")
    return _failures_status(outcome, args.allow_failures)


def _rate(outcome) -> str:
    """': 37.5 % of the finished runs' when runs failed, else nothing (``outcome``: a ``StudyOutcome``)."""
    finished = outcome.skipped + outcome.executed
    return f": {100.0 * outcome.failed / finished:.1f} % of the finished runs" if outcome.failed else ""


def _failures_status(outcome, allowed: float) -> int:
    """Exit status 1, with a line saying so, when more of the finished runs failed than the fraction ``allowed``."""
    finished = outcome.skipped + outcome.executed
    if outcome.failed == 0 or outcome.failed / finished <= allowed:   # (29 / 100 <= 0.29; 0.29 x 100 is not 29)
        return 0
    rate = 100.0 * outcome.failed / finished
    print(f"pchute study: {outcome.failed} of {finished} finished runs failed ({rate:.1f} %), more than "
          f"--allow-failures {allowed:g} allows: `pchute study-report` lists them", file=sys.stderr)
    return 1


def _study_report(args) -> int:
    from .study.report import study_report
    print(f"report: {study_report(args.folder)['report']}")
    return 0


def _add_animate(subparsers) -> None:
    animate = subparsers.add_parser(
        "animate", help="3D animation of a finished run (GIF, or MP4 with imageio-ffmpeg)",
        description="Draw a finished run from its result folder (never rerunning it): the bodies with their "
                    "attitudes at their sizes, every line coloured by its tension (grey dashed while slack), the "
                    "confluence, the followed body's trail, the clock and the tensions. Works without a display.")
    animate.add_argument("folder", help="result folder of `pchute run`")
    animate.add_argument("--out", default=None, metavar="FILE", help="FILE.gif or FILE.mp4 (default "
                         "FOLDER/animation.gif; MP4 needs `pip install imageio-ffmpeg`)")
    animate.add_argument("--speed", type=float, default=1.0, metavar="X",
                         help="seconds of run per second of animation (default 1)")
    animate.add_argument("--follow", default=None, metavar="BODY", help="body at the centre (default the vehicle)")
    animate.add_argument("--from", dest="start", type=float, default=None, metavar="T",
                         help="first run time drawn, s (default the run's start)")
    animate.add_argument("--to", dest="end", type=float, default=None, metavar="T",
                         help="last run time drawn, s (default the run's end)")
    animate.add_argument("--compare", default=None, metavar="OTHER_DIR",
                         help="another run's result folder, drawn over it in orange (e.g. full mass and SP)")
    animate.add_argument("--quiet", action="store_true", help="no progress line")
    animate.set_defaults(func=_animate)


def _animate(args) -> int:
    from .views.animation import Animation, Run, check_animation_path
    from .views.progress import TerminalProgress
    run = Run.load(args.folder)
    other = Run.load(args.compare) if args.compare else None
    out = check_animation_path(Path(args.out) if args.out else Path(args.folder) / "animation.gif")
    animation = Animation(run, other, args.follow, args.start, args.end, args.speed)
    progress = None
    if TerminalProgress.wanted(args.quiet):
        progress = TerminalProgress(animation.end)
    try:
        path = animation.save(out, progress)
    finally:
        if progress is not None:
            progress.close()
    print(f"{len(animation.times)} frames of {animation.start:g} s to {animation.end:g} s -> {path}")
    return 0


def _add_fit(subparsers) -> None:
    fit = subparsers.add_parser(
        "fit", help="fit free case keys to measured event times, final values and time histories",
        description="Bounded least squares over runs of a case (scipy's trust-region reflective method): the free "
                    "keys of the fit file within their bounds, residuals (model - measured) / std. The Jacobian's "
                    "runs go side by side to a process pool or a Dask cluster; every run is recorded in the fit "
                    "folder, and rerunning the same command resumes without running them again. Writes fit.json, "
                    "fit_report.md, targets.png and calibrated.toml.")
    fit.add_argument("fit_file", metavar="FIT", help="fit file (TOML), see docs/fit-format.md")
    fit.add_argument("--out", default=None, metavar="DIR", help="fit folder; default: fits/<fit file name>")
    _add_executor_arguments(fit, "local worker processes (default: one per free key plus one, at most every core)")
    fit.set_defaults(func=_fit)


def _fit(args) -> int:
    from .fit import load_fit, run_fit
    from .fit.report import write_report
    from .study.executors import check_worker_counts

    check_worker_counts(args.workers, args.dask_local)
    spec = load_fit(args.fit_file)
    out = Path(args.out) if args.out else Path("fits") / Path(args.fit_file).stem
    lock.start_background_build()   # the runs after this command's get the compiled module
    result, stopped = _interruptible(args, out, "the runs so far are recorded in",
                                     lambda executor: run_fit(spec, out, executor, args.workers))
    if stopped is not None:
        return stopped
    paths = write_report(spec, result, out)
    fitted = ", ".join(f"{k} = {v:.6g} +- {e:.2g}" for k, v, e in zip(result.keys, result.fitted,
                                                                       result.standard_error))
    print(f"{spec.name}: {fitted} ({result.runs} runs, {result.reused} read back) -> {paths['report']}")
    return 0


def _add_map(subparsers) -> None:
    mapped = subparsers.add_parser("map", help="a run or a study on a map: KML, GeoJSON, GPX, an offline HTML page",
                                   description="Write map.kml, .geojson, .gpx, .html: docs/results.md, Maps.")
    mapped.add_argument("folder", metavar="FOLDER", help="a result folder of `pchute run` or a study folder")
    mapped.add_argument("--out", default=None, metavar="DIR", help="write the files into DIR instead")
    mapped.set_defaults(func=_map)


def _map(args) -> int:
    from .study.maps import write_map
    print("map: " + ", ".join(str(path) for path in write_map(args.folder, args.out)))
    return 0


def _add_release_point(subparsers) -> None:
    from .airdrop.command import add_parser, release_point
    add_parser(subparsers).set_defaults(func=lambda args: _with_signals(release_point, args))


def _with_signals(command, args) -> int:
    with _signals_interrupt():
        return command(args)


def _add_view(subparsers) -> None:
    view = subparsers.add_parser(
        "view", help="replay a finished run in Exudyn's SolutionViewer (needs a display)",
        description="Replay a run from its result folder in Exudyn's interactive SolutionViewer: a display model "
                    "of its bodies, confluences and lines driven by the stored scene. Needs a display; without one "
                    "use `pchute animate`.")
    view.add_argument("folder", help="result folder of `pchute run`")
    view.set_defaults(func=_view)


def _view(args) -> int:
    from .views.viewer import view
    view(args.folder)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The ``pchute`` argument parser."""
    parser = _Parser(prog="pchute", description="Multibody parachute descent simulation on the Exudyn engine.")
    parser.add_argument("--version", action="version", version=f"pchute-exudyn {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    subparsers.required = True
    _add_run(subparsers)
    _add_new(subparsers)
    _add_compare(subparsers)
    _add_linearize(subparsers)
    _add_study(subparsers)
    _add_animate(subparsers)
    _add_view(subparsers)
    _add_map(subparsers)
    _add_fit(subparsers)
    _add_release_point(subparsers)
    return parser


_entry: dict = {"process": False}
"""Whether main runs as the process's command (``command``: it may then restart the process) and the figure process
``command`` started for a ``run``."""


def command() -> None:
    """The ``pchute`` console script and ``python -m pchute_exudyn``: ``main``, then the process ends without
    tearing the interpreter down (freeing every module's objects: 0.04 s, 0.1 s once matplotlib is loaded). By then
    every file is written and closed, pools and clusters shut down, and the output streams are flushed here."""
    _entry["process"] = True
    try:
        if sys.argv[1:2] == ["run"] and "--no-plot" not in sys.argv and not {"-h", "--help"} & set(sys.argv):
            from .views.figure_process import FigureProcess
            _entry["figure"] = FigureProcess()   # as early as can be: its import overlaps everything before the save
        code = main()
    except KeyboardInterrupt as exc:   # Ctrl-C or SIGTERM before the command's own handling began (``_interrupt``)
        print(f"{' '.join(['pchute', *sys.argv[1:2]])}: {str(exc) or 'interrupted'}", file=sys.stderr)
        code = _interrupted_status(exc)
    dataclass_code.save()   # atexit would not run: the classes this command compiled, for the next one
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):   # a closed or broken stream: nothing more can reach it
            pass
    os._exit(code)


def main(argv=None) -> int:
    """The command line: returns the exit status (``command`` is the entry point)."""
    args = build_parser().parse_args(argv)
    if selection.rejected_choice():
        print(f"pchute: error: {selection.rejected_choice()}", file=sys.stderr)
        return EXIT_USAGE
    try:
        return args.func(args)
    except PchuteError as exc:
        print(f"pchute {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    except KeyboardInterrupt as exc:   # Ctrl-C: not an error; a run says where it stopped (errors.Interrupted)
        print(f"pchute {args.command}: {str(exc) or 'interrupted'}", file=sys.stderr)
        return _interrupted_status(exc)
    except BrokenPipeError:   # the reader of the output went away (`pchute compare ... | head`): stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_ERROR
    except OSError as exc:   # a full disk, a read-only file system, a file that vanished: the file and the reason
        where = f"{_shown_path(exc.filename)!r}: " if exc.filename else ""
        print(f"pchute {args.command}: error: {where}{exc.strerror or _first_line(exc)}", file=sys.stderr)
        return EXIT_ERROR
    except MemoryError:
        print(f"pchute {args.command}: error: out of memory; shorten the run or raise its output step",
              file=sys.stderr)
        return EXIT_ERROR
    except Exception as exc:   # the last resort: a bug of ours, still one line (every known fault has its own)
        if _interrupt.RECEIVED[0] is not None:   # the interrupt, turned into an engine error where it landed
            interrupted = _interrupt.RECEIVED[0]()
            print(f"pchute {args.command}: {str(interrupted) or 'interrupted'}", file=sys.stderr)
            return _interrupted_status(interrupted)
        print(f"pchute {args.command}: internal error: {type(exc).__name__}: {_first_line(exc)} (please report this "
              "with the command line)", file=sys.stderr)
        return EXIT_ERROR


def _shown_path(filename) -> str:
    """The file a user asked for behind a failed write: io.atomic_writer's temporary '.NAME.XXXXXXXX.tmp' is NAME."""
    path = Path(os.fsdecode(filename))
    match = re.fullmatch(r"\.(.+)\.[^.]+\.tmp", path.name)
    return str(path.with_name(match.group(1)) if match else path)


def _first_line(exc: BaseException, limit: int = 200) -> str:
    """The first line of an exception's text, at most ``limit`` characters."""
    lines = str(exc).strip().splitlines()
    text = lines[0] if lines else type(exc).__name__
    return text if len(text) <= limit else text[:limit - 3] + "..."


if __name__ == "__main__":  # pragma: no cover
    command()

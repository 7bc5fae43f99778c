"""Command line: ``pchute run ...``. Thin over the Python API; user mistakes print one line and exit non-zero."""

from __future__ import annotations

import argparse
import sys
from dataclasses import fields
from pathlib import Path

from . import __version__, _kernel_mode
from .case.method_table import INTEGRATORS, METHODS
from .errors import InputError, PchuteError

EXIT_ERROR = 1
EXIT_USAGE = 2
EXIT_INTERRUPTED = 130   # 128 + SIGINT, as shells report an interrupted command


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line (no usage block)."""

    def error(self, message):
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def _add_run(subparsers) -> None:
    run = subparsers.add_parser(
        "run", help="simulate a case and write its result files",
        description="Simulate a case file and write timeseries.csv, result.npz, summary.json and overview.png "
                    "into the output folder. Prints a one-line summary.")
    run.add_argument("case", help="case file (TOML), e.g. cases/mer/case1.toml")
    run.add_argument("--method", choices=tuple(METHODS), default=None,
                     help="confluence method: " + "; ".join(f"{name} = {cls.summary}" + (
                         "" if cls.integrators == INTEGRATORS else f" ({', '.join(cls.integrators)} only)")
                         for name, cls in METHODS.items()) + "; default: the case's simulation.method")
    run.add_argument("--integrator", choices=INTEGRATORS, default=None,
                     help="rk4 = explicit Runge-Kutta 4, fixed step (the thesis's); implicit = Exudyn's "
                          "generalized-alpha; default: the case's simulation.integrator")
    run.add_argument("--dt", type=float, default=None, metavar="S",
                     help="integration step in s; default: the case's simulation.steps entry for the method")
    run.add_argument("--t-end", type=float, default=None, metavar="S",
                     help="simulated duration in s; default: the case's simulation.duration")
    run.add_argument("--out", default=None, metavar="DIR",
                     help="output folder (created if needed); default: results/<case>_<method>_<integrator>")
    run.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                     help="override a case field, validated like the file; repeatable. Keys are dotted "
                          "(bodies.vehicle.mass=800); a body or system name may lead (vehicle.mass=800); '*' "
                          "matches every entry (main.lines.*.damping=0); [i] indexes arrays (vehicle.inertia[0]=250)")
    _add_method_options(run)
    run.add_argument("--no-plot", action="store_true", help="do not write overview.png")
    run.add_argument("--exudyn-solution", action="store_true",
                     help="also write Exudyn's own solution file of each phase (exudyn_solution_phase<k>.txt, every "
                          "output step) for scripts that open Exudyn's viewer on the phase model; `pchute view` and "
                          "`pchute animate` need neither")
    run.add_argument("--overwrite", action="store_true",
                     help="replace the result already in --out (by default an earlier result is not replaced)")
    run.add_argument("--quiet", action="store_true",
                     help="no progress line (it is shown only on a terminal anyway); the one-line summary remains")
    run.set_defaults(func=_run)


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
    from .case import load_case
    from .io import check_result_folder
    from .progress import TerminalProgress
    from .simulation import resolve_method, resolve_run, simulate

    case = load_case(args.case, args.overrides)
    method_class = type(resolve_method(case, args.method))
    plan = resolve_run(case, method_class, args.integrator, args.dt, args.t_end, _method_options(args, method_class))
    method, integrator, step = method_class.name, plan.integrator, plan.step
    out = Path(args.out) if args.out else Path("results") / f"{Path(args.case).stem}_{method}_{integrator}"
    check_result_folder(out, args.overwrite)  # fail before a long run, not after it; nothing is created yet
    progress = TerminalProgress(plan.duration) if TerminalProgress.wanted(args.quiet) else None
    if _kernel_mode.start_background_compile() and not args.quiet:
        print("pchute run: note: this machine has no compiled kernels yet; this run uses their Python form (slower) "
              "while a background process compiles them for the next runs", file=sys.stderr)
    try:
        result = simulate(case, method_class, integrator, step, plan.duration, options=plan.method.options,
                          progress=progress, engine_solution=args.exudyn_solution)
    finally:
        if progress is not None:
            progress.close()
    result.save(out, plot=not args.no_plot, overwrite=args.overwrite)
    _print_run(result, out)
    return 0


def _print_run(result, out: Path) -> None:
    """The run's one-line summary."""
    s, f = result.summary, result.summary["final"]
    ending = "touchdown at" if s.get("end") == "touchdown" else "ended at"
    print(f"{s['case']}: {s['method']}/{s['integrator']} step {s['step']:g} s, {ending} {f['time']:.2f} s in "
          f"{s['wall_time']:.2f} s of wall time ({s['steps']} steps); final {s['vehicle']} altitude "
          f"{f['vehicle_altitude']:.2f} m, east {f['vehicle_east']:.3f} m, north {f['vehicle_north']:.3f} m -> {out}")


def _add_compare(subparsers) -> None:
    compare = subparsers.add_parser(
        "compare", help="compare two results (folders or CSV files, another tool's included)",
        description="Align result B with result A in time and report B - A: final vehicle altitude and lateral "
                    "position, per line the maximum and RMS tension difference (overall and after a settling "
                    "time), and the confluence lateral velocity. Prints the table; with --out also writes "
                    "comparison.md, comparison.json and overlay plots.")
    compare.add_argument("a", help="reference result: a result folder or a CSV file with a 'time' column (s)")
    compare.add_argument("b", help="result to check: a result folder or a CSV file with a 'time' column (s)")
    compare.add_argument("--out", default=None, metavar="DIR", help="folder for the table and the overlay plots")
    compare.add_argument("--settle", type=float, default=2.0, metavar="S",
                         help="settling time in s after which tension differences are also reported (default 2)")
    compare.add_argument("--map", action="append", default=[], metavar="THEIRS=OURS[*FACTOR]", dest="column_map",
                         help="rename (and scale) a column of B to this package's name, e.g. "
                              "--map alt_ft=vehicle_altitude*0.3048 --map T_riser_lbf=tension_riser*4.44822; "
                              "repeatable")
    compare.add_argument("--map-a", action="append", default=[], metavar="THEIRS=OURS[*FACTOR]",
                         help="the same for A")
    compare.set_defaults(func=_compare)


def _compare(args) -> int:

    from .compare import compare_results
    from .io import atomic_write_text, ensure_writable_dir, json_text
    from .plotting import plot_confluence_velocity_overlay, plot_tension_overlay, save_figure
    from .results import Result, parse_column_map

    if not (args.settle >= 0.0):
        raise InputError(f"--settle = {args.settle!r}: must be >= 0 (s)")
    out = ensure_writable_dir(args.out) if args.out else None
    maps = {"--map-a": parse_column_map(args.map_a), "--map": parse_column_map(args.column_map)}
    a = Result.load(args.a, maps["--map-a"])
    b = Result.load(args.b, maps["--map"])
    for flag, mapping, other, label in (("--map", maps["--map"], a, "A"), ("--map-a", maps["--map-a"], b, "B")):
        for theirs, (ours, _) in mapping.items():
            if ours not in other:   # a mistyped name of ours would silently drop that quantity from the comparison
                raise InputError(f"{flag} {theirs}={ours}: {label} has no column {ours!r}; its columns are: "
                                 f"{', '.join(other.names)}")
    vehicle = a.summary.get("vehicle", "vehicle")
    comparison = compare_results(a, b, args.a, args.b, args.settle, vehicle=vehicle)
    print(comparison.table(), end="")
    if out is not None:
        written = [out / "comparison.md", out / "comparison.json"]
        atomic_write_text(written[0], comparison.table())
        atomic_write_text(written[1], json_text(comparison.to_dict(), indent=2) + "\n")
        labelled = {f"A: {args.a}": a, f"B: {args.b}": b}
        if comparison.lines:
            written.append(out / "tensions.png")
            save_figure(plot_tension_overlay(labelled, list(comparison.lines)), written[-1])
        if comparison.confluence_velocity:
            written.append(out / "confluence_velocity.png")
            save_figure(plot_confluence_velocity_overlay(labelled), written[-1])
        print(f"wrote {', '.join(path.name for path in written)} in {out}")
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

    from .case import load_case
    from .io import json_text
    from .linear_report import format_report, linearization_report

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
    parser.add_argument("--dask-timeout", type=float, default=10.0, metavar="S",
                        help="seconds to wait for the Dask scheduler (default 10)")


def _executor(args):
    """The checked executor options: (executor or None for the local pool, its closing function or None)."""
    from .study import dask_executor

    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers = {args.workers}: must be >= 1")
    if args.dask_local is not None and args.dask_local < 1:
        raise InputError(f"--dask-local = {args.dask_local}: must be >= 1")
    if not args.dask_timeout > 0:
        raise InputError(f"--dask-timeout = {args.dask_timeout}: must be > 0 (s)")
    if args.dask_scheduler is None and args.dask_local is None:
        return None, None
    return dask_executor(args.dask_scheduler, args.dask_local, args.dask_timeout)


def _study(args) -> int:
    from .study import load_study, run_study

    spec = load_study(args.study_file)
    out = Path(args.out) if args.out else Path("studies") / Path(args.study_file).stem
    executor, close = _executor(args)
    try:
        counts = run_study(spec, out, executor, args.workers, progress=not args.no_progress,
                           retry_failed=args.retry_failed)
    except KeyboardInterrupt:
        print(f"pchute study: interrupted; finished runs are recorded in {out}: rerun the same command to resume",
              file=sys.stderr)
        return EXIT_INTERRUPTED
    finally:
        if close is not None:
            close()
    print(f"{spec.name}: {counts['executed']} runs in {counts['wall_time']:.1f} s ({counts['skipped']} already done, "
          f"{counts['failed']} failed of {counts['planned']}) -> {out}")
    return 0


def _study_report(args) -> int:
    from .study.report import study_report

    paths = study_report(args.folder)
    print(f"report: {paths['report']}")
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
    from .animation import Animation, Run
    from .progress import TerminalProgress

    run = Run.load(args.folder)
    other = Run.load(args.compare) if args.compare else None
    animation = Animation(run, other, args.follow, args.start, args.end, args.speed)
    out = Path(args.out) if args.out else Path(args.folder) / "animation.gif"
    progress = None
    if TerminalProgress.wanted(args.quiet):
        progress = TerminalProgress(animation.end)
    path = animation.save(out, progress)
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

    spec = load_fit(args.fit_file)
    out = Path(args.out) if args.out else Path("fits") / Path(args.fit_file).stem
    executor, close = _executor(args)
    try:
        result = run_fit(spec, out, executor, args.workers)
    except KeyboardInterrupt:
        print(f"pchute fit: interrupted; the runs so far are recorded in {out}: rerun the same command to resume",
              file=sys.stderr)
        return EXIT_INTERRUPTED
    finally:
        if close is not None:
            close()
    paths = write_report(spec, result, out)
    fitted = ", ".join(f"{k} = {v:.6g} +- {e:.2g}" for k, v, e in zip(result["keys"], result["fitted"],
                                                                       result["standard_error"]))
    print(f"{spec.name}: {fitted} ({result['runs']} runs, {result['reused']} read back) -> {paths['report']}")
    return 0


def _add_view(subparsers) -> None:
    view = subparsers.add_parser(
        "view", help="replay a finished run in Exudyn's SolutionViewer (needs a display)",
        description="Replay a run from its result folder in Exudyn's interactive SolutionViewer: a display model "
                    "of its bodies, confluences and lines driven by the stored scene. Needs a display; without one "
                    "use `pchute animate`.")
    view.add_argument("folder", help="result folder of `pchute run`")
    view.set_defaults(func=_view)


def _view(args) -> int:
    from .view import view

    view(args.folder)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The ``pchute`` argument parser."""
    parser = _Parser(prog="pchute", description="Multibody parachute descent simulation on the Exudyn engine.")
    parser.add_argument("--version", action="version", version=f"pchute-exudyn {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    subparsers.required = True
    _add_run(subparsers)
    _add_compare(subparsers)
    _add_linearize(subparsers)
    _add_study(subparsers)
    _add_animate(subparsers)
    _add_view(subparsers)
    _add_fit(subparsers)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``pchute`` console script."""
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except PchuteError as exc:
        print(f"pchute {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    except KeyboardInterrupt as exc:   # Ctrl-C: not an error; a run says where it stopped (errors.Interrupted)
        print(f"pchute {args.command}: {exc or 'interrupted'}", file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

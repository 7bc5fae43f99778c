"""Command line: ``pchute run ...``. Thin over the Python API; user mistakes print one line and exit non-zero."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from . import __version__
from .case.model import INTEGRATORS, METHODS
from .errors import PchuteError

EXIT_ERROR = 1
EXIT_USAGE = 2


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
    run.add_argument("--method", choices=METHODS, default=None,
                     help="confluence method: full = the confluence as a point mass (thesis Eqs. 1.1-1.7); "
                          "default: the case's simulation.method")
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
    run.add_argument("--no-plot", action="store_true", help="do not write overview.png")
    run.set_defaults(func=_run)


def _run(args) -> int:
    from .case import load_case
    from .io import ensure_writable_dir
    from .simulation import resolve_run, simulate

    case = load_case(args.case, args.overrides)
    method, integrator, step, duration = resolve_run(case, args.method, args.integrator, args.dt, args.t_end)
    out = Path(args.out) if args.out else Path("results") / f"{Path(args.case).stem}_{method}_{integrator}"
    ensure_writable_dir(out)  # fail before a long run, not after it
    result = simulate(case, method, integrator, step, duration)
    result.save(out, plot=not args.no_plot)
    s, f = result.summary, result.summary["final"]
    print(f"{s['case']}: {method}/{integrator} step {step:g} s, {duration:g} s simulated in {s['wall_time']:.2f} s "
          f"({s['steps']} steps); final {s['vehicle']} altitude {f['vehicle_altitude']:.2f} m, "
          f"east {f['vehicle_east']:.3f} m, north {f['vehicle_north']:.3f} m -> {out}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The ``pchute`` argument parser."""
    parser = _Parser(prog="pchute", description="Multibody parachute descent simulation on the Exudyn engine.")
    parser.add_argument("--version", action="version", version=f"pchute-exudyn {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    subparsers.required = True
    _add_run(subparsers)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``pchute`` console script."""
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except PchuteError as exc:
        print(f"pchute {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    except KeyboardInterrupt:
        print(f"pchute {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

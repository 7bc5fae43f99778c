"""``pchute release-point``: its options and what it prints (the command line keeps only the hook). Imported when
the parser is built, so only the standard library at the top."""

from __future__ import annotations

import sys
from pathlib import Path

TARGET_AND_AIRCRAFT = (
    ("--target-east", "M", "target east of the start point (m)"),
    ("--target-north", "M", "target north of the start point (m)"),
    ("--target-latitude", "DEG", "target latitude (deg; a case with a site)"),
    ("--target-longitude", "DEG", "target longitude (deg; a case with a site)"),
    ("--airspeed", "M/S", "the aircraft's airspeed (m/s); default the case's [start.release]"),
    ("--heading-deg", "DEG", "the aircraft's heading, clockwise from north (deg); default the case's"),
    ("--altitude", "M", "release altitude of the load's centre of mass (m); default the case's"))
SPREADS = (("--wind-error", None, "F", "relative 1-sigma scale of each wind key (default 0.15 where the case has "
                                       "a wind; 0: none)"),
           ("--wind-direction-error", None, "DEG", "1-sigma turn of a wind given as speed and from_deg (default 10 "
                                                   "where the case's wind has them; 0: none)"),
           ("--drag-error", 0.05, "F", "relative 1-sigma scale of each canopy's drag (default 0.05; 0: none)"),
           ("--release-error", 5.0, "M", "1-sigma release position error per axis (m; default 5; 0: none)"))


def add_parser(subparsers):
    """The ``release-point`` subcommand's parser, its options added."""
    rp = subparsers.add_parser(
        "release-point", help="the computed air release point (CARP) of an airdrop, and its landing footprint",
        description="Solve where the aircraft must release the load for the full simulation to land it on a target "
                    "(Broyden's method on the release position, one full run per step), then optionally run a "
                    "Monte Carlo dispersion there. Writes release_point.json, release_point.md and "
                    "release_case.toml (the case started at the release point) into the output folder. See "
                    "docs/release-point.md.")
    rp.add_argument("case", help="case file (TOML) with [start.release]")
    for flag, metavar, text in TARGET_AND_AIRCRAFT:
        rp.add_argument(flag, type=float, default=None, metavar=metavar, help=text)
    rp.add_argument("--tolerance", type=float, default=0.1, metavar="M",
                    help="miss distance (m) at which the solve stops (default 0.1)")
    rp.add_argument("--max-runs", type=int, default=10, metavar="N", help="full runs at most (default 10)")
    rp.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                    help="override a case field (as for pchute run); repeatable")
    monte_carlo = rp.add_mutually_exclusive_group()
    monte_carlo.add_argument("--runs", type=int, default=None, metavar="N",
                             help="Monte Carlo runs at the release point, with the dispersions below")
    monte_carlo.add_argument("--monte-carlo", default=None, metavar="STUDY",
                             help="a study file (docs/study-format.md) run at the release point, its case replaced "
                                  "by the release case")
    for flag, default, metavar, text in SPREADS:
        rp.add_argument(flag, type=float, default=default, metavar=metavar,
                        help=f"with --runs: {text}")
    rp.add_argument("--seed", type=int, default=1, help="with --runs: the study's seed (default 1)")
    rp.add_argument("--sampling", choices=("random", "latin_hypercube", "sobol"), default="latin_hypercube",
                    help="with --runs: how the draws are spread (default latin_hypercube)")
    rp.add_argument("--workers", type=int, default=None, metavar="N",
                    help="Monte Carlo worker processes (default: every core)")
    rp.add_argument("--out", default=None, metavar="DIR", help="output folder; default release_points/<case>")
    rp.add_argument("--overwrite", action="store_true", help="replace an earlier release point in --out")
    rp.add_argument("--quiet", action="store_true", help="no line per run (shown only on a terminal anyway)")
    return rp


def release_point(args) -> int:
    """Run the command: the solve, the Monte Carlo if asked, the folder; exit status 1 when it did not converge."""
    from ..views.progress import TerminalProgress
    from . import Dispersion, release_footprint, solve_release_point
    from .dispersion import one_case_study
    from .placement import merged_data, parsed_overrides
    from .release_files import check_release_folder, release_folder, write_release_case, write_release_point
    from .release_map import write_release_map

    out = Path(args.out) if args.out else Path("release_points") / Path(args.case).stem
    check_release_folder(out, args.overwrite)
    dispersion = None if args.runs is None else Dispersion(
        args.runs, args.wind_error, args.drag_error, args.release_error, args.seed, args.sampling,
        args.wind_direction_error)
    if dispersion is not None:   # before the solve's runs
        dispersion.check()
        dispersion.wind_parameters(merged_data(args.case, parsed_overrides(args.overrides)), args.case)
    if args.monte_carlo is not None:
        one_case_study(args.monte_carlo)   # a bad study file is one line before the solve's runs
    shown = TerminalProgress.wanted(args.quiet, sys.stderr)
    release = solve_release_point(
        args.case, args.target_east, args.target_north, target_latitude_deg=args.target_latitude,
        target_longitude_deg=args.target_longitude, overrides=args.overrides, airspeed=args.airspeed,
        heading_deg=args.heading_deg, altitude=args.altitude, tolerance=args.tolerance, max_runs=args.max_runs,
        report=_run_line if shown else None)
    footprint = None
    with release_folder(out, args.overwrite) as staging:
        write_release_case(staging, release)
        if dispersion is not None or args.monte_carlo is not None:
            footprint = release_footprint(staging, release, dispersion, args.monte_carlo, args.workers,
                                          progress=shown)
        write_release_point(staging, release, footprint)
        write_release_map(staging, release, footprint)
    print(_summary_line(release, out))
    if footprint is not None:
        print(_footprint_line(footprint))
    if not release.converged:
        print(f"pchute release-point: not converged: the last of {_runs(len(release.iterations))} misses the target "
              f"by {release.miss:.3f} m (tolerance {release.tolerance:g} m; raise --max-runs)", file=sys.stderr)
        return 1
    return 0


def _runs(count: int) -> str:
    return f"{count} run" + ("" if count == 1 else "s")


def _run_line(i) -> None:
    print(f"run {i.run}: release {i.release_east:.2f} m east, {i.release_north:.2f} m north -> miss {i.miss:.3f} m",
          file=sys.stderr)


def _summary_line(r, out: Path) -> str:
    site = "" if r.latitude_deg is None else f" ({r.latitude_deg:.6f}, {r.longitude_deg:.6f})"
    return (f"release at {r.release_east:.2f} m east, {r.release_north:.2f} m north{site}, {r.altitude:g} m; drift "
            f"{r.drift_east:.2f} m east, {r.drift_north:.2f} m north; miss {r.miss:.3f} m after "
            f"{_runs(len(r.iterations))} -> {out}")


def _footprint_line(f) -> str:
    (east_low, east_high), (north_low, north_high) = f.centre_interval
    s = f.statistics
    return (f"footprint of {s['count']} runs: centre {s['mean_east']:.2f} m east, {s['mean_north']:.2f} m north "
            f"(95 % interval {east_low:.2f} to {east_high:.2f} east, {north_low:.2f} to {north_high:.2f} north); "
            f"the target is {'inside' if f.target_inside else 'outside'} it")

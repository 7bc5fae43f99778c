"""What a study costs around its solves: the PA1 landing-footprint study on local worker processes.

Run:  python validation/study_overhead.py [--before DIR] [--runs 200] [--large 2000] [--workers 2]

Each side (this code, and with ``--before`` a checkout of the code before, ``git worktree add DIR COMMIT``) runs
validation/studies/pa1_footprint.toml with ``runs`` draws in its own process on ``workers`` local worker processes
(compiled kernels, warmed first) and reports the study's wall time, the sum of its runs' solve times (``wall_time``,
the engine's solve of each run) and their ratio, wall time x workers / sum of solve times: 1 would be no time
outside the solves at all. ``--large`` also runs a study of that many draws with this code. Writes
validation/output/study_overhead.md.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from script_arguments import OneLineParser, count, existing_folder, run_script, workers


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--before", type=existing_folder, default=None, help="checkout of the code before")
    parser.add_argument("--runs", type=count, default=200)
    parser.add_argument("--large", type=count, default=None, help="also a study of this many draws (this code)")
    parser.add_argument("--workers", type=workers, default=2)
    parser.add_argument("--compare-fixed", action="store_true",
                        help="with --large: the same draws at SP's fixed 1e-2 s too, and the footprint's percentiles "
                             "of the adaptive study against the fixed-step study's bootstrap intervals")
    args = parser.parse_args(argv)
    if args.compare_fixed and args.large is None:
        parser.refuse("--compare-fixed: only with --large N (it compares the large study's two step choices)")
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.study.statistics import percentile_table

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "output" / "study_overhead.md"
STUDY = HERE / "studies" / "pa1_footprint.toml"

OUTCOMES = ("final_east", "final_north", "touchdown_time", "touchdown_speed")
"""runs.csv columns of the footprint whose percentiles the fixed-step and adaptive studies compare."""
PERCENTILES = (1.0, 10.0, 50.0, 90.0, 99.0)

SIDE = r"""
import csv, json, sys, tempfile, time
OUTCOMES = ("final_east", "final_north", "touchdown_time", "touchdown_speed")
from pathlib import Path
from pchute_exudyn.study import load_study, run_study
runs, workers, study, cases, steps = int(sys.argv[1]), int(sys.argv[2]), Path(sys.argv[3]), sys.argv[4], sys.argv[5]
with tempfile.TemporaryDirectory() as folder:
    text = study.read_text().replace("runs = 200", f"runs = {runs}").replace('"../../cases/', f'"{cases}/')
    if steps != "study":
        text = text.replace('steps = ["auto"]', f"steps = [{steps}]")
    path = Path(folder) / "study.toml"
    path.write_text(text)
    started = time.perf_counter()
    counts = run_study(load_study(path), Path(folder) / "out", None, workers, progress=False)
    wall = time.perf_counter() - started
    rows = list(csv.DictReader(open(Path(folder) / "out" / "runs.csv")))
solves = [float(r["wall_time"]) for r in rows if r["status"] == "ok"]
whole = [float(r["run_time"]) for r in rows if r["status"] == "ok" and r.get("run_time")]
import pchute_exudyn
touchdowns = {key: [float(r[key]) for r in rows if r["status"] == "ok" and r.get("touchdown_time")]
              for key in OUTCOMES}
print(json.dumps({"runs": runs, "wall": wall, "solves": sum(solves), "failed": counts.failed,
                  "run_times": sum(whole) if len(whole) == len(solves) else None,
                  "package": str(Path(pchute_exudyn.__file__).parent), "outcomes": touchdowns}))
"""


def side(code: Path, runs: int, workers: int, steps: str = "study") -> dict:
    """One study run by the package in ``code`` (its own process, compiled kernels); ``steps``: the study file's
    (``study``) or the configuration's steps replaced (e.g. ``1.0e-2``)."""
    environment = {**os.environ, "PYTHONPATH": str(code), "PCHUTE_KERNELS": "compiled"}
    subprocess.run([sys.executable, "-m", "pchute_exudyn.kernels.build"], env=environment, check=True,
                   capture_output=True, cwd=code)
    with tempfile.TemporaryDirectory() as elsewhere:   # not the repository: `python -c` puts its folder first
        done = subprocess.run([sys.executable, "-c", SIDE, str(runs), str(workers), str(STUDY), str(ROOT / "cases"),
                               steps],
                              env=environment, check=True, capture_output=True, text=True, cwd=elsewhere)
    result = json.loads(done.stdout.strip().splitlines()[-1])
    if Path(result["package"]).resolve() != (code / "pchute_exudyn").resolve():
        raise SystemExit(f"the side meant to run {code} ran {result['package']}")
    result["ratio"] = result["wall"] * workers / result["solves"]
    return result


def commit_of(code: Path) -> str:
    found = subprocess.run(["git", "-C", str(code), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    return found.stdout.strip() or "?"


def row(label: str, r: dict) -> str:
    workers = r["ratio"] * r["solves"] / r["wall"]
    inside = "-" if r["run_times"] is None else f"{(r['run_times'] - r['solves']) / r['runs'] * 1000:.0f}"
    around = "-" if r["run_times"] is None else f"{(r['wall'] * workers - r['run_times']) / r['runs'] * 1000:.0f}"
    return (f"| {label} | {r['runs']} | {r['failed']} | {r['wall']:.1f} | {r['solves']:.1f} | {r['ratio']:.2f} | "
            f"{r['solves'] / r['runs']:.3f} | {inside} | {around} |")


def percentile_comparison(adaptive: dict, fixed: dict) -> list:
    """Markdown: each footprint outcome's PERCENTILES in the adaptive study against the fixed-step study's value and
    95 % bootstrap interval (``study.statistics.bootstrap_interval``), and whether it lies inside."""
    lines = ["## The footprint at adaptive steps against the fixed-step study", "",
             "| outcome | percentile | fixed 1e-2 s | its 95 % bootstrap interval | adaptive | inside |",
             "|---|---|---|---|---|---|"]
    rows, inside_all = percentile_table(fixed, adaptive, OUTCOMES, PERCENTILES)
    lines += rows
    lines += ["", f"Every percentile inside its interval: {'yes' if inside_all else 'NO'} ({len(adaptive['final_east'])} "
              f"and {len(fixed['final_east'])} touchdowns).", ""]
    return lines


def main(argv=None) -> int:
    args = arguments(argv)
    rows, comparison = [], []
    if args.before is not None:
        rows.append(row(f"before ({commit_of(args.before)}), 1e-2 s", side(args.before, args.runs, args.workers,
                                                                        "1.0e-2")))
    rows.append(row(f"now ({commit_of(ROOT)}), adaptive steps", side(ROOT, args.runs, args.workers)))
    if args.large:
        adaptive = side(ROOT, args.large, args.workers)
        rows.append(row(f"now ({commit_of(ROOT)}), {args.large} draws, adaptive steps", adaptive))
        if args.compare_fixed:
            fixed = side(ROOT, args.large, args.workers, "1.0e-2")
            rows.append(row(f"now ({commit_of(ROOT)}), {args.large} draws, 1e-2 s", fixed))
            comparison = percentile_comparison(adaptive["outcomes"], fixed["outcomes"])
    lines = ["# A study's time around its solves", "",
             f"`python validation/study_overhead.py{' --before DIR' if args.before else ''} --runs {args.runs}"
             f"{f' --large {args.large}' if args.large else ''} --workers {args.workers}`: "
             "validation/studies/pa1_footprint.toml (PA1 in wind and Dryden turbulence, SP; adaptive steps, the study's, "
             "unless the row says 1e-2 s) on "
             f"{args.workers} local worker processes, each side in its own process with compiled kernels; one "
             "machine, one after the other. Ratio = wall time x workers / sum of the runs' solve times (1: no time "
             "outside the solves).", "",
             "| code | runs | failed | wall time (s) | sum of solve times (s) | wall x workers / solves | mean solve (s) "
             "| per run in its worker, outside the solve (ms) | per run outside the workers' runs (ms of worker time) |",
             "|---|---|---|---|---|---|---|---|---|", *rows, "",
             "In its worker a run also loads its case, builds each phase's model and computes its outputs and "
             "summary (the record's `run_time` less its `wall_time`); outside the workers' runs: the study's set-up "
             "(drawing the runs: scipy.stats's import, 0.6 s), the workers' start, recording, the last runs' tail "
             "and the final tables. The code before records no `run_time`.", "", *comparison]
    atomic_write_text(OUT, "\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    run_script(main)

"""Parallel speed-up of a study: the same 40-run SP Monte Carlo with 1 worker and with 2, side by side in one run.

Run:  python validation/benchmark_study.py [--runs 40] [--duration 60] [--repeat 1] [--dask]

The study is `validation/studies/mer_monte_carlo.toml` cut to --runs runs (MER case 1, SP RK4 1e-2 s, 60 s each).
Each worker count runs it from scratch into a fresh temporary folder (process pool start-up, imports and the result
store included: the wall time a user waits for); with --repeat N the counts alternate N times and the fastest of
each is kept. The stored outputs of the two are checked to be identical. --dask adds a Dask LocalCluster of 2 workers.
Writes validation/output/benchmark_study.md.
"""

from __future__ import annotations

import csv
import dataclasses
import os
import tempfile
import time
from pathlib import Path

from script_arguments import OneLineParser, count, output_file, positive, run_script

HERE = Path(__file__).resolve().parent


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--runs", type=count, default=40, help="Monte Carlo runs (default 40)")
    parser.add_argument("--duration", type=positive, default=60.0, help="simulated time per run in s (default 60)")
    parser.add_argument("--repeat", type=count, default=1, help="alternate the worker counts this many times")
    parser.add_argument("--dask", action="store_true", help="also time a Dask LocalCluster of 2 workers")
    parser.add_argument("--out", type=output_file, default=str(HERE / "output" / "benchmark_study.md"))
    args = parser.parse_args(argv)
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions
from pchute_exudyn.study import load_study, run_study
from pchute_exudyn.study.runner import dask_executor

# per-run columns that legitimately differ between two executions of the same run
VOLATILE = {"wall_time", "run_time"}   # the solve, and the run as a whole in its worker


def outputs(folder: Path) -> list:
    with (folder / "runs.csv").open(newline="") as handle:
        return [{k: v for k, v in row.items() if k not in VOLATILE} for row in csv.DictReader(handle)]


def timed(spec, label: str, root: Path, workers: int | None = None, dask: bool = False) -> tuple:
    folder = root / f"{label}_{time.monotonic_ns()}"
    started = time.perf_counter()
    if dask:
        executor, close = dask_executor(local_workers=2)
        try:
            counts = run_study(spec, folder, executor=executor, progress=False)
        finally:
            close()
    else:
        counts = run_study(spec, folder, workers=workers, progress=False)
    wall = time.perf_counter() - started
    if counts.failed:
        raise SystemExit(f"{label}: {counts.failed} runs failed; see {folder / 'runs.csv'}")
    return wall, outputs(folder), sum(float(r["wall_time"]) for r in csv.DictReader((folder / "runs.csv").open()))


def main(argv=None) -> None:
    args = arguments(argv)
    spec = dataclasses.replace(load_study(HERE / "studies" / "mer_monte_carlo.toml"), runs=args.runs,
                               duration=args.duration, histories=False)
    configurations = [("1 worker (process pool)", dict(workers=1)), ("2 workers (process pool)", dict(workers=2))]
    if args.dask:
        configurations.append(("Dask LocalCluster, 2 workers", dict(dask=True)))
    best, stored, busy = {}, {}, {}
    with tempfile.TemporaryDirectory(prefix="pchute_benchmark_study_") as root:
        for _ in range(max(1, args.repeat)):
            for label, options in configurations:
                wall, rows, run_time = timed(spec, label.split()[0], Path(root), **options)
                print(f"  {label:32s} {wall:8.2f} s", flush=True)
                if label not in best or wall < best[label]:
                    best[label], busy[label] = wall, run_time
                stored[label] = rows
    serial = best[configurations[0][0]]
    identical = all(rows == stored[configurations[0][0]] for rows in stored.values())
    v = versions()
    lines = [f"# Study speed-up: {args.runs}-run SP Monte Carlo (MER case 1, SP RK4 1e-2 s, {args.duration:g} s each)",
             "",
             f"`python validation/benchmark_study.py{' --dask' if args.dask else ''}` (one process, worker counts one "
             "after the other; fastest of "
             f"{args.repeat}). {os.cpu_count()} cores. Exudyn {v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}, "
             f"Python {v['python']}, {v['platform']}.", "",
             "| executor | study wall time (s) | sum of run wall times (s) | speed-up over 1 worker |",
             "|---|---|---|---|"]
    for label, _ in configurations:
        lines.append(f"| {label} | {best[label]:.2f} | {busy[label]:.1f} | {serial / best[label]:.2f}x |")
    lines += ["", f"Stored inputs and outputs (all columns but wall_time and run_time) identical across executors: "
                  f"{'yes' if identical else 'NO'}.", ""]
    text = "\n".join(lines)
    print(text)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, text)
    if not identical:
        raise SystemExit("the executors stored different results")


if __name__ == "__main__":
    run_script(main)

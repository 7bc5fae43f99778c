"""The 200-run MER EDL Monte Carlo (validation/studies/mer_edl.toml) on 2 worker processes and on a Dask
LocalCluster of 2 workers, their tables compared, and its report.

Run:  python validation/mer_edl_study.py [--runs 200]

The process-pool study goes to validation/output/studies/mer_edl/ (with its report: the deployment Mach number and
dynamic pressure, peak loads and the heat shield's clearance as percentiles with bootstrap intervals, and the
deployment box figure); the Dask study to a temporary folder. Writes validation/output/studies/mer_edl.md.
"""

from __future__ import annotations

import dataclasses
import tempfile
import time
from pathlib import Path

from script_arguments import OneLineParser, count, run_script


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--runs", type=count, default=200, help="Monte Carlo runs (default 200)")
    args = parser.parse_args(argv)
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

from benchmark_study import outputs
from script_files import staged_folder

from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions
from pchute_exudyn.study import load_study, run_study
from pchute_exudyn.study.report import study_report
from pchute_exudyn.study.runner import dask_executor

HERE = Path(__file__).resolve().parent
OUT = HERE / "output" / "studies" / "mer_edl"


def main(argv=None) -> None:
    args = arguments(argv)
    spec = load_study(HERE / "studies" / "mer_edl.toml")
    if args.runs != spec.runs:
        spec = dataclasses.replace(spec, runs=args.runs)
    with staged_folder(OUT) as staging:   # a fresh study, moved over the committed one only when complete
        started = time.perf_counter()
        pool = run_study(spec, staging, workers=2, progress=False)
        pool_wall = time.perf_counter() - started
        with tempfile.TemporaryDirectory(prefix="pchute_mer_edl_dask_") as root:
            executor, close = dask_executor(local_workers=2)
            started = time.perf_counter()
            try:
                dask = run_study(spec, Path(root) / "dask", executor=executor, progress=False)
            finally:
                close()
            dask_wall = time.perf_counter() - started
            identical = outputs(staging) == outputs(Path(root) / "dask")
        paths = {name: OUT / Path(path).relative_to(staging) for name, path in study_report(staging).items()}
    v = versions()
    text = "\n".join([
        f"# MER EDL Monte Carlo: {spec.runs} runs on 2 workers and on a Dask LocalCluster", "",
        f"`python validation/mer_edl_study.py` ({spec.runs} runs of `cases/mer/edl.toml`, SP RK4 5e-3 s). Exudyn "
        f"{v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}, Python {v['python']}, {v['platform']}.", "",
        "| executor | ok | failed | study wall time (s) |", "|---|---|---|---|",
        f"| 2 worker processes | {pool.executed - pool.failed} | {pool.failed} | {pool_wall:.1f} |",
        f"| Dask LocalCluster, 2 workers | {dask.executed - dask.failed} | {dask.failed} | {dask_wall:.1f} |", "",
        f"Stored inputs and outputs (every column but wall_time and run_time) identical: {'yes' if identical else 'NO'}.",
        "", f"Report: `{Path(paths['report']).relative_to(HERE.parent).as_posix()}`.", ""])
    print(text)
    atomic_write_text(HERE / "output" / "studies" / "mer_edl.md", text)
    if not identical:
        raise SystemExit("the executors stored different results")


if __name__ == "__main__":
    run_script(main)

"""The 200-run PA1 cluster study (validation/studies/pa1_cluster.toml) on 2 worker processes and on a Dask
LocalCluster of 2 workers, side by side: the two run tables must be identical (the wall times aside).

Run:  python validation/cluster_study.py

Writes the study folder and its report into validation/output/studies/pa1_cluster/ (the 2-worker run), runs the Dask
one into a temporary folder, and writes validation/output/cluster/study_executors.md: the wall times, the
per-run solve times and whether the tables agree.
"""

from __future__ import annotations

import csv
import tempfile
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

from script_files import staged_folder

from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions
from pchute_exudyn.study import dask_executor, load_study, run_study
from pchute_exudyn.study.report import study_report

HERE = Path(__file__).resolve().parent
STUDY = HERE / "studies" / "pa1_cluster.toml"
OUT = HERE / "output" / "studies" / "pa1_cluster"
NOTE = HERE / "output" / "cluster" / "study_executors.md"


def table(folder: Path) -> list:
    """The study's run table without the columns that measure the machine (wall time)."""
    with (folder / "runs.csv").open(newline="") as handle:
        return [{k: v for k, v in row.items() if k != "wall_time"} for row in csv.DictReader(handle)]


def solve_time(folder: Path) -> float:
    with (folder / "runs.csv").open(newline="") as handle:
        return sum(float(row["wall_time"]) for row in csv.DictReader(handle))


def main(argv=None) -> int:
    spec = load_study(STUDY)
    with staged_folder(OUT) as staging:   # a fresh study, moved over the committed one only when complete
        pool = run_study(spec, staging, workers=2)
        with tempfile.TemporaryDirectory() as scratch:
            executor, close = dask_executor(local_workers=2)
            try:
                dask = run_study(spec, Path(scratch) / "dask", executor=executor)
            finally:
                close()
            same = table(Path(scratch) / "dask") == table(staging)
            dask_solve = solve_time(Path(scratch) / "dask")
        paths = {name: OUT / Path(path).relative_to(staging) for name, path in study_report(staging).items()}
    rows = table(OUT)
    failed = sum(row["status"] != "ok" for row in rows)
    v = versions()
    text = "\n".join([
        "# PA1 cluster study on two executors",
        "",
        "`python validation/cluster_study.py`: `validation/studies/pa1_cluster.toml` (200 SP runs of "
        "`cases/cev_pa1_cluster_winds.toml`, one main out drawn per run) on a local pool of 2 worker processes and on a "
        f"Dask LocalCluster of 2 workers, one after the other. Exudyn {v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}, "
        f"{v['platform']}.",
        "",
        "| executor | runs | failed | wall time (s) | sum of the runs' solve times (s) |",
        "|---|---|---|---|---|",
        f"| 2 worker processes | {pool.executed} | {pool.failed} | {pool.wall_time:.1f} | "
        f"{solve_time(OUT):.1f} |",
        f"| Dask LocalCluster, 2 workers | {dask.executed} | {dask.failed} | {dask.wall_time:.1f} | "
        f"{dask_solve:.1f} |",
        "",
        f"Run tables identical (every input and output column but the wall time): {'yes' if same else 'NO'}; "
        f"{len(rows)} runs, {failed} failed. Report: "
        f"[{Path(paths['report']).relative_to(HERE / 'output').as_posix()}](../{Path(paths['report']).relative_to(HERE / 'output').as_posix()}).",
        ""])
    atomic_write_text(NOTE, text)
    print(text)
    return 0 if same and not failed else 1


if __name__ == "__main__":
    run_script(main)

"""Monte Carlo at scale: a 2000-run footprint study on local workers, this code against the code before, side by side.

Run:  python validation/benchmark_study_scale.py [--study pa1|airdrop] [--runs 2000] [--workers 2] [--before DIR]

``--study pa1``: validation/studies/pa1_footprint.toml (PA1 in wind and Dryden turbulence, SP accurate preset,
adaptive steps); ``--study airdrop``: validation/studies/airdrop_footprint.toml (cases/airdrop/cluster_600m.toml, a
three-canopy cluster released at 600 m, in a steady wind: cluster_600m_wind.toml; the wind's speed and direction and
each canopy's drag dispersed). Each is cut to ``--runs`` draws (the same draws on both sides: the study's seed).
Each side (this code, and with ``--before`` a checkout of the code before, ``git worktree add DIR main``) runs the
study in its own process on ``--workers`` local worker processes with compiled kernels (built first if missing), one
side after the other, before first, on the same machine. The table gives each side's wall time, the sum of its runs'
solve times, the ratio wall x workers / sum of solves (1: nothing outside the solves), the time a run takes in its
worker outside its solve, and the steps; then whether every run's record (its outputs, status, warnings, steps; not
its timings) is identical on both sides, and each footprint outcome's percentiles now against the 95 % bootstrap
interval of the code before's (``study.statistics``). Writes validation/output/benchmark_study_scale_<study>.md. The
issue's target (issue 58, item 5): the 2000-run PA1 study in 60 s or less on 2 workers.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from script_arguments import OneLineParser, existing_folder, run_script

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
STUDIES = {"pa1": HERE / "studies" / "pa1_footprint.toml", "airdrop": HERE / "studies" / "airdrop_footprint.toml"}


def check_arguments(parser: OneLineParser, args) -> None:
    """Every argument, before anything runs or is written: one line naming the bad one (exit status 1)."""
    parser.check_counts(args)
    before = args.before
    if before is not None:
        if not (before / "pchute_exudyn" / "__init__.py").is_file():
            parser.refuse(f"--before {before}: not a checkout of pchute-exudyn (no pchute_exudyn/__init__.py); make "
                          "one with git worktree add DIR main")
        if before.resolve() == ROOT:
            parser.refuse(f"--before {before}: is this checkout; give the code before")


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--study", choices=sorted(STUDIES), default="pa1", help="which footprint study (default pa1)")
    parser.add_argument("--runs", type=int, default=2000, help="draws of the study (default 2000)")
    parser.add_argument("--workers", type=int, default=2, help="local worker processes (default 2)")
    parser.add_argument("--before", type=existing_folder, default=None, help="checkout of the code before")
    args = parser.parse_args(argv)
    check_arguments(parser, args)
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.study.statistics import percentile_table

TARGET = {"pa1": 60.0}
"""s: the issue's wall-time target of the 2000-run study on 2 workers."""
OUTCOMES = ("final_east", "final_north", "touchdown_time", "touchdown_speed")
"""The runs' outputs whose percentiles the two sides compare (m, m, s, m/s)."""
PERCENTILES = (1.0, 10.0, 50.0, 90.0, 99.0)
VOLATILE = ("wall_time", "run_time", "crc32")
"""A record's entries that differ between two executions of the same run: its timings and its line's checksum."""

SIDE = r"""
import hashlib, json, re, sys, tempfile, time
from pathlib import Path
from pchute_exudyn.study import load_study, run_study
runs, workers, study, cases = int(sys.argv[1]), int(sys.argv[2]), Path(sys.argv[3]), sys.argv[4]
outcomes, volatile = sys.argv[5].split(","), sys.argv[6].split(",")
with tempfile.TemporaryDirectory() as folder:
    text = re.sub(r"(?m)^runs = \d+", f"runs = {runs}", study.read_text()).replace('"../../cases/', f'"{cases}/')
    path = Path(folder) / "study.toml"
    path.write_text(text)
    started = time.perf_counter()
    counts = run_study(load_study(path), Path(folder) / "out", None, workers, progress=False)
    wall = time.perf_counter() - started
    records = [json.loads(line) for line in (Path(folder) / "out" / "runs.jsonl").read_text().splitlines()]
records.sort(key=lambda r: r["run"])
ok = [r for r in records if r["status"] == "ok"]
kept = [{k: v for k, v in r.items() if k not in volatile} for r in records]
import pchute_exudyn
print(json.dumps({
    "runs": runs, "wall": wall, "failed": counts.failed, "solves": sum(r["wall_time"] for r in ok),
    "run_times": sum(r["run_time"] for r in ok) if all(r.get("run_time") for r in ok) else None,
    "steps": sum(r.get("steps") or 0 for r in ok),
    "digests": [hashlib.sha256(json.dumps(r, sort_keys=True).encode()).hexdigest() for r in kept],
    "outcomes": {key: [r[key] for r in ok if r.get("touchdown_time") is not None] for key in outcomes},
    "package": str(Path(pchute_exudyn.__file__).parent)}))
"""


def side(code: Path, study: Path, runs: int, workers: int) -> dict:
    """The study run by the package in ``code`` in its own process (compiled kernels, built first)."""
    environment = {**os.environ, "PYTHONPATH": str(code), "PCHUTE_KERNELS": "compiled"}
    subprocess.run([sys.executable, "-m", "pchute_exudyn.kernels.build", "--if-missing"], env=environment, check=True,
                   capture_output=True, cwd=code)
    with tempfile.TemporaryDirectory() as elsewhere:   # not a checkout: `python -c` puts its folder first
        done = subprocess.run([sys.executable, "-c", SIDE, str(runs), str(workers), str(study), str(ROOT / "cases"),
                               ",".join(OUTCOMES), ",".join(VOLATILE)],
                              env=environment, capture_output=True, text=True, cwd=elsewhere)
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        raise SystemExit(f"benchmark_study_scale.py: the study failed with the code in {code}: {last}")
    result = json.loads(done.stdout.strip().splitlines()[-1])
    if Path(result["package"]).resolve() != (code / "pchute_exudyn").resolve():
        raise SystemExit(f"benchmark_study_scale.py: the side meant to run {code} ran {result['package']}")
    return result


def commit_of(code: Path) -> str:
    found = subprocess.run(["git", "-C", str(code), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    dirty = subprocess.run(["git", "-C", str(code), "status", "--porcelain", "--untracked-files=no", "--", ".",
                            ":(exclude)validation/output"], capture_output=True, text=True).stdout.strip()
    return (found.stdout.strip() or "?") + (" with uncommitted changes" if dirty else "")


def timing_row(label: str, r: dict, workers: int) -> str:
    """A markdown row: runs, failed, wall (s), sum of solves (s), ratio, mean solve (ms), per run in its worker
    outside the solve (ms), mean steps."""
    inside = "-" if r["run_times"] is None else f"{(r['run_times'] - r['solves']) / r['runs'] * 1000:.1f}"
    return (f"| {label} | {r['runs']} | {r['failed']} | {r['wall']:.1f} | {r['solves']:.1f} | "
            f"{r['wall'] * workers / r['solves']:.2f} | {r['solves'] / r['runs'] * 1000:.1f} | {inside} | "
            f"{r['steps'] / max(r['runs'] - r['failed'], 1):.0f} |")


def percentile_lines(now: dict, before: dict) -> list:
    """Each outcome's PERCENTILES now against the code before's value and 95 % bootstrap interval."""
    lines = ["| outcome | percentile | before | its 95 % bootstrap interval | now | inside |", "|---|---|---|---|---|---|"]
    rows, inside_all = percentile_table(before, now, OUTCOMES, PERCENTILES)
    lines += rows
    return lines + ["", f"Every percentile inside its interval: {'yes' if inside_all else 'NO'} ({len(now['final_east'])} "
                        f"and {len(before['final_east'])} touchdowns)."]


def report(args, now: dict, before: dict | None) -> list:
    """The report's lines."""
    command = (f"python validation/benchmark_study_scale.py --study {args.study} --runs {args.runs} --workers "
               f"{args.workers}{' --before DIR' if before else ''}")
    rows = [timing_row(f"before ({commit_of(args.before)})", before, args.workers)] if before else []
    rows.append(timing_row(f"now ({commit_of(ROOT)})", now, args.workers))
    lines = [f"# Monte Carlo at scale: {STUDIES[args.study].relative_to(ROOT)}", "",
             f"`{command}` on this machine ({os.cpu_count()} cores, shared with other work: compare the rows, which "
             "ran one after the other in the same invocation, not absolute times across reports). Each side in its "
             "own process, compiled kernels, the study's seed: the same draws.", "",
             "| code | runs | failed | wall time (s) | sum of solve times (s) | wall x workers / solves | mean solve "
             "(ms) | per run in its worker, outside the solve (ms) | mean steps |", "|---|---|---|---|---|---|---|---|---|",
             *rows, ""]
    target = TARGET.get(args.study)
    if target is not None and args.runs == 2000 and args.workers == 2:
        lines += [f"The issue's target, {target:g} s for the 2000 runs on 2 workers: "
                  f"{'met' if now['wall'] <= target else 'not met'} ({now['wall']:.1f} s"
                  + (f"; {before['wall'] / now['wall']:.2f} times faster than before" if before else "") + ").", ""]
    if before:
        same = sum(a == b for a, b in zip(now["digests"], before["digests"]))
        lines += [f"Runs whose record (outputs, status, warnings, steps; timings left out) is identical on both "
                  f"sides: {same} of {len(now['digests'])}.", "", "## The footprint now against before", "",
                  *percentile_lines(now["outcomes"], before["outcomes"]), ""]
    return lines


def main(argv=None) -> int:
    args = arguments(argv)
    study = STUDIES[args.study]
    before = side(args.before, study, args.runs, args.workers) if args.before is not None else None
    now = side(ROOT, study, args.runs, args.workers)
    lines = report(args, now, before)
    atomic_write_text(HERE / "output" / f"benchmark_study_scale_{args.study}.md", "\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    run_script(main)

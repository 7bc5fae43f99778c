"""Adaptive steps against the fixed steps of the code before: the long steady descent, side by side.

Run:  python validation/benchmark_steps.py --before DIR [--repeat 5]

``DIR`` is a checkout of the code before adaptive steps (``git worktree add DIR COMMIT``). Each side runs
``cases/simple/descent_440s.toml`` as it comes (no step set: this code takes adaptive steps, the code before half
the SP confluence's stability limit, rounded down: 1e-2 s) in a process of its own with compiled kernels, warmed up
first, ``--repeat`` interleaved rounds; the medians of the engine's solve (``summary.json``'s ``wall_time``) and of
the whole ``simulate`` call are compared, with the touchdown times. The same for MER case 1 (60 s), PA1 and the
rocket's dual deploy with SP asked for adaptive steps (``--dt auto``) against fixed steps in this code (the cases'
own, 1e-2 s for the rocket), for the record. Writes
validation/output/benchmark_steps.md.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from script_arguments import OneLineParser, count, existing_folder, run_script


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--before", type=existing_folder, required=True, help="a checkout of the code before")
    parser.add_argument("--repeat", type=count, default=5)
    args = parser.parse_args(argv)
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

from pchute_exudyn.results.io import atomic_write_text

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "output" / "benchmark_steps.md"
DESCENT = ROOT / "cases" / "simple" / "descent_440s.toml"

SIDE = r"""
import json, sys, time
import pchute_exudyn as pc
path, step, repeat, duration = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
step = None if step == "none" else step if step == "auto" else float(step)
duration = None if duration == "none" else float(duration)
case = pc.load_case(path)
pc.simulate(case, "sp", None, step, 5.0)   # warm-up: the compiled kernels loaded
rows = []
for _ in range(repeat):
    started = time.perf_counter()
    result = pc.simulate(case, "sp", None, step, duration)
    whole = time.perf_counter() - started
    touchdown = [e.time for e in result.summary.events_of("touchdown")]
    rows.append({"solve": result.summary.wall_time, "whole": whole, "steps": result.summary.steps,
                 "touchdown": touchdown[0] if touchdown else None, "end": result.final("time"),
                 "package": str(pc.__file__)})
print(json.dumps(rows))
"""


def side(code: Path, case: Path, step: str, repeat: int, duration: str = "none") -> list:
    """``repeat`` SP runs of ``case`` by the package in ``code`` (its own process, compiled kernels), to touchdown or
    for ``duration`` (s)."""
    environment = {**os.environ, "PYTHONPATH": str(code), "PCHUTE_KERNELS": "compiled"}
    subprocess.run([sys.executable, "-m", "pchute_exudyn.kernels.build", "--if-missing"], env=environment,
                   check=True, capture_output=True, cwd=code)
    with tempfile.TemporaryDirectory() as elsewhere:
        done = subprocess.run([sys.executable, "-c", SIDE, str(case), step, str(repeat), duration], env=environment,
                              check=True, capture_output=True, text=True, cwd=elsewhere)
    rows = json.loads(done.stdout.strip().splitlines()[-1])
    if Path(rows[0]["package"]).resolve().parent != (code / "pchute_exudyn").resolve():
        raise SystemExit(f"the side meant to run {code} ran {rows[0]['package']}")
    return rows


def interleaved(sides: dict, repeat: int) -> dict:
    """Each side's runs, one round of every side after another (``sides``: label -> (code, case, step[,
    duration]))."""
    runs = {label: [] for label in sides}
    for _ in range(repeat):
        for label, (code, case, step, *duration) in sides.items():
            runs[label] += side(code, case, step, 1, *duration)
    return runs


def median(rows: list, key: str) -> float:
    return statistics.median(row[key] for row in rows)


def table(runs: dict, reference: str) -> list:
    lines = ["| run | steps | solve (s), median | whole simulate (s), median | solve: reference / this | touchdown "
             "(s) | end (s) |", "|---|---|---|---|---|---|---|"]
    base = median(runs[reference], "solve")
    for label, rows in runs.items():
        touchdown = rows[0]["touchdown"]
        lines.append(f"| {label} | {rows[0]['steps']} | {median(rows, 'solve'):.3f} | {median(rows, 'whole'):.3f} | "
                     f"{base / median(rows, 'solve'):.2f}x | {'-' if touchdown is None else f'{touchdown:.4f}'} | "
                     f"{rows[0]['end']:.4f} |")
    return lines


def main(argv=None) -> int:
    args = arguments(argv)
    before = args.before.resolve()
    descent = interleaved({"before: fixed 1e-2 s (its default)": (before, DESCENT, "none"),
                           "now: adaptive steps (the default)": (ROOT, DESCENT, "none")}, args.repeat)
    labels = list(descent)
    touchdown = [descent[label][0]["touchdown"] for label in labels]
    ratio = median(descent[labels[0]], "solve") / median(descent[labels[1]], "solve")
    cases = {"MER case 1, 60 s": ROOT / "cases" / "mer" / "case1.toml", "PA1 to touchdown": ROOT / "cases" /
             "cev_pa1.toml", "rocket dual deploy": ROOT / "cases" / "rocket" / "dual_deploy.toml"}
    others = {}
    for name, path in cases.items():
        fixed = "0.01" if "rocket" in name else "none"
        duration = "60" if "60 s" in name else "none"
        others[name] = interleaved({f"{name}: fixed {'1e-2 s' if fixed != 'none' else 'step (its case)'}":
                                    (ROOT, path, fixed, duration), f"{name}: adaptive": (ROOT, path, "auto", duration)},
                                   args.repeat)
    text = ["# Adaptive steps against fixed steps", "",
            f"`python validation/benchmark_steps.py --before DIR --repeat {args.repeat}` (DIR: a checkout of the "
            "code before adaptive steps). Each run in a process of its own with compiled kernels, warmed up, "
            f"{args.repeat} interleaved rounds, medians; 'solve' is the engine's (`summary.json` `wall_time`), 'whole' "
            "the `simulate` call (case set-up, phases, outputs).", "",
            "## The 440-s descent (`cases/simple/descent_440s.toml`, as it comes)", "",
            *table(descent, labels[0]), "",
            f"Solve {ratio:.2f} times faster; touchdown {touchdown[1]:.4f} s against {touchdown[0]:.4f} s "
            f"({100.0 * (touchdown[1] / touchdown[0] - 1.0):+.4f} %).", ""]
    for name, runs in others.items():
        text += [f"## {name}", "", *table(runs, next(iter(runs))), ""]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(OUT, "\n".join(text))
    print("\n".join(text))
    return 0


if __name__ == "__main__":
    run_script(main)

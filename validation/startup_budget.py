"""Where a warm `pchute run` spends its time around the solve: MER case 1, SP, 60 s.

Run:  python validation/startup_budget.py [--repeat 3]

Side by side in one run: the whole process of ``pchute run cases/mer/case1.toml --method sp --no-plot`` (warm:
compiled kernels in the cache) against the solve time it reports, and the same with the overview figure; then a
profile of one such run in a fresh process (cProfile, every call), its cumulative times turned into shares of the
process's own wall time: imports, loading the compiled kernels (numba's first use included), the step-limit check
before the run, model building, the solve, the outputs and summary, writing the files (disjoint parts), and across them the loading of the compiled kernels.
Writes
validation/output/startup_budget.md.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CASE = ROOT / "cases" / "mer" / "case1.toml"
OUT = HERE / "output" / "startup_budget.md"

PROFILE = r"""
import cProfile, json, pstats, sys, time
started = time.perf_counter()
import pchute_exudyn.cli as cli
imported = time.perf_counter()
profile = cProfile.Profile()
profile.enable()
cli.main(sys.argv[1:])
profile.disable()
ended = time.perf_counter()
stats = pstats.Stats(profile).stats
def cumulative(*suffixes):
    return sum(value[3] for key, value in stats.items() if any(f"{key[0]}:{key[2]}".endswith(s) for s in suffixes))
print(json.dumps({"imports": imported - started, "profiled": ended - imported,
                  "kernels": cumulative("numba/core/dispatcher.py:compile"), "parts": {
    "step-limit check before the run (numba's first kernel load happens here)":
        cumulative("simulation.py:add_step_monitor"),
    "solve (Exudyn's SolveSystem, the stage kernels inside)": cumulative(":<built-in method exudyn.exudynCPP.SolveSystem>"),
    "outputs and summary": cumulative("outputs.py:derive_columns", "analysis.py:pendulum_columns",
                                      "simulation.py:summarize", "analysis.py:cluster_columns"),
    "writing the result files": cumulative("results.py:save"),
}}))
"""


def run_process(arguments: list) -> tuple[float, float]:
    """(process wall time, reported solve time) of one `pchute run`, s."""
    with tempfile.TemporaryDirectory() as folder:
        started = time.perf_counter()
        subprocess.run([sys.executable, "-m", "pchute_exudyn", "run", str(CASE), "--method", "sp", "--quiet",
                        "--out", f"{folder}/r", *arguments], check=True, capture_output=True)
        wall = time.perf_counter() - started
        solve = json.loads(Path(f"{folder}/r/summary.json").read_text())["wall_time"]
    return wall, solve


def profile() -> dict:
    with tempfile.TemporaryDirectory() as folder:
        done = subprocess.run([sys.executable, "-c", PROFILE, "run", str(CASE), "--method", "sp", "--quiet",
                               "--no-plot", "--out", f"{folder}/r"], check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    run_process(["--no-plot"])   # warm: the kernels compiled and cached, files in the page cache
    plain, plotted = [], []
    for _ in range(args.repeat):   # interleaved rounds
        plain.append(run_process(["--no-plot"]))
        plotted.append(run_process([]))
    wall = statistics.median(w for w, _ in plain)
    solve = statistics.median(s for _, s in plain)
    figure = statistics.median(w for w, _ in plotted) - wall
    budget = profile()
    parts = budget["parts"]
    scale = (wall - budget["imports"]) / budget["profiled"]   # profiled seconds -> plain seconds
    rest = budget["profiled"] - sum(parts.values())
    rows = [f"| imports (`import pchute_exudyn.cli`, unprofiled) | {budget['imports']:.3f} |"]
    rows += [f"| {name} | {value * scale:.3f} |" for name, value in parts.items()]
    rows += [f"| the rest (loading the case, model building, interpreter start and exit) | {rest * scale:.3f} |",
             f"| of all the above: loading the compiled kernels from numba's cache (numba's start-up included) | "
             f"{budget['kernels'] * scale:.3f} |"]
    lines = ["# A warm `pchute run` around its solve", "",
             f"`python validation/startup_budget.py --repeat {args.repeat}`: `pchute run cases/mer/case1.toml "
             f"--method sp --no-plot` (MER case 1, 60 s, SP at 1e-2 s), compiled kernels cached; medians of "
             f"{args.repeat} interleaved rounds.", "",
             "| quantity | value |", "|---|---|",
             f"| whole process, no figure (s) | {wall:.3f} |",
             f"| its solve (summary.json `wall_time`, s) | {solve:.3f} |",
             f"| process / solve | {wall / solve:.1f}x |",
             f"| the overview figure adds (s) | {figure:.3f} |", "",
             "## Where the process's time goes (one profiled run, scaled to the unprofiled wall time)", "",
             "| part | seconds |", "|---|---|", *rows, ""]
    OUT.write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The floor of a footprint study's time: what its solves cost in the engine alone, the package's per-step Python left out.

Run:  python validation/study_floor.py [--study pa1|airdrop] [--runs 20] [--workers 2]

Runs the first ``--runs`` draws of the study (validation/studies/pa1_footprint.toml or airdrop_footprint.toml, the
same draws as ``benchmark_study_scale.py``) one after the other in this process (a one-thread executor: the same
code path as a worker's run) with compiled kernels, and times each solve's parts: Exudyn's pre- and post-step hooks
(the package's per-step Python: step control and its stability caps, sampling, deployment watches, stop conditions)
and the rest, Exudyn's explicit RK4 with the stage functions (the forces: the compiled kernels and the Python call
that hands them the state). The rest is what no step control written in Python can take away: with the steps the
runs take (the explicit RK4's stability limits of the canopies on their lines, docs/models/step_control.md), the
study cannot finish on ``--workers`` cores in less than runs x (the rest per run) / workers. The table projects it
for 2000 runs and sets it against issue 58's 60-s target. Writes validation/output/study_floor_<study>.md.
"""

from __future__ import annotations

import json
import os
import re
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from script_arguments import OneLineParser, run_script

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
STUDIES = {"pa1": HERE / "studies" / "pa1_footprint.toml", "airdrop": HERE / "studies" / "airdrop_footprint.toml"}


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--study", choices=sorted(STUDIES), default="pa1", help="which footprint study (default pa1)")
    parser.add_argument("--runs", type=int, default=20, help="draws run (default 20)")
    parser.add_argument("--workers", type=int, default=2, help="workers of the projection (default 2)")
    args = parser.parse_args(argv)
    if not 1 <= args.runs <= 2000:
        parser.refuse(f"--runs = {args.runs}: must be from 1 to 2000")
    if args.workers < 1:
        parser.refuse(f"--workers = {args.workers}: must be >= 1")
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

PROJECTED_RUNS = 2000
TARGET = 60.0
"""s: issue 58's wall-time target of the 2000-run PA1 study on 2 workers."""


class Clock:
    """Seconds spent in some user functions Exudyn calls, over every solve of this process."""

    def __init__(self):
        self.seconds, self.calls = 0.0, 0

    def timed(self, hook):
        def timed_hook(*args):
            started = time.perf_counter()
            try:
                return hook(*args)
            finally:
                self.seconds += time.perf_counter() - started
                self.calls += 1
        return timed_hook


def install(hooks: Clock, forces: Clock) -> None:
    """Wrap the engine layer's hook factories, and the stage's force item, so that every hook and every stage
    function handed to Exudyn is timed."""
    from types import SimpleNamespace

    from pchute_exudyn.engine import solver, stage

    items = stage.eii

    def generic(*args, forceUserFunction=None, **kwargs):
        return items.ObjectGenericODE2(*args, forceUserFunction=forces.timed(forceUserFunction), **kwargs)
    stage.eii = SimpleNamespace(**{name: getattr(items, name) for name in dir(items) if not name.startswith("__")})
    stage.eii.ObjectGenericODE2 = generic

    pre, post = solver._pre_step_function, solver._post_step_function

    def timed_pre(*args, **kwargs):
        return hooks.timed(pre(*args, **kwargs))

    def timed_post(*args, **kwargs):
        hook, times, rows = post(*args, **kwargs)
        return hooks.timed(hook), times, rows
    solver._pre_step_function, solver._post_step_function = timed_pre, timed_post


def measure(study: Path, runs: int) -> dict:
    """The study's first ``runs`` draws in this process: per run its solve, its hooks' time and its steps."""
    from pchute_exudyn.study import load_study, run_study

    hooks, forces = Clock(), Clock()
    install(hooks, forces)
    with tempfile.TemporaryDirectory() as folder:
        text = re.sub(r"(?m)^runs = \d+", f"runs = {runs}", study.read_text())
        text = text.replace('"../../cases/', f'"{ROOT / "cases"}/')
        path = Path(folder) / "study.toml"
        path.write_text(text)
        with ThreadPoolExecutor(1) as executor:
            outcome = run_study(load_study(path), Path(folder) / "out", executor, progress=False)
        records = [json.loads(line) for line in (Path(folder) / "out" / "runs.jsonl").read_text().splitlines()]
    ok = [r for r in records if r["status"] == "ok"]
    return {"runs": len(ok), "failed": outcome.failed,
            "solves": sum(r["wall_time"] for r in ok), "whole": sum(r["run_time"] for r in ok),
            "hooks": hooks.seconds, "forces": forces.seconds, "force_calls": forces.calls,
            "steps": sum(r["steps"] for r in ok)}


def report(args, found: dict) -> list:
    n = found["runs"]
    solve, hooks, whole, forces = found["solves"] / n, found["hooks"] / n, found["whole"] / n, found["forces"] / n
    engine = solve - hooks
    calls = found["force_calls"] / found["steps"]
    floor = PROJECTED_RUNS * engine / args.workers
    now = PROJECTED_RUNS * whole / args.workers
    steps = found["steps"] / n
    command = f"python validation/study_floor.py --study {args.study} --runs {args.runs} --workers {args.workers}"
    lines = [f"# The floor of {STUDIES[args.study].relative_to(ROOT)}", "",
             f"`{command}` on this machine ({os.cpu_count()} cores; one process, the runs one after the other, "
             "compiled kernels). Per run, means over the runs:", "",
             "| part | per run (ms) | per step (us) | share of the solve |", "|---|---|---|---|",
             f"| the solve (the record's `wall_time`) | {solve * 1e3:.1f} | {solve / steps * 1e6:.1f} | 100 % |",
             f"| the package's per-step hooks (step control, caps, sampling, watches) | {hooks * 1e3:.1f} | "
             f"{hooks / steps * 1e6:.1f} | {hooks / solve * 100:.0f} % |",
             f"| the rest: Exudyn's RK4 and the stage functions (the forces) | {engine * 1e3:.1f} | "
             f"{engine / steps * 1e6:.1f} | {engine / solve * 100:.0f} % |",
             f"| of which the stage functions ({calls:.1f} calls a step: the compiled kernels and their Python call) | "
             f"{forces * 1e3:.1f} | {forces / steps * 1e6:.1f} | {forces / solve * 100:.0f} % |",
             f"| of which Exudyn's own (RK4, bodies, its calls into Python) | {(engine - forces) * 1e3:.1f} | "
             f"{(engine - forces) / steps * 1e6:.1f} | {(engine - forces) / solve * 100:.0f} % |",
             f"| the whole run in its worker (case, model, solve, outputs: `run_time`) | {whole * 1e3:.1f} | - | - |",
             "", f"Mean steps per run: {steps:.0f} ({found['runs']} runs, {found['failed']} failed).", "",
             f"Projected for {PROJECTED_RUNS} runs on {args.workers} workers: the whole runs {now:.0f} s; the engine "
             f"alone, with no per-step Python, no case loading, no outputs and no study overhead, {floor:.0f} s."]
    if args.study == "pa1" and args.workers == 2:
        lines += ["", f"Issue 58's target, {TARGET:g} s for the 2000-run PA1 study on 2 workers: "
                  + ("below the engine's floor at these steps (" if floor > TARGET else "above the floor (")
                  + f"{floor:.0f} s): " + ("reaching it needs fewer steps (another model or integrator: the "
                  "shipped cases' results would change), not less overhead." if floor > TARGET else
                  "reachable by cutting the per-step Python and the per-run overhead.")]
    return lines


def main(argv=None) -> int:
    args = arguments(argv)
    os.environ.setdefault("PCHUTE_KERNELS", "compiled")
    sys.path.insert(0, str(ROOT))
    from pchute_exudyn.results.io import atomic_write_text

    found = measure(STUDIES[args.study], args.runs)
    if not found["runs"]:
        raise SystemExit("study_floor.py: every run failed")
    lines = report(args, found)
    atomic_write_text(HERE / "output" / f"study_floor_{args.study}.md", "\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    run_script(main)

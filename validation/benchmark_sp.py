"""Speed of the singular-perturbation method against the full-mass model, side by side in one run, and where an SP
stage's time goes.

Run:  python validation/benchmark_sp.py [--repeat 3] [--duration 60] [--budget] [--before DIR]

1. MER case 1 (``--duration`` s) and PA1 (to touchdown): full mass RK4 at the thesis's steps (1e-4 s, 5e-4 s), full
   mass implicit at 1e-2 s, and SP at 1e-2 s with the thesis's settings and with the default (``accurate``)
   preset, each timed ``--repeat`` times in interleaved rounds (median kept: this machine is noisy); speed-ups
   against full RK4 and against full implicit, and each run's accuracy against the full RK4 run.
2. First run on a machine: the whole process of ``pchute run cases/mer/case1.toml --method sp`` with an empty
   numba cache (every kernel compiled) and again with the cache it left.
3. ``--budget``: a sampling profile (py-spy, ``pip install py-spy``) of an MER case 1 SP run, shares turned into
   microseconds per solver stage: Exudyn's own work, the crossings into Python (counted per stage, each priced by
   a model whose user functions do nothing), engine reads, the SP kernel, aerodynamics, the rest of the stage's
   Python, and the per-step hooks; the aerodynamics that run inside the compiled stage kernel are timed apart.
4. ``--before DIR`` (a checkout of the code before, ``git worktree add DIR COMMIT``): DIR profiled the same way for
   the before/after budget, its first run, and SP solve times of both codes side by side (each in its own process,
   interleaved rounds): MER case 1, PA1 with constants, and PA1 with the aerodynamic databases now.

Writes validation/output/benchmark_sp.md (the budget section only with --budget).
"""

from __future__ import annotations

import collections
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from script_arguments import OneLineParser, count, existing_folder, output_file, positive, run_script

HERE = Path(__file__).resolve().parent


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--duration", type=positive, default=60.0, help="MER simulated time in s (default 60)")
    parser.add_argument("--repeat", type=count, default=3, help="interleaved rounds; the median is kept (default 3)")
    parser.add_argument("--budget", action="store_true", help="add the per-stage budget (needs py-spy)")
    parser.add_argument("--before", type=existing_folder, default=None, help="a checkout of the code before, for the budget")
    parser.add_argument("--out", type=output_file, default=str(HERE / "output" / "benchmark_sp.md"))
    args = parser.parse_args(argv)
    if args.budget and shutil.which("py-spy") is None:
        parser.refuse("--budget: py-spy is not installed (pip install py-spy)")
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.results.compare import compare_results
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions

ROOT = HERE.parent
MER = ROOT / "cases" / "mer" / "case1.toml"
PA1 = ROOT / "cases" / "cev_pa1.toml"
FULL_OPEN = 27.5   # s: PA1's mains at full drag area (validation/cev_pa1.py)
THESIS = {"preset": "thesis"}
THESIS_PA1 = {"preset": "thesis", "order": 0}   # the PA1 case asks for order 1 itself


def runs_of(case_name: str) -> list:
    """(label, method, integrator, step, SP options) of one case's comparison, the reference first."""
    full_step = 1e-4 if case_name == "mer" else 5e-4
    thesis = THESIS if case_name == "mer" else THESIS_PA1
    return [(f"full rk4 {full_step:g}", "full", "rk4", full_step, {}),
            ("full implicit 0.01", "full", "implicit", 1e-2, {}),
            ("sp thesis 0.01", "sp", "rk4", 1e-2, thesis),
            ("sp accurate 0.01", "sp", "rk4", 1e-2, {"preset": "accurate", "order": 1, "kappa_max": 10.0}),
            ("sp accurate 0.02", "sp", "rk4", 2e-2, {"preset": "accurate", "order": 1, "kappa_max": 10.0})]


def timed_rounds(cases: dict, repeat: int, duration: float) -> dict:
    """Every run of every case, ``repeat`` interleaved rounds; (case, label) -> (results of the last round, walls)."""
    out = {}
    for _ in range(repeat):
        for name, case in cases.items():
            for label, method, integrator, step, options in runs_of(name):
                result = pc.simulate(case, method, integrator, step, duration if name == "mer" else None,
                                     **options)
                previous = out.get((name, label), (None, []))[1]
                out[(name, label)] = (result, [*previous, result.summary.wall_time])
                print(f"  {name} {label:22s} {result.summary.wall_time:7.3f} s", flush=True)
    return out


def attitude_difference(reference, result) -> float:
    """Largest capsule attitude-angle difference (deg) after the mains are fully open."""
    m = (reference.time > FULL_OPEN) & (reference.time <= min(reference.time[-1], result.time[-1]))
    return max(float(np.abs(np.interp(reference.time[m], result.time, result[c]) - reference[c][m]).max())
               for c in ("capsule_yaw_deg", "capsule_pitch_deg", "capsule_roll_deg"))


def speed_table(name: str, timed: dict) -> list:
    labels = [run[0] for run in runs_of(name)]
    reference, ref_walls = timed[(name, labels[0])]
    implicit = statistics.median(timed[(name, "full implicit 0.01")][1])
    ref_wall = statistics.median(ref_walls)
    vehicle = "vehicle" if name == "mer" else "capsule"
    head = ("| run | wall time (s), median | steps | speed-up over full RK4 | speed-up over full implicit 1e-2 | "
            + ("final altitude diff (m) | max tension diff after 2 s (N) |" if name == "mer" else
               "touchdown time diff (s) | max capsule attitude diff after 27.5 s (deg) | max tension diff after "
               "27.5 s (N) |"))
    rows = [head, "|---|---|---|---|---|---|---|"]
    for label in labels:
        result, walls = timed[(name, label)]
        wall = statistics.median(walls)
        if name == "mer":
            tension = max(m["max_settled"] for m in compare_results(reference, result, settle_time=2.0).lines.values())
            accuracy = (f"{result.final('vehicle_altitude') - reference.final('vehicle_altitude'):+.3f} | "
                        f"{tension:.3g}")
        else:
            c = compare_results(reference, result, settle_time=FULL_OPEN, vehicle=vehicle,
                                confluence="main_confluence")
            tension = max(m["max_settled"] for m in c.lines.values() if math.isfinite(m["max_settled"]))
            accuracy = (f"{result.time[-1] - reference.time[-1]:+.3f} | {attitude_difference(reference, result):.3f}"
                        f" | {tension:.3g}")
        rows.append(f"| {name} {label} | {wall:.3f} | {result.summary.steps} | {ref_wall / wall:.1f}x | "
                    f"{implicit / wall:.2f}x | {accuracy} |")
    return rows


def _whole_process(env: dict, out: Path, checkout: Path = ROOT) -> float:
    started = time.perf_counter()
    subprocess.run([sys.executable, "-m", "pchute_exudyn", "run", str(checkout / "cases" / "mer" / "case1.toml"),
                    "--method", "sp", "--out", str(out)], env=env, check=True, capture_output=True, cwd=checkout)
    return time.perf_counter() - started


def first_run(before: Path | None) -> list:
    """Whole-process time of ``pchute run`` on MER case 1 with SP: where the kernel folder holds no compiled module
    of this source (the Python form runs while a background process builds the module), after that build, and
    with the jit form compiling every kernel in the run itself; with ``before``, the same command on that
    checkout."""
    folder = Path(tempfile.mkdtemp(prefix="pchute-first-run-"))
    base = {k: v for k, v in os.environ.items() if not k.startswith("PCHUTE_KERNEL")}
    try:
        auto = {**base, "PCHUTE_KERNEL_DIR": str(folder / "kernels")}
        first = _whole_process(auto, folder / "first")
        deadline = time.monotonic() + 300.0
        while not list((folder / "kernels").glob("kernels_*.json")) and time.monotonic() < deadline:
            time.sleep(0.5)
        later = statistics.median(_whole_process(auto, folder / f"later{i}") for i in range(3))
        forced = _whole_process({**base, "NUMBA_CACHE_DIR": str(folder / "forced"), "PCHUTE_KERNELS": "jit"},
                                folder / "forced_run")
        old = None if before is None else statistics.median(
            _whole_process({**base, "PYTHONPATH": str(before)}, folder / f"before{i}", before) for i in range(3))
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    rows = ["| `pchute run cases/mer/case1.toml --method sp`, whole process | wall time (s) |", "|---|---|",
            f"| first run without a compiled module of this source (an edited kernel; the Python form runs while a "
            f"background process builds the module) | {first:.2f} |",
            f"| later runs (the compiled module; median of 3) | {later:.2f} |",
            f"| a run that compiles every kernel itself (PCHUTE_KERNELS=jit, empty numba cache) | {forced:.2f} |"]
    if old is not None:
        rows.append(f"| the code before ({commit_of(before)}), same command (median of 3) | {old:.2f} |")
    return rows + ["", "A fresh install builds the module (`setup.py`): its first run is a later run "
                   "(`validation/startup_budget.py`).", "",
                   f"numba and llvmlite installed: {installed_megabytes():.0f} MB."]


def installed_megabytes() -> float:
    """Disk size (MB) of the installed numba and llvmlite packages."""
    import importlib.util
    total = 0
    for name in ("numba", "llvmlite"):
        folder = Path(importlib.util.find_spec(name).origin).parent
        total += sum(f.stat().st_size for f in folder.rglob("*") if f.is_file())
    return total / 1e6


# -- the per-stage budget ---------------------------------------------------------------------------------------------

CATEGORIES = [  # (label, function names as py-spy reports them; the first listed category of a stack wins)
    ("engine reads of the state", ("Stage.refresh", "BodySnapshot.refresh", "GetMarkerOutput", "GetNodeOutput")),
    ("SP kernel and its glue", ("SPConfluence.stage_solve", "SPConfluence.stage_solve_with_bodies",
                                "fused_force", "SPConfluence.settled_by_stage",
                                "SPConfluence.advance", "SPConfluence.settle", "SPConfluence._settled",
                                "SPConfluence.sample", "SPConfluence.compute", "confluence_velocity",
                                "ReducedConfluence.solve", "ReducedConfluence._rhs")),
    ("aerodynamics, Python side (before: all of it; now: the drag-area schedules and any retry)",
     ("BodyAerodynamics.force", "aerodynamic_load", "AerodynamicLoads.apply", "AerodynamicLoads.apply_after",
      "AerodynamicLoads.schedule")),
    ("stage force item: kinematics kernels, sums (Python side)", ("Stage.force",)),
    ("post-step: outputs, v0 update", ("post_step",)),
    ("pre-step: step monitor, NaN check", ("pre_step",)),
]
WORKLOAD = ("import pchute_exudyn as pc; case = pc.load_case({case!r}); pc.simulate(case, 'sp', 'rk4', 1e-2, 5.0)\n"
            "for _ in range(4): print('WALL', pc.simulate(case, 'sp', 'rk4', 1e-2, {duration}).summary.wall_time)")


def profile(checkout: Path, duration: float) -> tuple[dict, float, int]:
    """py-spy samples of SP runs of MER case 1 with the package in ``checkout`` (run from there, so that it is the
    package imported): category -> share of the solve, the median wall time of the same runs without the profiler
    and the steps of a run."""
    raw = Path(tempfile.mkdtemp(prefix="pchute-spy-")) / "raw.txt"
    script = WORKLOAD.format(case=str(checkout / "cases" / "mer" / "case1.toml"), duration=duration)
    env = {**os.environ, "PYTHONPATH": str(checkout)}
    plain = subprocess.run([sys.executable, "-c", script], env=env, cwd=checkout, capture_output=True, text=True,
                           check=True)
    walls = [float(line.split()[1]) for line in plain.stdout.splitlines() if line.startswith("WALL ")]
    subprocess.run(["py-spy", "record", "-r", "1000", "-f", "raw", "-o", str(raw), "--", sys.executable, "-c",
                    script], env=env, cwd=checkout, capture_output=True, text=True, check=True)
    counts, total = collections.Counter(), 0
    for line in raw.read_text().splitlines():
        stack, n = line.rsplit(" ", 1)
        frames = [f.split(" (")[0] for f in stack.split(";")]
        if not any(f == "_solve" for f in frames) or "_compile_for_args" in stack:
            continue
        total += int(n)
        counts[_category(frames)] += int(n)
    shutil.rmtree(raw.parent, ignore_errors=True)
    steps = round(duration / 1e-2)
    return {k: v / total for k, v in counts.items()}, statistics.median(walls), steps


def _category(frames: list) -> str:
    for label, names in CATEGORIES:
        if any(f.endswith(name) or f.split(".")[-1] == name for f in frames for name in names):
            return label
    return "Exudyn: its own work and the crossings"


def crossing_cost() -> float:
    """Microseconds per crossing from the engine into a Python user function that does nothing (a generic ODE2
    force over two rigid bodies, RK4): measured against the same model without it."""
    import exudyn as exu
    import exudyn.itemInterface as eii

    def solve(with_function: bool) -> float:
        mbs = exu.SystemContainer().AddSystem()
        nodes = []
        for k in range(2):
            node = mbs.AddNode(eii.NodeRigidBodyRotVecLG(referenceCoordinates=[0, 0, 10 * k, 0.1, 0.2, 0.3]))
            mbs.AddObject(eii.ObjectRigidBody(nodeNumber=node, mass=10, inertia=[1, 2, 3, 0, 0, 0]))
            nodes.append(node)
        forces = np.zeros(12)
        if with_function:
            mbs.AddObject(eii.ObjectGenericODE2(nodeNumbers=nodes, forceUserFunction=lambda *args: forces))
        mbs.Assemble()
        settings = exu.SimulationSettings()
        settings.timeIntegration.numberOfSteps, settings.timeIntegration.endTime = 20000, 1.0
        settings.timeIntegration.explicit.computeEndOfStepAccelerations = False
        settings.solution.file.write, settings.solution.sensors.active = False, False
        settings.timeIntegration.verboseMode = 0
        console, exu.config.printToConsole = exu.config.printToConsole, False
        started = time.perf_counter()
        mbs.SolveDynamic(settings, solverType=exu.DynamicSolverType.RK44, showHints=False)
        wall = time.perf_counter() - started
        exu.config.printToConsole = console
        return wall
    base = min(solve(False) for _ in range(3))
    return (min(solve(True) for _ in range(3)) - base) / (20000 * 4) * 1e6


CROSSINGS = ("1 (the stage force item) + 0.5 (the pre- and post-step hooks, per step / 4) before; 1 + 0.25 now (an "
             "RK4 run without pre-step hooks has no pre-step call)")
CROSSING_COUNT = {"before": 1.5, "after": 1.25}


def aerodynamics_in_kernel() -> float:
    """Microseconds per stage of MER case 1's aerodynamics as the fused stage kernel runs them
    (``physics.aerodynamics.aerodynamics_stage``: py-spy sees no further into the compiled call than the SP kernel
    that makes it): the kernel on the model's own packed arguments, called 200 000 times from a compiled loop (in a
    process of its own running the jit form: a compiled loop calls the kernel as numba compiles it)."""
    from pchute_exudyn.physics.compiled import MODE
    if MODE != "jit":
        done = subprocess.run([sys.executable, "-c", "import sys; sys.path.insert(0, sys.argv[1]); import benchmark_sp; "
                               "print(benchmark_sp.aerodynamics_in_kernel())", str(HERE)], check=True,
                              capture_output=True, text=True, env={**os.environ, "PCHUTE_KERNELS": "jit"})
        return float(done.stdout.strip().splitlines()[-1])
    import numba

    from pchute_exudyn.engine.solver import integrate
    from pchute_exudyn.methods.sp import SingularPerturbation
    from pchute_exudyn.physics.aerodynamics import aerodynamics_stage
    from pchute_exudyn.run.phases import initial_phase

    case = pc.load_case(MER)
    model = SingularPerturbation().build(case, initial_phase(case))
    integrate(model, "rk4", 1e-2, 1.0, 0.1)
    loads, stage = model.stage.loads, model.stage
    data, field, work = loads.parts
    generalized = np.zeros_like(stage.generalized)

    @numba.njit
    def loop(count, t, states, data, field, work, generalized):
        for i in range(count):
            aerodynamics_stage(t + i * 1e-9, states, data, field, work, generalized)

    loop(10, 1.0, stage.states, data, field, work, generalized)
    best = math.inf
    for _ in range(5):
        started = time.perf_counter()
        loop(200000, 1.0, stage.states, data, field, work, generalized)
        best = min(best, (time.perf_counter() - started) / 200000 * 1e6)
    return best


def budget(duration: float, before: Path | None) -> list:
    cost = crossing_cost()
    in_kernel = aerodynamics_in_kernel()
    profiles = {"after": profile(ROOT, duration)}
    if before is not None:
        profiles["before"] = profile(before, duration)
    order = [k for k in ("before", "after") if k in profiles]
    rows = ["| per RK4 stage (us) | " + " | ".join(order) + " |", "|---|" + "---|" * len(order)]
    per_stage = {k: wall / (steps * 4) * 1e6 for k, (_, wall, steps) in profiles.items()}
    aero_label = CATEGORIES[2][0]
    for label in ["Exudyn: its own work and the crossings"] + [label for label, _ in CATEGORIES]:
        cells = [f"{profiles[k][0].get(label, 0.0) * per_stage[k]:.1f}" for k in order]
        rows.append(f"| {label} | " + " | ".join(cells) + " |")
        if label.startswith("Exudyn"):
            rows.append(f"| - of which crossings, estimated (count x {cost:.2f} us, an empty force user function) | "
                        + " | ".join(f"{CROSSING_COUNT[k] * cost:.1f}" for k in order) + " |")
        if label.startswith("SP kernel"):
            rows.append("| - of which the aerodynamics inside the fused stage kernel (timed apart: "
                        "`aerodynamics_in_kernel`) | " + " | ".join("-" if k == "before" else f"{in_kernel:.2f}"
                                                                    for k in order) + " |")
    totals = {k: profiles[k][0].get(aero_label, 0.0) * per_stage[k] + (in_kernel if k == "after" else 0.0)
              for k in order}
    rows.append("| **aerodynamics in all** (Python side + inside the kernel) | "
                + " | ".join(f"**{totals[k]:.2f}**" for k in order) + " |")
    rows.append("| **total per stage** (wall time / 4 steps) | " + " | ".join(f"**{per_stage[k]:.1f}**"
                                                                           for k in order) + " |")
    notes = [f"Crossings per stage: {CROSSINGS}. The estimate prices every crossing like the generic-object force "
             "call (Exudyn's sampled share can come out below it). The aerodynamics run inside the SP "
             "kernel's call now (one compiled call per stage for the kinematics, the SP solve and every body's "
             "load), so their cost is timed apart on the model's own arguments and shown under the SP kernel; "
             "the Python side is what stays in Python (MER has no drag-area schedule: nothing)."]
    return rows + [""] + notes


BEFORE_SCRIPT = """
import time, sys
import pchute_exudyn as pc
cases = [(label, pc.load_case(path)) for label, path in {cases!r}]
for label, case in cases:   # load the compiled kernels first
    pc.simulate(case, "sp", "rk4", 1e-2, 1.0)
for label, case in cases:
    duration = {duration} if label.startswith("mer") else None
    print(f"WALL|{{label}}|{{pc.simulate(case, 'sp', 'rk4', 1e-2, duration).summary.wall_time}}", flush=True)
"""


def against_before(before: Path, repeat: int, duration: float) -> list:
    """SP solve times of this code and of the checkout ``before``, each in its own process (the package imported
    from its folder), in ``repeat`` interleaved rounds: MER case 1 (``duration`` s) and PA1 with constants, and
    PA1 with the aerodynamic databases here."""
    runs = {"before": [("mer", before / "cases" / "mer" / "case1.toml"), ("pa1", before / "cases" / "cev_pa1.toml")],
            "now": [("mer", MER), ("pa1", PA1), ("pa1 aero", ROOT / "cases" / "cev_pa1_aero.toml")]}
    walls: dict = {}
    for _ in range(repeat):
        for side, checkout in (("before", before), ("now", ROOT)):
            script = BEFORE_SCRIPT.format(cases=[(label, str(path)) for label, path in runs[side]], duration=duration)
            env = {**os.environ, "PYTHONPATH": str(checkout), "PCHUTE_KERNELS": "compiled"}
            done = subprocess.run([sys.executable, "-c", script], env=env, cwd=checkout, capture_output=True,
                                  text=True, check=True)
            for line in done.stdout.splitlines():
                if line.startswith("WALL|"):
                    _, label, wall = line.split("|")
                    walls.setdefault((side, label), []).append(float(wall))
    median = {key: statistics.median(values) for key, values in walls.items()}
    rows = ["| SP at 1e-2 s | before (s) | now (s) | before / now |", "|---|---|---|---|"]
    for label, now_key, before_key in ((f"MER case 1, {duration:g} s", "mer", "mer"),
                                       ("PA1 to touchdown, constant coefficients (cev_pa1.toml)", "pa1", "pa1"),
                                       ("PA1 with the aerodynamic databases (cev_pa1_aero.toml) now, against PA1 "
                                        "with constants before", "pa1 aero", "pa1")):
        old, new = median[("before", before_key)], median[("now", now_key)]
        rows.append(f"| {label} | {old:.3f} | {new:.3f} | {old / new:.2f}x |")
    return rows


def commit_of(checkout: Path) -> str:
    done = subprocess.run(["git", "-C", str(checkout), "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True)
    return done.stdout.strip() or checkout.name


def main(argv=None) -> None:
    args = arguments(argv)
    cases = {"mer": pc.load_case(MER), "pa1": pc.load_case(PA1)}
    budget_rows = []
    if args.budget:   # first: it needs py-spy, and should fail before the long timings
        budget_rows = budget(min(args.duration, 20.0), args.before)
    for case in cases.values():   # load the compiled kernels before any timing
        pc.simulate(case, "sp", "rk4", 1e-2, 1.0)
    timed = timed_rounds(cases, max(1, args.repeat), args.duration)
    before_rows = [] if args.before is None else against_before(args.before, max(1, args.repeat), args.duration)
    v = versions()
    text = ["# Singular perturbation against full mass: speed, side by side",
            "",
            f"`python validation/benchmark_sp.py --repeat {args.repeat}{' --budget' if args.budget else ''}` (one "
            f"process, {args.repeat} interleaved rounds, medians). Exudyn {v['exudyn']}, pchute-exudyn "
            f"{v['pchute_exudyn']}, Python {v['python']}, {v['platform']}. Accuracy against the full-mass RK4 run "
            "of the same case. `sp thesis`: kappa_max 5, massless (order 0); `sp accurate`: the default preset, "
            "kappa_max 10, the confluence mass to first order.",
            "",
            f"## MER case 1, {args.duration:g} s", "", *speed_table("mer", timed), "",
            "## PA1 (Orion pad abort), to touchdown", "", *speed_table("pa1", timed), "",
            "## First run", "", *first_run(args.before), ""]
    if before_rows:
        text += [f"## Against the code before ({commit_of(args.before)})", "",
                 f"SP solve times (`wall_time`), each code in its own process with compiled kernels, {args.repeat} "
                 "interleaved rounds, medians. The databases run compiled in the same stage call as the "
                 "constants.", "", *before_rows, ""]
    if args.budget:
        text += ["## Where an SP stage's time goes (MER case 1, SP at 1e-2 s)", "",
                 "py-spy samples of four SP runs of 20 s (shares of the solve), turned into microseconds per RK4 "
                 "stage with the median wall time of the same runs without the profiler; the crossings priced by a "
                 "model whose force user function returns a constant (`crossing_cost`), shown under Exudyn's "
                 "share. A sample counts in the first category of its stack, in the order listed. `--before DIR`: "
                 f"a checkout of commit {commit_of(args.before) if args.before else '-'}, the code before "
                 "(`git worktree add DIR COMMIT`).", "",
                 *budget_rows, ""]
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, "\n".join(text))
    print("\n".join(text))


if __name__ == "__main__":
    run_script(main)

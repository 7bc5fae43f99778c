"""How fast a run is around its solve: a warm `pchute run`, where its time goes, and the first runs after a fresh
install, side by side with the code before.

Run:  python validation/startup_budget.py [--repeat 5] [--before DIR] [--no-install]

1. Warm runs: the whole process of ``pchute run cases/mer/case1.toml --method sp --no-plot`` (MER case 1, 60 s, SP
   at 1e-2 s; the process's wall time, interpreter start and exit included) against the solve it reports
   (summary.json ``wall_time``; process / solve: the median of each run's own ratio, which a machine's load
   moves less), and the same with the overview figure; with ``--before DIR`` (a checkout of the
   code before, ``git worktree add DIR COMMIT``, its kernels compiled and cached first) the same commands with that
   code, in interleaved rounds (medians); and the whole process of ``pchute --help`` in the same rounds.
2. Where a warm process's time goes: one run with each part timed (no profiler): interpreter start and exit, the
   package's imports, loading the compiled kernel module, the case, the model, the step-limit checks, the solve,
   the outputs and summary, each result file.
3. A fresh install (unless ``--no-install``, which keeps the earlier report's section, marked as kept): a copy of
   this code's files in a new folder, a new virtual environment, the README's install command (pip's download
   cache kept, every cache of ours empty: kernel folder, bytecode, numba's and matplotlib's caches); then the
   first and a later run of the 440-s single-canopy descent (cases/simple/descent_440s.toml) and of MER case 1
   with SP, with the figure (the plain command) and without.
   With ``--before DIR``, the same for that code.

Writes validation/output/startup_budget.md.
"""

from __future__ import annotations

import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from script_arguments import OneLineParser, count, existing_folder, run_script


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--repeat", type=count, default=5)
    parser.add_argument("--before", type=existing_folder, default=None, help="checkout of the code before")
    parser.add_argument("--no-install", action="store_true", help="skip the fresh-install section")
    args = parser.parse_args(argv)
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "output" / "startup_budget.md"
MER = Path("cases") / "mer" / "case1.toml"
LONG = Path("cases") / "simple" / "descent_440s.toml"
INSTALL = 'python -m pip install -e ".[test]"'   # the README quick start's (checked below)

TIMED = r"""
import os, sys, time
started = time.perf_counter()
parts = {}
def timed(module, name, label):
    function = getattr(module, name)
    def wrapper(*args, **kwargs):
        begun = time.perf_counter()
        try:
            return function(*args, **kwargs)
        finally:
            parts[label] = parts.get(label, 0.0) + time.perf_counter() - begun
    setattr(module, name, wrapper)
import numpy
numpy_loaded = time.perf_counter()
import pchute_exudyn
package_loaded = time.perf_counter()
import pchute_exudyn.cli as cli
import pchute_exudyn.engine.solver as solver, pchute_exudyn.run.simulation as simulation, pchute_exudyn.results.result as results
import pchute_exudyn.boundary as boundary, pchute_exudyn.methods.sp as sp
imported = time.perf_counter()
timed(boundary, "load_case", "loading the case file")   # the command's (the API's checked load_case)
timed(sp.SingularPerturbation, "build", "building the Exudyn model")
timed(simulation, "add_step_monitor", "step-limit check before the run")
timed(solver, "_solve", "solve (Exudyn's SolveDynamic, the stage kernels inside)")
for name in ("derive_columns", "cluster_columns", "pendulum_columns", "summarize", "check_history", "concatenate"):
    timed(simulation, name, "outputs, checks and summary")
timed(results, "table_text", "formatting timeseries.csv")
timed(results, "atomic_write_text", "writing timeseries.csv and summary.json")
timed(numpy, "savez", "writing result.npz")
if os.environ.get("TIMED_FIGURE"):   # the figure process, started as the command starts it (cli.command)
    import pchute_exudyn.views.figure_process as figure_process
    timed(figure_process.FigureProcess, "draw", "waiting for the figure process to draw overview.png")
    cli._entry["figure"] = figure_process.FigureProcess()
code = cli.main(sys.argv[1:])
ended = time.perf_counter()
import json
print("PARTS" + json.dumps({"importing numpy": numpy_loaded - started,
                           "importing pchute_exudyn (the case layer; choosing and loading the kernel module)":
                               package_loaded - numpy_loaded,
                           "importing the engine, Exudyn, the command line and the simulation layer":
                               imported - package_loaded,
                           "main": ended - imported, **parts}), flush=True)
os._exit(code)   # as the command does (pchute_exudyn.cli.command)
"""
MODULE_LOAD = ("import os, time; os.environ['PCHUTE_KERNELS'] = 'python'; import pchute_exudyn.kernels.selection as k; "
               "t = time.perf_counter(); assert k.load_compiled() is not None; print(time.perf_counter() - t)")


def environment(extra: dict | None = None, code: Path | None = None) -> dict:
    """The processes' environment: this one's, less the kernel choice and ``PYTHONDONTWRITEBYTECODE`` (a warm run
    reads the modules' bytecode from ``__pycache__`` as a user's second run does; with the variable set, as in some
    sandboxes, every run compiles the package's 300 modules again, 0.3 s of a 1 s run)."""
    base = {k: v for k, v in os.environ.items()
            if not k.startswith("PCHUTE_KERNEL") and k != "PYTHONDONTWRITEBYTECODE"}
    if code is not None:   # the code before, imported from its checkout with its compiled (numba) kernels
        base.update(PYTHONPATH=str(code), PCHUTE_KERNELS="compiled")
    return {**base, **(extra or {})}


def run_process(python: str, code: Path, case: Path, arguments: list, env: dict) -> tuple[float, float]:
    """(whole-process wall time, reported solve time) of one ``pchute run``, s."""
    with tempfile.TemporaryDirectory() as folder:
        started = time.perf_counter()
        subprocess.run([python, "-m", "pchute_exudyn", "run", str(code / case), "--method", "sp", "--quiet",
                        "--out", f"{folder}/r", *arguments], check=True, capture_output=True, cwd=code, env=env)
        wall = time.perf_counter() - started
        solve = json.loads(Path(f"{folder}/r/summary.json").read_text())["wall_time"]
    return wall, solve


def help_process(code: Path, env: dict) -> float:
    """The whole-process wall time of ``pchute --help`` (s)."""
    started = time.perf_counter()
    subprocess.run([sys.executable, "-m", "pchute_exudyn", "--help"], check=True, capture_output=True, cwd=code,
                   env=env)
    return time.perf_counter() - started


def warm_rounds(repeat: int, before: Path | None) -> dict:
    """{(side, figure): [(wall, solve)], (side, "help"): [wall]} over ``repeat`` interleaved rounds, each side
    warmed first."""
    sides = {"now": (ROOT, environment())}
    if before is not None:
        sides["before"] = (before, environment(code=before))
    for code, env in sides.values():
        run_process(sys.executable, code, MER, ["--no-plot"], env)
        run_process(sys.executable, code, MER, [], env)
    found: dict = {}
    for _ in range(repeat):
        for side, (code, env) in sides.items():
            for figure in (False, True):
                found.setdefault((side, figure), []).append(
                    run_process(sys.executable, code, MER, [] if figure else ["--no-plot"], env))
            found.setdefault((side, "help"), []).append(help_process(code, env))
    return found


def budget(figure: bool) -> dict:
    """The timed parts of one warm run in a fresh process (s), and its whole wall time."""
    with tempfile.TemporaryDirectory() as folder:
        started = time.perf_counter()
        done = subprocess.run([sys.executable, "-c", TIMED, "run", str(ROOT / MER), "--method", "sp", "--quiet",
                               "--out", f"{folder}/r"] + ([] if figure else ["--no-plot"]), check=True,
                              capture_output=True, text=True, cwd=ROOT,
                              env=environment({"TIMED_FIGURE": "1"} if figure else {}))
        wall = time.perf_counter() - started
    parts = json.loads(next(line for line in done.stdout.splitlines() if line.startswith("PARTS"))[5:])
    module = subprocess.run([sys.executable, "-c", MODULE_LOAD], check=True, capture_output=True, text=True,
                            cwd=ROOT, env=environment())
    return {"wall": wall, **parts, "module": float(module.stdout.strip())}


def _median(pairs, index):
    return statistics.median(pair[index] for pair in pairs)


def warm_section(rounds: dict, repeat: int, before: Path | None) -> list:
    lines = ["| code | whole process, no figure (s) | its solve (s) | process / solve | with the figure (s) | "
             "the figure adds (s) | `pchute --help` (s) |", "|---|---|---|---|---|---|---|"]
    for side in ("before", "now"):
        if (side, False) not in rounds:
            continue
        plain, plotted = rounds[(side, False)], rounds[(side, True)]
        wall, solve, with_figure = _median(plain, 0), _median(plain, 1), _median(plotted, 0)
        label = f"before ({commit_of(before)})" if side == "before" else f"now ({commit_of(ROOT)})"
        ratio = statistics.median(process / solved for process, solved in plain)   # each round's own: a load shared
        lines.append(f"| {label} | {wall:.3f} | {solve:.3f} | {ratio:.2f}x | {with_figure:.3f} | "
                     f"{with_figure - wall:.3f} | {statistics.median(rounds[(side, 'help')]):.3f} |")
    return lines


def budget_section(parts: dict) -> list:
    parts = dict(parts)
    wall, main, module = parts.pop("wall"), parts.pop("main"), parts.pop("module")
    imports = [key for key in parts if key.startswith("importing") and key != "importing matplotlib"]
    timed = sum(value for key, value in parts.items() if key not in imports)
    interpreter = wall - main - sum(parts[key] for key in imports)
    rows = [f"| {name} | {value:.3f} |" for name, value in parts.items()]
    rows += [f"| the rest of the command (arguments, the run's plan, phases, the solver's set-up, printing) | "
             f"{main - timed:.3f} |",
             f"| interpreter start and exit | {interpreter:.3f} |",
             f"| **whole process** | **{wall:.3f}** |",
             f"| of the imports: loading the compiled kernel module (its source key, table and extension; a "
             f"process of its own) | {module:.4f} |"]
    return ["| part | seconds |", "|---|---|", *rows]


# -- a fresh install ---------------------------------------------------------------------------------------------------

def copy_of(code: Path, target: Path) -> Path:
    """The files git knows in ``code`` (committed or not, ignored ones left out) copied to ``target``."""
    listed = subprocess.run(["git", "-C", str(code), "ls-files", "-co", "--exclude-standard", "-z"],
                            capture_output=True, check=True).stdout.decode().split("\0")
    for name in filter(None, listed):
        source = code / name
        if source.is_file():
            (target / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target / name)
    return target


def fresh_install(code: Path, folder: Path, cases: list) -> dict:
    """Install ``code`` as the README says into a new venv in ``folder`` and time its first and later runs."""
    tree = copy_of(code, folder / "code")
    subprocess.run([sys.executable, "-m", "venv", str(folder / "venv")], check=True)
    python = str(folder / "venv" / "bin" / "python")
    caches = {"XDG_CACHE_HOME": str(folder / "cache"), "NUMBA_CACHE_DIR": str(folder / "numba"),
              "MPLCONFIGDIR": str(folder / "matplotlib")}
    env = {**{k: v for k, v in os.environ.items()
              if not k.startswith(("PCHUTE_", "PYTHONPATH", "VIRTUAL_ENV", "PYTHONDONTWRITEBYTECODE"))},
           "PATH": f"{folder / 'venv' / 'bin'}:{os.environ['PATH']}", **caches}
    subprocess.run([python, "-m", "pip", "install", "--quiet", "--upgrade", "pip"], check=True, env=env)
    started = time.perf_counter()
    subprocess.run(INSTALL.replace("python", python, 1), shell=True, check=True, cwd=tree, env=env,
                   capture_output=True)
    found = {"install": time.perf_counter() - started}
    for case, arguments, label in cases:
        if not (tree / case).is_file():
            continue
        first = run_process(python, tree, case, arguments, env)
        time.sleep(1.0)   # a background build (the code before) gets its chance; later runs take the median
        later = [run_process(python, tree, case, arguments, env) for _ in range(3)]
        found[label] = (first, (_median(later, 0), _median(later, 1)))
    return found


def install_section(results: dict) -> list:
    lines = ["| code | run | first run after the install (s) | later runs (s, median of 3) | first / later | "
             "first run's solve (s) |", "|---|---|---|---|---|---|"]
    for side, found in results.items():
        for label, times in found.items():
            if label == "install":
                continue
            first, later = times
            lines.append(f"| {side} | {label} | {first[0]:.2f} | {later[0]:.2f} | {first[0] / later[0]:.2f}x | "
                         f"{first[1]:.2f} |")
    lines += [""] + [f"Install command took {found['install']:.0f} s ({side})." for side, found in results.items()]
    return lines


INSTALL_HEADING = "## The first runs after a fresh install"
KEPT = " (kept from an earlier report: this one ran with --no-install)"


def kept_install_section(text: str) -> list:
    """The fresh-install section of an earlier report, marked as kept (``--no-install`` keeps it); [] if none."""
    if INSTALL_HEADING not in text:
        return []
    section = text[text.index(INSTALL_HEADING):].rstrip("\n").splitlines()
    return [INSTALL_HEADING + KEPT, *section[1:], ""]


def commit_of(code: Path | None) -> str:
    if code is None:
        return "-"
    found = subprocess.run(["git", "-C", str(code), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    dirty = subprocess.run(["git", "-C", str(code), "status", "--porcelain", "--untracked-files=no", "--", ".",
                            ":(exclude)validation/output"], capture_output=True, text=True).stdout.strip()
    return (found.stdout.strip() or "?") + (" with uncommitted changes" if dirty else "")


def main(argv=None) -> int:
    args = arguments(argv)
    earlier = OUT.read_text() if OUT.is_file() else ""
    readme = (ROOT / "README.md").read_text()
    if INSTALL not in readme:
        raise SystemExit(f"the README's install command is no longer {INSTALL}")
    if args.before is not None:   # the code before: its kernels compiled into numba's cache first
        subprocess.run([sys.executable, "-m", "pchute_exudyn.kernels.build"], env=environment(code=args.before),
                       cwd=args.before, check=True, capture_output=True)
    rounds = warm_rounds(args.repeat, args.before)
    parts = budget(figure=False)
    figure = budget(figure=True)
    lines = ["# How fast a run is around its solve", "",
             f"`python validation/startup_budget.py --repeat {args.repeat}"
             f"{' --before DIR' if args.before else ''}{' --no-install' if args.no_install else ''}` on this "
             f"machine ({os.cpu_count()} cores), code {commit_of(ROOT)}. Wall times of whole processes "
             "(interpreter start and exit included), medians of interleaved rounds.", "",
             "## A warm `pchute run cases/mer/case1.toml --method sp`", "",
             "Kernels compiled and loaded as each code does it (now: the compiled module; before: numba's cache); "
             "files in the page cache.", "", *warm_section(rounds, args.repeat, args.before), "",
             "## Where a warm run's time goes (one run of each, each part timed, no profiler)", "",
             "Without the figure (`--no-plot`):", "", *budget_section(parts), "",
             "With the figure:", "", *budget_section(figure), ""]
    if not args.no_install:
        results = {}
        cases = [(MER, ["--method", "full", "--integrator", "rk4"], "the README's first run (MER case 1, full mass, "
                  "RK4 1e-4 s, with the figure)"),
                 (LONG, [], "440-s descent (descent_440s.toml), with the figure"),
                 (LONG, ["--no-plot"], "440-s descent, --no-plot"),
                 (MER, [], "MER case 1 SP, with the figure"), (MER, ["--no-plot"], "MER case 1 SP, --no-plot")]
        for side, code in (("before", args.before), ("now", ROOT)):
            if code is None:
                continue
            with tempfile.TemporaryDirectory(prefix="pchute-fresh-") as folder:
                label = f"{side} ({commit_of(code)})"
                before_cases = cases if side == "now" else \
                    [(c if c != LONG else _long_case(Path(folder)), a, n) for c, a, n in cases]
                results[label] = fresh_install(code, Path(folder), before_cases)
        lines += [INSTALL_HEADING, "",
                  f"A new virtual environment and the README's install command (`{INSTALL}`) on a copy of the "
                  "code's files; empty kernel folder, bytecode, numba and matplotlib caches (pip's download cache "
                  "kept). The code before has no 440-s case file: the same file is copied into its tree.", "",
                  *install_section(results), ""]
    else:
        lines += kept_install_section(earlier)
    from pchute_exudyn.results.io import atomic_write_text

    atomic_write_text(OUT, "\n".join(lines))
    print("\n".join(lines))
    return 0


def _long_case(folder: Path) -> Path:
    """The 440-s case copied into the code before's tree (it has none): the path relative to its tree."""
    target = folder / "code" / LONG
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy2(ROOT / LONG, target)
    return LONG


if __name__ == "__main__":
    run_script(main)

"""Regression check across versions: run a fixed set of configurations with one source tree and compare every column
of their results with another's.

Run:  python validation/regression.py run OUT [--source TREE]     # TREE: a checkout of any version (default: this)
      python validation/regression.py compare A B                 # A, B: two OUT folders

The runs go through the command line (``python -m pchute_exudyn run``), whose flags have not changed, so an old
checkout can produce the reference: ``git worktree add /tmp/old <commit>`` and ``run /tmp/ref --source /tmp/old``.
The set: MER cases 1-6 with SP (order 0, order 1, force rule with kappa_max 10), equilibrium point and implicit full
mass over 60 s and full-mass RK4 over 20 s; PA1 with SP, equilibrium point, implicit and RK4 full mass to touchdown.
``compare`` prints per run the largest difference over all columns relative to max(|value|, 1) and over the final
altitudes, positions and tensions, and whether the event logs agree; it exits 1 when any run differs by more than
--tolerance (default 1e-9).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from script_arguments import OneLineParser, existing_folder, non_negative, output_path, run_script

HERE = Path(__file__).resolve().parent


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    commands = parser.add_subparsers(dest="command", required=True)
    run_command = commands.add_parser("run", help="run every configuration into OUT")
    run_command.add_argument("out", type=output_path)
    run_command.add_argument("--source", type=existing_folder, default=HERE.parent, help="source tree to run (default: this one)")
    compare = commands.add_parser("compare", help="compare two OUT folders")
    compare.add_argument("a", type=existing_folder)
    compare.add_argument("b", type=existing_folder)
    compare.add_argument("--tolerance", type=non_negative, default=1e-9)
    args = parser.parse_args(argv)
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

import numpy as np

SP_VARIANTS = {"sp0": ["--method", "sp"], "sp1": ["--method", "sp", "--sp-order", "1"],
               "spforce": ["--method", "sp", "--slack-rule", "force", "--kappa-max", "10"],
               "eq": ["--method", "equilibrium"], "imp": ["--method", "full", "--integrator", "implicit"]}


def configurations() -> list:
    """(name, case file relative to the tree, extra arguments) of every run."""
    runs = [(f"mer{c}_{name}", f"cases/mer/case{c}.toml", args) for c in range(1, 7)
            for name, args in SP_VARIANTS.items()]
    runs += [(f"mer{c}_full", f"cases/mer/case{c}.toml", ["--method", "full", "--t-end", "20"]) for c in range(1, 7)]
    runs += [(f"pa1_{name}", "cases/cev_pa1.toml", args) for name, args in
             (("sp", ["--method", "sp"]), ("eq", ["--method", "equilibrium"]),
              ("imp", ["--method", "full", "--integrator", "implicit"]), ("full", ["--method", "full"]))]
    return runs


def run_all(out: Path, source: Path) -> int:
    env = {**os.environ, "PYTHONPATH": str(source)}
    failed = 0
    for name, case, args in configurations():
        command = [sys.executable, "-m", "pchute_exudyn", "run", str(source / case), *args, "--no-plot",
                   "--out", str(out / name)]
        done = subprocess.run(command, cwd=source, env=env, capture_output=True, text=True)
        print(f"{name}: {(done.stdout or done.stderr).strip()}", flush=True)
        failed += done.returncode != 0
    return 1 if failed else 0


def _difference(a: np.ndarray, b: np.ndarray) -> float:
    if a.shape != b.shape or not np.array_equal(np.isfinite(a), np.isfinite(b)):
        return float("inf")
    finite = np.isfinite(a)
    if not finite.any():
        return 0.0
    return float(np.max(np.abs(a[finite] - b[finite]) / np.maximum(np.abs(a[finite]), 1.0)))


def compare_all(a_root: Path, b_root: Path, tolerance: float) -> int:
    worst = 0.0
    for name, _, _ in configurations():
        files = [root / name / "result.npz" for root in (a_root, b_root)]
        if not all(f.is_file() for f in files):
            print(f"{name}: missing in {' and '.join(str(f.parent) for f in files if not f.is_file())}")
            worst = float("inf")
            continue
        with np.load(files[0]) as a, np.load(files[1]) as b:
            columns = [k for k in a.files if k not in ("units", "summary")]
            differences = {k: _difference(a[k], b[k]) if k in b.files else float("inf") for k in columns}
            finals = [k for k in columns if k.endswith(("_altitude", "_east", "_north")) or k.startswith("tension_")]
            final = max((_difference(a[k][-1:], b[k][-1:]) for k in finals if k in b.files), default=0.0)
            events = json.loads(str(a["summary"]))["events"] == json.loads(str(b["summary"]))["events"]
        column, largest = max(differences.items(), key=lambda item: item[1])
        print(f"{name:14s} all columns {largest:.2e} ({column}); finals {final:.2e}; events equal: {events}")
        worst = max(worst, largest)
    print(f"largest relative difference: {worst:.3g}")
    return 0 if worst <= tolerance else 1


def main(argv=None) -> int:
    args = arguments(argv)
    if args.command == "run":
        return run_all(args.out.resolve(), args.source.resolve())
    return compare_all(args.a, args.b, args.tolerance)


if __name__ == "__main__":
    run_script(main)

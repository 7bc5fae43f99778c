"""Every existing result unchanged, bit for bit: the same runs with this code and with an earlier checkout.

Run:  python validation/unchanged.py --before DIR [--out FILE]

DIR is a checkout of the code to compare against (``git worktree add DIR <commit>``). Each side runs in its own
process (``PYTHONPATH`` set to its checkout, the kernels compiled), records every column of RUNS and their summaries,
and the two are compared column by column with ``numpy.array_equal`` (NaN equal to NaN): a column that differs in
any bit is reported, as is a summary value that differs. Columns and summary keys the newer code adds are listed,
not counted as differences. Writes FILE (default validation/output/cluster/bitwise.md).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from script_arguments import OneLineParser, existing_folder, output_file, run_script

HERE = Path(__file__).resolve().parent


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--before", type=existing_folder, help="checkout of the code to compare against")
    parser.add_argument("--out", type=output_file, default=HERE / "output" / "cluster" / "bitwise.md")
    parser.add_argument("--record", type=Path, help=argparse.SUPPRESS)   # one side, in its own process
    args = parser.parse_args(argv)
    if args.record is None and args.before is None:
        parser.error("--before DIR is required")
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

import numpy as np

ROOT = HERE.parent
RUNS = [
    ("MER 1, SP accurate, 10 s", "cases/mer/case1.toml", dict(method="sp", duration=10.0)),
    ("MER 1, SP thesis, 10 s", "cases/mer/case1.toml", dict(method="sp", duration=10.0, preset="thesis", order=0)),
    ("MER 3, SP, 10 s", "cases/mer/case3.toml", dict(method="sp", duration=10.0)),
    ("MER 4, SP, 10 s", "cases/mer/case4.toml", dict(method="sp", duration=10.0)),
    ("MER 5, full RK4, 1.5 s", "cases/mer/case5.toml", dict(method="full", integrator="rk4", duration=1.5)),
    ("MER 1, equilibrium, 10 s", "cases/mer/case1.toml", dict(method="equilibrium", duration=10.0)),
    ("MER 1, full implicit, 10 s", "cases/mer/case1.toml", dict(method="full", integrator="implicit", duration=10.0)),
    ("MER 1 apparent mass, SP, 5 s", "cases/mer/case1_apparent_mass.toml", dict(method="sp", duration=5.0)),
    ("PA1, SP, to touchdown", "cases/cev_pa1.toml", dict(method="sp")),
    ("PA1, full implicit, 20 s", "cases/cev_pa1.toml", dict(method="full", integrator="implicit", duration=20.0)),
    ("PA1, full RK4, 11 s", "cases/cev_pa1.toml", dict(method="full", integrator="rk4", duration=11.0)),
    ("PA1, equilibrium, 15 s", "cases/cev_pa1.toml", dict(method="equilibrium", duration=15.0)),
    ("PA1 inflation, SP, to touchdown", "cases/cev_pa1_inflation.toml", dict(method="sp")),
    ("PA1 inflation, full implicit, 30 s", "cases/cev_pa1_inflation.toml",
     dict(method="full", integrator="implicit", duration=30.0)),
    ("PA1 winds, SP, to touchdown", "cases/cev_pa1_winds.toml", dict(method="sp")),
    ("PA1 calibrated, SP, to touchdown", "cases/cev_pa1_calibrated.toml", dict(method="sp")),
    ("simple (chapter 2), full", "cases/simple/simple.toml", dict(method="full")),
    # every other case file (issue 33: the aerodynamics beyond 90 deg and the runaway bounds change none of them)
    ("MER 2, SP, 10 s", "cases/mer/case2.toml", dict(method="sp", duration=10.0)),
    ("MER 6, SP, 10 s", "cases/mer/case6.toml", dict(method="sp", duration=10.0)),
    ("MER 5 aero, SP, 20 s", "cases/mer/case5_aero.toml", dict(method="sp", duration=20.0)),
    ("PA1 aero, SP, to touchdown", "cases/cev_pa1_aero.toml", dict(method="sp")),
    ("PA1 cluster, SP, to touchdown", "cases/cev_pa1_cluster.toml", dict(method="sp")),
    ("PA1 cluster main out, SP, to touchdown", "cases/cev_pa1_cluster_main_out.toml", dict(method="sp")),
    ("PA1 cluster winds, SP, to touchdown", "cases/cev_pa1_cluster_winds.toml", dict(method="sp")),
    ("PA1 cluster, full implicit, 30 s", "cases/cev_pa1_cluster.toml",
     dict(method="full", integrator="implicit", duration=30.0)),
    # issue 46: a case without steps takes adaptive steps now; at its former default step (1e-2 s) it is unchanged
    ("440-s descent, SP 1e-2 s, to touchdown", "cases/simple/descent_440s.toml", dict(method="sp", step=1e-2)),
    ("PA1 triggers, SP, to touchdown", "cases/cev_pa1_triggers.toml", dict(method="sp")),
    ("MER 5 aero trim, SP, 20 s", "cases/mer/case5_aero_trim.toml", dict(method="sp", duration=20.0)),
    ("MER EDL, SP, to touchdown", "cases/mer/edl.toml", dict(method="sp")),
    # issue 54: every shipped case (the rocket's reduced canopies, the supersonic disk-gap-band family)
    ("rocket dual deploy, SP, to touchdown", "cases/rocket/dual_deploy.toml", dict(method="sp")),
    ("rocket dual deploy, equilibrium, 60 s", "cases/rocket/dual_deploy.toml", dict(method="equilibrium",
                                                                                 duration=60.0)),
    ("MSL, SP, to touchdown", "cases/edl/msl.toml", dict(method="sp")),
    ("Mars 2020, SP, to touchdown", "cases/edl/mars2020.toml", dict(method="sp")),
    ("ASPIRE SR01, SP, to touchdown", "cases/edl/aspire_sr01.toml", dict(method="sp")),
    ("ASPIRE SR02, SP, to touchdown", "cases/edl/aspire_sr02.toml", dict(method="sp")),
    ("ASPIRE SR03, SP, to touchdown", "cases/edl/aspire_sr03.toml", dict(method="sp")),
    ("MSL, full implicit, 20 s", "cases/edl/msl.toml", dict(method="full", integrator="implicit", duration=20.0)),
    ("PA1 inflation (a riser by table), full RK4, 3 s", "cases/cev_pa1_inflation.toml",
     dict(method="full", integrator="rk4", duration=3.0)),
    ("PA1 inflation, equilibrium, 15 s", "cases/cev_pa1_inflation.toml", dict(method="equilibrium",
                                                                              duration=15.0)),
]
MACHINE = ("wall_time", "created", "versions", "steps_per_second", "case_file")
"""Summary keys that describe the machine or the moment, not the result."""


def record(out: Path) -> None:
    """Run RUNS with the pchute_exudyn this process imports, on the case files of the checkout it runs in (its
    working folder: each side flies its own files, so a case that names a new key to keep its model, such as
    ``packed = false``, is compared with its file before the key existed); each run's columns (.npz) and summary
    (.json)."""
    import pchute_exudyn as pc

    out.mkdir(parents=True, exist_ok=True)
    for i, (label, case_file, options) in enumerate(RUNS):
        result = pc.simulate(pc.load_case(Path.cwd() / case_file), **options)
        np.savez(out / f"{i:02d}.npz", **{k: np.asarray(v) for k, v in result.columns.items()})
        written = result.summary if isinstance(result.summary, dict) else result.summary.to_dict()   # either API
        summary = {k: v for k, v in written.items() if k not in MACHINE}
        (out / f"{i:02d}.json").write_text(json.dumps(summary, default=str))
        print(f"  {label}", flush=True)


def compare(before: Path, after: Path) -> tuple[list, int, int]:
    """Markdown rows per run, the columns compared and the differences (columns and summary values)."""
    rows, compared, differ = [], 0, 0
    for i, (label, _, _) in enumerate(RUNS):
        a, b = np.load(before / f"{i:02d}.npz"), np.load(after / f"{i:02d}.npz")
        changed = [k for k in a.files if k not in b.files or a[k].shape != b[k].shape
                   or not np.array_equal(a[k], b[k], equal_nan=True)]
        added = sorted(set(b.files) - set(a.files))
        sa, sb = (_leaves(json.loads((folder / f"{i:02d}.json").read_text())) for folder in (before, after))
        summary = [k for k in sa if k not in sb or not _same(sa[k], sb[k])]
        new = sorted({k.split("/")[0] if k.count("/") < 1 else k.rsplit("/", 1)[0] + "/..." for k in set(sb) - set(sa)})
        compared += len(a.files)
        differ += len(changed) + len(summary)
        rows.append(f"| {label} | {len(a.files)} | {len(changed)}{': ' + ', '.join(changed) if changed else ''} | "
                    f"{len(sa)} | {len(summary)}{': ' + ', '.join(summary) if summary else ''} | "
                    f"{', '.join(added) or '-'} | {', '.join(new) or '-'} |")
    return rows, compared, differ


def _same(a, b) -> bool:
    """Equal, a NaN (a quantity absent at the end, such as a cut-away system's final position) equal to a NaN."""
    return a == b or (isinstance(a, float) and isinstance(b, float) and a != a and b != b)


def _leaves(value, path: str = "") -> dict:
    """A summary as {path: value} of its leaves (``events[3]/time``), so that entries added beside old ones (a new
    column's unit) are told apart from old ones that changed."""
    if isinstance(value, dict):
        return {k: v for key, item in value.items() for k, v in _leaves(item, f"{path}/{key}" if path else key).items()}
    if isinstance(value, list):
        return {k: v for i, item in enumerate(value) for k, v in _leaves(item, f"{path}[{i}]").items()}
    return {path: value}


def main(argv=None) -> int:
    args = arguments(argv)
    if args.record is not None:
        record(args.record)
        return 0
    commits = {}
    with tempfile.TemporaryDirectory() as scratch:
        for side, checkout in (("before", args.before.resolve()), ("after", ROOT)):
            print(f"{side}: {checkout}", flush=True)
            env = {**os.environ, "PYTHONPATH": str(checkout), "PCHUTE_KERNELS": "compiled"}
            subprocess.run([sys.executable, __file__, "--record", str(Path(scratch) / side)], env=env, check=True,
                           cwd=checkout)
            commits[side] = subprocess.run(["git", "-C", str(checkout), "rev-parse", "--short", "HEAD"],
                                           capture_output=True, text=True).stdout.strip()
        rows, compared, differ = compare(Path(scratch) / "before", Path(scratch) / "after")
    text = "\n".join([
        "# Existing results, bit for bit",
        "",
        f"`python validation/unchanged.py --before DIR`, DIR a checkout of {commits['before']} (before), against "
        f"this code ({commits['after']}{', with uncommitted changes' if _dirty() else ''}). Each side in its own "
        "process with compiled kernels; every column compared with numpy.array_equal (NaN equal to NaN), every "
        "summary value (every leaf of summary.json but the machine's: wall time, versions, date, file path) with == "
        "(NaN equal to NaN).",
        "",
        "| run | columns | columns that differ | summary values | summary values that differ | columns added | "
        "summary entries added |",
        "|---|---|---|---|---|---|---|",
        *rows,
        "",
        f"{compared} columns compared, {differ} differences (columns and summary values).",
        ""])
    from pchute_exudyn.results.io import atomic_write_text
    args.out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(args.out, text)
    print(text)
    return 0 if differ == 0 else 1


def _dirty() -> bool:
    return bool(subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True).stdout.strip())


if __name__ == "__main__":
    run_script(main)

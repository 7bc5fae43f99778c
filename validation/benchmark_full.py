"""Benchmark of the full-mass model: MER case 1 (60 s) with RK4 and the implicit integrator, side by side.

Run:  python validation/benchmark_full.py [--duration 60]

Prints (and writes to validation/output/benchmark_full.md) the wall time, steps per second and the differences from
RK4 at the thesis step 1e-4 s, for RK4 at 1e-4/2e-4/3e-4 s, the implicit generalized-alpha at 1e-3/1e-2 s, and RK4 at
1e-4 s with the line law as a Python user function instead of the symbolic one (why the symbolic one is used).
All runs happen in one process, one after the other, so the ratios compare like with like on a noisy machine.
"""

from __future__ import annotations

import platform
from pathlib import Path

from script_arguments import OneLineParser, output_file, positive, run_script

HERE = Path(__file__).resolve().parent


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--duration", type=positive, default=60.0, help="simulated time in s (default 60)")
    parser.add_argument("--out", type=output_file, default=str(HERE / "output" / "benchmark_full.md"), help="table file")
    args = parser.parse_args(argv)
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

import pchute_exudyn as pc
from pchute_exudyn.results.compare import compare_results
from pchute_exudyn.results.io import atomic_write_text

RUNS = [("rk4", 1e-4, "symbolic"), ("rk4", 2e-4, "symbolic"), ("rk4", 3e-4, "symbolic"),
        ("implicit", 1e-3, "symbolic"), ("implicit", 1e-2, "symbolic"), ("rk4", 1e-4, "python")]


def main(argv=None) -> None:
    args = arguments(argv)
    case = pc.load_case(HERE.parent / "cases" / "mer" / "case1.toml")
    results = []
    for integrator, step, law in RUNS:
        result = pc.simulate(case, "full", integrator, step, args.duration, line_law=law)
        results.append((integrator, step, law, result))
        print(f"  {integrator:8s} {step:7.0e} {law:8s} {result.summary.wall_time:8.2f} s", flush=True)
    reference = results[0][3]
    rows = ["| integrator | step (s) | line law | wall time (s) | steps | steps/s | time vs RK4 1e-4 | "
            "final altitude - ref (m) | max tension diff (N) |", "|---|---|---|---|---|---|---|---|---|"]
    for integrator, step, law, result in results:
        s = result.summary
        tension = max(m["max"] for m in compare_results(reference, result).lines.values())
        rows.append(f"| {integrator} | {step:g} | {law} | {s.wall_time:.2f} | {s.steps} | "
                    f"{s.steps / s.wall_time:,.0f} | {s.wall_time / reference.summary.wall_time:.3f} | "
                    f"{result.final('vehicle_altitude') - reference.final('vehicle_altitude'):+.2e} | {tension:.3g} |")
    versions = reference.summary.versions
    text = "\n".join([
        f"# Full-mass model benchmark: MER case 1, {args.duration:g} s",
        "",
        f"Reference: RK4 at 1e-4 s, final vehicle altitude {reference.final('vehicle_altitude'):.3f} m. "
        f"Machine: {platform.processor() or platform.machine()}, Python {versions['python']}, "
        f"Exudyn {versions['exudyn']}, pchute-exudyn {versions['pchute_exudyn']}.",
        "",
        *rows,
        "",
        "Command: `python validation/benchmark_full.py`",
        ""])
    print(text)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, text)


if __name__ == "__main__":
    run_script(main)

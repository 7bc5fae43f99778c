"""Speed of the singular-perturbation method against the full-mass model: MER case 1, side by side in one run.

Run:  python validation/benchmark_sp.py [--duration 60] [--repeat 1]

Times, one after the other in one process: full mass RK4 at 1e-4 s (the thesis's reference), full mass implicit at
1e-2 s, and SP RK4 at 1e-2 s with each slack rule; prints wall times, ratios to the reference and accuracy against
it, then profiles one SP run to show where its time per step goes (engine reads, SP kernel, aerodynamics, Exudyn's
own work). Writes validation/output/benchmark_sp.md. With --repeat N each run is timed N times and the fastest kept.
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
from pathlib import Path

import pchute_exudyn as pc
from pchute_exudyn.compare import compare_results
from pchute_exudyn.io import atomic_write_text
from pchute_exudyn.simulation import versions

HERE = Path(__file__).resolve().parent
RUNS = [("full", "rk4", 1e-4, None), ("full", "implicit", 1e-2, None), ("sp", "rk4", 1e-2, "stretch"),
        ("sp", "rk4", 1e-2, "force")]
# profile entries (function name as cProfile reports it) -> category; cumulative time of each
CATEGORIES = {"confluence_velocity": "SP kernel (physics.singular_perturbation)",
              "GetMarkerOutput": "engine reads of attach points and aero centre (GetMarkerOutput)",
              "aerodynamic_load": "parachute aerodynamics user function (incl. its engine reads)",
              "post_step": "post-step hook: v0 update and output sampling",
              "pre_step": "pre-step hook: step monitor and NaN check"}


def profile_sp(case, duration: float) -> list:
    profiler = cProfile.Profile()
    profiler.enable()
    result = pc.simulate(case, "sp", "rk4", 1e-2, duration)
    profiler.disable()
    steps = result.summary["steps"]
    stats = pstats.Stats(profiler).stats
    totals = {}
    for (_, _, name), (_, calls, tottime, cumtime, _) in stats.items():
        # cProfile names built-ins "<built-in method exudyn.exudynCPP.GetMarkerOutput>"
        key = name.removeprefix("<built-in method exudyn.exudynCPP.").removesuffix(">")
        if key in CATEGORIES:
            previous = totals.get(key, (0, 0.0))
            totals[key] = (previous[0] + calls, previous[1] + (tottime if key == "GetMarkerOutput" else cumtime))
        if key == "SolveSystem":
            totals["SolveSystem"] = (calls, tottime)
    rows = ["| per SP step (profiled, so slower than unprofiled) | calls per step | us per step |", "|---|---|---|"]
    for name, label in list(CATEGORIES.items()) + [("SolveSystem", "Exudyn's own work (RK4 stages, bodies, "
                                                                   "gravity; SolveSystem's own time)")]:
        if name in totals:
            calls, seconds = totals[name]
            per_step = "-" if name == "SolveSystem" else f"{calls / steps:.1f}"
            rows.append(f"| {label} | {per_step} | {seconds / steps * 1e6:.1f} |")
    return rows


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=60.0, help="simulated time in s (default 60)")
    parser.add_argument("--repeat", type=int, default=1, help="time each run this many times, keep the fastest")
    parser.add_argument("--out", default=str(HERE / "output" / "benchmark_sp.md"))
    args = parser.parse_args(argv)
    case = pc.load_case(HERE.parent / "cases" / "mer" / "case1.toml")
    results = []
    for method, integrator, step, rule in RUNS:
        best = None
        for _ in range(max(1, args.repeat)):
            result = pc.simulate(case, method, integrator, step, args.duration, slack_rule=rule)
            if best is None or result.summary["wall_time"] < best.summary["wall_time"]:
                best = result
        results.append((f"{method} {integrator} {step:g}" + (f" ({rule})" if rule else ""), best))
        print(f"  {results[-1][0]:28s} {best.summary['wall_time']:8.2f} s", flush=True)
    reference = results[0][1]
    rows = ["| run | wall time (s) | steps | ratio to full RK4 1e-4 | speed-up | final altitude diff (m) | "
            "max tension diff after 2 s (N) |", "|---|---|---|---|---|---|---|"]
    for label, result in results:
        wall = result.summary["wall_time"]
        tension = max(m["max_settled"] for m in compare_results(reference, result, settle_time=2.0).lines.values())
        rows.append(f"| {label} | {wall:.2f} | {result.summary['steps']} | {wall / reference.summary['wall_time']:.4f} "
                    f"| {reference.summary['wall_time'] / wall:.1f}x | "
                    f"{result.final('vehicle_altitude') - reference.final('vehicle_altitude'):+.3f} | {tension:.3g} |")
    profile = profile_sp(case, min(args.duration, 20.0))
    v = versions()
    text = "\n".join([
        f"# Singular perturbation against full mass: MER case 1, {args.duration:g} s",
        "",
        f"`python validation/benchmark_sp.py` (one process, runs one after the other; fastest of {args.repeat}). "
        f"Exudyn {v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}, Python {v['python']}, {v['platform']}.",
        "",
        *rows,
        "",
        "Where an SP step's time goes (cProfile of a 20 s SP run at 1e-2 s; categories overlap where one calls "
        "another):",
        "",
        *profile,
        ""])
    print(text)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out, text)


if __name__ == "__main__":
    main()

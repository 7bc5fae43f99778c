"""The reduced method at every line damping (issue 37): SP's any_damping preset (a relaxation time
tau = 5e-3 s: each line damped at least tau K in the solve) at 1e-2 s against full mass RK4 at a step stable for that
damping and full mass implicit at 1e-2 s, MER case 3 with every line's damping scaled by 1, 0.1, 0.01 and 0, PA1 with
its lines' damping scaled by 0.1 and 0.

Run:  python validation/any_damping.py   (about 10 minutes: the undamped references need RK4 at 2e-5 s)
Writes validation/output/any_damping/table.md.
"""

from __future__ import annotations

import math
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

from pchute_exudyn import load_case, simulate
from pchute_exudyn.errors import PchuteError
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
RUNS = [("MER case 3", "cases/mer/case3.toml", 60.0, scale, step) for scale, step in
        ((1.0, 1e-4), (0.1, 1e-4), (0.01, 2e-5), (0.0, 2e-5))]
RUNS += [("PA1", "cases/cev_pa1.toml", None, scale, step) for scale, step in ((0.1, 1e-4), (0.0, 2e-5))]


def _scaled(path: str, scale: float) -> list:
    case = load_case(ROOT / path)
    return [f"{system.name}.lines.{line.name}.damping={line.damping * scale!r}"
            for system in case.systems.values() for line in system.lines]


def _run(path, overrides, duration, method, integrator, step, **options):
    try:
        return simulate(load_case(ROOT / path, overrides), method, integrator, step, duration, history=False,
                        **options)
    except PchuteError as exc:
        return str(exc).splitlines()[0][:140]


def _row(label, scale, name, result, reference, implicit=None) -> str:
    if isinstance(result, str):
        return f"| {label} | {scale:g} | {name} | failed: {result} | | | | | |"
    final, ref = result.summary.final, reference.summary.final
    peaks = [result.summary.peak_tension[k] / v - 1.0 for k, v in reference.summary.peak_tension.items()
             if v and result.summary.peak_tension.get(k)]
    worst = max(peaks, key=abs) if peaks else math.nan
    return (f"| {label} | {scale:g} | {name} | {final.altitude - ref.altitude:+.3f} | "
            f"{final.east - ref.east:+.3f} | {100 * worst:+.2f} | {final.time:.2f} | "
            f"{result.summary.wall_time:.3f} | {_speed(result, implicit)} |")


def _speed(result, implicit) -> str:
    """Full mass implicit's solve time over this run's (''): how many times faster than it."""
    if implicit is None or isinstance(implicit, str):
        return ""
    return f"{implicit.summary.wall_time / result.summary.wall_time:.2f}x"


def main() -> None:
    v = versions()
    lines = ["# The reduced method at every line damping", "",
             f"`python validation/any_damping.py`. Exudyn {v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}, Python "
             f"{v['python']}, {v['platform']}. Differences against full mass RK4 at the step in the reference row "
             "(final vehicle altitude and east, the worst peak line tension); solve wall times, and their ratio to full "
             "mass implicit at 1e-2 s where that run completes (it runs away on MER below x0.1). The equilibrium "
             "point is the massless limit the relaxed method tends to as C -> 0: without damping the full-mass "
             "confluence rings at sqrt(K / m_c), which no massless method has, and the peak tensions of both differ "
             "from full mass by that ringing.", "",
             "| case | damping x | run | altitude diff (m) | east diff (m) | worst peak tension diff (%) | end (s) | "
             "solve (s) | speed-up over full implicit 1e-2 |", "|---|---|---|---|---|---|---|---|---|"]
    for label, path, duration, scale, step in RUNS:
        overrides = _scaled(path, scale)
        reference = _run(path, overrides, duration, "full", "rk4", step)
        if isinstance(reference, str):
            lines.append(f"| {label} | {scale:g} | full RK4 {step:g} (reference) | failed: {reference} | | | | | |")
            continue
        implicit = _run(path, overrides, duration, "full", "implicit", 1e-2)
        lines.append(f"| {label} | {scale:g} | full RK4 {step:g} (reference) | 0 | 0 | 0 | "
                     f"{reference.summary.final.time:.2f} | {reference.summary.wall_time:.3f} | "
                     f"{_speed(reference, implicit)} |")
        lines.append(_row(label, scale, "full implicit 1e-2", implicit, reference, implicit))
        for name, method, options in (("SP accurate 1e-2", "sp", {"preset": "accurate"}),
                                      ("SP any_damping 1e-2", "sp", {"preset": "any_damping"}),
                                      ("equilibrium point 1e-2 (the massless limit)", "equilibrium", {})):
            lines.append(_row(label, scale, name, _run(path, overrides, duration, method, "rk4", 1e-2, **options),
                              reference, implicit))
        print("\n".join(lines[-5:]), flush=True)
    text = "\n".join(lines + [""])
    print(text)
    atomic_write_text(HERE / "output" / "any_damping" / "table.md", text)


if __name__ == "__main__":
    run_script(main)

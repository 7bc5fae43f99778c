"""Triggers, sensors and separations (issue 36): the figures of docs/models/triggers.md and docs/models/mer_edl.md.

Run:  python validation/triggers.py

* PA1 by triggers (cases/cev_pa1_triggers.toml) against its fixed sequence (cases/cev_pa1.toml), SP and full mass:
  each event's time and the touchdown;
* a user trigger function equal to the built-in one: the runs compared column by column;
* MER EDL (cases/mer/edl.toml) with SP, full mass RK4 and full mass implicit: touchdown, deployment conditions, peak
  loads, heat shield clearance and wall time, side by side;
* the closed forms of tests/integration/test_triggers.py with their errors.
Writes validation/output/triggers/triggers.md.
"""

from __future__ import annotations

import math
import sys
import tempfile
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

from pchute_exudyn import load_case, simulate
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))
from tests.integration.test_triggers import VACUUM, G, noise_draws  # noqa: E402  (the closed forms, written once)

EVENTS = ("deploy", "cutaway", "touchdown")


def _events(result) -> dict:
    return {f"{e.kind} {getattr(e, 'system', '')}".strip(): e.time for e in result.summary.events
            if e.kind in EVENTS}


def pa1_lines() -> list:
    lines = ["## PA1 by triggers against its fixed sequence", "",
             "| method | event | cev_pa1.toml (s) | cev_pa1_triggers.toml (s) | difference (s) |", "|---|---|---|---|---|"]
    for method in ("sp", "full"):
        fixed = _events(simulate(load_case(ROOT / "cases" / "cev_pa1.toml"), method=method))
        triggered = _events(simulate(load_case(ROOT / "cases" / "cev_pa1_triggers.toml"), method=method))
        for name, time in fixed.items():
            lines.append(f"| {method} | {name} | {time:.6f} | {triggered[name]:.6f} | {triggered[name] - time:+.2e} |")
    return lines + [""]


def cost_lines(repeat: int = 5) -> list:
    """What sensing costs: PA1 with fixed times and by triggers (20 Hz; every step), SP, interleaved, medians."""
    import statistics
    import time

    cases = {"cev_pa1.toml (fixed times)": load_case(ROOT / "cases" / "cev_pa1.toml"),
             "cev_pa1_triggers.toml (20 Hz)": load_case(ROOT / "cases" / "cev_pa1_triggers.toml"),
             "cev_pa1_triggers.toml, every step": load_case(ROOT / "cases" / "cev_pa1_triggers.toml",
                                                            ["main.deploy_trigger.rate=1000"])}
    solve, whole = {name: [] for name in cases}, {name: [] for name in cases}
    for _ in range(repeat):
        for name, case in cases.items():
            started = time.perf_counter()
            result = simulate(case, method="sp", history=False)
            whole[name].append(time.perf_counter() - started)
            solve[name].append(result.summary.wall_time)
    base = statistics.median(whole[next(iter(cases))])
    lines = ["## What sensing costs (PA1 to touchdown, SP, medians of "
             f"{repeat} interleaved runs)", "", "| case | solve (s) | simulate() (s) | ratio to fixed times |",
             "|---|---|---|---|"]
    for name in cases:
        lines.append(f"| {name} | {statistics.median(solve[name]):.3f} | {statistics.median(whole[name]):.3f} | "
                     f"{statistics.median(whole[name]) / base:.3f} |")
    return lines + ["", "(A rate of 1000 Hz above 1 / step samples at every step.)", ""]


def user_function_lines() -> list:
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "avionics_v36.py").write_text(
            "def fire_main(time, sensed, state):\n"
            "    return sensed['altitude_ground'] <= 796.0 and sensed['vertical_velocity'] < 0.0\n")
        case = Path(folder) / "user.toml"
        base = (ROOT / "cases" / "cev_pa1_triggers.toml").as_posix()
        case.write_text(f'extends = "{base}"\nremove = ["systems.main.deploy_trigger"]\n[systems.main]\n'
                        'deploy_trigger = { function = "avionics_v36:fire_main", rate = 20.0 }\n')
        builtin = simulate(load_case(ROOT / "cases" / "cev_pa1_triggers.toml"), method="sp")
        user = simulate(load_case(case), method="sp")
    same = sum(np.array_equal(builtin[n], user[n], equal_nan=True) for n in builtin.columns)
    return ["## A user function equal to the built-in trigger", "",
            f"PA1 by triggers to touchdown, SP: {same} of {len(builtin.columns)} columns bitwise equal "
            f"(last sample {builtin.summary.final.time:.4f} s and {user.summary.final.time:.4f} s).", ""]


def edl_lines() -> list:
    lines = ["## MER EDL, SP against full mass", "",
             "| method | step (s) | touchdown (s) | vs full RK4 | touchdown speed (m/s) | line stretch (s) | Mach | q (Pa) | "
             "peak riser (N) | peak bridle1 (N) | heat shield clearance at +2 s (m) | wall (s) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    runs = [("sp", "rk4", 5e-3), ("full", "rk4", 1e-4), ("full", "implicit", 1e-2), ("equilibrium", "rk4", 1e-2)]
    results = {run: simulate(load_case(ROOT / "cases" / "mer" / "edl.toml"), run[0], run[1], run[2]) for run in runs}
    def touchdown_of(result):
        return result.summary.touchdown.time

    reference = touchdown_of(results[runs[1]])
    for (method, integrator, step), result in results.items():
        s = result.summary
        deploy = s.events_of("deploy")[0]
        conditions = deploy.trigger["conditions"]
        touchdown = touchdown_of(result)
        speed = s.touchdown.speed
        lines.append(f"| {method} {integrator} | {step:g} | {touchdown:.5f} | "
                     f"{100 * (touchdown - reference) / reference:+.4f} % | {speed:.3f} | {deploy.time:.4f} | "
                     f"{conditions['mach']:.4f} | {conditions['dynamic_pressure']:.1f} | "
                     f"{s.peak_tension['riser']:.0f} | {s.peak_tension['bridle1']:.0f} | "
                     f"{s.separations['heat_shield'].clearance:.3f} | {s.wall_time:.2f} |")
    return lines + [""]


def closed_form_lines() -> list:
    lines = ["## Closed forms (a body in vacuum over a flat planet, full mass RK4 1e-2 s)", "",
             "| check | expected (s) | fired (s) | error (s) |", "|---|---|---|---|"]
    crossing = math.sqrt(2.0 * 300.0 / G)
    with tempfile.TemporaryDirectory() as folder:
        for label, trigger, down, expected in (
                ("altitude 2700 m, every step, lag 0.37 s", '{ quantity = "altitude", below = 2700.0, lag = 0.37 }',
                 0.0, crossing + 0.37),
                ("altitude 2700 m, 20 Hz, lag 0.25 s",
                 '{ quantity = "altitude", below = 2700.0, lag = 0.25, rate = 20.0 }', 0.0, crossing + 0.25),
                ("apogee, thrown up at 30 m/s", '{ quantity = "apogee" }', -30.0, 30.0 / G)):
            path = Path(folder) / "vacuum.toml"
            path.write_text(VACUUM.format(g=G, altitude=3000.0, down=down, trigger=trigger, duration=12.0, speed=0.0))
            event = simulate(load_case(path)).summary.events_of("separation")[0]
            lines.append(f"| {label} | {expected:.9f} | {event.time:.9f} | {event.time - expected:+.2e} |")
    fired, propagated = noise_draws(500)
    spread = float(np.std(fired, ddof=1))
    return lines + ["", f"Barometric noise, 500 seeded draws (50 Pa, AR(1), 100 Hz, 2000 m, 10 m/s): standard deviation "
                        f"of the fired altitude {spread:.3f} m against the propagated sigma_p / (rho g) = "
                        f"{propagated:.3f} m (ratio {spread / propagated:.4f}); mean {float(np.mean(fired)):.3f} m.", ""]


def main() -> None:
    v = versions()
    lines = ["# Triggers, sensors and separations", "",
             f"`python validation/triggers.py`. Exudyn {v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}, Python "
             f"{v['python']}, {v['platform']}.", ""]
    lines += closed_form_lines() + pa1_lines() + user_function_lines() + cost_lines() + edl_lines()
    text = "\n".join(lines)
    print(text)
    atomic_write_text(HERE / "output" / "triggers" / "triggers.md", text)


if __name__ == "__main__":
    run_script(main)

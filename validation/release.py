"""A cargo cluster released from an aircraft: opening loads by SP and full mass, the swing, the steady rate.

Run:  python validation/release.py

`pchute new` writes the case (validation/output/release/cargo_release.toml): 2000 kg under three 30.5 m flat circular
canopies, released at 65 m/s (about 130 kn) in level flight heading east from 1500 m, line stretch 1 s later (a static
line), each canopy opening by the flat circular canopy's fill constant (n = 8, exponent 2, overinflation 1.7). Runs:
SP at the case's step, full mass with RK4 at its stability step and with the implicit integrator at 1e-2 s. Writes
validation/output/release/release.md (each canopy's opening load and its time by each method, SP against full mass
RK4; the settled rate against the rate `pchute new` states; when the swing has died down) and release.png (altitude,
air speed, riser tensions and the payload's pendulum angle).
"""

from __future__ import annotations

import time
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.authoring.choices import NewCase
from pchute_exudyn.authoring.layout import layout
from pchute_exudyn.results.io import atomic_write_text, atomic_writer
from pchute_exudyn.run.simulation import versions

HERE = Path(__file__).resolve().parent
OUT = HERE / "output" / "release"
CHOICES = dict(planet="earth", mass=2000.0, canopy_diameter=30.5, canopy_type="flat_circular", canopies=3,
               altitude=1500.0, release_airspeed=65.0, release_heading_deg=90.0, static_line_time=1.0,
               name="cargo release")
RUNS = [("SP", "sp", "rk4", None), ("full mass RK4", "full", "rk4", None), ("full mass implicit", "full", "implicit",
                                                                              1e-2)]
LOAD_TOLERANCE, RATE_TOLERANCE, CALM = 0.03, 0.01, 2.0   # -, -, deg


def opening_loads(result) -> dict:
    """Each canopy's opening load (N) and its time (s) from summary.json's opening_loads."""
    loads = {}
    for canopy, stages in result.summary.opening_loads.items():
        (peak,) = stages[0]["peaks"].values()
        loads[canopy] = (peak["tension"], peak["time"])
    return loads


def calm_after(result) -> float:
    """The time (s) after which the payload's pendulum angle stays below CALM deg."""
    angle = result["vehicle_pendulum_deg"]
    above = np.flatnonzero(angle > CALM)
    return float(result.time[above[-1] + 1]) if len(above) else 0.0


def figure(results: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(4, 1, figsize=(9, 10), sharex=True)
    for (label, result), style in zip(results.items(), ("-", "--", ":")):
        t = result.time
        speed = np.linalg.norm(np.stack([result[f"vehicle_velocity_{a}"] for a in ("east", "north", "down")]), axis=0)
        axes[0].plot(t, result["vehicle_altitude"], style, label=label)
        axes[1].plot(t, speed, style, label=label)
        for i in (1, 2, 3):
            axes[2].plot(t, result[f"tension_riser_canopy{i}"] / 1e3, style, color=f"C{i - 1}",
                         label=f"canopy{i}, {label}" if label != "full mass implicit" else None)
        axes[3].plot(t, result["vehicle_pendulum_deg"], style, label=label)
    for ax, text in zip(axes, ("payload altitude (m)", "payload air speed (m/s)", "riser tension (kN)",
                               "payload pendulum angle (deg)")):
        ax.set_ylabel(text)
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper right")
    axes[2].legend(loc="upper right", fontsize=7, ncol=2)
    axes[3].set_xlabel("time since release (s)")
    axes[3].set_xlim(0.0, 90.0)
    fig.suptitle("2000 kg under three 30.5 m flat circular canopies, released at 65 m/s from 1500 m (still air)")
    fig.tight_layout()
    with atomic_writer(path, "wb") as handle:
        fig.savefig(handle, format="png", dpi=110)


def main(argv=None) -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / "cargo_release.toml"
    atomic_write_text(path, pc.new_case_text(**CHOICES))
    case = pc.load_case(path)
    plan = layout(NewCase(**CHOICES))
    results, walls = {}, {}
    for label, method, integrator, step in RUNS:
        started = time.perf_counter()
        results[label] = pc.simulate(case, method, integrator, step)
        walls[label] = time.perf_counter() - started
    loads = {label: opening_loads(result) for label, result in results.items()}
    failed, rows = [], []
    for canopy in loads["SP"]:
        reference = loads["full mass RK4"][canopy][0]
        cells = []
        for label in results:
            tension, when = loads[label][canopy]
            cells.append(f"{tension / 1e3:.2f} kN at {when:.2f} s ({tension / reference - 1:+.2%})")
        difference = loads["SP"][canopy][0] / reference - 1.0
        if abs(difference) > LOAD_TOLERANCE:
            failed.append(f"{canopy}: SP {difference:+.2%} from full mass RK4")
        rows.append(f"| {canopy} | " + " | ".join(cells) + " |")
    settle_rows = []
    for label, result in results.items():
        descent = result.summary.descent
        stated = plan.steady_rate(0.0)
        rate_error = descent.mean_rate / stated - 1.0
        if label == "SP" and abs(rate_error) > RATE_TOLERANCE:
            failed.append(f"settled rate {rate_error:+.2%} from the stated one")
        when = np.interp(-500.0, -result["vehicle_altitude"], result.time)
        at_500 = float(np.interp(when, result.time, result["vehicle_velocity_down"]))
        settle_rows.append(f"| {label} | {result.summary.step:g} | {result.summary.final.time:.2f} | "
                           f"{calm_after(result):.1f} | {at_500:.4f} ({at_500 / plan.steady_rate(500.0) - 1:+.2%}) | "
                           f"{descent.mean_rate:.4f} ({rate_error:+.2%}) | "
                           f"{result.summary.final.east:.1f} | {walls[label]:.1f} |")
    figure(results, OUT / "release.png")
    v = versions()
    text = "\n".join([
        "# A cargo cluster released from an aircraft",
        "",
        f"`python validation/release.py` (pchute_exudyn {v['pchute_exudyn']}, Exudyn {v['exudyn']}). The case is "
        "`pchute new`'s (cargo_release.toml beside this file): 2000 kg under three 30.5 m flat circular canopies, "
        "released at 65 m/s in level flight heading east from 1500 m in still air; line stretch after a 1 s static "
        "line; each canopy fills by the flat circular canopy's fill constant n = 8 (t_fill = n D0 / V = "
        f"{results['SP'].summary.events[2].fill_time:.2f} s at the measured "
        f"{results['SP'].summary.events[2].speed:.1f} m/s), drag area growing as (t / t_fill)^2, overshooting "
        "to 1.7 and falling back.",
        "",
        f"Checks: each canopy's opening load by SP within {LOAD_TOLERANCE:.0%} of full mass RK4's; the settled rate "
        f"(the last 5 s before touchdown) within {RATE_TOLERANCE:.0%} of the rate `pchute new` states for the ground "
        f"({plan.steady_rate(0.0):.4f} m/s). **{'All hold.' if not failed else 'Failed: ' + '; '.join(failed)}**",
        "",
        "## Opening loads (each canopy's riser, summary.json `opening_loads`)",
        "",
        "| canopy | " + " | ".join(f"{label} (vs full mass RK4)" for label in results) + " |",
        "|---|" + "---|" * len(results),
        *rows,
        "",
        "## The swing and the steady rate",
        "",
        f"| run | step (s) | touchdown (s) | pendulum below {CALM:g} deg after (s) | rate at 500 m (m/s, vs stated) | "
        "settled rate (m/s, vs stated at 0 m) | landing east of the release (m) | wall (s) |",
        "|---|---|---|---|---|---|---|---|",
        *settle_rows,
        "",
        "![release](release.png)",
        ""])
    atomic_write_text(OUT / "release.md", text)
    print(text)
    return 0 if not failed else 1


if __name__ == "__main__":
    run_script(main)

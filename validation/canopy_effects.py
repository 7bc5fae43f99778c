"""What the canopy physics of docs/models/canopy.md changes, and what it costs.

Run:  python validation/canopy_effects.py        # about 3 minutes; writes validation/output/canopy/effects.md
                                                  # and the figures opening_loads.png, apparent_mass_mer.png

1. PA1 with fill-constant openings (cases/cev_pa1_inflation.toml): SP against full mass RK4 (touchdown, the main
   riser's peak in each stage, engine solve times side by side, median of three rounds); the figure of the
   drag-area fractions and riser tensions with each stage's peak.
2. Apparent mass on MER (cases 1 and 5, 60 s, SP; case 1 also full mass implicit): final position, peak tensions,
   the parachute's swing period (case 5: the vehicle starts rotated 10 deg, the system swings).
3. Apparent mass on PA1 (cases/cev_pa1.toml with apparent mass on both canopy bodies, see PA1_APPARENT): touchdown
   time and speed, peak loads.
4. Cost of each feature: engine solve time with it on against off, side by side in one process.
"""

from __future__ import annotations

import statistics
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from pchute_exudyn import load_case, simulate  # noqa: E402
from pchute_exudyn.results.io import atomic_write_text, atomic_writer  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "validation" / "output" / "canopy"
MER = ROOT / "cases" / "mer"
PA1 = ROOT / "cases" / "cev_pa1.toml"
PA1_INFLATION = ROOT / "cases" / "cev_pa1_inflation.toml"
MER_APPARENT = ["parachute.apparent_mass={projected_radius = 5.3, axial = 1.0, lateral = 0.5, rotational = 0.1}"]
PA1_APPARENT = [
    # projected radius 0.67 D0 / 2 of one canopy, scaled to the volume of the canopies the body stands for
    # (2 drogues of D0 7.0 m, 3 mains of D0 35.4 m): R = 0.335 D0 n^(1/3); canopy.md's representative k
    "drogue_canopy.apparent_mass={projected_radius = 2.95, axial = 1.0, lateral = 0.5, rotational = 0.1}",
    "main_canopy.apparent_mass={projected_radius = 17.1, axial = 1.0, lateral = 0.5, rotational = 0.1}"]


def touchdown(summary):
    return summary.touchdown


def pa1_inflation(lines: list) -> None:
    case = load_case(PA1_INFLATION)
    rounds = [{method: simulate(case, method) for method in ("full", "sp")} for _ in range(3)]
    runs = rounds[-1]
    ratio = statistics.median(r["full"].summary.wall_time / r["sp"].summary.wall_time for r in rounds)
    sp, full = runs["sp"].summary, runs["full"].summary
    lines += ["## 1. PA1 with fill-constant openings: SP against full mass", "",
              "`cases/cev_pa1_inflation.toml`; full mass RK4 at 5e-4 s, SP (order 1) RK4 at 1e-2 s. Engine solve "
              f"times, three rounds side by side: full/SP median **{ratio:.1f}x** (last round full "
              f"{full.wall_time:.2f} s, SP {sp.wall_time:.2f} s).", "",
              "| | full mass | SP | difference |", "|---|---|---|---|"]
    t_full, t_sp = touchdown(full), touchdown(sp)
    lines += [f"| touchdown time (s) | {t_full.time:.3f} | {t_sp.time:.3f} | "
              f"{t_sp.time - t_full.time:+.3f} s |",
              f"| touchdown speed (m/s) | {t_full.speed:.3f} | {t_sp.speed:.3f} | "
              f"{t_sp.speed - t_full.speed:+.3f} m/s |"]
    for a, b in zip(full.opening_loads["main"], sp.opening_loads["main"]):
        pa, pb = a["peaks"]["riser"], b["peaks"]["riser"]
        lines.append(f"| main riser peak, stage {a['stage']} (N, at s) | {pa['tension']:.0f} at {pa['time']:.2f} | "
                     f"{pb['tension']:.0f} at {pb['time']:.2f} | {100 * (pb['tension'] / pa['tension'] - 1):+.2f} % |")
    drogue_full, drogue_sp = full.opening_loads["drogue"][0], sp.opening_loads["drogue"][0]
    lines.append(f"| drogue riser peak (N) | {drogue_full['peaks']['riser']['tension']:.0f} | "
                 f"{drogue_sp['peaks']['riser']['tension']:.0f} | "
                 f"{100 * (drogue_sp['peaks']['riser']['tension'] / drogue_full['peaks']['riser']['tension'] - 1):+.2f}"
                 " % |")
    lines += ["", "Stage starts and fills (SP run):", "", "| event | system | stage | time (s) | speed (m/s) | "
              "fill time (s) |", "|---|---|---|---|---|---|"]
    lines += [f"| {e.kind} | {e.system} | {e.stage} | {e.time:.3f} | {getattr(e, 'speed', float('nan')):.2f} | "
              f"{getattr(e, 'fill_time', float('nan')):.3f} |" for e in sp.events
              if e.kind in ("stage_start", "disreef", "fill_end")]
    plot_openings(runs)
    lines += ["", "![opening loads](opening_loads.png)", ""]


def plot_openings(runs: dict) -> None:
    fig, axes = plt.subplots(3, 1, figsize=(10, 10), sharex=True)
    sp = runs["sp"]
    for system in ("drogue", "main"):
        axes[0].plot(sp.columns["time"], sp.columns[f"{system}_drag_area_fraction"], label=system)
    axes[0].set_ylabel("drag-area fraction (-)")
    for ax, system in ((axes[1], "main"), (axes[2], "drogue")):
        for method, style in (("full", "-"), ("sp", "--")):
            result = runs[method]
            ax.plot(result.columns["time"], result.columns[f"tension_{system}_riser"] / 1e3, style,
                    label=f"{method} riser")
            for stage in result.summary.opening_loads[system]:
                peak = stage["peaks"]["riser"]
                ax.plot(peak["time"], peak["tension"] / 1e3, "o" if method == "full" else "x", color="k")
                if method == "full":
                    ax.annotate(f"stage {stage['stage']}: {peak['tension'] / 1e3:.0f} kN",
                                (peak["time"], peak["tension"] / 1e3), textcoords="offset points", xytext=(6, 4))
        ax.set_ylabel(f"{system} riser tension (kN)")
    axes[2].set_xlabel("time (s)")
    axes[0].set_xlim(0, 40)
    for ax in axes:
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right")
    fig.suptitle("PA1 with fill-constant openings: drag-area fraction and riser loads (peak of each stage marked)")
    fig.tight_layout()
    with atomic_writer(OUT / "opening_loads.png", "wb") as handle:
        fig.savefig(handle, format="png", dpi=110)
    plt.close(fig)


def swing_period(result) -> float:
    """Mean period (s) of the parachute's swing rate about body z over the last 50 s (upward zero crossings,
    linearly interpolated); MER case 5 swings about z (its vehicle starts rotated about body z)."""
    time, rate = result.columns["time"], result.columns["parachute_rate_z"]
    keep = time >= time[-1] - 50.0
    time, rate = time[keep], rate[keep] - rate[keep].mean()
    crossings = [time[i] - rate[i] * (time[i + 1] - time[i]) / (rate[i + 1] - rate[i])
                 for i in range(len(rate) - 1) if rate[i] < 0.0 <= rate[i + 1]]
    return float(np.mean(np.diff(crossings))) if len(crossings) > 2 else float("nan")


def mer_apparent_mass(lines: list) -> None:
    lines += ["## 2. Apparent mass on MER (60 s)", "",
              "The parachute's apparent mass with canopy.md's representative values (R_p = 5.3 m, k = 1.0 / 0.5 / "
              "0.1; `cases/mer/case1_apparent_mass.toml`) on top of the 16 kg of the thesis (which already counts "
              "entrained air): this shows the model's effect, not a recalibration.", "",
              "| case, method | vehicle altitude (m) | east (m) | riser peak (N) | riser at 60 s (N) | "
              "parachute swing period (s; case 1 does not swing) |", "|---|---|---|---|---|---|"]
    results = {}
    for number, method, integrator in ((1, "sp", "rk4"), (1, "full", "implicit"), (5, "sp", "rk4")):
        for label, overrides in (("without", []), ("with", MER_APPARENT)):
            result = simulate(load_case(MER / f"case{number}.toml", overrides), method, integrator)
            results[(number, method, label)] = result
            final = result.summary.final
            lines.append(f"| case {number} {method} {integrator}, {label} apparent mass | "
                         f"{final.altitude:.3f} | {final.east:.4f} | "
                         f"{result.summary.peak_tension['riser']:.1f} | "
                         f"{result.columns['tension_riser'][-1]:.1f} | "
                         f"{swing_period(result) if number == 5 else float('nan'):.3f} |")
    on = results[(1, "sp", "with")]
    lines += ["", f"Apparent mass of the parachute along its axis: {on.columns['parachute_apparent_mass_axial'][0]:.2f}"
              f" kg at the start, {on.columns['parachute_apparent_mass_axial'][-1]:.2f} kg at 60 s (the air gets "
              "denser); laterally half that.", "", "![apparent mass, MER case 5](apparent_mass_mer.png)", ""]
    fig, ax = plt.subplots(figsize=(10, 4))
    for label in ("without", "with"):
        result = results[(5, "sp", label)]
        ax.plot(result.columns["time"], result.columns["parachute_rate_z"], label=f"{label} apparent mass")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("parachute rate about body z (rad/s)")
    ax.set_title("MER case 5 (SP): the parachute's swing with and without its apparent mass")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    with atomic_writer(OUT / "apparent_mass_mer.png", "wb") as handle:
        fig.savefig(handle, format="png", dpi=110)
    plt.close(fig)


def pa1_apparent_mass(lines: list) -> None:
    lines += ["## 3. Apparent mass on PA1", "",
              "`cases/cev_pa1.toml` (time-table schedules) with apparent mass on both canopy bodies (projected radius "
              "0.67 D0 / 2 per canopy, scaled to the volume of the 2 drogues / 3 mains each body stands for: 2.95 m "
              "and 17.1 m; canopy.md's k). The model takes R_p of the inflated canopy from line stretch on, so "
              "during the reefed stages it overstates the air carried: an upper bound of the effect.", "",
              "| method, apparent mass | touchdown (s) | touchdown speed (m/s) | main riser peak (N) | "
              "drogue riser peak (N) |", "|---|---|---|---|---|"]
    for method in ("sp", "full"):
        for label, overrides in (("without", []), ("with", PA1_APPARENT)):
            summary = simulate(load_case(PA1, overrides), method).summary
            down = touchdown(summary)
            lines.append(f"| {method}, {label} | {down.time:.3f} | {down.speed:.3f} | "
                         f"{summary.peak_tension['main_riser']:.0f} | "
                         f"{summary.peak_tension['drogue_riser']:.0f} |")
    lines.append("")


COSTS = [
    ("apparent mass, MER case 1, 20 s, SP RK4 1e-2 s", MER / "case1.toml", MER_APPARENT, "sp", "rk4", 20.0),
    ("apparent mass, MER case 1, 20 s, full RK4 1e-4 s", MER / "case1.toml", MER_APPARENT, "full", "rk4", 20.0),
    ("apparent mass, MER case 1, 20 s, full implicit 1e-2 s", MER / "case1.toml", MER_APPARENT, "full",
     "implicit", 20.0),
    ("inflation + riser table, PA1 to touchdown, SP RK4 1e-2 s", PA1, None, "sp", "rk4", None),
    ("inflation + riser table, PA1 to touchdown, full RK4 5e-4 s", PA1, None, "full", "rk4", None),
]


def costs(lines: list) -> None:
    lines += ["## 4. What each feature costs", "",
              "Engine solve time with the feature against without, run one after the other in this process "
              "(best of two). PA1's feature run is `cases/cev_pa1_inflation.toml` (fill-constant openings and the "
              "riser's load-elongation table) against `cases/cev_pa1.toml`.", "",
              "| feature, run | without (s) | with (s) | ratio |", "|---|---|---|---|"]
    for label, case_file, overrides, method, integrator, duration in COSTS:
        times = {}
        for key, case in (("without", load_case(case_file)),
                          ("with", load_case(case_file, overrides) if overrides else load_case(PA1_INFLATION))):
            times[key] = min(simulate(case, method, integrator, duration=duration).summary.wall_time
                             for _ in range(2))
        lines.append(f"| {label} | {times['without']:.3f} | {times['with']:.3f} | "
                     f"{times['with'] / times['without']:.2f}x |")
    lines.append("")


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    lines = ["# Canopy physics: effects and costs", "",
             "Written by `python validation/canopy_effects.py`; closed forms in `closed_forms.md` "
             "(`python validation/canopy_checks.py`).", ""]
    for part in (pa1_inflation, mer_apparent_mass, pa1_apparent_mass, costs):
        part(lines)
        print(f"done: {part.__name__}", flush=True)
    atomic_write_text(OUT / "effects.md", "\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    run_script(main)

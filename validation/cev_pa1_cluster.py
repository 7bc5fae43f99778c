"""Orion/CEV PA1 with every canopy its own body (docs/models/cluster.md): SP against full mass, one main out, and
the figure of the three mains' riser loads and flyout angles.

Run:  python validation/cev_pa1_cluster.py

Runs `cases/cev_pa1_cluster.toml` with full mass (RK4 at 5e-4 s, implicit at 1e-2 s), SP at 1e-2 s (the accurate
preset) and the equilibrium point at 1e-2 s, `cases/cev_pa1_cluster_main_out.toml` with SP and full mass implicit, and
`cases/cev_pa1_inflation.toml` (the same model with lumped canopies) with SP, one after the other in one process, then
TIMING_ROUNDS interleaved rounds of full RK4 and SP for the speed-up. Writes into validation/output/cluster/:
``pa1_cluster.md`` (touchdown, each main riser's peak, load share, flyout, pendulum and rate of descent per run;
agreement with full mass RK4; the speed-up; the main-out case against the nominal one) and ``mains.png``.
"""

from __future__ import annotations

import math
import statistics
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.physics.atmosphere import US76
from pchute_exudyn.physics.cluster import DEFAULT_DRAG_EFFICIENCY
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions
from pchute_exudyn.views.plotting import new_figure, save_figure

HERE = Path(__file__).resolve().parent
CASES = HERE.parent / "cases"
CLUSTER, MAIN_OUT, LUMPED = (CASES / f"{name}.toml" for name in ("cev_pa1_cluster", "cev_pa1_cluster_main_out",
                                                                  "cev_pa1_inflation"))
OUT = HERE / "output" / "cluster"
RUNS = [("full rk4 5e-4", CLUSTER, "full", "rk4", 5e-4), ("full implicit 1e-2", CLUSTER, "full", "implicit", 1e-2),
        ("sp 1e-2", CLUSTER, "sp", "rk4", 1e-2), ("equilibrium 1e-2", CLUSTER, "equilibrium", "rk4", 1e-2),
        ("main out: sp 1e-2", MAIN_OUT, "sp", "rk4", 1e-2),
        ("main out: full implicit 1e-2", MAIN_OUT, "full", "implicit", 1e-2),
        ("lumped canopies: sp 1e-2", LUMPED, "sp", "rk4", 1e-2)]
REFERENCE, SP, OUT_SP = "full rk4 5e-4", "sp 1e-2", "main out: sp 1e-2"
MAINS = ("main1", "main2", "main3")
TIMING_ROUNDS = 3   # interleaved (full RK4, SP) rounds: each ratio from runs next to each other, the median reported


def touchdown(result):
    return result.summary.touchdown


def riser_peaks(result) -> dict:
    """Each main's riser peak (N) from the summary (the lumped case: its one riser's peak, shared by three)."""
    cluster = result.summary.cluster.get("main")
    if cluster is None:
        return {"lumped riser / 3": result.summary.peak_tension["main_riser"] / 3.0}
    return {canopy: (None if peak is None else peak["tension"]) for canopy, peak in cluster.riser_peak.items()}


def row(label: str, result) -> str:
    s = result.summary
    td = touchdown(result)
    peaks = riser_peaks(result)
    cluster = s.cluster.get("main")
    flyout = "" if cluster is None else " / ".join("-" if cluster.flyout_deg[c] is None else
                                                    f"{cluster.flyout_deg[c]['mean']:.1f}" for c in MAINS)
    share = "" if cluster is None else f"{cluster.peak_load_share:.3f} at {cluster.peak_load_share_time:.2f} s"
    return (f"| {label} | {td.time:.3f} | {td.speed:.3f} | {s.descent.mean_rate:.3f} | "
            + " / ".join("-" if v is None else f"{v / 1e3:.2f}" for v in peaks.values())
            + f" | {share} | {flyout} | {s.pendulum.max_vertical_deg:.2f} / {s.pendulum.rms_vertical_deg:.2f}"
            f" | {s.wall_time:.2f} |")


def plot_mains(nominal, main_out, reference) -> object:
    """The three mains' riser tensions and flyout angles, nominal (SP and full mass RK4) and with main3 out."""
    figure, axes = new_figure(2, 2, size=(12.0, 7.0), sharex=True)
    for column, (title, result) in enumerate((("all three mains (SP 1e-2 s; full mass RK4 5e-4 s dotted)", nominal),
                                              ("main3 never inflates (SP 1e-2 s)", main_out))):
        top, bottom = axes[0, column], axes[1, column]
        for k, canopy in enumerate(MAINS):
            tension, style = result[f"tension_main_riser{k + 1}"], ("-", "--", "-.")[k]   # equal curves stay visible
            if np.isfinite(tension).any():
                top.plot(result.time, tension / 1e3, style, color=f"C{k}", linewidth=0.8, label=canopy)
                bottom.plot(result.time, result[f"{canopy}_flyout_deg"], style, color=f"C{k}", linewidth=0.8,
                            label=canopy)
            if column == 0:
                top.plot(reference.time, reference[f"tension_main_riser{k + 1}"] / 1e3, ":", color=f"C{k}",
                         linewidth=0.8)
                bottom.plot(reference.time, reference[f"{canopy}_flyout_deg"], ":", color=f"C{k}", linewidth=0.8)
        top.set_title(title, fontsize="medium")
        top.set_ylabel("riser tension (kN)")
        bottom.set_ylabel("flyout from the cluster axis (deg)")
        bottom.set_xlabel("time since tower jettison (s)")
        for ax in (top, bottom):
            ax.set_xlim(9.0, 45.0)
            ax.grid(True, alpha=0.3)
        top.legend(fontsize="small")
    figure.suptitle("PA1 main cluster: each main's riser load and flyout angle (cases/cev_pa1_cluster*.toml)")
    return figure


def main(argv=None) -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    results = {}
    for label, case_file, method, integrator, step in RUNS:
        results[label] = pc.simulate(pc.load_case(case_file), method, integrator, step)
        print(f"  {label:30s} {results[label].summary.wall_time:7.2f} s", flush=True)
    case = pc.load_case(CLUSTER)
    rounds = []
    for _ in range(TIMING_ROUNDS):
        rounds.append((pc.simulate(case, "full", "rk4", 5e-4).summary.wall_time,
                       pc.simulate(case, "sp", "rk4", 1e-2).summary.wall_time))
        print(f"  timing round: full RK4 {rounds[-1][0]:.2f} s, SP {rounds[-1][1]:.2f} s", flush=True)
    save_figure(plot_mains(results[SP], results[OUT_SP], results[REFERENCE]), OUT / "mains.png")

    reference = results[REFERENCE]
    agree = ["| run | touchdown - full RK4 (s) | main riser peaks - full RK4 (%) | peak load share - full RK4 |",
             "|---|---|---|---|"]
    ref_peaks, ref_share = riser_peaks(reference), reference.summary.cluster["main"].peak_load_share
    for label in ("full implicit 1e-2", SP, "equilibrium 1e-2"):
        result = results[label]
        peaks = riser_peaks(result)
        agree.append(f"| {label} | {touchdown(result).time - touchdown(reference).time:+.3f} | "
                     + " / ".join(f"{100 * (peaks[c] / ref_peaks[c] - 1):+.2f}" for c in MAINS)
                     + f" | {result.summary.cluster['main'].peak_load_share - ref_share:+.3f} |")
    ratios = [full / sp for full, sp in rounds]
    timing = ["| round | full RK4 5e-4 s (s) | SP 1e-2 s (s) | speed-up |", "|---|---|---|---|"]
    timing += [f"| {i} | {full:.2f} | {sp:.2f} | {full / sp:.1f}x |" for i, (full, sp) in enumerate(rounds, 1)]

    nominal, out = results[SP].summary, results[OUT_SP].summary
    eta3, eta2 = DEFAULT_DRAG_EFFICIENCY[2], DEFAULT_DRAG_EFFICIENCY[1]
    expected = math.sqrt(1.5) * math.sqrt(eta3 / eta2)
    ratio = out["descent"]["mean_rate"] / nominal["descent"]["mean_rate"]
    rho = US76().density(1200.0)
    weight = (7500.0 + 3 * 141.0 + 8.0) * 3.986004418e14 / (6371000.0 + 1200.0) ** 2
    hand = {n: math.sqrt(2.0 * weight / (rho * n * DEFAULT_DRAG_EFFICIENCY[n - 1] * 0.80 * 982.0)) for n in (2, 3)}
    share = {k: v["peak_load_share"] for k, v in nominal["cluster"].items()}
    v = versions()
    header = ("| run | touchdown (s) | touchdown speed (m/s) | rate of descent, last 5 s (m/s) | main riser peaks "
              "(kN) | peak load share | mean flyout once open (deg) | capsule pendulum once open, max / RMS (deg) | "
              "wall time (s) |")
    text = "\n".join([
        "# Orion/CEV PA1 with its clusters as separate bodies",
        "",
        "`python validation/cev_pa1_cluster.py`; models `cases/cev_pa1_cluster.toml` (two drogue bodies, three main "
        "bodies, each on its own riser with its own reefed opening and canopy-canopy contact), "
        "`cases/cev_pa1_cluster_main_out.toml` (main3 never inflates) and, for comparison, "
        "`cases/cev_pa1_inflation.toml` (the same model with each cluster as one body). Representative values, not "
        f"flight data (the case files give their sources). One process, runs one after the other; Exudyn "
        f"{v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}, {v['platform']}.",
        "",
        header, "|---|---|---|---|---|---|---|---|---|",
        *[row(label, result) for label, result in results.items()],
        "",
        "Riser peaks are each main's largest riser tension over the run (the opening shock of its first reefed stage "
        "or a disreef); the lumped row gives its one riser's peak over three. Load share: the largest main riser "
        "tension over the mean of the mains' (1 = even), counted where the mean is at least 10 % of its largest. "
        "Flyout: each main's angle at the confluence from the cluster axis (confluence to the mains' mean centre), "
        "averaged from full open to touchdown.",
        "",
        "## SP and the equilibrium point against full mass RK4 5e-4 s",
        "",
        *agree,
        "",
        f"Speed, {TIMING_ROUNDS} rounds side by side (full mass RK4 at its stable 5e-4 s, SP at 1e-2 s):",
        "",
        *timing,
        "",
        f"Median speed-up of SP over full mass RK4: {statistics.median(ratios):.1f}x.",
        "",
        "## One main out",
        "",
        f"* Rate of descent over the last 5 s: {out['descent']['mean_rate']:.3f} m/s under two mains against "
        f"{nominal['descent']['mean_rate']:.3f} m/s under three, {ratio:.4f} times; sqrt(3/2) = {math.sqrt(1.5):.4f}, "
        f"and with the cluster drag efficiency of two canopies ({eta2:g}) against three ({eta3:g}) "
        f"sqrt(3/2) sqrt(eta3/eta2) = {expected:.4f} ({100 * (ratio / expected - 1):+.2f} %: the capsule's own drag, "
        "the same in both, and the flyout angles, which differ). The packed main stays in the capsule, so the weight "
        "is the same in both runs.",
        f"* Hand calculation at the 1200 m ground (rho = {rho:.4f} kg/m^3, the whole weight on the mains' drag, "
        f"C_A = 0.80 per main times eta): {hand[3]:.3f} m/s under three mains, {hand[2]:.3f} m/s under two; "
        f"CPAS's limit under two mains is 33 ft/s (10.06 m/s) at sea level.",
        "* Main riser peaks: " + ", ".join(f"{c} {riser_peaks(results[OUT_SP])[c] / 1e3:.1f} kN (nominal "
                                           f"{riser_peaks(results[SP])[c] / 1e3:.1f} kN)" for c in ("main1", "main2"))
        + "; main3 carries nothing.",
        f"* Peak load share, nominal: drogues {share['drogue']:.3f}, mains {share['main']:.3f}.",
        "",
        "![each main's riser load and flyout angle](mains.png)",
        ""])
    atomic_write_text(OUT / "pa1_cluster.md", text)
    print(text)
    return 0


if __name__ == "__main__":
    run_script(main)

"""Orion/CEV Pad Abort 1 descent (thesis section 3.2.2): full mass against singular perturbation, the event log, and
the thesis's figures.

Run:  python validation/cev_pa1.py

Runs `cases/cev_pa1.toml` (the representative model of docs/models/cev_pa1.md) with the full-mass model (RK4 at
the thesis's 5e-4 s; implicit at 1e-2 s), SP at 1e-2 s with the package's accurate preset (the confluence mass to
first order, kappa_max 10: the case's setting, both slack rules) and with the thesis's settings (massless Eq. 3.10,
kappa_max 5), SP order 1 at 2e-3 s (convergence) and the
equilibrium method at 1e-2 s, one after the other in one process, plus a diagnostic full-mass run with both
confluence masses divided by 100 (the massless limit). Writes
into validation/output/cev_pa1/: ``pa1.md`` (event log like thesis Table 3.9, agreement with the full-mass model,
wall times beside the thesis's 80.57 s and 35.80 s) and the figures of thesis Figs. 3.25-3.29 and 5.1-5.5.
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
from pchute_exudyn.results.compare import compare_results
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions
from pchute_exudyn.views.plotting import new_figure, plot_tension_overlay, save_figure

HERE = Path(__file__).resolve().parent
CASE = HERE.parent / "cases" / "cev_pa1.toml"
OUT = HERE / "output" / "cev_pa1"
RUNS = [("full rk4 5e-4", "full", "rk4", 5e-4, None, None),
        ("full implicit 1e-2", "full", "implicit", 1e-2, None, None),
        ("sp order 1 stretch 1e-2", "sp", "rk4", 1e-2, "stretch", 1),
        ("sp order 1 force 1e-2", "sp", "rk4", 1e-2, "force", 1),
        ("sp order 0 stretch 1e-2", "sp", "rk4", 1e-2, "stretch", 0),
        ("sp order 0 force 1e-2", "sp", "rk4", 1e-2, "force", 0),
        ("sp order 1 stretch 2e-3", "sp", "rk4", 2e-3, "stretch", 1),
        ("equilibrium 1e-2", "equilibrium", "rk4", 1e-2, None, None)]
SP_PRESET = {1: {"preset": "accurate", "order": 1}, 0: {"preset": "thesis", "order": 0}}
"""SP order 1 runs the package's accurate preset (kappa_max 10), order 0 the thesis's settings (kappa_max 5)."""
SP = "sp order 1 stretch 1e-2"          # the case's SP setting at the thesis's SP step
SP_THESIS = "sp order 0 stretch 1e-2"   # the thesis's massless SP
THESIS_EVENTS = [("Jettison tower (start)", "start", 21.00, 0.00), ("Deploy drogue parachutes", "deploy drogue", 24.50,
                 3.50), ("Deploy main parachutes", "deploy main", 30.50, 9.50),
                 ("Drogue cut-away", "cutaway drogue", None, None),
                 ("Attain 30 ft/s descent rate", "descent_rate", 52.74, 31.74), ("Touchdown", "touchdown", 99.87, 78.87)]
FULL_OPEN = 9.5 + 18.0   # s: the mains reach their full drag area 18 s after deployment
TIMING_ROUNDS = 3        # interleaved (full RK4, SP order 1, SP order 0) rounds for the speed-up: this machine is
                         # noisy, so each ratio comes from runs next to each other and the median is reported


def timing_rounds(case) -> list:
    """Wall times (s) of full RK4 5e-4, SP order 1 and SP order 0 at 1e-2, run one after the other, per round."""
    rounds = []
    for _ in range(TIMING_ROUNDS):
        rounds.append([pc.simulate(case, "full", "rk4", 5e-4).summary.wall_time,
                       pc.simulate(case, "sp", "rk4", 1e-2, **SP_PRESET[1]).summary.wall_time,
                       pc.simulate(case, "sp", "rk4", 1e-2, **SP_PRESET[0]).summary.wall_time])
        full, order1, order0 = rounds[-1]
        print(f"  timing round: full {full:.2f} s, sp order 1 {order1:.2f} s, sp order 0 {order0:.2f} s", flush=True)
    return rounds


def event_time(result, key):
    for e in result.summary.events:
        system = getattr(e, "system", None)
        label = e.kind if system is None else f"{e.kind} {system}"
        if label == key:
            return e.time
    return None


def touchdown(result):
    return result.summary.touchdown


def plot_lines(results, system, title, t_range=None):
    lines = [f"{system}_bridle1", f"{system}_bridle2", f"{system}_bridle3", f"{system}_riser"]
    figure = plot_tension_overlay(results, lines, title=title, t_max=None if t_range is None else t_range[1])
    if t_range is not None:
        for ax in figure.axes:
            ax.set_xlim(*t_range)
    return figure


def plot_columns(results, columns, ylabels, title, t_range=None):
    figure, axes = new_figure(len(columns), 1, size=(9.0, 2.3 * len(columns) + 0.8), sharex=True)
    for ax, column, ylabel in zip(axes[:, 0], columns, ylabels):
        for label, result in results.items():
            ax.plot(result.time, result[column], label=label, linewidth=0.8)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        if t_range is not None:   # scale the values to the window, not to the whole descent
            ax.set_xlim(*t_range)
            shown = np.concatenate([r[column][(r.time >= t_range[0]) & (r.time <= t_range[1])]
                                    for r in results.values()])
            shown = shown[np.isfinite(shown)]
            if shown.size:
                pad = 0.05 * max(shown.max() - shown.min(), 1e-9)
                ax.set_ylim(shown.min() - pad, shown.max() + pad)
    axes[0, 0].legend(fontsize="small")
    axes[-1, 0].set_xlabel("time since tower jettison (s)")
    figure.suptitle(title)
    return figure


def main(argv=None) -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    case = pc.load_case(CASE)
    results = {}
    for label, method, integrator, step, rule, order in RUNS:
        results[label] = pc.simulate(case, method, integrator, step, slack_rule=rule, **SP_PRESET.get(order, {}))
        print(f"  {label:22s} {results[label].summary.wall_time:7.2f} s", flush=True)
    rounds = timing_rounds(case)
    light = pc.load_case(CASE, {"systems.main.confluence.mass": 0.08, "systems.drogue.confluence.mass": 0.03})
    results_light = pc.simulate(light, "full", "implicit", 1e-3)
    reference = results["full rk4 5e-4"]
    shown = {k: results[k] for k in ("full rk4 5e-4", SP, SP_THESIS, "equilibrium 1e-2")}

    # figures (thesis Figs. 3.25-3.29, 5.1-5.5)
    save_figure(plot_lines(shown, "main", "PA1 main system line tensions (thesis Figs. 3.25-3.27, 5.1)"),
                OUT / "tensions_main.png")
    save_figure(plot_lines(shown, "main", "PA1 main system line tensions, deployment and disreefing",
                           (9.0, 32.0)), OUT / "tensions_main_deployment.png")
    save_figure(plot_lines(shown, "drogue", "PA1 drogue system line tensions", (3.0, 10.0)),
                OUT / "tensions_drogue.png")
    save_figure(plot_columns(shown, [f"main_confluence_relative_velocity_{a}" for a in "xyz"],
                             [f"{a} (m/s)" for a in "xyz"],
                             "Main confluence velocity relative to the capsule, capsule body axes (thesis Fig. 3.28)",
                             (9.0, 40.0)), OUT / "confluence_relative_velocity.png")
    save_figure(plot_columns(shown, ["capsule_yaw_deg", "capsule_pitch_deg", "capsule_roll_deg"],
                             ["yaw (deg)", "pitch (deg)", "roll (deg)"],
                             "Capsule attitude angles (descent frame: down, east, south; thesis Fig. 3.29)"),
                OUT / "capsule_attitude.png")
    save_figure(plot_columns(shown, ["capsule_alpha_deg", "capsule_beta_deg", "capsule_angle_of_attack_deg"],
                             ["alpha (deg)", "beta (deg)", "total (deg)"],
                             "Capsule angle of attack and sideslip (thesis Fig. 5.3)"), OUT / "capsule_alpha_beta.png")
    save_figure(plot_columns(shown, [f"main_canopy_relative_position_{a}" for a in "xyz"],
                             [f"{a} (m)" for a in "xyz"],
                             "Main canopy position relative to the capsule, capsule body axes (thesis Fig. 5.4)"),
                OUT / "parachute_relative_position.png")
    save_figure(plot_columns(shown, [f"main_canopy_relative_velocity_{a}" for a in "xyz"],
                             [f"{a} (m/s)" for a in "xyz"],
                             "Main canopy velocity relative to the capsule, capsule body axes (thesis Fig. 5.5)"),
                OUT / "parachute_relative_velocity.png")
    rocking = {k: results[k] for k in ("full rk4 5e-4", SP, SP_THESIS)}
    save_figure(plot_columns({**rocking, "full, confluence masses / 100": results_light}, ["capsule_yaw_deg"],
                             ["yaw (deg)"], "Capsule rocking under the full mains: order-0 SP is the massless limit, "
                             "order 1 keeps the confluence mass", (60.0, 70.0)), OUT / "capsule_rocking.png")

    # event log (thesis Table 3.9)
    rows = ["| event | thesis (2009 plan): since ignition (s) | thesis (2009 plan): simulation (s) | " + " | ".join(results) + " |",
            "|---|---|---|" + "---|" * len(results)]
    for name, key, since_ignition, simulated in THESIS_EVENTS:
        ours = []
        for result in results.values():
            t = event_time(result, key)
            ours.append("" if t is None else f"{t:.2f}")
        rows.append(f"| {name} | {'' if since_ignition is None else f'{since_ignition:.2f}'} | "
                    f"{'' if simulated is None else f'{simulated:.2f}'} | " + " | ".join(ours) + " |")
    rows.append("| touchdown speed (m/s) | | | " + " | ".join(f"{touchdown(r).speed:.3f}" for r in results.values())
                + " |")

    # steady-descent hand calculation: the weight of everything under way (capsule, main canopy, main confluence)
    # carried by the full mains' drag, 1/2 rho v^2 C_A S, at the ground
    rho = US76().density(1200.0)
    weight = (7500.0 + 423.0 + 8.0) * 3.986004418e14 / (6371000.0 + 1200.0) ** 2
    hand = math.sqrt(2.0 * weight / (rho * 0.76 * 2946.0))

    # agreement with the full-mass RK4 reference
    agree = ["| run | touchdown time diff (s) | touchdown position diff (m) | max |attitude angle diff| after "
             f"{FULL_OPEN:g} s (deg): yaw / pitch / roll | largest tension diff after {FULL_OPEN:g} s, max (RMS) (N) |"
             " wall time (s) | speed-up over full RK4 |", "|---|---|---|---|---|---|---|"]
    ref_td = touchdown(reference)
    for label, result in list(results.items()) + [("full implicit 1e-3, confluence masses / 100", results_light)]:
        if result is reference:
            continue
        td = touchdown(result)
        m = (reference.time > FULL_OPEN) & (reference.time <= min(reference.time[-1], result.time[-1]))
        angles = [np.abs(np.interp(reference.time[m], result.time, result[c]) - reference[c][m]).max()
                  for c in ("capsule_yaw_deg", "capsule_pitch_deg", "capsule_roll_deg")]
        c = compare_results(reference, result, settle_time=FULL_OPEN, vehicle="capsule", confluence="main_confluence")
        worst = max(((k, m) for k, m in c.lines.items() if np.isfinite(m["max_settled"])),
                    key=lambda item: item[1]["max_settled"])
        agree.append(f"| {label} | {td.time - ref_td.time:+.3f} | {c.final['capsule lateral position']:.3f} "
                     f"(altitude {c.final['capsule altitude']:+.2f}) | "
                     f"{angles[0]:.2f} / {angles[1]:.3f} / {angles[2]:.2f} | {worst[0]}: "
                     f"{worst[1]['max_settled']:.0f} ({worst[1]['rms_settled']:.0f}) | "
                     f"{result.summary.wall_time:.2f} | "
                     f"{reference.summary.wall_time / result.summary.wall_time:.1f}x |")
    per_line = ["| line | " + " | ".join(k for k in results if k != "full rk4 5e-4") + " |",
                "|---|" + "---|" * (len(results) - 1)]
    comparisons = {k: compare_results(reference, r, settle_time=FULL_OPEN, vehicle="capsule",
                                      confluence="main_confluence") for k, r in results.items() if r is not reference}
    for line in comparisons[SP].lines:
        cells = [f"{c.lines[line]['max']:.0f} / {c.lines[line]['rms']:.0f}" for c in comparisons.values()]
        per_line.append(f"| {line} | " + " | ".join(cells) + " |")
    ratios = [full / order1 for full, order1, _ in rounds]
    ratios_thesis = [full / order0 for full, _, order0 in rounds]
    timing = ["| round | full RK4 5e-4 s (s) | SP order 1, 1e-2 s (s) | speed-up | SP order 0, 1e-2 s (s) | speed-up |",
              "|---|---|---|---|---|---|"]
    for i, ((full, order1, order0), r1, r0) in enumerate(zip(rounds, ratios, ratios_thesis), 1):
        timing.append(f"| {i} | {full:.2f} | {order1:.2f} | {r1:.1f}x | {order0:.2f} | {r0:.1f}x |")
    massless = results[SP_THESIS]
    m = (massless.time > FULL_OPEN) & (massless.time <= min(massless.time[-1], results_light.time[-1]))
    sp_vs_light = np.abs(np.interp(massless.time[m], results_light.time, results_light["capsule_yaw_deg"])
                         - massless["capsule_yaw_deg"][m]).max()
    v = versions()
    text = "\n".join([
        "# Orion/CEV Pad Abort 1: full mass against singular perturbation",
        "",
        "`python validation/cev_pa1.py`; model `cases/cev_pa1.toml` (docs/models/cev_pa1.md: representative values,",
        "not flight data). Times from tower jettison. Runs one after the other in one process; "
        f"Exudyn {v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}, {v['platform']}.",
        "",
        "## Event log (thesis Table 3.9)",
        "",
        "The thesis columns are Table 3.9: the timeline the thesis simulated in 2009, before PA-1 flew (6 May 2010), "
        "not flight data. docs/models/cev_pa1.md (\"The thesis's timeline beside the flight\") sets the flight's "
        "public figures beside it.",
        "",
        *rows,
        "",
        f"Steady-descent hand calculation with the model's main drag area (C_A S = 0.76 x 2946 m^2, rho = {rho:.4f} "
        f"kg/m^3 at the 1200 m ground, carrying the weight of capsule, main canopy and confluence): {hand:.3f} m/s; "
        f"the full-mass touchdown speed is {ref_td.speed:.3f} m/s ({100 * (ref_td.speed / hand - 1):+.1f}%: the "
        "capsule's own drag).",
        "",
        "## Agreement with the full-mass RK4 5e-4 s reference",
        "",
        *agree,
        "",
        "Tension differences per line over the whole descent, max / RMS (N):",
        "",
        *per_line,
        "",
        "## Speed-up, measured side by side",
        "",
        f"{TIMING_ROUNDS} rounds, each running the full-mass RK4 reference and both SP orders one after the other (the "
        "wall times in the table above come from single runs and vary by 10% or more on this machine):",
        "",
        *timing,
        "",
        f"Median speed-up of SP at 1e-2 s over the full-mass RK4 run at 5e-4 s: {statistics.median(ratios):.1f}x "
        f"(order 1), {statistics.median(ratios_thesis):.1f}x (order 0); thesis: 80.57 s and 35.80 s, 2.25x, POST2 "
        "on a 2.8 GHz Pentium.",
        "",
        "Notes:",
        "",
        "* Under the full mains the capsule rocks on its bridles at about 1.2 Hz, +-2 deg decaying slowly "
        "(`capsule_rocking.png`), and the 8 kg main confluence moves with it. The thesis's massless SP (order 0) runs "
        "that mode about 0.5 % fast, so over 45 s its rocking drifts out of phase with the full-mass model's: that "
        "is its capsule yaw difference above. With both confluence masses divided by 100 the full-mass run agrees "
        f"with order-0 SP to {sp_vs_light:.2f} deg in yaw after {FULL_OPEN:g} s: order 0 is the massless limit, and "
        "its difference is the confluence mass's physics, not SP's numerics.",
        "* SP order 1 (the case's setting) keeps the confluence's weight and inertia to first order in the same "
        "solve (backward-difference acceleration; `pchute_exudyn.methods.sp`) at the same step and "
        "cost: it follows the full-mass rocking, tensions and touchdown time, and converges to the full-mass model "
        "as the step falls (the 2e-3 s row).",
        "* The implicit full-mass run keeps the confluence mass and agrees closely with the RK4 reference at 1e-2 s.",
        ""])
    atomic_write_text(OUT / "pa1.md", text)
    print(text)
    return 0


if __name__ == "__main__":
    run_script(main)

"""MER cases 1-6: the singular-perturbation and equilibrium-point methods against the full-mass model, beside the
thesis's numbers.

Run:  python validation/mer_compare.py [--cases 1 2 ...] [--reuse]

For each case it runs the full-mass model (RK4 at the thesis step 1e-4 s, the reference), the SP method with both
slack rules at the thesis steps (1e-2 s for cases 1-4; 2e-3 s and 1e-2 s for cases 5-6), the equilibrium-point method
(Raiszadeh, the thesis's ref. 7) at 1e-2 s, and the full-mass model with the implicit integrator at 1e-2 s. It writes
into validation/output/mer/:

* ``mer_table.md``: one row per case, method and step: final vehicle altitude and lateral position differences from
  the reference beside the thesis's (section 3.2.1), the largest tension difference per line after the first 2 s,
  the wall time and the speed-up over the reference;
* ``case<N>_tensions.png`` and ``case<N>_tensions_first10s.png`` (thesis Figs. 3.5-3.10, 3.12-3.14, 3.16-3.18,
  3.20-3.22) and ``case<N>_confluence_velocity.png`` (Figs. 3.11, 3.15, 3.19, 3.23): full and SP overlaid.

Runs are sequential so wall times are comparable. With --reuse, runs already in output/mer/runs/ are read back
instead of recomputed (their wall times are those measured when they ran).
"""

from __future__ import annotations

import time
from pathlib import Path

from script_arguments import OneLineParser, run_script


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--cases", type=int, nargs="+", default=[1, 2, 3, 4, 5, 6], choices=range(1, 7))
    parser.add_argument("--reuse", action="store_true", help="read runs already saved instead of recomputing")
    args = parser.parse_args(argv)
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.results.compare import compare_results
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions as library_versions
from pchute_exudyn.views.plotting import plot_confluence_velocity_overlay, plot_tension_overlay, save_figure

HERE = Path(__file__).resolve().parent
CASES = HERE.parent / "cases" / "mer"
OUT = HERE / "output" / "mer"

# thesis section 3.2.1: SP minus full-mass final altitude and lateral position (m), by case and SP step
THESIS = {(1, 1e-2): (9.8, 0.0), (2, 1e-2): (9.9, 0.0), (3, 1e-2): (9.0, 1.2), (4, 1e-2): (9.3, 0.95),
          (5, 2e-3): (2.0, 0.02), (5, 1e-2): (8.5, 0.65), (6, 2e-3): (1.9, 0.026)}
FIGURES = {1: "3.5", 2: "3.6-3.7", 3: "3.8-3.11", 4: "3.12-3.15", 5: "3.16-3.19", 6: "3.20-3.23"}


def runs_for(case_number: int) -> list:
    """(label, method, integrator, step, slack rule, SP order) of every run of a case; the first is the reference.
    "sp" runs are the thesis's massless SP (order 0); "sp order1" keeps the confluence mass to first order."""
    sp_steps = [1e-2] if case_number <= 4 else [2e-3, 1e-2]
    runs = [("full rk4 1e-4", "full", "rk4", 1e-4, None, None)]
    for step in sp_steps:
        for rule in ("stretch", "force"):
            runs.append((f"sp {rule} {step:g}", "sp", "rk4", step, rule, 0))
        runs.append((f"sp order1 stretch {step:g}", "sp", "rk4", step, "stretch", 1))
    if case_number in (3, 4):  # diagnostic: the slack-phase C_c at a large step is what shifts the tension phase
        runs.append(("sp stretch 0.001", "sp", "rk4", 1e-3, "stretch", 0))
    runs.append(("equilibrium 0.01", "equilibrium", "rk4", 1e-2, None, None))
    runs.append(("full implicit 1e-2", "full", "implicit", 1e-2, None, None))
    return runs


def run_case(case_number: int, reuse: bool) -> dict:
    case = pc.load_case(CASES / f"case{case_number}.toml")
    results = {}
    for label, method, integrator, step, rule, order in runs_for(case_number):
        folder = OUT / "runs" / f"case{case_number}_{label.replace(' ', '_')}"
        if reuse and (folder / "timeseries.csv").is_file():
            results[label] = pc.Result.load(folder)
        else:
            started = time.perf_counter()
            results[label] = pc.simulate(case, method, integrator, step, slack_rule=rule, order=order)
            results[label].save(folder, plot=False, overwrite=True)
            print(f"  case {case_number} {label:22s} {time.perf_counter() - started:7.2f} s", flush=True)
    return results


def table_rows(case_number: int, results: dict) -> list:
    reference_label = next(iter(results))
    reference = results[reference_label]
    rows = []
    for label, result in results.items():
        if label == reference_label:
            rows.append(f"| {case_number} | {label} | reference: {reference.final('vehicle_altitude'):.2f} m | | "
                        f"{np.hypot(reference.final('vehicle_east'), reference.final('vehicle_north')):.3f} m | | "
                        "| | | | " f"{reference.summary.wall_time:.2f} | 1 |")
            continue
        c = compare_results(reference, result, reference_label, label, settle_time=2.0)
        step = result.summary.step
        massless = result.summary.method == "sp" and result.summary.method_settings.get("sp_order", 0) == 0
        thesis = THESIS.get((case_number, step)) if massless else None
        thesis_alt, thesis_lat = (f"{thesis[0]:g}", f"{thesis[1]:g}") if thesis else ("", "")
        tension = [f"{c.lines[line]['max_settled']:.2f} ({c.lines[line]['rms_settled']:.2f})"
                   for line in ("bridle1", "bridle2", "bridle3", "riser")]
        speedup = reference.summary.wall_time / result.summary.wall_time
        rows.append(f"| {case_number} | {label} | {c.final['vehicle altitude']:+.3f} | {thesis_alt} | "
                    f"{c.final['vehicle lateral position']:.3f} | {thesis_lat} | " + " | ".join(tension)
                    + f" | {result.summary.wall_time:.2f} | {speedup:.1f} |")
    return rows


def figures(case_number: int, results: dict) -> None:
    title = f"MER case {case_number} (thesis Figs. {FIGURES[case_number]})"
    save_figure(plot_tension_overlay(results, title=f"{title}: line tensions"),
                OUT / f"case{case_number}_tensions.png")
    save_figure(plot_tension_overlay(results, title=f"{title}: line tensions, first 10 s", t_max=10.0),
                OUT / f"case{case_number}_tensions_first10s.png")
    save_figure(plot_confluence_velocity_overlay(results, title=f"{title}: confluence lateral velocity"),
                OUT / f"case{case_number}_confluence_velocity.png")


HEADER = """# MER cases 1-6: singular perturbation, equilibrium point and implicit full mass against the full-mass RK4 reference

Reference: full-mass model, RK4 at 1e-4 s (the thesis's reference). Differences are run minus reference at 60 s;
"thesis" columns are the SP - full differences of Fuller (2009), section 3.2.1 (POST2). Tension columns: largest
|difference| after the first 2 s, and in brackets its RMS (N). Wall times measured one run after another in one
process (`python validation/mer_compare.py`); speed-up = reference wall time / run wall time. The "sp stretch 0.001"
rows of cases 3-4 are a diagnostic beyond the thesis's runs (see the notes below the table).

| case | run | final altitude diff (m) | thesis (m) | final lateral diff (m) | thesis (m) | bridle1 (N) | bridle2 (N) | bridle3 (N) | riser (N) | wall time (s) | speed-up |
|---|---|---|---|---|---|---|---|---|---|---|---|
"""


NOTES = """Notes (measured with this script and `validation/output/mer/case*_tensions_first10s.png`):

* Final positions: SP is within 0.26 m in altitude and 0.09 m laterally of the full-mass reference in every case
  and step with the stretch rule (0.58 m and 0.15 m with the force rule; the thesis's POST2 differences: 1.9-9.9 m
  and up to 1.2 m).
* SP order 1 (`--sp-order 1`, the confluence's weight and inertia to first order): the +0.24 m altitude bias of the
  massless SP is the confluence's missing weight (0.15 kg of 777 kg) and vanishes (within 0.03 m in every case);
  in the swinging cases 5-6 the bridle-tension differences fall from 7-8.5 N to 0.04-0.11 N at either step. In
  the slack-heavy cases 3-4 it changes little: there the C_c episodes at a 0.01 s step dominate.
* Case 1 (and 2), stretch rule: bridles within 0.4 N and riser within 0.6 N after 2 s (thesis: 1 N and 6 N).
* Cases 3-4: the largest tension differences after 2 s are tens of newtons because SP's oscillation lags the
  reference by a few hundredths of a second while the swing-and-bounce oscillation grows to +-75 N (thesis: "the
  same phase lag seen in test case 2"). The lag is set in the first second: all lines start at free length (slack by
  definition), so C_c ties the confluence to its previous velocity through whole 0.01 s steps while the vehicle
  moves at 1 m/s, giving spikes of about 130 N where the full-mass tensions are near zero (the thesis's "erratic
  force profile"). At 1e-3 s the same SP runs differ by at most 4.2 N (RMS 1.7 N), ten times less (diagnostic
  rows), so the lag is an effect of the step, not of removing the confluence mass. Raising kappa_max from the
  thesis's 5 to 10 does as well, at 0.01 s and no extra cost (case 4: 82 N -> 4.2 N;
  `validation/output/studies/kappa_max/`).
* The force (active-set) rule does not track the reference better here: dropping a line whose linear tension dips
  negative brings in C_c more often, and each C_c episode at a 0.01 s step adds phase error. Its discontinuous
  set changes also amplify the 1e-7 asymmetry of mer.md's 7-digit attach points into a 5 cm lateral drift in
  case 1, where the full-mass model and the stretch rule stay on the vertical; for the same reason its results move
  by centimetres with round-off-level changes to the code.
* The equilibrium-point method (no confluence states; the confluence at the balance of the line *stiffness* forces,
  moving with the Appendix B velocity) matches SP in cases 1-2 and places the vehicle as well everywhere (within
  0.24 m and 0.01 m). It needs no confluence damping, so its tensions in the slack-heavy cases 3-4 lag less than
  SP's at 0.01 s. But it damps swinging: its confluence ignores the line damping in the balance, so in a rigid swing
  the bridles see a spurious stretch rate and their damping drains the swing (case 5-6 bridle swing amplitude about
  half the reference's, differences up to 69 N). Its warm-started, damped Newton solves converged at every stage
  (0 failures in 30 000 solves per case, at most 5 iterations). It costs about twice SP's time.
* The implicit full-mass model at 1e-2 s is faster than both at the same step and closer to the reference.
"""


def main(argv=None) -> int:
    args = arguments(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    rows = []
    for number in args.cases:
        results = run_case(number, args.reuse)
        rows.extend(table_rows(number, results))
        figures(number, results)
    versions = library_versions()
    text = HEADER + "\n".join(rows) + "\n\n" + NOTES + (f"\nExudyn {versions['exudyn']}, pchute-exudyn {versions['pchute_exudyn']}, "
                                       f"Python {versions['python']}, {versions['platform']}.\n")
    atomic_write_text(OUT / "mer_table.md", text)
    print(text)
    return 0


if __name__ == "__main__":
    run_script(main)

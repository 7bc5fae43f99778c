"""PA1 and MER with aerodynamic databases: SP against full mass, and the swing with and without the databases.

Run:  python validation/cev_pa1_aero.py

Writes validation/output/aero/pa1_aero.md:

* ``cases/cev_pa1_aero.toml`` (the capsule's C_A, C_N, C_m over Mach and angle of attack with pitch and roll
  damping; the canopies' C_A and C_N over the angle with pitch damping) with full mass RK4 at the thesis's step
  (5e-4 s, the reference), full mass implicit and SP at 1e-2 s: touchdown, and the capsule's pendulum angle under
  the open mains (from 27.5 s: its swing amplitude, ``analysis.swing_amplitude``, its largest value and RMS) and
  under the drogues (4.5 to 9.5 s), each to the vertical and to the airspeed;
* the same case without the capsule's database (cev_pa1.toml's constants: C_A 1.25, its C_N table, no moment, no
  damping) and cev_pa1.toml itself, to read what the databases change;
* MER case 5 with and without the parachute's C_m and pitch damping (``cases/mer/case5_aero.toml``, stable about
  zero angle of attack) and with a disk-gap-band trimming at 5 deg (``cases/mer/case5_aero_trim.toml``), SP against
  full RK4 at the thesis's step, 30 s: the vehicle's swing, the canopy's mean angle of attack once settled, the drift.
"""

from __future__ import annotations

from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.analysis import swing_amplitude
from pchute_exudyn.run.simulation import versions

HERE = Path(__file__).resolve().parent
CASES = HERE.parent / "cases"
OUT = HERE / "output" / "aero"
MAINS_OPEN, DROGUES_OPEN, MAINS_DEPLOY = 27.5, 4.5, 9.5   # s (cev_pa1.toml's schedules)
MER_SETTLED = 15.0
"""MER case 5: from this time (s) the canopy has settled on its trim; its mean angle of attack is taken after it."""
NO_CAPSULE_DATABASE = {   # cev_pa1.toml's capsule: constants, no moment, no damping
    "bodies.capsule.aerodynamics.axial_coefficient": 1.25,
    "bodies.capsule.aerodynamics.normal_coefficient": {"alpha_deg": [0.0, 10.0, 20.0, 30.0, 45.0, 60.0, 90.0],
                                                       "value": [0.0, 0.05, 0.10, 0.14, 0.18, 0.18, 0.10]},
    "bodies.capsule.aerodynamics.moment_coefficient": 0.0, "bodies.capsule.aerodynamics.pitch_damping": 0.0,
    "bodies.capsule.aerodynamics.roll_damping": 0.0}
PA1_RUNS = [("databases", "cev_pa1_aero.toml", {}), ("no capsule database", "cev_pa1_aero.toml", NO_CAPSULE_DATABASE),
            ("cev_pa1.toml (constants, no damping)", "cev_pa1.toml", {})]
METHODS = [("full rk4 5e-4", "full", "rk4", 5e-4), ("full implicit 1e-2", "full", "implicit", 1e-2),
           ("sp 1e-2", "sp", "rk4", 1e-2)]


def touchdown(result) -> float:
    return result.summary.touchdown.time


def swing(columns, column: str, start: float, end: float = np.inf) -> tuple:
    """(amplitude, largest) of ``column`` (deg) between ``start`` and ``end`` (s)."""
    window = (columns["time"] >= start) & (columns["time"] <= end)
    values = columns[column][window]
    values = values[np.isfinite(values)]
    return swing_amplitude(values), float(values.max())


def pa1_rows() -> tuple[list, dict]:
    rows, results = [], {}
    for name, case_file, overrides in PA1_RUNS:
        case = pc.load_case(CASES / case_file, overrides)
        for label, method, integrator, step in METHODS:
            if name != "databases" and method == "full" and integrator == "rk4":
                continue   # the reference only for the databases case
            result = pc.simulate(case, method, integrator, step)
            results[(name, label)] = result
            c = result.columns
            mains = [swing(c, f"capsule_pendulum{kind}_deg", MAINS_OPEN) for kind in ("", "_airspeed")]
            drogues = swing(c, "capsule_pendulum_deg", DROGUES_OPEN, MAINS_DEPLOY)
            rows.append(f"| {name} | {label} | {touchdown(result):.3f} | {mains[0][0]:.3f} / {mains[0][1]:.3f} | "
                        f"{mains[1][0]:.3f} / {mains[1][1]:.3f} | {drogues[0]:.2f} / {drogues[1]:.2f} | "
                        f"{result.summary.wall_time:.2f} |")
            print(rows[-1], flush=True)
    return rows, results


def agreement_rows(results: dict) -> list:
    reference = results[("databases", "full rk4 5e-4")]
    rows = []
    for label in ("full implicit 1e-2", "sp 1e-2"):
        result = results[("databases", label)]
        amplitude = [swing(r.columns, f"capsule_pendulum{kind}_deg", MAINS_OPEN)[0] for r in (result, reference)
                     for kind in ("", "_airspeed")]
        rows.append(f"| {label} | {touchdown(result) - touchdown(reference):+.3f} | "
                    f"{amplitude[0] - amplitude[2]:+.3f} | {amplitude[1] - amplitude[3]:+.3f} |")
    return rows


def mer_rows() -> list:
    rows = []
    for name in ("case5.toml", "case5_aero.toml", "case5_aero_trim.toml"):
        case = pc.load_case(CASES / "mer" / name)
        amplitudes = {}
        for label, method, integrator, step in (("full rk4 1e-4", "full", "rk4", 1e-4), ("sp", "sp", "rk4", None)):
            result = pc.simulate(case, method, integrator, step, 30.0)
            amplitudes[label] = swing(result.columns, "vehicle_pendulum_deg", 0.0)
            late = result["time"] >= MER_SETTLED
            rows.append(f"| {name} | {label} | {amplitudes[label][0]:.3f} | {amplitudes[label][1]:.3f} | "
                        f"{np.mean(result['parachute_angle_of_attack_deg'][late]):.2f} | "
                        f"{result['vehicle_east'][-1]:+.2f} | {result.summary.wall_time:.2f} |")
            print(rows[-1], flush=True)
        rows.append(f"| {name} | sp - full rk4 | {amplitudes['sp'][0] - amplitudes['full rk4 1e-4'][0]:+.3f} | | | | |")
    return rows


def main(argv=None) -> int:
    pa1, results = pa1_rows()
    agreement = agreement_rows(results)
    mer = mer_rows()
    v = versions()
    text = ["# PA1 and MER with aerodynamic databases", "",
            f"`python validation/cev_pa1_aero.py`; models `cases/cev_pa1_aero.toml` and `cases/mer/case5_aero.toml` "
            f"(representative values; the case files give their sources and say which are assumed). One process, "
            f"runs one after the other; Exudyn {v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}, {v['kernels']} "
            f"kernels, {v['platform']}.", "",
            "## PA1: the capsule's swing", "",
            "| model | run | touchdown (s) | under the open mains, to the vertical: amplitude / largest (deg) | "
            "under the open mains, to the airspeed: amplitude / largest (deg) | under the drogues, to the vertical: "
            "amplitude / largest (deg) | wall time (s) |", "|---|---|---|---|---|---|---|", *pa1, "",
            "Under the open mains: from 27.5 s (full drag area) to touchdown; under the drogues: from their full "
            "drag area (4.5 s) to the mains' deployment (9.5 s). The amplitude is the mean of the swing's peaks "
            "(`analysis.swing_amplitude`, the summary's `pendulum.amplitude_*`).", "",
            "## PA1 with the databases: SP and full mass implicit against full mass RK4 5e-4 s", "",
            "| run | touchdown - full RK4 (s) | amplitude to the vertical - full RK4 (deg) | amplitude to the airspeed "
            "- full RK4 (deg) |", "|---|---|---|---|", *agreement, "",
            "## MER case 5: the vehicle's swing with and without the parachute's moment and damping (30 s)", "",
            "`case5_aero.toml`'s disk-gap-band is statically stable about zero angle of attack; "
            "`case5_aero_trim.toml`'s trims at 5 deg (assumed; Cruz et al., AIAA 2003-2129, found disk-gap-bands "
            "trimming at non-zero angles), and glides there.", "",
            f"| case | run | amplitude (deg) | largest (deg) | parachute angle of attack, mean over {MER_SETTLED:g}-30 s "
            "(deg) | vehicle east at 30 s (m) | wall time (s) |", "|---|---|---|---|---|---|---|", *mer, ""]
    OUT.mkdir(parents=True, exist_ok=True)
    atomic_write_text(OUT / "pa1_aero.md", "\n".join(text))
    print("\n".join(text))
    return 0


if __name__ == "__main__":
    run_script(main)

"""The aerodynamic-database closed forms through the engine (docs/models/aerodatabase.md, "Checks").

Run:  python validation/aero_checks.py

The case is the test suite's tests/cases/pivot_wind.toml (tests/integration/test_aerodatabase.py asserts the same checks): a
body pivoted at its centre of mass (1e12 kg, no gravity) in a uniform steady wind of V = 20 m/s, q = 4 Pa, S = 2 m^2,
d = 1.5 m, I = 10 kg m^2 (transverse), I_xx = 5 kg m^2. Writes validation/output/aero/closed_forms.md:

* C_m = C_malpha alpha (C_malpha = -0.5 /rad): the swing's frequency against omega^2 = -q S d C_malpha / I, with
  every method;
* with pitch damping C_mq = -2: the damping ratio from the decay of the swing's peaks against
  zeta = -q S d^2 C_mq / (4 V I omega);
* roll damping C_lp = -2, aligned and spinning: the roll rate's decay against lambda = -q S d^2 C_lp / (2 V I_xx);
* drag over Mach (C_A = 0.9, 1.0, 1.5, 1.3 at Mach 0.3, 0.8, 1.2, 2.0, a = 300 m/s): the force of the stage kernel
  at Mach 0.5, 1.1 and 2.5 against q S C_A(M);
* MER case 1 with C_A and C_N as Mach tables equal to its constants against the constants (largest difference over
  every column).
"""

from __future__ import annotations

import math
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions

HERE = Path(__file__).resolve().parent
PIVOT = HERE.parent / "tests" / "cases" / "pivot_wind.toml"
MER1 = HERE.parent / "cases" / "mer" / "case1.toml"
OUT = HERE / "output" / "aero"
DENSITY, WIND, AREA, LENGTH, INERTIA, ROLL_INERTIA, SOUND = 0.02, 20.0, 2.0, 1.5, 10.0, 5.0, 300.0
PRESSURE = 0.5 * DENSITY * WIND ** 2
MOMENT_SLOPE, PITCH_DAMPING, ROLL_DAMPING = -0.5, -2.0, -2.0
METHODS = [("full mass", "full"), ("SP", "sp"), ("equilibrium point", "equilibrium")]
MACH_DRAG = {"mach": [0.3, 0.8, 1.2, 2.0], "value": [0.9, 1.0, 1.5, 1.3]}


def crossings(time, signal):
    i = np.flatnonzero((signal[:-1] < 0.0) != (signal[1:] < 0.0))
    return time[i] - signal[i] * (time[i + 1] - time[i]) / (signal[i + 1] - signal[i])


def swing(overrides=None, method="full"):
    columns = pc.simulate(pc.load_case(PIVOT, overrides or {}), method).columns
    return columns["time"], columns["body_yaw_deg"] + 90.0, columns


def omega_closed() -> float:
    return math.sqrt(-PRESSURE * AREA * LENGTH * MOMENT_SLOPE / INERTIA)


def frequency_rows() -> list:
    rows = []
    for label, method in METHODS:
        time, angle, _ = swing(method=method)
        omega = 2.0 * math.pi / (2.0 * np.mean(np.diff(crossings(time, angle))))
        rows.append((f"frequency, {label}", f"{omega:.9f} rad/s", f"{omega_closed():.9f} rad/s",
                     f"{omega / omega_closed() - 1:+.1e}", "1e-3"))
    return rows


def damping_row() -> tuple:
    time, angle, _ = swing({"bodies.body.aerodynamics.pitch_damping": PITCH_DAMPING})
    inner = np.abs(angle[1:-1])
    peaks = np.flatnonzero((inner > np.abs(angle[:-2])) & (inner >= np.abs(angle[2:]))) + 1
    decay = -np.polyfit(time[peaks], np.log(np.abs(angle[peaks])), 1)[0]
    damped = 2.0 * math.pi / (2.0 * np.mean(np.diff(crossings(time, angle))))
    zeta = decay / math.hypot(damped, decay)
    expected = -PRESSURE * AREA * LENGTH ** 2 * PITCH_DAMPING / (4.0 * WIND * INERTIA * omega_closed())
    return ("pitch damping: damping ratio, full mass", f"{zeta:.6f}", f"{expected:.6f}", f"{zeta / expected - 1:+.1e}",
            "2e-2")


def roll_row() -> tuple:
    _, _, columns = swing({"bodies.body.initial.yaw_deg": -90.0, "bodies.body.initial.rate_x": 1.0,
                           "bodies.body.aerodynamics.roll_damping": ROLL_DAMPING, "simulation.duration": 10.0})
    rate = -np.polyfit(columns["time"], np.log(columns["body_rate_x"]), 1)[0]
    expected = -PRESSURE * AREA * LENGTH ** 2 * ROLL_DAMPING / (2.0 * WIND * ROLL_INERTIA)
    return ("roll damping: decay rate, full mass", f"{rate:.9f} 1/s", f"{expected:.9f} 1/s",
            f"{rate / expected - 1:+.1e}", "1e-6")


def mach_rows() -> list:
    from pchute_exudyn.engine.solver import integrate
    from pchute_exudyn.methods.full import FullMass
    from pchute_exudyn.run.phases import initial_phase
    rows = []
    for wind, where in ((150.0, "between breakpoints"), (330.0, "through the transonic rise"),
                        (750.0, "beyond the table, held")):
        axial = float(np.interp(wind / SOUND, MACH_DRAG["mach"], MACH_DRAG["value"]))   # linear, held at the ends
        case = pc.load_case(PIVOT, {"atmosphere.wind.east": wind, "bodies.body.initial.yaw_deg": -90.0,
                                    "bodies.body.aerodynamics.axial_coefficient": MACH_DRAG})
        model = FullMass().build(case, initial_phase(case))
        integrate(model, "rk4", 1e-3, 1e-3, 1e-3)
        model.stage.refresh(1e-3)
        model.stage.loads.apply(1e-3)
        row = model.stage.states[model.stage.row["body"]]
        speed = float(np.linalg.norm(row[12:15] - np.array([wind, 0.0, 0.0])))
        expected = 0.5 * DENSITY * speed ** 2 * AREA * axial
        force = float(np.linalg.norm(model.stage.loads.values[0, :3]))
        rows.append((f"drag {where}: Mach {speed / SOUND:.4f} (C_A {axial:.4f})", f"{force:.6f} N", f"{expected:.6f} N",
                     f"{force / expected - 1:+.1e}", "1e-9"))
    return rows


def table_row() -> tuple:
    base = pc.load_case(MER1)
    aero = base.bodies["parachute"].aerodynamics
    axial, normal = aero.axial_coefficient.value, aero.normal_coefficient
    tables = {"bodies.parachute.aerodynamics.axial_coefficient": {"mach": [0.0, 3.0], "value": [axial, axial]},
              "bodies.parachute.aerodynamics.normal_coefficient": {
                  "mach": [0.0, 3.0], "alpha_deg": list(normal.angle_deg), "value": [list(normal.value)] * 2}}
    one = pc.simulate(base, "sp", duration=60.0).columns
    two = pc.simulate(pc.load_case(MER1, tables), "sp", duration=60.0).columns
    worst = max(float(np.nanmax(np.abs(two[k] - v)) / max(1.0, float(np.nanmax(np.abs(v)))))
                for k, v in one.items() if not k.endswith("_mach"))
    return ("Mach tables equal to the constants of MER case 1, SP, 60 s", f"{worst:.1e} (largest relative difference)",
            "0", f"{worst:.1e}", "1e-12")


def main(argv=None) -> int:
    rows = [*frequency_rows(), damping_row(), roll_row(), *mach_rows(), table_row()]
    v = versions()
    lines = ["# Aerodynamic databases: closed forms through the engine", "",
             f"`python validation/aero_checks.py`; case tests/cases/pivot_wind.toml (tests/integration/test_aerodatabase.py "
             f"asserts the same). Exudyn {v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}, {v['kernels']} kernels.", "",
             "| check | measured | closed form | relative difference | tolerance |", "|---|---|---|---|---|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    lines += ["", "The pivoted body: 1e12 kg (the force cannot move it) with its aerodynamic centre at its centre of mass "
              "in a 20 m/s wind, q = 4 Pa, S = 2 m^2, d = 1.5 m, I = 10 kg m^2, I_xx = 5 kg m^2; its swing obeys "
              "theta'' = (q S d C_malpha / I) theta + (q S d^2 C_mq / (2 V I)) theta' exactly (the tables are linear "
              "in alpha), so the frequency and damping ratio are exact up to the integrator's error. Frequencies from "
              "the zero crossings of the yaw from the wind line; the damping ratio from a fit of the log of the peaks "
              "(zeta omega) and the damped frequency; the roll decay from a fit of log p(t). Drag: the stage kernel's "
              "force after one step (the engine's state), C_A linear between Mach breakpoints and held beyond the "
              "last."]
    OUT.mkdir(parents=True, exist_ok=True)
    atomic_write_text(OUT / "closed_forms.md", "\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    run_script(main)

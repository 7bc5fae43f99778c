"""A new case from `pchute new` (the issue's choices: Earth, 100 kg, C_D S = 40 m^2, from 3000 m), run as written.

Run:  python validation/new_case_checks.py

Writes validation/output/new_case/: payload.toml (the file `pchute new` wrote) and checks.md:

* each method and integrator, with the step each takes from its stability limit (the case sets none): SP and full
  mass implicit to touchdown, full mass RK4 and the equilibrium point for their first 20 s;
* the steady rate of descent at 2500, 1500 and 500 m against sqrt(2 m g / (rho C_D S)) (m the suspended mass, g at
  the vehicle, rho at the canopy's centre, which is where its drag acts);
* the cross-check against RocketPy's export of the same descent (validation/rocketpy/descent.csv, unedited) with
  `pchute compare`'s descent figures, non-rotating and rotating Earth.
"""

from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.cli import main as pchute
from pchute_exudyn.physics.atmosphere import US76
from pchute_exudyn.registries.methods import METHODS
from pchute_exudyn.results.compare import compare_results
from pchute_exudyn.results.csv_dialects import parse_column_map
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions
from pchute_exudyn.run.step_control import stability_step

HERE = Path(__file__).resolve().parent
OUT = HERE / "output" / "new_case"
ROCKETPY = HERE / "rocketpy" / "descent.csv"
CHOICES = ["--planet", "earth", "--mass", "100", "--drag-area", "40", "--altitude", "3000", "--name", "payload"]
ALTITUDES = (2500.0, 1500.0, 500.0)
RADIUS, DRAG_AREA = 6378137.0, 40.0
RUNS = [("sp", "rk4", None), ("full", "implicit", None), ("full", "rk4", 20.0), ("equilibrium", "rk4", 20.0)]
ROCKETPY_MAP = ["Z=vehicle_altitude", "Vz=vehicle_velocity_down*-1"]


def run_all(case_path: Path) -> dict:
    case = pc.load_case(case_path)
    results = {}
    for method, integrator, duration in RUNS:
        start = time.perf_counter()
        result = pc.simulate(case, method, integrator, duration=duration)
        step, limit = stability_step(case, METHODS[method](), integrator)
        results[(method, integrator)] = (result, step, limit, time.perf_counter() - start)
    return results


def rate_rows(case, results) -> list:
    mass = sum(b.mass for b in case.bodies.values()) + case.systems["main"].confluence.mass
    rows = []
    for key in (("sp", "rk4"), ("full", "implicit")):
        result = results[key][0]
        for altitude in ALTITUDES:
            when = np.interp(-altitude, -result["vehicle_altitude"], result.time)
            rate = float(np.interp(when, result.time, result["vehicle_velocity_down"]))
            canopy = float(np.interp(when, result.time, result["canopy_altitude"]))
            gravity = math.hypot(*case.start.gravity_scalar(*case.start.local_position(altitude, 0.0, 0.0)))
            closed = math.sqrt(2.0 * mass * gravity / (US76().density(canopy) * DRAG_AREA))
            rows.append(f"| {key[0]} {key[1]} | {altitude:g} | {when:.2f} | {rate:.5f} | {closed:.5f} | "
                        f"{rate / closed - 1.0:+.1e} |")
    return rows, mass


def rocketpy_rows(results, case_path) -> list:
    theirs = pc.Result.load(ROCKETPY, parse_column_map(ROCKETPY_MAP))
    rotating = pc.simulate(pc.load_case(case_path, {"planet.rotation_rate": 7.292115e-5}), "sp")
    rows = []
    for label, ours in (("non-rotating Earth (the case as written)", results[("sp", "rk4")][0]),
                        ("rotating Earth (--set planet.rotation_rate=7.292115e-5)", rotating)):
        d = compare_results(ours, theirs, altitudes=ALTITUDES).descent
        a, b = d["a"], d["b"]
        cells = [f"{(rb / ra - 1.0) * 100:+.3f} %" for ra, rb in zip(a["rates"], b["rates"])]
        rows.append(f"| {label} | {' / '.join(cells)} | {a['ground_time']:.3f} / {b['ground_time']:.3f} "
                    f"({b['ground_time'] - a['ground_time']:+.3f}) | {a['ground_rate']:.4f} / {b['ground_rate']:.4f} |")
    return rows


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:
        written = Path(folder) / "payload.toml"
        if pchute(["new", str(written), *CHOICES]) != 0:
            return 1
        text = written.read_text()
    atomic_write_text(OUT / "payload.toml", text)
    case_path = OUT / "payload.toml"
    case = pc.load_case(case_path)
    results = run_all(case_path)
    rates, mass = rate_rows(case, results)
    runs = [f"| {m} {i} | {step:g} | {limit:.3g} | {r.summary.end} at {r.final('time'):.2f} s | "
            f"{r.final('vehicle_altitude'):.2f} | {r.summary.wall_time:.2f} |"
            for (m, i), (r, step, limit, _) in results.items()]
    lines = ["# A new case from `pchute new`, run as written", "",
             f"`python validation/new_case_checks.py`; Exudyn {versions()['exudyn']}, pchute-exudyn {pc.__version__}. "
             "`pchute new payload.toml --planet earth --mass 100 --drag-area 40 --altitude 3000` wrote "
             "[payload.toml](payload.toml) (a disk-gap-band canopy by default); no edits.", "",
             "## Each method, the step from its stability limit", "",
             "| run | step (s) | stability limit (s) | end | final vehicle altitude (m) | wall time (s) |",
             "|---|---|---|---|---|---|", *runs, "",
             f"## Steady rate of descent against sqrt(2 m g / (rho C_D S)), m = {mass:.6f} kg, C_D S = 40 m^2", "",
             "g the case's normal gravity at the vehicle (docs/models/gravity.md); rho (US76) at the canopy's centre, "
             "where its drag acts.", "",
             "| run | vehicle altitude (m) | time (s) | rate (m/s) | closed form (m/s) | relative difference |",
             "|---|---|---|---|---|---|", *rates, "",
             "## Against RocketPy's export of the same descent (validation/rocketpy/descent.csv, unedited)", "",
             f"`pchute compare` with `--map {ROCKETPY_MAP[0]} --map \"{ROCKETPY_MAP[1]}\"`. RocketPy: a 111.109091 kg "
             "point mass, C_D S = 40 m^2 at the point mass, ISA, Somigliana normal gravity of the rotating Earth.", "",
             "| ours | rate of descent RocketPy / ours - 1 at 2500 / 1500 / 500 m | time to ground ours / RocketPy "
             "(s) | rate at the ground ours / RocketPy (m/s) |", "|---|---|---|---|",
             *rocketpy_rows(results, case_path), "",
             "Both fly the normal gravity of the WGS-84 ellipsoid (with the frame rotating, ours adds only the Coriolis "
             "term, as RocketPy does); RocketPy takes the air at the point mass, 17 m below our canopy (0.17 % "
             "denser; -0.085 % in rate), which is the difference left."]
    atomic_write_text(OUT / "checks.md", "\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    run_script(main)

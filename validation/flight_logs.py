"""Seven real dual-deploy flights predicted blind from their published parameters, compared with their logs and
fitted to them, with RocketPy on the same inputs.

Run:  PYTHONPATH=.:/tmp/rpkg python validation/flight_logs.py --logs DIR [--flight NAME ...] [--no-fit]

DIR holds the flights' AltOS logs as published (validation/flights/SOURCES.md says where; each is checked against the
SHA-256 in validation/flights/flights.toml: read unedited). For each flight:

1. **The day's air.** The log's own GPS gives the day's temperature above the standard's
   (``FlightLog.gps_temperature_offset``); the air is one layer of standard lapse through the pad's pressure (the
   log's) at that temperature (``physics.barometric.lapse_layer``), written as a table atmosphere. The log's
   barometric heights are read through it (``physics.barometric.geometric_heights``).
2. **Our blind prediction.** ``pchute new --dual-deploy`` with the team's published mass, length, diameter and
   canopies (diameter, C_D), the rocket's body drag on, the drogue staying on its harness, the harness at the centre
   of mass (``--harness-offset 0``: the shock cord at the sections' joint, the rocket across the flow), the flight
   computer's apogee lag and main height (its reading, through the day's air), from the log's apogee at rest; flown
   by SP. Nothing is taken from the log's descent.
3. **RocketPy on the same inputs** (validation/flight_rocketpy.py): the same mass, canopies (drogue + main under the
   main), triggers, start and air; RocketPy flies no drag of the rocket itself.
4. **The comparison** (``results.log_compare``): each side's descent rates over the log's bands, apogee to
   touchdown; every rate read by the same rule (Theil-Sen slopes over the same height bands).
5. **The fit** (``pchute fit`` with a ``log`` target): both canopies' S0 (so their C_D S) free, the body drag and
   everything else as published; the fitted C_D S and the residuals.

Writes validation/output/flight_logs/<flight>/ (case, air table, comparison, fit) and summary.json, and the page
docs/validation/flight_logs.md.
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import math
import subprocess
import sys
from pathlib import Path

import tomllib
from script_arguments import OneLineParser, existing_folder, output_path, run_script, workers

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "output" / "flight_logs"
FLIGHTS = HERE / "flights" / "flights.toml"


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--logs", type=existing_folder, required=True, help="folder of the published logs")
    parser.add_argument("--flight", action="append", help="a flights.toml table (default: all)")
    parser.add_argument("--no-fit", action="store_true", help="skip the fits")
    parser.add_argument("--workers", type=workers, default=3, help="each fit's worker processes (default 3)")
    parser.add_argument("--out", type=output_path, default=OUT)
    args = parser.parse_args(argv)
    with FLIGHTS.open("rb") as handle:
        flights = tomllib.load(handle)["flights"]
    for name in args.flight or list(flights):
        if name not in flights:
            parser.refuse(f"--flight {name}: no such flight in {FLIGHTS.relative_to(ROOT)} (it has {', '.join(flights)})")
        if not (args.logs / flights[name]["log"]).is_file():
            parser.refuse(f"--logs {args.logs}: has no {flights[name]['log']} (the log of flight {name})")
    if importlib.util.find_spec("rocketpy") is None:
        parser.refuse('rocketpy is not installed: pip install -e ".[bench]"')
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

import numpy as np

sys.path.insert(0, str(HERE))
from flight_rocketpy import drag_area, fly_rocketpy, load_flights  # noqa: E402

PAGE = ROOT / "docs" / "validation" / "flight_logs.md"
AIR_STEP = 20.0
"""m: the day's air table's spacing (the density changes 0.2 % over it; the table interpolates log-linearly)."""
FIT_STD = 2.0
"""m: the std of a log's height in the fit (the barometer's noise and a tumbling rocket's swing): it weighs the
samples, not the fitted values."""
FIT_RANGE = (0.25, 4.0)
"""The fit's bounds on each canopy's S0, as factors on the published one."""
LAG_RANGE = 6.0
"""s: the fit's upper bound on the main's lag. The lag stands for its deployment and opening, which the blind case
takes as instant: fitted without it, the main's C_D S would absorb the seconds a real main takes to open."""


def day_air(log, flight: dict) -> dict:
    """The day's air of a log: the GPS temperature offset (K, fixes), the pad's pressure (Pa) and temperature (K),
    and the table (altitude m above sea level, density kg/m^3, temperature K, pressure Pa) from 100 m under sea level
    to 1 km over the apogee."""
    from pchute_exudyn.physics.barometric import lapse_layer, standard_temperature

    offset, fixes = log.gps_temperature_offset()
    pad_pressure = float(np.median(log.pressure[: log.phases.launch_index + 1]))
    pad_temperature = float(standard_temperature(log.pad_altitude)) + offset
    heights = np.arange(-flight["pad_gps_altitude"] - 100.0, log.phases.apogee_height - log.phases.pad_level + 1000.0,
                        AIR_STEP)   # from under sea level: a run asks the air at the reference surface too
    pressure, temperature, density = lapse_layer(heights, pad_pressure, pad_temperature)
    return {"offset": offset, "fixes": fixes, "pad_pressure": pad_pressure, "pad_temperature": pad_temperature,
            "altitude": flight["pad_gps_altitude"] + heights, "density": density, "temperature": temperature,
            "pressure": pressure, "density_at": lambda z: lapse_layer(z, pad_pressure, pad_temperature)[2]}


def write_air(air: dict, path: Path) -> None:
    from pchute_exudyn.results.io import atomic_write_text

    rows = ["altitude,density,temperature"]   # m, kg/m^3, K (case-format.md)
    rows += [f"{a:.3f},{d:.9g},{t:.6g}" for a, d, t in zip(air["altitude"], air["density"], air["temperature"])]
    atomic_write_text(path, "\n".join(rows) + "\n")


def write_case(name: str, flight: dict, start_height: float, main_height: float, folder: Path) -> Path:
    """Our blind case (module docstring, step 2) in ``folder``, flying in the table ``air.csv`` beside it."""
    path = folder / "case.toml"
    options = {"--planet": "earth", "--mass": flight["mass"], "--length": flight["length"],
               "--diameter": flight["diameter"], "--drogue-diameter": flight["drogue"]["diameter"],
               "--drogue-drag-coefficient": flight["drogue"]["drag_coefficient"],
               "--main-diameter": flight["main"]["diameter"],
               "--main-drag-coefficient": flight["main"]["drag_coefficient"], "--main-height": main_height,
               "--height": start_height, "--ground-elevation": flight["pad_gps_altitude"],
               "--apogee-lag": flight.get("drogue_lag", 0.0), "--harness-offset": 0.0, "--name": name}
    arguments = [item for key, value in options.items() for item in (key, f"{value:.6g}" if not isinstance(value, str)
                                                                     else value)]
    subprocess.run([sys.executable, "-m", "pchute_exudyn", "new", "--dual-deploy", str(path), "--overwrite",
                    "--body-drag", "on", "--drogue-after-main", "attached", *arguments], check=True,
                   capture_output=True)
    from pchute_exudyn.results.io import atomic_write_text

    text = path.read_text()
    atomic_write_text(path, text.replace('[atmosphere]\nmodel = "us76"', '[atmosphere]\nmodel = "table"   # the day\'s air, '
                                 'from the log (validation/flight_logs.py)\nfile = "air.csv"'))
    return path


def fit(folder: Path, case: Path, log_path: Path, flight: dict, workers: int) -> dict:
    """``pchute fit`` of both canopies' S0 and the main's lag to the log's descent; {key: (published, fitted, standard
    error)} and the residuals' RMS (m)."""
    rows = ["[fit]", 'name = "canopies"', f'case = "{case.name}"', 'method = "sp"', ""]
    published = {}
    for which in ("drogue", "main"):
        key = f"{which}_canopy.aerodynamics.reference_area"
        area = math.pi * flight[which]["diameter"] ** 2 / 4.0
        published[key] = area
        rows += [f'[free."{key}"]', f"low = {FIT_RANGE[0] * area:.6g}", f"high = {FIT_RANGE[1] * area:.6g}", ""]
    rows += ['[free."main.deploy_trigger.lag"]', "low = 0.0", f"high = {LAG_RANGE:g}", "initial = 0.5", ""]
    rows += ["[[targets]]", f'log = "{log_path.resolve()}"', f"std = {FIT_STD}"]
    from pchute_exudyn.results.io import atomic_write_text

    atomic_write_text(folder / "fit.toml", "\n".join(rows) + "\n")
    subprocess.run([sys.executable, "-m", "pchute_exudyn", "fit", str(folder / "fit.toml"), "--out",
                    str(folder / "fit"), "--workers", str(workers)], check=True, capture_output=True)
    outcome = json.loads((folder / "fit" / "fit.json").read_text())
    residuals = np.asarray(outcome["residuals"]) * FIT_STD
    return {"keys": {key: (published.get(key), value, error) for key, value, error in
                     zip(outcome["keys"], outcome["fitted"], outcome["standard_error"])},
            "at_bound": outcome["at_bound"], "rms": float(np.sqrt(np.mean(residuals ** 2))), "runs": outcome["runs"]}


def one_flight(name: str, flight: dict, logs: Path, out: Path, do_fit: bool, workers: int) -> dict:
    from pchute_exudyn import load_case, simulate
    from pchute_exudyn.physics.barometric import geometric_heights
    from pchute_exudyn.results.flight_log import read_flight_log
    from pchute_exudyn.results.io import atomic_write_text
    from pchute_exudyn.results.log_compare import compare_with_log

    log_path = logs / flight["log"]
    digest = hashlib.sha256(log_path.read_bytes()).hexdigest()
    if digest != flight["log_sha256"]:
        raise SystemExit(f"{log_path}: SHA-256 {digest} is not the published file's {flight['log_sha256']}")
    folder = out / name
    folder.mkdir(parents=True, exist_ok=True)
    log = read_flight_log(log_path)
    air = day_air(log, flight)
    write_air(air, folder / "air.csv")
    apogee, main = geometric_heights(np.array([log.phases.apogee_height - log.phases.pad_level,
                                               flight["main_height"]]), log.pad_altitude, air["density_at"])
    case = write_case(name, flight, float(apogee), float(main), folder)
    result = simulate(load_case(case), "sp")
    comparison = compare_with_log(result, log, str(case), str(log_path), air["density_at"], "the day's, from the log",
                                  flight["pad_gps_altitude"])
    atomic_write_text(folder / "comparison.md", comparison.table())
    flown = dict(flight, apogee_height=float(apogee), main_height=float(main), bands=comparison.bands)
    rocketpy = fly_rocketpy(flown, {"height": air["altitude"], "pressure": air["pressure"],
                                    "temperature": air["temperature"]})
    row = {"flight": name, "label": flight["label"], "log": flight["log"], "log_sha256": digest,
           "mass": flight["mass"], "drogue_cd_s": drag_area(flight["drogue"]), "main_cd_s": drag_area(flight["main"]),
           "temperature_offset": air["offset"], "gps_fixes": air["fixes"], "pad_temperature": air["pad_temperature"],
           "apogee_height": float(apogee), "main_height": float(main), "bands": comparison.bands,
           "log_rates": {k: v[0] for k, v in comparison.log.rates.items()},
           "our_rates": {k: v[0] for k, v in comparison.run.rates.items()},
           "rocketpy_rates": {k: v[0] for k, v in rocketpy["rates"].items()},
           "descent_time": {"log": comparison.log.descent_time, "ours": comparison.run.descent_time,
                            "rocketpy": rocketpy["descent_time"]}}
    if do_fit:
        row["fit"] = fit(folder, case, log_path, flight, workers)
    return row


def relative(value: float, reference: float) -> float:
    return (value - reference) / reference


def page(rows: list, command: str) -> str:
    lines = ["# Real flights: descent rates predicted blind, compared and fitted", "",
             f"Written by `{command}` (validation/flight_logs.py; the flights' parameters and sources: "
             "validation/flights/flights.toml and SOURCES.md).", "",
             "Seven dual-deploy flights of the NUSTARS team (Northwestern University), logged by an Altus Metrum "
             "TeleMega and read unedited (each log's SHA-256 is checked). The prediction is blind: the team's published "
             "mass, length, diameter and canopies (nominal diameter, C_D), the flight computer's apogee lag and main "
             "height, the log's apogee and pad, and the day's air from the log's own GPS (the temperature offset "
             "at which its barometric heights match its GPS heights). Nothing is taken from the descent itself. "
             "Our case: `pchute new --dual-deploy` with the body's drag (docs/models/slender_body.md), the drogue "
             "staying on its harness, the harness at the centre of mass (the rocket across the flow). RocketPy: the "
             "same mass, canopies (drogue + main under the main), triggers, start and air, without the rocket's own "
             "drag, which RocketPy does not model under a parachute. Rates: Theil-Sen slopes over the same height "
             "bands on all three (results.log_compare: the drogue's band 10 to 70 % of the way from the rate "
             "change to the apogee, the main's 15 to 60 % of the rate change's height).", "",
             "## The flights", "",
             "| flight | what | date | motor | descent mass (kg) | log (SHA-256, first 12) |", "|---|---|---|---|---|---|"]
    flights = load_flights()
    for row in rows:
        f = flights[row["flight"]]
        lines.append(f"| {row['flight']} | {f['label']} | {f['date']} | {f['motor']} | {row['mass']:.2f} | "
                     f"`{f['log']}` ({row['log_sha256'][:12]}) |")
    lines += ["", "Every number's source (repository, path, commit) is in validation/flights/flights.toml; the logs "
              "and design files are from https://github.com/NUSTARS/launch-vehicle (no licence stated), none from "
              "RocketPy's data/rockets/.", "", "## Blind descent rates", "",
              "| flight | mass (kg) | day's air (K over standard) | band (m above the pad) | log (m/s) | ours (m/s) | "
              "ours - log | RocketPy (m/s) | RocketPy - log |", "|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        for label, (low, high) in row["bands"].items():
            log, ours, rp = (row[k][label] for k in ("log_rates", "our_rates", "rocketpy_rates"))
            lines.append(f"| {row['flight']} | {row['mass']:.2f} | {row['temperature_offset']:+.1f} | {label} "
                         f"{low:.0f}-{high:.0f} | {log:.2f} | {ours:.2f} | {relative(ours, log):+.1%} | {rp:.2f} | "
                         f"{relative(rp, log):+.1%} |")
    lines += ["", "| flight | apogee to touchdown: log (s) | ours (s) | ours - log | RocketPy (s) | RocketPy - log |",
              "|---|---|---|---|---|---|"]
    for row in rows:
        t = row["descent_time"]
        lines.append(f"| {row['flight']} | {t['log']:.1f} | {t['ours']:.1f} | {relative(t['ours'], t['log']):+.1%} | "
                     f"{t['rocketpy']:.1f} | {relative(t['rocketpy'], t['log']):+.1%} |")
    lines += ["", "## Summary", ""] + summary_lines(rows)
    fitted = [row for row in rows if "fit" in row]
    if fitted:
        lines += ["", "## Fitted C_D S", "",
                  "`pchute fit` with the log's descent as its target (`log = ...`, std 2 m), both canopies' S0 free "
                  f"within {FIT_RANGE[0]:g} to {FIT_RANGE[1]:g} times the published and the main's lag within 0 to "
                  f"{LAG_RANGE:g} s (standing for its deployment and opening, which the blind case takes as instant), "
                  "everything else as in the blind case (the body's drag included). The standard errors are "
                  "those of 2 m independent noise; the residuals (model error, a tumbling rocket's swing) are larger, "
                  "so they understate the uncertainty of a real flight's values.", "",
                  "| flight | drogue C_D S published (m^2) | fitted | main C_D S published (m^2) | fitted | "
                  "main's lag fitted (s) | RMS residual (m) | runs |", "|---|---|---|---|---|---|---|---|"]
        for row in fitted:
            f = row["fit"]
            (dp, dv, de), (mp, mv, me), (_, lv, le) = f["keys"].values()
            flight = load_flights()[row["flight"]]
            cd_d, cd_m = flight["drogue"]["drag_coefficient"], flight["main"]["drag_coefficient"]
            bound = [" (at a bound)" if b else "" for b in f["at_bound"]]
            lines.append(f"| {row['flight']} | {cd_d * dp:.3f} | {cd_d * dv:.3f} +- {cd_d * de:.2g}{bound[0]} | "
                         f"{cd_m * mp:.2f} | {cd_m * mv:.2f} +- {cd_m * me:.2g}{bound[1]} | {lv:.2f} +- {le:.2g}"
                         f"{bound[2]} | {f['rms']:.1f} | {f['runs']} |")
    return "\n".join(lines) + "\n"


def summary_lines(rows: list) -> list:
    """Which flights are within 10 % on both rates, and where ours is closer than RocketPy's."""
    within = [r["flight"] for r in rows if all(abs(relative(r["our_rates"][k], r["log_rates"][k])) <= 0.10
                                               for k in r["bands"])]
    closer = {label: [r["flight"] for r in rows if label in r["bands"]
                      and abs(relative(r["our_rates"][label], r["log_rates"][label]))
                      < abs(relative(r["rocketpy_rates"][label], r["log_rates"][label]))] for label in ("drogue", "main")}
    both = [r["flight"] for r in rows if r["flight"] in closer["drogue"] and r["flight"] in closer["main"]]
    overall = [r["flight"] for r in rows if rms_error(r, "our_rates") < rms_error(r, "rocketpy_rates")]
    slow = [r for r in rows if "main" in r["bands"] and max(r["our_rates"]["main"], r["rocketpy_rates"]["main"])
            < r["log_rates"]["main"]]
    timely = [r for r in rows if abs(relative(r["descent_time"]["ours"], r["descent_time"]["log"])) <= 0.10]
    return [f"* Within 10 % on both rates: {len(within)} of {len(rows)} flights ({', '.join(within) or 'none'}).",
            f"* Ours closer than RocketPy under the drogue: {len(closer['drogue'])} of {len(rows)}; under the main: "
            f"{len(closer['main'])} of {len(rows)}; on both: {len(both)} ({', '.join(both) or 'none'}).",
            f"* Ours closer than RocketPy on the RMS of the two rates' relative errors: {len(overall)} of {len(rows)} "
            f"({', '.join(overall) or 'none'}).",
            f"* Under the main both miss the same way: RocketPy, without the rocket's own drag, comes down about 1 % "
            f"faster than ours, and both come down slower than the log on {len(slow)} of {len(rows)} flights: the "
            "published C_D 2.2 of the main is optimistic for them, or the main opens late (the fits put 0.7 to 3.8 s "
            "between the main's trigger and its C_D S), or a mass is low (2026 FT2 may have flown its 3 kg payload or "
            "not).",
            f"* Apogee to touchdown: ours within 10 % on {len(timely)} of {len(rows)} flights; where ours hangs the "
            "rocket broadside and the log's drogue rate is faster, the blind descent runs long."]


def rms_error(row: dict, side: str) -> float:
    """The RMS over a flight's bands of the relative error of ``side``'s rates against the log's."""
    return math.sqrt(sum(relative(row[side][k], row["log_rates"][k]) ** 2 for k in row["bands"]) / len(row["bands"]))


def main(argv=None) -> int:
    args = arguments(argv)
    flights = load_flights()
    rows = []
    for name in args.flight or list(flights):
        rows.append(one_flight(name, flights[name], args.logs, args.out, not args.no_fit, args.workers))
        r = rows[-1]
        print(f"{name}: " + ", ".join(f"{k} log {r['log_rates'][k]:.2f} ours {r['our_rates'][k]:.2f} RocketPy "
                                      f"{r['rocketpy_rates'][k]:.2f} m/s" for k in r["bands"]), flush=True)
    command = "python validation/flight_logs.py --logs DIR" + ("" if args.flight is None else " --flight " +
                                                               " --flight ".join(args.flight))
    text = page(rows, command)
    print(text)
    if args.flight is None:
        from pchute_exudyn.results.io import atomic_write_text

        atomic_write_text(PAGE, text)
        atomic_write_text(args.out / "summary.json", json.dumps(rows, indent=1, default=float, allow_nan=False) + "\n")
    return 0


if __name__ == "__main__":
    run_script(main)

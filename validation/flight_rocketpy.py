"""RocketPy 1.13 on the published inputs of a real flight (validation/flights/flights.toml), and the flight's own log
read by the same rules, band for band.

Run:  PYTHONPATH=.:/tmp/rpkg python validation/flight_rocketpy.py [--flight NAME ...] [--cache DIR] [--json FILE]

RocketPy's side (``fly_rocketpy``) is built as validation/benchmark_rocketpy.py builds it, by import: a ``Rocket``
with no motor and no drag of the flight's descent mass, parachutes with RocketPy's triggers ("apogee", a height above
the ground), and a ``Flight`` from ``initial_solution`` at the log's apogee (its height above the pad, at rest or
with a given horizontal velocity). The drogue deploys at the apogee after the flight computer's lag, the main at the
height where the log's flight computer entered its ``main`` state. RocketPy flies one C_D S at a time (a later
parachute's replaces the earlier's); the harness decides the main's: ``"drogue_stays"`` gives it drogue + main (the
drogue stays on its harness, as on these rockets: the comparison's variant), ``"main_replaces"`` the main's alone.
The air is RocketPy's standard atmosphere with the pad at the log's pressure altitude (then RocketPy's heights are
the heights the altimeter reads: the log needs no conversion), or a custom atmosphere from ``air`` (pressure Pa and
temperature K over heights above sea level; the pad then at ``pad_gps_altitude``).

The descent rates are read on both sides by pchute_exudyn.results.log_compare's rules (its bands DROGUE_BAND and
MAIN_BAND, the Theil-Sen slope of the samples in a band) with one change: the bands are set from the height where the
flight computer entered its ``main`` state, not from log_compare's halfway rate change, which on all seven of these
logs falls on a barometric spike (27-52 m/s in the 1 s median) and lands 300-2300 m above the main's deployment
(reported as ``rate_change`` for reference). RocketPy's states are
read linearly between its solver's points on a RATE_GRID grid first (its Functions of time are splines that ring
at a deployment). The log's touchdown: the first sample after the apogee within TOUCHDOWN_MARGIN of the lowest
running median (AltOS declares ``landed`` seconds late; the Midland log has no ``landed``).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np
import tomllib

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from benchmark_rocketpy import finite, rocketpy_track  # noqa: E402
from benchmark_rocketpy import fly_rocketpy as fly_benchmark_inputs  # noqa: E402  (one home for the RocketPy build)

FLIGHTS = HERE / "flights" / "flights.toml"
CACHE = Path("/work/data-cache/flight_logs/raw")
LOG_COMPARE_FALLBACK = Path("/work/main/pchute_exudyn/results/log_compare.py")
SAMPLING_RATE = 100.0
"""Hz: the flight computer's trigger sampling (a TeleMega samples its barometer at 100 Hz in flight)."""
RATE_GRID = 0.05
"""s: RocketPy's heights are read linearly between its solver's points on this grid before a band's slope."""
TOUCHDOWN_MARGIN = 1.0
"""m above the lowest running-median height after the apogee at which the log's touchdown is taken."""
HARNESSES = ("drogue_stays", "main_replaces")


def log_rules():
    """pchute_exudyn.results.log_compare (its rate change, bands and band slopes): from the package, or until it is
    committed there, the file in /work/main loaded as the package's module (its imports resolve in this package)."""
    try:
        from pchute_exudyn.results import log_compare
        return log_compare
    except ImportError:
        importlib.import_module("pchute_exudyn.results")   # the parent its relative imports resolve in
        name = "pchute_exudyn.results.log_compare"
        spec = importlib.util.spec_from_file_location(name, LOG_COMPARE_FALLBACK)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
        return module


# -- the flights' inputs ----------------------------------------------------------------------------------------------

def load_flights(path: Path = FLIGHTS) -> dict:
    """Name -> the flight's table of flights.toml (masses kg, lengths m, canopies' diameter m and C_D)."""
    with path.open("rb") as handle:
        return tomllib.load(handle)["flights"]


def drag_area(canopy: dict) -> float:
    """m^2: C_D x the nominal area pi D^2 / 4 of a canopy's table (``diameter`` m, ``drag_coefficient``)."""
    return canopy["drag_coefficient"] * math.pi * canopy["diameter"] ** 2 / 4.0


def log_descent(path: Path):
    """(time s after the apogee, height m above the pad, the log's apogee time s, its ``FlightLog``) of an AltOS log
    from its apogee to its touchdown (module docstring)."""
    from pchute_exudyn.physics.flight_phases import running_median
    from pchute_exudyn.results.flight_log import read_flight_log

    log = read_flight_log(path)
    phases = log.phases
    time = log.time[phases.apogee_index:] - phases.apogee_time
    height = log.height[phases.apogee_index:] - phases.pad_level
    smooth = running_median(time, height, 1.0)
    end = int(np.nonzero(smooth <= smooth.min() + TOUCHDOWN_MARGIN)[0][0]) + 1
    return time[:end], height[:end], phases.apogee_time, log


# -- RocketPy ---------------------------------------------------------------------------------------------------------

def rocketpy_environment(flight: dict, air: dict | None):
    """RocketPy's Environment at the pad: the standard atmosphere at the pad's pressure altitude, or ``air``'s
    custom atmosphere (``air["height"]`` m above sea level, ``air["pressure"]`` Pa, ``air["temperature"]`` K) at
    the pad's GPS altitude; no wind."""
    from rocketpy import Environment
    elevation = flight["pad_altitude"] if air is None else flight["pad_gps_altitude"]
    env = Environment(latitude=flight.get("latitude", 0.0), longitude=flight.get("longitude", 0.0),
                      elevation=elevation)
    if air is None:
        env.set_atmospheric_model(type="standard_atmosphere")
    else:
        heights = np.asarray(air["height"], float)
        env.set_atmospheric_model(type="custom_atmosphere",
                                  pressure=np.column_stack([heights, np.asarray(air["pressure"], float)]),
                                  temperature=np.column_stack([heights, np.asarray(air["temperature"], float)]),
                                  wind_u=0.0, wind_v=0.0)
    return env


def rocketpy_inputs(flight: dict, elevation: float, harness: str = "drogue_stays") -> dict:
    """The inputs validation/benchmark_rocketpy.py builds its Rocket and initial solution from, for ``flight``: its
    descent mass (kg), a slender cylinder's inertia (the attitude does not act: no aerodynamic surfaces), the drogue
    at the apogee after ``drogue_lag`` and the main at ``main_height`` (m above the pad) with the C_D S ``harness``
    gives it, the start at the apogee (m above sea level) with ``horizontal_velocity`` (m/s east, default 0)."""
    if harness not in HARNESSES:
        raise ValueError(f"harness {harness!r}: one of {', '.join(HARNESSES)}")
    mass, radius, length = flight["mass"], 0.5 * flight["diameter"], flight["length"]
    drogue, main = drag_area(flight["drogue"]), drag_area(flight["main"])
    main_cd_s = drogue + main if harness == "drogue_stays" else main
    parachutes = [{"name": "drogue", "cd_s": drogue, "trigger": "apogee", "sampling_rate": SAMPLING_RATE,
                   "lag": flight.get("drogue_lag", 0.0)},
                  {"name": "main", "cd_s": main_cd_s, "trigger": float(flight["main_height"]),
                   "sampling_rate": SAMPLING_RATE, "lag": flight.get("main_lag", 0.0)}]
    transverse = mass * (3.0 * radius**2 + length**2) / 12.0
    return {"mass": mass, "radius": radius, "inertia": (transverse, transverse, 0.5 * mass * radius**2),
            "parachutes": parachutes,
            "position": (0.0, 0.0, elevation + flight["apogee_height"]),
            "velocity": (flight.get("horizontal_velocity", 0.0), 0.0, 0.0),
            "heading_deg": 90.0, "inclination_deg": 0.0}


def band_rates(time, height, bands: dict) -> dict:
    """Label -> (m/s positive down, samples) over each band (label -> (low, high) m above the pad), by
    log_compare.band_rate."""
    rules = log_rules()
    return {label: rules.band_rate(np.asarray(time, float), np.asarray(height, float), *limits)
            for label, limits in bands.items()}


def fly_rocketpy(flight: dict, air: dict | None = None, harness: str = "drogue_stays") -> dict:
    """RocketPy's descent of ``flight`` (a flights.toml table with ``apogee_height`` m above the pad and ``bands``
    label -> (low, high) m above the pad added) in ``air`` (None: the standard atmosphere; module docstring):
    ``time`` (s from the apogee, on a RATE_GRID grid), ``height`` (m above the pad), ``rates`` (label -> (m/s
    positive down, samples)), ``descent_time`` (s from the apogee to the touchdown), ``deployed`` (name -> s after
    the apogee), ``main_cd_s`` (m^2) and the ``harness``."""
    env = rocketpy_environment(flight, air)
    inputs = rocketpy_inputs(flight, env.elevation, harness)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # RocketPy's notes on a rocket without motor or aerodynamic surfaces
        run, _ = fly_benchmark_inputs(env, inputs)
    track = rocketpy_track(run)
    grid = np.arange(track["time"][0], track["time"][-1], RATE_GRID)
    height = np.interp(grid, track["time"], track["altitude"]) - env.elevation
    deployed = {p.name: float(t) + p.lag for t, p in run.parachute_events}
    return {"time": grid, "height": height, "rates": band_rates(grid, height, flight["bands"]),
            "descent_time": float(run.t_final), "deployed": deployed,
            "main_cd_s": inputs["parachutes"][1]["cd_s"], "harness": harness}


# -- the comparison ---------------------------------------------------------------------------------------------------

def measured(flight: dict, cache: Path) -> dict:
    """The log's descent read by log_compare's rules: apogee height (m above the pad), rate change (s, m), bands
    (label -> (low, high) m), rates (label -> (m/s, samples)), apogee to touchdown (s)."""
    rules = log_rules()
    time, height, apogee_time, _ = log_descent(cache / flight["log"])
    main = (main_state_time(time, height, flight["main_height"]), float(flight["main_height"]))
    bands = rules.bands(float(height[0]), main)
    return {"apogee_height": float(height[0]), "apogee_time": apogee_time, "main_state": main,
            "rate_change": rules.rate_change(time, height), "bands": bands,
            "rates": band_rates(time, height, bands), "descent_time": float(time[-1] - time[0])}


def main_state_time(time, height, main_height: float) -> float:
    """s after the apogee at which the log's descent first comes down to ``main_height`` (m above the pad: the
    height of its first ``main`` sample)."""
    below = int(np.nonzero(np.asarray(height) <= main_height)[0][0])
    return float(time[below])


def compare(name: str, flight: dict, cache: Path, air: dict | None = None) -> dict:
    """One flight: the log's figures and RocketPy's in both harness variants over the log's bands."""
    log = measured(flight, cache)
    flown = dict(flight, apogee_height=log["apogee_height"], bands=log["bands"])
    runs = {harness: fly_rocketpy(flown, air, harness) for harness in HARNESSES}
    return {"flight": name, "label": flight["label"], "mass": flight["mass"],
            "drogue_cd_s": drag_area(flight["drogue"]), "main_cd_s": drag_area(flight["main"]),
            "main_height": flight["main_height"], "log": log,
            "rocketpy": {h: {k: v for k, v in r.items() if k not in ("time", "height")} for h, r in runs.items()}}


def table(rows: list) -> str:
    """Markdown: per flight, the log's drogue and main rates and RocketPy's (both harnesses), with RocketPy - log."""
    lines = ["| flight | mass (kg) | band | log (m/s) | RocketPy, drogue stays (m/s) | (RP - log) / log | "
             "RocketPy, main replaces (m/s) | (RP - log) / log |", "|---|---|---|---|---|---|---|---|"]
    for row in rows:
        for label, (low, high) in row["log"]["bands"].items():
            measured_rate = row["log"]["rates"][label][0]
            cells = [row["flight"], f"{row['mass']:.2f}", f"{label} {low:.0f}-{high:.0f} m", f"{measured_rate:.2f}"]
            for harness in HARNESSES:
                rate = row["rocketpy"][harness]["rates"][label][0]
                cells += [f"{rate:.2f}", f"{(rate - measured_rate) / measured_rate:+.1%}"]
            lines.append("| " + " | ".join(cells) + " |")
        times = [row["log"]["descent_time"]] + [row["rocketpy"][h]["descent_time"] for h in HARNESSES]
        lines.append(f"| {row['flight']} | | apogee to touchdown (s) | {times[0]:.1f} | {times[1]:.1f} | "
                     f"{(times[1] - times[0]) / times[0]:+.1%} | {times[2]:.1f} | {(times[2] - times[0]) / times[0]:+.1%} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--flight", action="append", help="a flights.toml table name (default: all)")
    parser.add_argument("--cache", type=Path, default=CACHE, help="folder of the logs (default %(default)s)")
    parser.add_argument("--json", type=Path, help="also write the figures as JSON here")
    args = parser.parse_args(argv)
    flights = load_flights()
    names = args.flight or list(flights)
    rows = []
    for name in names:
        row = compare(name, flights[name], args.cache)
        rows.append(row)
        print(f"{name}: apogee {row['log']['apogee_height']:.1f} m, rate change {row['log']['rate_change']}, "
              f"RocketPy deployments {row['rocketpy']['drogue_stays']['deployed']}", flush=True)
    print()
    print(table(rows))
    if args.json:
        args.json.write_text(json.dumps(finite(rows), indent=1, allow_nan=False) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

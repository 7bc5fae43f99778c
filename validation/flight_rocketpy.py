"""RocketPy 1.13 on the published inputs of a real flight (validation/flights/flights.toml): the RocketPy side of
validation/flight_logs.py.

RocketPy's side (``fly_rocketpy``) is built as validation/benchmark_rocketpy.py builds it, by import: a ``Rocket``
with no motor and no drag of the flight's descent mass, parachutes with RocketPy's triggers ("apogee", a height above
the ground), and a ``Flight`` from ``initial_solution`` at the log's apogee (its height above the pad, at rest or
with a given horizontal velocity). The drogue deploys at the apogee after the flight computer's lag, the main at the
given height. RocketPy flies one C_D S at a time (a later parachute's replaces the earlier's); the harness decides the
main's: ``"drogue_stays"`` gives it drogue + main (the drogue stays on its harness, as on these rockets: the
comparison's variant), ``"main_replaces"`` the main's alone. The air is RocketPy's standard atmosphere with the pad
at the log's pressure altitude, or a custom atmosphere from ``air`` (pressure Pa and temperature K over heights above
sea level; the pad then at ``pad_gps_altitude``). RocketPy models no drag of the rocket itself under a parachute.

Its descent rates are read by pchute_exudyn.results.log_compare's rules (the Theil-Sen slope of the samples in a
band), on its states read linearly between its solver's points on a RATE_GRID grid (its Functions of time are
splines that ring at a deployment).
"""

from __future__ import annotations

from script_arguments import module_of

if __name__ == "__main__":
    module_of(__file__, __doc__, "flight_logs.py")   # --help says what it is; a run does nothing, so it says so

import math
import sys
import warnings
from pathlib import Path

import numpy as np
import tomllib

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from benchmark_rocketpy import fly_rocketpy as fly_benchmark_inputs  # noqa: E402  (one home for the RocketPy build)
from benchmark_rocketpy import rocketpy_track  # noqa: E402

FLIGHTS = HERE / "flights" / "flights.toml"
SAMPLING_RATE = 100.0
"""Hz: the flight computer's trigger sampling (a TeleMega samples its barometer at 100 Hz in flight)."""
RATE_GRID = 0.05
"""s: RocketPy's heights are read linearly between its solver's points on this grid before a band's slope."""
HARNESSES = ("drogue_stays", "main_replaces")
MAX_STEP = 0.5
"""s: RocketPy's largest solver step. Its triggers are sampled only between solver steps and its ground impact ends a
step first: in a steady descent through a smooth custom atmosphere its solver's steps grow past 20 s and step over
the main's trigger height to the ground (seen on 2026 FT3: the main never deployed)."""


# -- the flights' inputs ----------------------------------------------------------------------------------------------

def load_flights(path: Path = FLIGHTS) -> dict:
    """Name -> the flight's table of flights.toml (masses kg, lengths m, canopies' diameter m and C_D)."""
    with path.open("rb") as handle:
        return tomllib.load(handle)["flights"]


def drag_area(canopy: dict) -> float:
    """m^2: C_D x the nominal area pi D^2 / 4 of a canopy's table (``diameter`` m, ``drag_coefficient``)."""
    return canopy["drag_coefficient"] * math.pi * canopy["diameter"] ** 2 / 4.0


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
    physics.flight_phases.band_rate, as results.log_compare reads both sides."""
    from pchute_exudyn.physics.flight_phases import band_rate

    return {label: band_rate(time, height, *limits)
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
        run, _ = fly_benchmark_inputs(env, inputs, max_time_step=MAX_STEP)
    track = rocketpy_track(run)
    grid = np.arange(track["time"][0], track["time"][-1], RATE_GRID)
    height = np.interp(grid, track["time"], track["altitude"]) - env.elevation
    deployed = {p.name: float(t) + p.lag for t, p in run.parachute_events}
    return {"time": grid, "height": height, "rates": band_rates(grid, height, flight["bands"]),
            "descent_time": float(run.t_final), "deployed": deployed,
            "main_cd_s": inputs["parachutes"][1]["cd_s"], "harness": harness}

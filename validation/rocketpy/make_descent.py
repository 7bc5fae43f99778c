#!/usr/bin/env python3
"""Produce a RocketPy reference descent: a payload under one open parachute.

Runs a RocketPy ``Flight`` that starts at a given altitude with a given
downward speed, with a parachute that is already fully open (trigger always
True, lag 0), down to ground impact, and writes RocketPy's own CSV export
(``FlightDataExporter.export_data``) unedited.

RocketPy is NOT a dependency of pchute-exudyn; run this with a separate venv:

    python3 -m venv /tmp/rpy && /tmp/rpy/bin/pip install rocketpy
    /tmp/rpy/bin/python validation/rocketpy/make_descent.py
"""

import argparse
import os
from importlib.metadata import version

from rocketpy import EmptyMotor, Environment, Flight, Rocket

try:  # newer RocketPy (e.g. 1.13) exports through FlightDataExporter
    from rocketpy.simulation.flight_data_exporter import FlightDataExporter
except ImportError:  # older RocketPy: Flight.export_data
    FlightDataExporter = None

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mass", type=float, default=111.109091,
                    help="total suspended mass, kg (default 111.109091: `pchute new --planet earth --mass 100 --drag-area 40 --altitude 3000`)")
    ap.add_argument("--cd-s", type=float, default=40.0,
                    help="parachute drag area Cd*S, m^2 (default 40)")
    ap.add_argument("--altitude", type=float, default=3000.0,
                    help="start altitude above sea level = above ground, m "
                         "(default 3000)")
    ap.add_argument("--speed", type=float, default=7.73735,
                    help="initial downward speed, m/s (default 7.73735, the steady rate at 3000 m of that case)")
    ap.add_argument("--time-step", type=float, default=0.5,
                    help="export time step, s (default 0.5; 0.1 gives a "
                         "~170 kB file)")
    ap.add_argument("--out", default=os.path.join(HERE, "descent.csv"),
                    help="output CSV (default descent.csv next to this script)")
    args = ap.parse_args()

    # Environment: equator, sea-level ground, RocketPy's default standard
    # atmosphere (ISA, no wind) and default gravity (gravity=None -> Somigliana
    # normal gravity with a height correction).
    env = Environment(latitude=0.0, longitude=0.0, elevation=0.0)
    env.set_atmospheric_model(type="standard_atmosphere")

    # "Rocket" = the payload. With no motor (EmptyMotor: zero mass, zero
    # thrust) its dry mass, which u_dot_parachute uses, is exactly `mass`.
    # Body drag and inertia are irrelevant: the parachute phase is 3-DOF and
    # uses only the parachute's cd_s.
    rocket = Rocket(
        radius=0.1,
        mass=args.mass,
        inertia=(1.0, 1.0, 1.0),
        power_off_drag=0.0,
        power_on_drag=0.0,
        center_of_mass_without_motor=0.0,
    )
    rocket.add_motor(EmptyMotor(), position=0.0)

    # Parachute open from t = 0: trigger always True, no lag. radius=0 (and so
    # height=0, which falls back to radius) makes RocketPy's added mass
    # ma = k * rho * (2/3) * pi * R^2 * H exactly zero.
    rocket.add_parachute(
        "main",
        cd_s=args.cd_s,
        trigger=lambda p, h, y: True,
        sampling_rate=100,
        lag=0,
        radius=0.0,
    )

    # Initial state [t, x, y, z, vx, vy, vz, e0, e1, e2, e3, w1, w2, w3]:
    # at altitude, moving straight down, upright attitude, no rotation.
    initial = [0.0, 0.0, 0.0, args.altitude, 0.0, 0.0, -args.speed,
               1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]

    # time_overshoot=False puts a parachute trigger check at t = 0, before
    # any integration step, so the whole flight is the parachute phase.
    # The flight ends at ground impact (z = elevation); max_time is only a cap.
    flight = Flight(
        rocket=rocket,
        environment=env,
        rail_length=1.0,  # unused when initial_solution is given
        initial_solution=initial,
        max_time=3600.0,
        max_time_step=0.1,
        time_overshoot=False,
        name="pchute-exudyn single-parachute descent",
    )

    # RocketPy's own CSV export, unedited.
    variables = ("z", "vz", "speed")
    if FlightDataExporter is not None:
        FlightDataExporter(flight).export_data(
            args.out, *variables, time_step=args.time_step)
    else:
        flight.export_data(args.out, *variables, time_step=args.time_step)

    print(f"rocketpy {version('rocketpy')}")
    print(f"parachute opened at t = {flight.parachute_events[0][0]:.3f} s")
    print(f"impact at t = {flight.t_final:.4f} s, "
          f"vz = {flight.impact_velocity:.4f} m/s")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

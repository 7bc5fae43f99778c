#!/usr/bin/env python3
"""Produce a RocketPy flight export through apogee: a 20 kg rocket coasting up from 1000 m above the ground at
Spaceport America, drogue at apogee (1 s lag), main at 300 m above the ground, down to impact.

Writes RocketPy's own CSV export (``FlightDataExporter.export_data``) unedited, with the columns ``pchute new
--from-rocketpy`` reads (position, velocity over the ground, attitude quaternion, latitude, longitude, height above
the ground). RocketPy is NOT a dependency of pchute-exudyn; run this with it installed (README.md here).
"""

import argparse
import math
import os
from importlib.metadata import version

from rocketpy import EmptyMotor, Environment, Flight, Rocket
from rocketpy.simulation.flight_data_exporter import FlightDataExporter

HERE = os.path.dirname(os.path.abspath(__file__))
VARIABLES = ("x", "y", "z", "vx", "vy", "vz", "e0", "e1", "e2", "e3", "latitude", "longitude", "altitude")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time-step", type=float, default=0.5, help="export time step, s (default 0.5)")
    ap.add_argument("--out", default=os.path.join(HERE, "dual_deploy_flight.csv"), help="output CSV")
    args = ap.parse_args()

    env = Environment(latitude=32.99, longitude=-106.97, elevation=1400.0)
    env.set_atmospheric_model(type="standard_atmosphere")
    rocket = Rocket(radius=0.075, mass=21.31, inertia=(10.44, 10.44, 0.056), power_off_drag=0.5,
                    power_on_drag=0.5, center_of_mass_without_motor=0.0,
                    coordinate_system_orientation="tail_to_nose")
    rocket.add_motor(EmptyMotor(), position=0.0)
    rocket.add_parachute("drogue", cd_s=1.0, trigger="apogee", sampling_rate=100, lag=1.0)
    rocket.add_parachute("main", cd_s=10.0, trigger=300.0, sampling_rate=100, lag=0.0)
    # coasting at 1000 m above the ground, 160 m/s up and 15 m/s east, the nose along the velocity
    pitch = 1.4773   # rad: atan2(160, 15), the nose tilted east
    half = 0.5 * (0.5 * math.pi - pitch)   # a rotation about north (y) tilting body z toward east
    initial = [0.0, 0.0, 0.0, 2400.0, 15.0, 0.0, 160.0, math.cos(half), 0.0, math.sin(half), 0.0, 0.0, 0.0, 0.0]
    flight = Flight(rocket=rocket, environment=env, rail_length=1.0, initial_solution=initial, max_time=600.0,
                    max_time_step=0.0997, name="pchute-exudyn dual deploy through apogee")
    FlightDataExporter(flight).export_data(args.out, *VARIABLES, time_step=args.time_step)
    print(f"rocketpy {version('rocketpy')}")
    print(f"apogee {flight.apogee:.3f} m at t = {flight.apogee_time:.4f} s")
    for event in flight.parachute_events:
        print(f"{event[1].name} deployed at t = {event[0]:.3f} s")
    print(f"impact at t = {flight.t_final:.4f} s")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

"""The true values a trigger's sensor reads of a body of a case (``registries.quantities.QUANTITIES``): from its
position and velocity, the case's planet, atmosphere and air motion. Pure computation on a case (no engine): the
engine's trigger monitor samples it, the run's sequence records it at a triggered deployment."""

from __future__ import annotations

import math

import numpy as np

from ..physics.atmosphere import GAMMA_AT, pressure_of
from ..registries.quantities import derive_quantities
from .model import Case


def true_values(case: Case, position, velocity, time: float, air_motion=None) -> dict:
    """The true values a sensor reads (``registries.quantities.SENSED``, plus density in kg/m^3, speed of sound in m/s,
    gravity in m/s^2, position and velocity) of a body at start-frame ``position`` (m) and ``velocity`` (m/s) at
    ``time`` (s); ``air_motion``: the case's (``Case.air_motion``), made once by a caller that samples often."""
    x, y, z = (float(v) for v in position)
    altitude = case.start.altitude_scalar(x, y, z)
    velocity = np.asarray(velocity, float)
    ground = case.start.velocity_to_planet_fixed(np.array([x, y, z]), velocity, time)
    air_motion = case.air_motion() if air_motion is None else air_motion
    air = velocity if air_motion.still else velocity - np.array(air_motion(x, y, z, altitude, time))
    airspeed = float(np.linalg.norm(air))
    density, sound = case.atmosphere.state(altitude) if case.atmosphere is not None else (0.0, math.nan)
    gamma = case.atmosphere.kernel_parameters()[GAMMA_AT] if case.atmosphere is not None else 1.4
    truth = {"altitude": altitude, "altitude_ground": altitude - case.simulation.ground_altitude,
             "pressure": pressure_of(density, sound, gamma), "density": density, "speed_of_sound": sound,
             "vertical_velocity": -float(np.dot(case.start.down(np.array([x, y, z])), velocity)),
             "speed": float(np.linalg.norm(ground)), "airspeed": airspeed,
             "gravity": math.hypot(*case.start.gravity_scalar(x, y, z)),
             "position": np.array([x, y, z]), "velocity": velocity}
    derive_quantities(truth, truth)   # Mach number, dynamic pressure (``registries.quantities.QUANTITIES``)
    return truth


def pressure_function(case: Case):
    """h (m) -> (pressure in Pa, density in kg/m^3) of the case's atmosphere (``physics.atmosphere.pressure_of``)."""
    gamma = case.atmosphere.kernel_parameters()[GAMMA_AT]

    def pressure_at(altitude: float) -> tuple:
        density, sound = case.atmosphere.state(altitude)
        return pressure_of(density, sound, gamma), density
    return pressure_at

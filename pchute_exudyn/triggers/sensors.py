"""What a trigger's sensor reads (``triggers.definition.Sensor``), from the true values at a sample: a barometric
altitude from a pressure with noise in Pa (white or AR(1) correlated), a navigated speed with noise in m/s, each
noise stream seeded from the case's seed and the event's name alone. Pure numpy: no run, no user code."""

from __future__ import annotations

import math
import zlib

import numpy as np

from ..registries.quantities import QUANTITIES, SENSED, derive_quantities
from .definition import Sensor


def stream_seed(seed: int, event: str, stream: int) -> np.random.SeedSequence:
    """The seed of noise ``stream`` (0: pressure, 1: speed) of the trigger of ``event``: from the case's seed and the
    event's name alone (CRC-32, the same in every Python process), so any machine, method and step draws the same."""
    return np.random.SeedSequence([int(seed), zlib.crc32(event.encode()), stream])


class NoiseStream:
    """Gaussian noise of standard deviation ``sigma``, one value per sample in order, AR(1) with coefficient
    exp(-period / correlation_time) (stationary from the first sample), white when ``correlation_time`` is 0."""

    def __init__(self, seed: np.random.SeedSequence, sigma: float, period: float | None, correlation_time: float):
        self.rng = np.random.Generator(np.random.PCG64(seed))
        self.sigma = sigma
        self.phi = math.exp(-period / correlation_time) if correlation_time > 0.0 and period else 0.0
        self.value = None

    def next(self) -> float:
        if self.sigma == 0.0:
            return 0.0
        e = float(self.rng.standard_normal())
        if self.value is None:
            self.value = self.sigma * e
        else:
            self.value = self.phi * self.value + self.sigma * math.sqrt(1.0 - self.phi * self.phi) * e
        return self.value


def barometric_altitude(truth: dict, pressure: float, pressure_at) -> float:
    """The altitude (m) whose pressure is ``pressure`` (Pa), by Newton's method on ``pressure_at(h) -> (p, rho)``
    from the true state (hydrostatic slope dp/dh = -rho g)."""
    if not pressure > 0.0:   # a reading at or below zero: above the atmosphere as far as the altimeter knows
        return math.inf
    h, gravity = truth["altitude"], truth["gravity"]
    p, rho = truth["pressure"], truth["density"]
    for _ in range(50):   # converges in 2-4 iterations for errors of 1 % of p, in under 10 for 90 %
        step = (p - pressure) / (rho * gravity)
        step = max(min(step, 5.0 * p / (rho * gravity)), -5.0 * p / (rho * gravity))   # at most 5 scale heights
        h += step
        if abs(step) < 1e-6:
            break
        p, rho = pressure_at(h)
    return h


def sense(truth: dict, sensor: Sensor, pressure_error: float, speed_error: float, pressure_at) -> dict:
    """The sensed values (``SENSED``) from the true ones, with the sample's pressure error (Pa) and speed error (m/s),
    biases included."""
    sensed = {name: truth[name] for name in SENSED}
    if pressure_error != 0.0:
        sensed["pressure"] = truth["pressure"] + pressure_error
        altitude = barometric_altitude(truth, sensed["pressure"], pressure_at)
        sensed["altitude_ground"] += altitude - truth["altitude"]
        sensed["altitude"] = altitude
    if speed_error != 0.0:
        for quantity in QUANTITIES:
            if quantity.error == "speed":
                sensed[quantity.name] = truth[quantity.name] + speed_error
        derive_quantities(sensed, truth)
    return sensed


"""The air's inertial velocity at a point: the planet's rotation carries it (omega x r) and the wind blows over the
ground, its east/north components turning with the ground. Plain floats: it runs in per-stage user functions.
"""

from __future__ import annotations

import math


class AirMotion:
    """Air velocity (m/s, start-frame inertial components) at start-frame points.

    Parameters
    ----------
    start : physics.planet.StartFrame
    wind : physics.atmosphere.Wind or None
    """

    def __init__(self, start, wind=None):
        self.wind = wind
        self.omega = tuple(start.rotation_vector.tolist())
        self.center = tuple(start.planet_center.tolist())
        rate = start.planet.rotation_rate
        self.rate = rate
        self.axis = tuple((start.rotation_vector / rate).tolist()) if rate else (0.0, 0.0, 1.0)
        self.still = wind is None and rate == 0.0

    def __call__(self, x: float, y: float, z: float, altitude: float, time: float):
        """Air velocity at start-frame point (x, y, z) (m) of geodetic ``altitude`` (m) at ``time`` (s)."""
        vx = vy = vz = 0.0
        if self.wind is not None:
            vx, vy = self.wind.at(altitude)
            if self.rate:  # the ground's east/north axes have turned by omega t about the polar axis
                kx, ky, kz = self.axis
                c, s = math.cos(self.rate * time), math.sin(self.rate * time)
                along = kx * vx + ky * vy
                vx, vy, vz = (vx * c + (ky * vz - kz * vy) * s + kx * along * (1 - c),
                              vy * c + (kz * vx - kx * vz) * s + ky * along * (1 - c),
                              vz * c + (kx * vy - ky * vx) * s + kz * along * (1 - c))
        if self.rate:
            ox, oy, oz = self.omega
            dx, dy, dz = x - self.center[0], y - self.center[1], z - self.center[2]
            vx += oy * dz - oz * dy
            vy += oz * dx - ox * dz
            vz += ox * dy - oy * dx
        return vx, vy, vz

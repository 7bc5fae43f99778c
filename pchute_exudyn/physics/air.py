"""The air's inertial velocity at a point: the planet's rotation carries it (omega x r) and the wind blows over the
ground: the steady wind, turbulence and gusts (``physics.wind``) in the start point's east/north/up axes, which turn
with the ground. Plain floats: it runs in per-stage user functions.
"""

from __future__ import annotations

import math

import numpy as np

from .wind import gust_velocity


class AirMotion:
    """Air velocity (m/s, start-frame inertial components) at start-frame points.

    Parameters
    ----------
    start : physics.planet.StartFrame
    wind : physics.atmosphere.Wind, physics.wind.PowerLawWind or None
        The steady wind (its ``at(altitude)`` gives east, north in m/s).
    turbulence : physics.wind.DrydenTurbulence or None
    gusts : tuple of physics.wind.Gust
    """

    def __init__(self, start, wind=None, turbulence=None, gusts=()):
        self.wind, self.turbulence, self.gusts = wind, turbulence, tuple(gusts)
        self.moving = wind is not None or turbulence is not None or bool(self.gusts)
        self.omega = tuple(start.rotation_vector.tolist())
        self.center = tuple(start.planet_center.tolist())
        rate = start.planet.rotation_rate
        self.rate = rate
        self.axis = tuple((start.rotation_vector / rate).tolist()) if rate else (0.0, 0.0, 1.0)
        self.still = not self.moving and rate == 0.0

    def local(self, altitude: float, time: float):
        """(steady wind + gusts, turbulence) at geodetic ``altitude`` (m) and ``time`` (s): two (east, north, up)
        triples (m/s) relative to the ground, in the start point's axes."""
        east, north = self.wind.at(altitude) if self.wind is not None else (0.0, 0.0)
        ge, gn, gu = gust_velocity(self.gusts, time)
        turbulence = (self.turbulence.velocity(altitude, east, north) if self.turbulence is not None
                      else (0.0, 0.0, 0.0))
        return (east + ge, north + gn, gu), turbulence

    def relative(self, positions, velocities, altitudes, times) -> np.ndarray:
        """Velocities (m/s) relative to the air of points at start-frame ``positions`` (n, 3) (m) moving at
        ``velocities`` (n, 3) (m/s), of geodetic ``altitudes`` (n,) (m) at ``times`` (n,) (s): for whole histories;
        NaN rows where the altitude is not finite (a body absent then)."""
        velocities = np.asarray(velocities, float)
        out = np.full(velocities.shape, np.nan)
        for i in np.flatnonzero(np.isfinite(altitudes)):
            out[i] = velocities[i] - np.array(self(*positions[i].tolist(), float(altitudes[i]), float(times[i])))
        return out

    def __call__(self, x: float, y: float, z: float, altitude: float, time: float):
        """Air velocity at start-frame point (x, y, z) (m) of geodetic ``altitude`` (m) at ``time`` (s)."""
        vx = vy = vz = 0.0
        if self.moving:
            if self.turbulence is None and not self.gusts:
                vx, vy = self.wind.at(altitude)   # the steady wind alone (as before turbulence and gusts)
            else:
                (vx, vy, vz), (tx, ty, tz) = self.local(altitude, time)
                vx, vy, vz = vx + tx, vy + ty, vz + tz
            if self.rate:  # the ground's east/north axes have turned by omega t about the polar axis
                kx, ky, kz = self.axis
                c, s = math.cos(self.rate * time), math.sin(self.rate * time)
                along = kx * vx + ky * vy + kz * vz
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

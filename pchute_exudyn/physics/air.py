"""The air's inertial velocity at a point: the planet's rotation carries it (omega x r) and the wind blows over the
ground: the steady wind, turbulence and gusts (``physics.wind``) in the start point's east/north/up axes, which turn
with the ground. A compiled kernel (``air_velocity``) on packed parameters, which the per-stage aerodynamics call
and ``AirMotion`` wraps for Python callers.
"""

from __future__ import annotations

import math

import numpy as np

from .compiled import kernel
from .wind import NO_WIND, gust_rows, gust_sum, steady_wind, turbulence_velocity

AIR_COLUMNS = 13
"""``AirMotion.parameters``: moving (1/0), steady wind only (1/0: no turbulence and no gusts), the rotation rate
(rad/s), its unit axis (3), the angular velocity (3, rad/s), the planet centre (3, m, start frame), turbulence (1/0)."""
AIR_MOVING, AIR_STEADY_ONLY, AIR_RATE, AIR_AXIS, AIR_OMEGA, AIR_CENTER, AIR_TURBULENT = 0, 1, 2, 3, 6, 9, 12
"""Where each of them is (the vectors' first component)."""


class AirMotion:
    """Air velocity (m/s, start-frame inertial components) at start-frame points.

    Parameters
    ----------
    start : physics.planet.StartFrame
    wind : physics.atmosphere.Wind, physics.wind.PowerLawWind or None
        The steady wind (its ``at(altitude)`` gives east, north in m/s).
    turbulence : physics.wind.DrydenTurbulence or None
    gusts : tuple of physics.wind.Gust

    Notes
    -----
    The kernels take ``parameters`` (AIR_COLUMNS), ``wind`` (the steady wind's kernel parameters), ``gusts`` (rows of
    ``physics.wind.GUST_COLUMNS``), ``turbulence`` (its kernel parameters) and ``field()`` (its frozen field, which
    grows as higher air is asked for: a kernel reports the cells it needs and ``extend`` generates them).
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
        steady_only = self.moving and turbulence is None and not self.gusts
        self.parameters = np.array([float(self.moving), float(steady_only), rate, *self.axis, *self.omega,
                                    *self.center, float(turbulence is not None)])
        self.wind_parameters = wind.kernel_parameters() if wind is not None else np.array([NO_WIND])
        self.gust_rows = gust_rows(self.gusts)
        self.turbulence_parameters = (turbulence.kernel_parameters() if turbulence is not None
                                      else np.array([0.0, 1.0, 1.0, 0.0]))

    def field(self) -> np.ndarray:
        """The turbulence's frozen field as generated so far (3, cells); empty without turbulence."""
        return self.turbulence.field if self.turbulence is not None else np.zeros((3, 2))

    def extend(self, cells: int) -> None:
        """Generate the turbulence's field up to ``cells`` cells (a kernel asked for them)."""
        self.turbulence.extend_to(int(cells))

    def local(self, altitude: float, time: float):
        """(steady wind + gusts, turbulence) at geodetic ``altitude`` (m) and ``time`` (s): two (east, north, up)
        triples (m/s) relative to the ground, in the start point's axes."""
        east, north = steady_wind(self.wind_parameters, float(altitude))
        ge, gn, gu = gust_sum(self.gust_rows, float(time))
        turbulence = (self.turbulence.velocity(altitude, east, north) if self.turbulence is not None
                      else (0.0, 0.0, 0.0))
        return (east + ge, north + gn, gu), turbulence

    def relative(self, positions, velocities, altitudes, times) -> np.ndarray:
        """Velocities (m/s) relative to the air of points at start-frame ``positions`` (n, 3) (m) moving at
        ``velocities`` (n, 3) (m/s), of geodetic ``altitudes`` (n,) (m) at ``times`` (n,) (s): for whole histories;
        NaN rows where the altitude is not finite (a body absent then). One kernel call (``relative_velocities``)."""
        arguments = (np.ascontiguousarray(positions, float), np.ascontiguousarray(velocities, float),
                     np.ascontiguousarray(altitudes, float), np.ascontiguousarray(times, float))
        out = np.full(arguments[1].shape, np.nan)
        while True:
            needed = relative_velocities(self.parameters, self.wind_parameters, self.gust_rows,
                                         self.turbulence_parameters, self.field(), *arguments, out)
            if not needed:
                return out
            self.extend(needed)

    def local_history(self, altitudes, times) -> tuple:
        """``local`` at every sample of geodetic ``altitudes`` (n,) (m) and ``times`` (n,) (s): two (n, 3) arrays
        (m/s), NaN rows where the altitude is not finite. One kernel call (``local_air``)."""
        altitudes, times = np.ascontiguousarray(altitudes, float), np.ascontiguousarray(times, float)
        steady, turbulence = np.full((len(altitudes), 3), np.nan), np.full((len(altitudes), 3), np.nan)
        while True:
            needed = local_air(self.wind_parameters, self.gust_rows, self.turbulence_parameters, self.field(),
                               self.turbulence is not None, altitudes, times, steady, turbulence)
            if not needed:
                return steady, turbulence
            self.extend(needed)

    def __call__(self, x: float, y: float, z: float, altitude: float, time: float):
        """Air velocity at start-frame point (x, y, z) (m) of geodetic ``altitude`` (m) at ``time`` (s)."""
        while True:
            vx, vy, vz, needed = air_velocity(self.parameters, self.wind_parameters, self.gust_rows,
                                              self.turbulence_parameters, self.field(), float(x), float(y), float(z),
                                              float(altitude), float(time))
            if not needed:
                return vx, vy, vz
            self.extend(needed)


@kernel
def air_velocity(parameters, wind, gusts, turbulence, field, x, y, z, altitude, time):
    """(vx, vy, vz) air velocity (m/s, start frame) at start-frame point (x, y, z) (m) of geodetic ``altitude``
    (m) at ``time`` (s), and 0; or (0, 0, 0, cells) when the turbulence field must first grow to that many cells.
    The arguments are ``AirMotion``'s packed parts."""
    vx = vy = vz = 0.0
    rate = parameters[AIR_RATE]
    if parameters[AIR_MOVING] > 0.0:
        if parameters[AIR_STEADY_ONLY] > 0.0:   # the steady wind alone (as before turbulence and gusts)
            vx, vy = steady_wind(wind, altitude)
        else:
            east, north = steady_wind(wind, altitude)
            ge, gn, gu = gust_sum(gusts, time)
            tx = ty = tz = 0.0
            if parameters[AIR_TURBULENT] > 0.0:
                tx, ty, tz, needed = turbulence_velocity(field, turbulence, altitude, east, north)
                if needed:
                    return 0.0, 0.0, 0.0, needed
            vx, vy, vz = east + ge, north + gn, gu
            vx, vy, vz = vx + tx, vy + ty, vz + tz
        if rate:  # the ground's east/north axes have turned by omega t about the polar axis
            axis = AIR_AXIS
            kx, ky, kz = parameters[axis], parameters[axis + 1], parameters[axis + 2]
            c, s = math.cos(rate * time), math.sin(rate * time)
            along = kx * vx + ky * vy + kz * vz
            vx, vy, vz = (vx * c + (ky * vz - kz * vy) * s + kx * along * (1 - c),
                          vy * c + (kz * vx - kx * vz) * s + ky * along * (1 - c),
                          vz * c + (kx * vy - ky * vx) * s + kz * along * (1 - c))
    if rate:
        omega, center = AIR_OMEGA, AIR_CENTER
        ox, oy, oz = parameters[omega], parameters[omega + 1], parameters[omega + 2]
        dx, dy, dz = x - parameters[center], y - parameters[center + 1], z - parameters[center + 2]
        vx += oy * dz - oz * dy
        vy += oz * dx - ox * dz
        vz += ox * dy - oy * dx
    return vx, vy, vz, 0


@kernel
def relative_velocities(parameters, wind, gusts, turbulence, field, positions, velocities, altitudes, times, out):
    """Each sample's velocity relative to the air (``air_velocity``) into ``out`` (n, 3) (m/s), where its altitude is
    finite; 0, or the cells the turbulence field must first grow to. The arguments as ``AirMotion.relative``'s."""
    for i in range(altitudes.shape[0]):
        if not math.isfinite(altitudes[i]):
            continue
        vx, vy, vz, needed = air_velocity(parameters, wind, gusts, turbulence, field, positions[i, 0],
                                          positions[i, 1], positions[i, 2], altitudes[i], times[i])
        if needed:
            return needed
        out[i, 0], out[i, 1], out[i, 2] = velocities[i, 0] - vx, velocities[i, 1] - vy, velocities[i, 2] - vz
    return 0


@kernel
def local_air(wind, gusts, turbulence, field, has_turbulence, altitudes, times, steady, local_turbulence):
    """``AirMotion.local`` at each sample of finite altitude: the steady wind plus gusts into ``steady`` and the
    turbulence into ``local_turbulence`` ((n, 3) east, north, up, m/s); 0, or the cells the field must first grow
    to."""
    for i in range(altitudes.shape[0]):
        altitude = altitudes[i]
        if not math.isfinite(altitude):
            continue
        east, north = steady_wind(wind, altitude)
        ge, gn, gu = gust_sum(gusts, times[i])
        tx = ty = tz = 0.0
        if has_turbulence:
            tx, ty, tz, needed = turbulence_velocity(field, turbulence, altitude, east, north)
            if needed:
                return needed
        steady[i, 0], steady[i, 1], steady[i, 2] = east + ge, north + gn, gu
        local_turbulence[i, 0], local_turbulence[i, 1], local_turbulence[i, 2] = tx, ty, tz
    return 0

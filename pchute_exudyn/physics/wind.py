"""Wind models beyond a constant or tabulated steady wind: a power-law profile over the ground, Dryden turbulence and
"1 - cosine" discrete gusts (docs/models/canopy.md, "Winds"). Plain floats: they run in per-stage user functions.

Conventions: east, north, up components (m/s) of the air's velocity relative to the ground in the start point's
local axes; a direction given as ``from_deg`` is where the air comes from, clockwise from north (meteorological:
270 deg is a west wind, blowing east).

Turbulence is a frozen field along the height above the ground: a parachute descends through the air mass, so a
component's correlation over a height step equals its correlation in time at the descent rate V over (height step)
/ V (Taylor's hypothesis, vertical). The field is generated as filtered white noise on a uniform height grid, cell by
cell upwards from the ground, from a seed alone: every method, step and machine sees the same air.

The formulas evaluated at every solver stage are compiled kernels on packed parameters (``steady_wind``,
``gust_sum``, ``field_components``, ``turbulence_velocity``); the models' Python methods call them, so the per-stage
aerodynamics (``physics.air``) and the outputs compute the same numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .compiled import kernel
from .planet import hypot

FOOT = 0.3048
"""m per ft (the MIL-F-8785C low-altitude formulas are written in feet)."""


def wind_from_direction(speed: float, from_deg: float) -> tuple:
    """(east, north) components (m/s) of a wind of ``speed`` (m/s) coming from ``from_deg`` (deg, clockwise from
    north)."""
    angle = math.radians(from_deg)
    return -speed * math.sin(angle), -speed * math.cos(angle)


NO_WIND, TABLE_WIND, POWER_LAW_WIND = 0.0, 1.0, 2.0
"""A steady wind's kind (``kernel_parameters()[WIND_KIND_AT]``): none, constant or altitude table
(``physics.atmosphere.Wind``: then n, and n altitudes, n east and n north components, or for a constant n = 0, east,
north), or power law (east, north, h_ref, p, h_ground)."""
WIND_KIND_AT, TABLE_ROWS_AT, TABLE_HEAD = 0, 1, 2
"""A steady wind's kind, a table's n, and where the table's columns (a constant's east and north) start."""
POWER_EAST_AT, POWER_NORTH_AT, POWER_HEIGHT_AT, POWER_EXPONENT_AT, POWER_GROUND_AT = 1, 2, 3, 4, 5
"""A power law's east and north wind at the reference height (m/s), h_ref (m), p (-) and h_ground (m)."""
TURBULENCE_GROUND_AT, TURBULENCE_CELL_AT, TURBULENCE_HEADING_AT = 0, 1, 2
"""``DrydenTurbulence.kernel_parameters``: the ground altitude (m), the field's cell (m), the heading (east, north)."""


@kernel
def steady_wind(parameters, altitude):
    """(east, north) steady wind (m/s) at geodetic ``altitude`` (m) of the wind ``parameters``
    (``kernel_parameters`` of ``physics.atmosphere.Wind`` or ``PowerLawWind``; [NO_WIND] for none)."""
    kind = parameters[WIND_KIND_AT]
    if kind == TABLE_WIND:
        n = int(parameters[TABLE_ROWS_AT])
        head = TABLE_HEAD
        if n == 0:
            return parameters[head], parameters[head + 1]
        if altitude <= parameters[head]:
            i, w = 1, 0.0
        elif altitude >= parameters[head + n - 1]:
            i, w = n - 1, 1.0
        else:
            i = 1
            while parameters[head + i] <= altitude:   # bisect_right, as physics.interpolation.bracket
                i += 1
            w = (altitude - parameters[head + i - 1]) / (parameters[head + i] - parameters[head + i - 1])
        east, north = head + n, head + 2 * n
        return (parameters[east + i - 1] + w * (parameters[east + i] - parameters[east + i - 1]),
                parameters[north + i - 1] + w * (parameters[north + i] - parameters[north + i - 1]))
    if kind == POWER_LAW_WIND:
        height = altitude - parameters[POWER_GROUND_AT]
        if height <= 0.0:
            return 0.0, 0.0
        factor = (height / parameters[POWER_HEIGHT_AT]) ** parameters[POWER_EXPONENT_AT]
        return parameters[POWER_EAST_AT] * factor, parameters[POWER_NORTH_AT] * factor
    return 0.0, 0.0


@dataclass(frozen=True)
class PowerLawWind:
    """Steady wind w(h) = w_ref ((h - h_ground) / h_ref)^p above the ground and none below it.

    Attributes
    ----------
    east, north : float
        The wind at the reference height (m/s).
    reference_height : float
        h_ref, above the ground (m).
    exponent : float
        p (-), in [0, 1] (1/7 over open terrain).
    ground_altitude : float
        h_ground, geodetic (m).
    """

    east: float
    north: float
    reference_height: float
    exponent: float
    ground_altitude: float = 0.0

    def kernel_parameters(self) -> np.ndarray:
        """The wind for ``steady_wind``."""
        return np.array([POWER_LAW_WIND, self.east, self.north, self.reference_height, self.exponent,
                         self.ground_altitude])

    def at(self, altitude: float):
        """(east, north) wind (m/s) at geodetic ``altitude`` (m)."""
        return steady_wind(self.kernel_parameters(), float(altitude))

    def largest_speed(self, top: float) -> float:
        """The wind's largest speed (m/s) up to geodetic altitude ``top`` (m): the power law grows with height."""
        return math.hypot(*self.at(top))


# -- Dryden turbulence --------------------------------------------------------------------------------------------

def dryden_correlation(component: str, lag: float, length: float) -> float:
    """Normalised autocorrelation R(lag) / sigma^2 of a Dryden component over separation ``lag`` for scale length
    ``length`` (same unit): exp(-lag/L) for u, exp(-lag/L) (1 - lag / (2L)) for v and w."""
    r = abs(lag) / length
    return math.exp(-r) if component == "u" else math.exp(-r) * (1.0 - 0.5 * r)


@kernel
def low_altitude_scales(height: float, wind_speed_6m: float) -> tuple:
    """(sigma_u, sigma_v, sigma_w) (m/s) and (L_u, L_v, L_w) (m) at ``height`` above the ground (m) from the wind
    speed at 6 m (20 ft, m/s): MIL-F-8785C's low-altitude forms, sigma_w = 0.1 W20, sigma_u = sigma_v = sigma_w /
    (0.177 + 0.000823 h)^0.4, L_w = h, L_u = L_v = h / (0.177 + 0.000823 h)^1.2 (h in ft), for 10 ft <= h <= 1000
    ft. Below 10 ft they hold their 10-ft values. Above 1000 ft the scale lengths (then all 1000 ft) grow linearly
    to 1750 ft at 2000 ft and stay there (the medium-altitude value); the intensities stay at 0.1 W20, the value
    the forms reach at 1000 ft (the medium/high-altitude intensities need a probability of exceedance)."""
    h = min(max(height / FOOT, 10.0), 1000.0)
    base = 0.177 + 0.000823 * h
    sigma_w = 0.1 * wind_speed_6m
    sigma_uv = sigma_w / base ** 0.4
    length_w, length_uv = h * FOOT, h / base ** 1.2 * FOOT
    above = height / FOOT - 1000.0
    if above > 0.0:
        length_w = length_uv = (1000.0 + 750.0 * min(above / 1000.0, 1.0)) * FOOT
    return (sigma_uv, sigma_uv, sigma_w), (length_uv, length_uv, length_w)


CELLS_PER_LENGTH = 20
"""Grid cells per smallest scale length (linear interpolation keeps >= 97.5 % of the variance between cells)."""
BLOCK = 4096
"""Cells generated at a time, each block from its own child seed (so a field extends upwards deterministically)."""


class DrydenTurbulence:
    """Dryden turbulence (MIL-F-8785C spectral forms) as a frozen field over the height above the ground.

    Components: u along the mean wind's horizontal direction at that height (without wind: along ``heading``), v
    horizontal to its left, w up. Each is a unit-variance process on a uniform height grid, scaled by its
    intensity: u first order (correlation exp(-s/L)), v and w second order (exp(-s/L) (1 - s/(2L))), each
    discretised exactly cell to cell (the correlation between grid points is the Dryden value for any cell size),
    and linear between cells. Below the ground the field holds its ground value.

    Parameters
    ----------
    seed : int
        Seed of the white noise (>= 0).
    ground_altitude : float
        Geodetic altitude of the ground (m).
    sigma : tuple of 3 float or None
        Intensities sigma_u, sigma_v, sigma_w (m/s), constant with height; or None with ``wind_speed_6m``.
    length : tuple of 3 float or None
        Scale lengths L_u, L_v, L_w (m), with ``sigma``.
    wind_speed_6m : float or None
        Wind speed at 6 m (m/s): intensities and lengths from ``low_altitude_scales`` at each height.
    heading : tuple of 2 float
        Unit (east, north) direction of u where there is no mean wind.
    """

    def __init__(self, seed: int, ground_altitude: float = 0.0, sigma=None, length=None, wind_speed_6m=None,
                 heading=(1.0, 0.0)):
        self.seed, self.ground_altitude, self.heading = int(seed), float(ground_altitude), tuple(heading)
        self.sigma = None if sigma is None else tuple(float(s) for s in sigma)
        self.length = None if length is None else tuple(float(x) for x in length)
        self.wind_speed_6m = wind_speed_6m
        shortest = min(self.length) if self.length is not None else 10.0 * FOOT
        self.cell = shortest / CELLS_PER_LENGTH      # m
        self.values: list = [[], [], []]             # u, v, w at the cells (m/s)
        self.field = np.zeros((3, 0))                # the same as an array, for the kernels
        self._state = None                           # (xi_u, z_v1, z_v2, z_w1, z_w2) after the last cell

    def scales(self, height: float) -> tuple:
        """(sigma_u, sigma_v, sigma_w) (m/s) and (L_u, L_v, L_w) (m) at ``height`` above the ground (m)."""
        if self.sigma is not None:
            return self.sigma, self.length
        return low_altitude_scales(height, self.wind_speed_6m)

    def largest_sigma(self, top: float) -> float:
        """The largest intensity (m/s) of any component between the ground and geodetic altitude ``top`` (m)
        (the low-altitude forms' sigma_u and sigma_v fall with height: largest at the ground)."""
        heights = np.linspace(0.0, max(top - self.ground_altitude, 0.0), 21)
        return max(max(self.scales(float(h))[0]) for h in heights)

    def _extend(self) -> None:
        """Generate the next BLOCK cells from block k's own seed, continuing the recursions (``dryden_block``)."""
        k = len(self.values[0]) // BLOCK
        noise = np.random.Generator(np.random.PCG64(np.random.SeedSequence([self.seed, k]))).standard_normal(
            (BLOCK, 5))
        state = np.array(self._state if self._state is not None else noise[0])   # stationary: N(0, 1)
        fixed = self.sigma is not None
        sigma, length = (np.array(self.sigma), np.array(self.length)) if fixed else (np.zeros(3), np.zeros(3))
        block = np.empty((3, BLOCK))
        dryden_block(noise, k * BLOCK, state, self.cell, fixed, sigma, length, float(self.wind_speed_6m or 0.0), block)
        for values, row in zip(self.values, block.tolist()):
            values.extend(row)
        self._state = tuple(state.tolist())
        self.field = np.array(self.values)

    def extend_to(self, cells: int) -> None:
        """Generate the field up to at least ``cells`` cells."""
        while len(self.values[0]) < cells:
            self._extend()

    def kernel_parameters(self) -> np.ndarray:
        """(ground altitude m, cell m, heading east, heading north) for ``turbulence_velocity``."""
        return np.array([self.ground_altitude, self.cell, *self.heading])

    def components(self, altitude: float) -> tuple:
        """(u, v, w) (m/s) at geodetic ``altitude`` (m)."""
        while True:
            u, v, w, needed = field_components(self.field, self.ground_altitude, self.cell, float(altitude))
            if not needed:
                return u, v, w
            self.extend_to(needed)

    def velocity(self, altitude: float, mean_east: float, mean_north: float) -> tuple:
        """(east, north, up) turbulence (m/s) at ``altitude`` (m) under a mean wind (m/s) that orients u and v."""
        while True:
            east, north, up, needed = turbulence_velocity(self.field, self.kernel_parameters(), float(altitude),
                                                          float(mean_east), float(mean_north))
            if not needed:
                return east, north, up
            self.extend_to(needed)


@kernel
def field_components(field, ground, cell, altitude):
    """(u, v, w) (m/s) of the frozen field ``field`` (3, n cells of ``cell`` m from the ``ground`` altitude, m) at
    geodetic ``altitude`` (m), linear between cells and held below the ground, and 0; or (0, 0, 0, cells) when the
    field must first be generated up to that many cells."""
    position = max(altitude - ground, 0.0) / cell
    i = int(position)
    if i + 1 >= field.shape[1]:
        return 0.0, 0.0, 0.0, i + 2
    f = position - i
    return (field[0, i] + f * (field[0, i + 1] - field[0, i]), field[1, i] + f * (field[1, i + 1] - field[1, i]),
            field[2, i] + f * (field[2, i + 1] - field[2, i]), 0)


@kernel
def turbulence_velocity(field, parameters, altitude, mean_east, mean_north):
    """(east, north, up) turbulence (m/s) at ``altitude`` (m), u along the mean wind (m/s; without one, along the
    heading), and 0; or (0, 0, 0, cells) when the field must first be generated further (``field_components``).
    ``parameters``: ``DrydenTurbulence.kernel_parameters``."""
    u, v, w, needed = field_components(field, parameters[TURBULENCE_GROUND_AT], parameters[TURBULENCE_CELL_AT],
                                       altitude)
    if needed:
        return 0.0, 0.0, 0.0, needed
    speed = hypot(mean_east, mean_north)
    if speed > 1e-9:
        ce, cn = mean_east / speed, mean_north / speed
    else:
        ce, cn = parameters[TURBULENCE_HEADING_AT], parameters[TURBULENCE_HEADING_AT + 1]
    return u * ce - v * cn, u * cn + v * ce, w, 0


SQRT3 = math.sqrt(3.0)


@kernel
def dryden_block(noise, first, state, cell, fixed, sigma, length, wind_speed_6m, block):
    """The cells ``first`` .. ``first`` + n - 1 of a Dryden field (``DrydenTurbulence``) into ``block`` (3, n): the
    recursions continued from ``state`` (xi_u, z_v1, z_v2, z_w1, z_w2; updated in place) with the white ``noise``
    (n, 5); the intensities and scale lengths ``sigma`` and ``length`` (m/s, m) when ``fixed``, else the
    low-altitude forms at each cell's height from ``wind_speed_6m`` (m/s). Cell 0 is the initial state itself."""
    xu, v1, v2, w1, w2 = state[0], state[1], state[2], state[3], state[4]
    s0, s1, s2, l0, l1, l2 = sigma[0], sigma[1], sigma[2], length[0], length[1], length[2]
    for i in range(noise.shape[0]):
        if not fixed:
            (s0, s1, s2), (l0, l1, l2) = low_altitude_scales((first + i) * cell, wind_speed_6m)
        if first + i > 0:
            xu = _first_order(xu, cell / l0, noise[i, 0])
            v1, v2 = _second_order(v1, v2, cell / l1, noise[i, 1], noise[i, 2])
            w1, w2 = _second_order(w1, w2, cell / l2, noise[i, 3], noise[i, 4])
        block[0, i] = s0 * xu
        block[1, i] = s1 * 0.5 * (v1 + SQRT3 * v2)
        block[2, i] = s2 * 0.5 * (w1 + SQRT3 * w2)
    state[0], state[1], state[2], state[3], state[4] = xu, v1, v2, w1, w2


@kernel
def _first_order(x: float, r: float, noise: float) -> float:
    """One cell of a unit-variance first-order process (cell / L = ``r``): exact AR(1)."""
    a = math.exp(-r)
    return a * x + math.sqrt(1.0 - a * a) * noise


@kernel
def _second_order(z1: float, z2: float, r: float, n1: float, n2: float) -> tuple:
    """One cell of the Dryden v/w shaping filter (1 + sqrt(3) L s) / (1 + L s)^2 in unit-covariance state
    coordinates: z' = M z + chol(I - M M^T) n with M = exp(-r) [[1 + r, r], [-r, 1 - r]] (the filter's transition
    over the cell, scaled by its stationary covariance diag(L^3/4, L/4)); the output (z1 + sqrt(3) z2) / 2 has unit
    variance and correlation exp(-s/L) (1 - s/(2L))."""
    e = math.exp(-r)
    m11, m12, m21, m22 = e * (1.0 + r), e * r, -e * r, e * (1.0 - r)
    q11 = 1.0 - m11 * m11 - m12 * m12
    q12 = -(m11 * m21 + m12 * m22)
    q22 = 1.0 - m21 * m21 - m22 * m22
    l11 = math.sqrt(max(q11, 0.0))
    l21 = q12 / l11 if l11 > 0.0 else 0.0
    l22 = math.sqrt(max(q22 - l21 * l21, 0.0))
    return m11 * z1 + m12 * z2 + l11 * n1, m21 * z1 + m22 * z2 + l21 * n1 + l22 * n2


# -- discrete gusts -----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Gust:
    """A "1 - cosine" gust: (A/2) (1 - cos(2 pi (t - t0) / T)) for t0 <= t <= t0 + T along ``direction``.

    Attributes
    ----------
    amplitude : float
        A, the peak air speed (m/s).
    start : float
        t0 (s, run time).
    length : float
        T, the pulse's duration (s, > 0).
    direction : tuple of 3 float
        Unit (east, north, up) direction the air moves in.
    """

    amplitude: float
    start: float
    length: float
    direction: tuple

    def speed(self, time: float) -> float:
        """The gust's air speed (m/s) at ``time`` (s)."""
        return gust_speed(self.amplitude, self.start, self.length, float(time))


GUST_COLUMNS = 6
"""A gust for the kernels: amplitude (m/s), start (s), length (s), direction (east, north, up)."""


def gust_rows(gusts) -> np.ndarray:
    """``gusts`` as rows of GUST_COLUMNS for ``gust_sum``."""
    return np.array([[g.amplitude, g.start, g.length, *g.direction] for g in gusts], float).reshape(-1, GUST_COLUMNS)


@kernel
def gust_speed(amplitude, start, length, time):
    """(A/2) (1 - cos(2 pi (t - t0) / T)) (m/s) for t0 <= t <= t0 + T, else 0."""
    phase = (time - start) / length
    if not 0.0 <= phase <= 1.0:
        return 0.0
    return 0.5 * amplitude * (1.0 - math.cos(2.0 * math.pi * phase))


@kernel
def gust_sum(rows, time):
    """(east, north, up) air velocity (m/s) of the gusts ``rows`` (GUST_COLUMNS) at ``time`` (s)."""
    e = n = u = 0.0
    for j in range(rows.shape[0]):
        speed = gust_speed(rows[j, 0], rows[j, 1], rows[j, 2], time)
        if speed:
            e, n, u = e + speed * rows[j, 3], n + speed * rows[j, 4], u + speed * rows[j, 5]
    return e, n, u


def gust_velocity(gusts, time: float) -> tuple:
    """(east, north, up) air velocity (m/s) of all ``gusts`` at ``time`` (s)."""
    return gust_sum(gust_rows(gusts), float(time))

"""A barometric altimeter's heights read through the day's air.

An altimeter measures pressure and reports the height that pressure has in the standard atmosphere (US76's first
layer: T = 288.15 K - 6.5 K/km x h, p = 101325 Pa (T / 288.15 K)^(g0 / (R L))). On a day warmer than the standard the
air is less dense, pressure falls more slowly with height, and the altimeter reads low: on a 35 C day at a 200 m pad
a reported 1000 m is some 1070 m. The true heights follow from the hydrostatic balance of the day's air,
dp = -rho(z) g dz: a sample whose standard height is h above a pad of standard height h_pad lies at the height z
above the pad where g * integral_0^z rho_day = p_std(h_pad) - p_std(h_pad + h) (``geometric_heights``). The day's air
is a density profile: a case's atmosphere, or a layer of constant lapse through the pad's pressure and temperature
(``lapse_layer``) where the log or a sounding gives them.
"""

from __future__ import annotations

import numpy as np

from .atmosphere import US76_G0, US76_P0, US76_R, US76_R0, US76_T0

STANDARD_LAPSE = 0.0065
"""K/m: the temperature's fall with height in US76's first layer (0 to 11 km), the altimeters' standard."""
DAY_REACH = 1.25
"""The day's column is integrated this many times the samples' heights (above and below the pad)."""
GRID_STEP = 1.0
"""m: the spacing of the day's density profile integrated for the heights (the density changes 0.01 % per m)."""


def standard_temperature(pressure_altitude):
    """K at ``pressure_altitude`` (m, US76's first layer; array or float): T0 - L h."""
    return US76_T0 - STANDARD_LAPSE * np.asarray(pressure_altitude, float)


def standard_pressure(pressure_altitude):
    """Pa at ``pressure_altitude`` (m, US76's first layer; array or float): p0 (1 - L h / T0)^(g0 / (R L))."""
    ratio = standard_temperature(pressure_altitude) / US76_T0
    return US76_P0 * ratio ** (US76_G0 / (US76_R * STANDARD_LAPSE))


def pressure_altitude(pressure):
    """m: the standard height of ``pressure`` (Pa; array or float), ``standard_pressure``'s inverse."""
    ratio = (np.asarray(pressure, float) / US76_P0) ** (US76_R * STANDARD_LAPSE / US76_G0)
    return US76_T0 * (1.0 - ratio) / STANDARD_LAPSE


def lapse_layer(heights, pressure: float, temperature: float, lapse: float = STANDARD_LAPSE,
                gravity: float = US76_G0):
    """The day's air at ``heights`` (m above the point where it has ``pressure`` Pa and ``temperature`` K) as one
    layer of constant ``lapse`` (K/m, temperature falling with height): (pressures Pa, temperatures K, densities
    kg/m^3). p = p_g (T / T_g)^(g / (R L)), rho = p / (R T); ``gravity`` in m/s^2."""
    temperatures = temperature - lapse * np.asarray(heights, float)
    if lapse == 0.0:
        pressures = pressure * np.exp(-gravity * np.asarray(heights, float) / (US76_R * temperature))
    else:
        pressures = pressure * (temperatures / temperature) ** (gravity / (US76_R * lapse))
    return pressures, temperatures, pressures / (US76_R * temperatures)


def geometric_heights(barometric_heights, pad_pressure_altitude: float, day_density, gravity: float = US76_G0):
    """Heights above the pad (m) of an altimeter's ``barometric_heights`` (m above the pad, standard atmosphere)
    in the day's air: ``day_density(z)`` gives its density (kg/m^3) at heights z (m above the pad, an array);
    ``pad_pressure_altitude`` (m) is the pad's standard height (its pressure's: the log's own above-sea-level
    reading, else the pad's elevation); ``gravity`` (m/s^2) the site's. Each sample's pressure drop below the pad's
    is matched with the day's column of air (module docstring)."""
    heights = np.asarray(barometric_heights, float)
    drops = standard_pressure(pad_pressure_altitude) - standard_pressure(pad_pressure_altitude + heights)
    # The day's column: a grid reaching DAY_REACH past the samples (a day's temperature is within 20 % of the
    # standard's, and so is the height a pressure drop takes).
    low = min(float(heights.min()), 0.0) * DAY_REACH - 10.0
    high = max(float(heights.max()), 0.0) * DAY_REACH + 10.0
    grid = np.arange(low, high + GRID_STEP, GRID_STEP)
    density = np.asarray(day_density(grid), float)
    column = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(grid))]) * gravity
    column -= np.interp(0.0, grid, column)   # zero at the pad
    return np.interp(drops, column, grid)


def offset_day_density(pad_pressure: float, pad_temperature: float, lapse: float = STANDARD_LAPSE,
                       gravity: float = US76_G0):
    """The day's density (kg/m^3) at heights z (m above the pad) as a function: one layer of ``lapse`` (K/m)
    through the pad's ``pad_pressure`` (Pa) and ``pad_temperature`` (K) (``lapse_layer``)."""
    return lambda z: lapse_layer(z, pad_pressure, pad_temperature, lapse, gravity)[2]


def temperature_offset(barometric_heights, gps_heights, pad_pressure_altitude: float,
                       gravity: float = US76_G0) -> float:
    """K: the day's temperature above the standard's (the same at every height) at which the altimeter's
    ``barometric_heights`` (m above the pad) read through the day (``geometric_heights``) best match ``gps_heights``
    (m above the pad, the same samples) in least squares. The heights change almost linearly with the offset: two
    trial days and a Newton step from the better one."""
    baro, gps = np.asarray(barometric_heights, float), np.asarray(gps_heights, float)
    pad_pressure = float(standard_pressure(pad_pressure_altitude))
    standard_pad = float(standard_temperature(pad_pressure_altitude))

    def misfit(offset: float) -> float:
        day = offset_day_density(pad_pressure, standard_pad + offset, gravity=gravity)
        heights = geometric_heights(baro, pad_pressure_altitude, day, gravity)
        return float(np.dot(heights - gps, heights)) / float(np.dot(heights, heights))

    offset, trial = 0.0, 10.0
    for _ in range(3):   # secant steps on the projected misfit (linear to 1e-3 over +-30 K)
        low, high = misfit(offset), misfit(offset + trial)
        offset -= low * trial / (high - low)
    return offset


WATER_TO_AIR = 0.621972
"""The molar mass of water over dry air's (-): 18.01528 / 28.9644 (US76's air)."""


def moist_air_density(pressure, temperature, mixing_ratio):
    """kg/m^3 of moist air at ``pressure`` (Pa), ``temperature`` (K) and water-vapour ``mixing_ratio`` (kg of
    water per kg of dry air; arrays or floats): p / (R_d T_v), the virtual temperature T_v = T (1 + r / eps) / (1 + r)
    with eps = WATER_TO_AIR (a sounding's humid layer is up to 2 % lighter than dry air at its temperature)."""
    ratio = np.asarray(mixing_ratio, float)
    virtual = np.asarray(temperature, float) * (1.0 + ratio / WATER_TO_AIR) / (1.0 + ratio)
    return np.asarray(pressure, float) / (US76_R * virtual)


def dewpoint_mixing_ratio(pressure, dewpoint):
    """kg of water vapour per kg of dry air at ``pressure`` (Pa) whose dew point is ``dewpoint`` (K; arrays or
    floats): r = eps e / (p - e), e the saturation vapour pressure over water at the dew point,
    611.2 Pa exp(17.67 t / (t + 243.5)) with t in deg C (Bolton 1980, 0.3 % from -35 to 35 C); eps = WATER_TO_AIR."""
    celsius = np.asarray(dewpoint, float) - 273.15
    vapour = 611.2 * np.exp(17.67 * celsius / (celsius + 243.5))
    return WATER_TO_AIR * vapour / (np.asarray(pressure, float) - vapour)


def geometric_altitude(geopotential_height):
    """m above sea level of a ``geopotential_height`` (m', a radiosonde's HGHT; array or float): h = r0 H / (r0 - H),
    r0 US76's 6 356 766 m (0.9 m apart at 2 km)."""
    height = np.asarray(geopotential_height, float)
    return US76_R0 * height / (US76_R0 - height)

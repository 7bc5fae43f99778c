"""Atmosphere models: density and the speed of sound as functions of geodetic altitude.

Each model's formulas are compiled kernels (``atmosphere_state`` for the per-stage aerodynamics, which takes the model
as ``kernel_parameters``); its Python methods (``density``, ``temperature``, ``speed_of_sound``) call the same
kernels, so there is one home per formula. A model with a validity range raises ``OutsideAtmosphereError``
outside it (the kernels report it as a status the caller turns into the error). This module reads no files and imports
nothing from the rest of the package: ``case.tables`` reads atmosphere tables, the engine turns the exception into
the user's message.

Speed of sound a = sqrt(gamma R T) of an ideal gas: US76 with its own R = R*/M0 and gamma = 1.4; the Mars model with
its R = 192.1 J/(kg K) and gamma = MARS_GAMMA; a table from its temperature column and the case's gamma and R, or a
constant the case gives; a model without any has none (a Mach-number table then is an error).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .compiled import bound, kernel
from .interpolation import bracket_packed
from .wind import TABLE_WIND, steady_wind


class OutsideAtmosphereError(ValueError):
    """An altitude outside the range an atmosphere model covers.

    Parameters
    ----------
    altitude : float
        The altitude asked for (m, geodetic/geometric).
    low, high : float
        The range the model covers (m, geodetic/geometric).
    model : str
        The model, as the message names it, e.g. ``"US76 atmosphere"`` or ``"atmosphere table atm.csv"``.
    hint : str, optional
        What to do about it, appended to the message after a semicolon.
    """

    def __init__(self, altitude: float, low: float, high: float, model: str, hint: str = ""):
        self.altitude = altitude
        self.low = low
        self.high = high
        self.model = model
        self.hint = hint
        message = f"altitude {altitude:.1f} m is outside the {model} ({low:g} to {high:g} m)"
        super().__init__(f"{message}; {hint}" if hint else message)

    def __reduce__(self):  # pickle (dask workers) with the constructor's arguments, not the message
        return type(self), (self.altitude, self.low, self.high, self.model, self.hint)


class AtmosphereTableError(ValueError):
    """Invalid atmosphere table values.

    Attributes
    ----------
    field : str
        ``"altitude"`` or ``"density"`` when one column is at fault, ``""`` for the table as a whole.
    value : list of float or None
        The offending column when ``field`` names one.
    """

    def __init__(self, field: str, message: str, value: list | None = None):
        self.field = field
        self.value = value
        super().__init__(message)


US76_KIND, MARS_KIND, TABLE_KIND = 0.0, 1.0, 2.0
"""``kernel_parameters()[KIND_AT]``: which model."""
NO_SOUND, SOUND_FROM_TEMPERATURE, SOUND_CONSTANT = 0.0, 1.0, 2.0
"""``kernel_parameters()[SOUND_KIND_AT]``: how the speed of sound is had (none, sqrt(gamma R T), a constant)."""
KIND_AT, SOUND_KIND_AT, GAMMA_AT, GAS_CONSTANT_AT, SOUND_AT, ROWS_AT, DENSITY_SCALE_AT = 0, 1, 2, 3, 4, 5, 6
"""Where each value of ``kernel_parameters()`` is: the model's kind, how the speed of sound is had, gamma (-), R
(J/(kg K)), a constant speed of sound (m/s), n (a table's rows), the factor (-) on the model's density
(``ScaledAtmosphere``; 1 by default)."""
PARAMETER_HEAD = 7
"""The values before a table's columns: a table then has n altitudes (m), n log-densities and n temperatures
(K)."""


class Atmosphere:
    """Base class: subclasses give their ``kernel_parameters`` and the range they cover; the methods evaluate the
    compiled kernels (kg/m^3, K, m/s at geodetic altitude in m)."""

    name = "atmosphere"

    def kernel_parameters(self) -> np.ndarray:  # pragma: no cover - interface
        raise NotImplementedError

    def outside(self, altitude: float) -> OutsideAtmosphereError:  # pragma: no cover - interface
        """The error for ``altitude`` (m) outside the model."""
        raise NotImplementedError

    @property
    def has_speed_of_sound(self) -> bool:
        """Whether the model gives the speed of sound (a Mach-number table needs it)."""
        return self.kernel_parameters()[SOUND_KIND_AT] != NO_SOUND

    def state(self, altitude: float) -> tuple:
        """(density kg/m^3, speed of sound m/s or NaN) at geodetic ``altitude`` (m), from one kernel call."""
        density, sound, status = _atmosphere_state(self.kernel_parameters(), float(altitude))
        if status != 0.0:
            raise self.outside(altitude)
        return density, sound

    def states(self, altitudes) -> tuple:
        """(densities kg/m^3, speeds of sound m/s or NaN) at geodetic ``altitudes`` (n,) (m), from one kernel call
        (``atmosphere_states``); each value as ``state`` gives it."""
        altitudes = np.ascontiguousarray(altitudes, float)
        out = np.empty((2, len(altitudes)))
        outside = atmosphere_states(self.kernel_parameters(), altitudes, out)
        if outside >= 0:
            raise self.outside(float(altitudes[outside]))
        return out[0], out[1]

    def density(self, altitude: float) -> float:
        """Density (kg/m^3) at geodetic ``altitude`` (m)."""
        return self.state(altitude)[0]

    def speed_of_sound(self, altitude: float) -> float:
        """Speed of sound (m/s) at geodetic ``altitude`` (m) (NaN for a model that has none)."""
        return self.state(altitude)[1]


MARS_GAMMA = 1.33
"""Ratio of specific heats of Mars's air for its speed of sound (-): CO2-rich gas at the 230-240 K of the NASA Glenn
model below 10 km (CO2 alone: 1.31 at 250 K, 1.35 at 200 K); assumed, the model gives none."""
MARS_R = 192.1
"""J/(kg K): the Glenn model's gas constant (its 0.1921 kJ/(kg K))."""


@kernel
def mars_grc_temperature(altitude):
    """The Glenn Mars model's temperature (deg C) at geodetic ``altitude`` (m)."""
    if altitude < 7000.0:
        return -31.0 - 0.000998 * altitude
    return -23.4 - 0.00222 * altitude


@kernel
def mars_grc_pressure(altitude):
    """The Glenn Mars model's pressure (kPa) at geodetic ``altitude`` (m)."""
    return 0.699 * math.exp(-0.00009 * altitude)


@dataclass(frozen=True)
class MarsGRC(Atmosphere):
    """NASA Glenn Research Center's Mars atmosphere (``docs/models/mer.md``, "Atmosphere").

    T [deg C] = -31 - 0.000998 h below 7000 m, -23.4 - 0.00222 h above; p [kPa] = 0.699 exp(-0.00009 h);
    rho [kg/m^3] = p / (0.1921 (T + 273.1)), with h the geodetic altitude in m; speed of sound
    sqrt(MARS_GAMMA MARS_R (T + 273.1)). No range: it covers every altitude.
    """

    name = "mars_grc"

    def kernel_parameters(self) -> np.ndarray:
        return _MARS_PARAMETERS

    def temperature(self, altitude: float) -> float:
        """Temperature (deg C) at ``altitude`` (m)."""
        return mars_grc_temperature(float(altitude))

    def pressure(self, altitude: float) -> float:
        """Pressure (kPa) at ``altitude`` (m)."""
        return mars_grc_pressure(float(altitude))


@dataclass(frozen=True)
class TabulatedAtmosphere(Atmosphere):
    """Density tabulated against altitude, interpolated linearly in log(density).

    Log-linear interpolation is exact for an exponential atmosphere between the points, which linear interpolation
    is not. Outside the table the model refuses to extrapolate: ``density`` raises ``OutsideAtmosphereError``.
    ``case.tables.read_atmosphere_table`` builds one from a CSV file.

    Parameters
    ----------
    altitude : sequence of float
        Strictly increasing geodetic altitudes (m), at least 2; stored as a tuple of floats.
    density_values : sequence of float
        Densities (kg/m^3) at those altitudes, all > 0; stored as a tuple of floats.
    source : str
        Where the table came from (file path), for messages.
    temperature : sequence of float
        Temperatures (K, > 0) at those altitudes, linear between them, for the speed of sound sqrt(gamma R T);
        empty: none.
    gamma : float
        Ratio of specific heats (-) of the table's gas (default: Earth's air, 1.4).
    gas_constant : float
        Specific gas constant R (J/(kg K)) of the table's gas (default: Earth's air, 287.05287).
    speed_of_sound_constant : float or None
        Without temperatures, a constant speed of sound (m/s); None: the table has none.

    Raises
    ------
    AtmosphereTableError
        (a ValueError) if the columns differ in length, have fewer than 2 rows, the altitudes do not increase
        strictly or a density is not > 0.
    """

    altitude: tuple
    density_values: tuple
    source: str = "table"
    temperature: tuple = ()
    gamma: float = 1.4
    gas_constant: float = 287.05287
    speed_of_sound_constant: float | None = None
    name = "table"

    def __post_init__(self):
        altitude = tuple(float(a) for a in self.altitude)
        density = tuple(float(r) for r in self.density_values)
        if len(altitude) != len(density):
            raise AtmosphereTableError("", f"atmosphere table has {len(altitude)} altitudes but "
                                           f"{len(density)} densities")
        if len(altitude) < 2:
            raise AtmosphereTableError("", f"atmosphere table needs at least 2 rows, got {len(altitude)}")
        if any(not (b > a) for a, b in zip(altitude, altitude[1:])):
            raise AtmosphereTableError("altitude", "altitudes must be strictly increasing", list(altitude))
        if any(not (r > 0.0) for r in density):
            raise AtmosphereTableError("density", "densities must all be > 0 (kg/m^3)", list(density))
        temperature = tuple(float(t) for t in self.temperature)
        if temperature and len(temperature) != len(altitude):
            raise AtmosphereTableError("temperature", f"atmosphere table has {len(altitude)} altitudes but "
                                                      f"{len(temperature)} temperatures", list(temperature))
        if any(not (t > 0.0) for t in temperature):
            raise AtmosphereTableError("temperature", "temperatures must all be > 0 (K)", list(temperature))
        object.__setattr__(self, "altitude", altitude)
        object.__setattr__(self, "density_values", density)
        object.__setattr__(self, "temperature", temperature)
        object.__setattr__(self, "_log_density", tuple(math.log(r) for r in density))
        sound = (SOUND_FROM_TEMPERATURE if temperature else
                 SOUND_CONSTANT if self.speed_of_sound_constant is not None else NO_SOUND)
        head = [TABLE_KIND, sound, self.gamma, self.gas_constant, self.speed_of_sound_constant or 0.0,
                len(altitude), 1.0]
        object.__setattr__(self, "_parameters", np.array(head + list(altitude) + list(self._log_density)
                                                         + list(temperature or (0.0,) * len(altitude))))

    def kernel_parameters(self) -> np.ndarray:
        return self._parameters

    def outside(self, altitude: float) -> OutsideAtmosphereError:
        return OutsideAtmosphereError(altitude, self.altitude[0], self.altitude[-1],
                                      f"atmosphere table {self.source}", "extend the table")


# U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562), part 1, constants in SI units.
US76_R0 = 6356766.0               # m, effective Earth radius of the geopotential conversion H = R0 h / (R0 + h)
US76_G0 = 9.80665                 # m/s^2, standard gravity (with the geopotential metre: m'^2/s^2 per m')
US76_R_STAR = 8314.32             # J/(kmol K), gas constant as the standard defines it
US76_M0 = 28.9644                 # kg/kmol, sea-level mean molecular weight of air
US76_R = US76_R_STAR / US76_M0    # J/(kg K), specific gas constant of air: 287.0531
US76_T0 = 288.15                  # K, sea-level temperature
US76_P0 = 101325.0                # Pa, sea-level pressure
# (base geopotential altitude m', lapse rate K/m') of the standard's seven layers, up to 84 852 m'
US76_LAYERS = ((0.0, -0.0065), (11000.0, 0.0), (20000.0, 0.001), (32000.0, 0.0028),
               (47000.0, 0.0), (51000.0, -0.0028), (71000.0, -0.002))


def _us76_layer_table():
    """Per layer, in plain floats: (H_b m', T_b K, L K/m', p_b Pa, rho_b kg/m^3, k) with k = -(1 + g0 M0 / (R* L))
    for L != 0 (rho = rho_b (T / T_b)^k) and k = -g0 M0 / (R* T_b) for L = 0 (rho = rho_b exp(k (H - H_b)));
    the base values follow from T0 and p0 by the standard's temperature and pressure equations, layer by layer."""
    gmr = US76_G0 * US76_M0 / US76_R_STAR     # K/m', 0.034163195
    rows = []
    temperature, pressure = US76_T0, US76_P0
    for i, (base, lapse) in enumerate(US76_LAYERS):
        if i:
            previous, previous_lapse = US76_LAYERS[i - 1]
            top_temperature = temperature + previous_lapse * (base - previous)
            if previous_lapse == 0.0:
                pressure *= math.exp(-gmr * (base - previous) / temperature)
            else:
                pressure *= (temperature / top_temperature) ** (gmr / previous_lapse)
            temperature = top_temperature
        k = -(1.0 + gmr / lapse) if lapse != 0.0 else -gmr / temperature
        rows.append((base, temperature, lapse, pressure, pressure / (US76_R * temperature), k))
    return tuple(rows)


_US76 = _us76_layer_table()


@dataclass(frozen=True)
class US76(Atmosphere):
    """U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562, NOAA/NASA/USAF, 1976), part 1 (the seven layers of the
    lower atmosphere, to 86 km geometric), ``docs/models/cev_pa1.md``; the first layer extended down to -5 km.

    The layers are defined on geopotential altitude H = r0 h / (r0 + h) (m'), r0 = 6 356 766 m, from the geometric
    (geodetic) altitude h (m). In layer b with base H_b, base temperature T_b and lapse rate L_b (K/m': -6.5, 0, +1,
    +2.8, 0, -2.8, -2.0 K/km from H_b = 0, 11, 20, 32, 47, 51, 71 km'; top 84.852 km'):
    T = T_b + L_b (H - H_b) (K); p = p_b (T_b / T)^(g0 M0 / (R* L_b)) for L_b != 0,
    p = p_b exp(-g0 M0 (H - H_b) / (R* T_b)) for L_b = 0 (Pa); rho = p M0 / (R* T) (kg/m^3). Constants: T0 = 288.15 K,
    p0 = 101 325 Pa, g0 = 9.80665 m/s^2, R* = 8 314.32 J/(kmol K), M0 = 28.9644 kg/kmol (R*/M0 = 287.0531 J/(kg K)).
    The layer base values are computed once, at import; ``density`` uses plain floats.

    Outside -5 000 to 86 000 m geometric altitude the methods raise ``OutsideAtmosphereError``.
    """

    name = "us76"
    floor = -5000.0       # m, geometric
    ceiling = 86000.0     # m, geometric

    def kernel_parameters(self) -> np.ndarray:
        return _US76_PARAMETERS

    def outside(self, altitude: float) -> OutsideAtmosphereError:
        return OutsideAtmosphereError(altitude, self.floor, self.ceiling, "US76 atmosphere")

    def geopotential_altitude(self, altitude: float) -> float:
        """Geopotential altitude H (m') of geometric ``altitude`` h (m): H = r0 h / (r0 + h)."""
        return US76_R0 * altitude / (US76_R0 + altitude)

    def temperature(self, altitude: float) -> float:
        """Temperature (K) at geometric ``altitude`` (m)."""
        if not (self.floor <= altitude <= self.ceiling):
            raise self.outside(altitude)
        return us76_temperature(_US76_LAYERS, float(altitude))

    def pressure(self, altitude: float) -> float:
        """Pressure (Pa) at geometric ``altitude`` (m)."""
        return self.density(altitude) * US76_R * self.temperature(altitude)


@kernel
def _us76_layer(layers, altitude):
    """(geopotential altitude H in m', the row of its layer in ``layers``) for geometric ``altitude`` (m)."""
    geopotential = 6356766.0 * altitude / (6356766.0 + altitude)
    i = 0
    while i + 1 < layers.shape[0] and layers[i + 1, 0] <= geopotential:   # bisect_right over the layer bases
        i += 1
    return geopotential, i


@kernel
def us76_temperature(layers, altitude):
    """US76 temperature (K) at geometric ``altitude`` (m) (no range check), from the layer table ``layers``."""
    geopotential, i = _us76_layer(layers, altitude)
    return layers[i, 1] + layers[i, 2] * (geopotential - layers[i, 0])


@kernel
def us76_density(layers, altitude):
    """US76 density (kg/m^3) at geometric ``altitude`` (m) (no range check), from the layer table ``layers``."""
    geopotential, i = _us76_layer(layers, altitude)
    base, base_temperature, lapse, base_density, k = (layers[i, 0], layers[i, 1], layers[i, 2], layers[i, 4],
                                                      layers[i, 5])
    if lapse == 0.0:
        return base_density * math.exp(k * (geopotential - base))
    return base_density * (1.0 + lapse * (geopotential - base) / base_temperature) ** k


@kernel
def _table_interpolate(parameters, column, i, w):
    """Linear between rows i - 1 and i of a table atmosphere's ``column`` (1: log-density, 2: temperature)."""
    n = int(parameters[ROWS_AT])
    start = PARAMETER_HEAD + column * n
    return parameters[start + i - 1] + w * (parameters[start + i] - parameters[start + i - 1])


@kernel
def atmosphere_state(parameters, altitude):
    """(density in kg/m^3, speed of sound in m/s or NaN, status) at geodetic ``altitude`` (m) of the atmosphere
    ``parameters`` (``Atmosphere.kernel_parameters``); status 1 when the altitude is outside the model."""
    kind, sound = parameters[KIND_AT], parameters[SOUND_KIND_AT]
    if kind == US76_KIND:
        if not (-5000.0 <= altitude <= 86000.0):
            return math.nan, math.nan, 1.0
        density = us76_density(_US76_LAYERS, altitude)
        temperature = us76_temperature(_US76_LAYERS, altitude) if sound == SOUND_FROM_TEMPERATURE else 0.0
    elif kind == MARS_KIND:
        celsius = mars_grc_temperature(altitude)
        density = mars_grc_pressure(altitude) / (0.1921 * (celsius + 273.1))
        temperature = celsius + 273.1
    else:
        n = int(parameters[ROWS_AT])
        if not (parameters[PARAMETER_HEAD] <= altitude <= parameters[PARAMETER_HEAD + n - 1]):
            return math.nan, math.nan, 1.0
        i, w = bracket_packed(parameters, PARAMETER_HEAD, n, altitude)
        density = math.exp(_table_interpolate(parameters, 1, i, w))
        temperature = _table_interpolate(parameters, 2, i, w) if sound == SOUND_FROM_TEMPERATURE else 0.0
    density *= parameters[DENSITY_SCALE_AT]   # 1 unless dispersed (exact: x 1.0 changes no bit)
    if sound == SOUND_FROM_TEMPERATURE:
        return density, math.sqrt(parameters[GAMMA_AT] * parameters[GAS_CONSTANT_AT] * temperature), 0.0
    if sound == SOUND_CONSTANT:
        return density, parameters[SOUND_AT], 0.0
    return density, math.nan, 0.0


_US76_LAYERS = np.array(_US76)
"""The layer table as an array for the kernels: (H_b, T_b, L, p_b, rho_b, k) per layer."""
_US76_PARAMETERS = np.array([US76_KIND, SOUND_FROM_TEMPERATURE, 1.4, US76_R, 0.0, 0.0, 1.0])
_MARS_PARAMETERS = np.array([MARS_KIND, SOUND_FROM_TEMPERATURE, MARS_GAMMA, MARS_R, 0.0, 0.0, 1.0])


def pressure_of(density: float, sound: float, gamma: float) -> float:
    """p = rho a^2 / gamma (Pa) of an ideal gas from its density (kg/m^3), speed of sound (m/s) and gamma (-):
    rho R T, what a barometric sensor reads (``triggers.sensors``)."""
    return density * sound * sound / gamma


@dataclass(frozen=True)
class ScaledAtmosphere(Atmosphere):
    """Another model's atmosphere with its density multiplied by ``density_scale`` (-, > 0) at every altitude, its
    temperature and speed of sound unchanged: a Monte Carlo's density dispersion (``[atmosphere] density_scale``)."""

    base: Atmosphere
    density_scale: float

    @property
    def name(self) -> str:
        return self.base.name

    def kernel_parameters(self) -> np.ndarray:
        parameters = self.base.kernel_parameters().copy()
        parameters[DENSITY_SCALE_AT] = self.density_scale
        return parameters

    def outside(self, altitude: float) -> OutsideAtmosphereError:
        return self.base.outside(altitude)


@dataclass(frozen=True)
class Wind:
    """Horizontal wind: the air's velocity relative to the ground in the start point's east and north axes (m/s),
    constant or tabulated against geodetic altitude (m), linear between the points and constant beyond the ends.

    ``east`` > 0 is air moving east (a west wind). ``altitude`` is empty for a constant wind.
    """

    altitude: tuple
    east: tuple
    north: tuple

    @classmethod
    def constant(cls, east: float, north: float) -> Wind:
        return cls((), (float(east),), (float(north),))

    def kernel_parameters(self) -> np.ndarray:
        """The wind for ``physics.wind.steady_wind``: 1 (a table), n rows (0 for a constant), then the altitudes,
        east and north components (a constant: east, north)."""
        return np.array([TABLE_WIND, len(self.altitude), *self.altitude, *self.east, *self.north])

    def at(self, altitude: float):
        """(east, north) wind (m/s) at ``altitude`` (m)."""
        return steady_wind(self.kernel_parameters(), float(altitude))

    def largest_speed(self, top: float) -> float:
        """The wind's largest speed (m/s) at any altitude (``top``, m, unused: a table holds its ends beyond them,
        and its speed is largest at one of its points)."""
        return max(math.hypot(e, n) for e, n in zip(self.east, self.north))


@kernel
def atmosphere_states(parameters, altitudes, out):
    """``atmosphere_state`` at each of ``altitudes`` (m): densities (kg/m^3) into ``out[0]``, speeds of sound (m/s)
    into ``out[1]``; -1, or the index of the first altitude outside the model."""
    for i in range(altitudes.shape[0]):
        density, sound, status = atmosphere_state(parameters, altitudes[i])
        if status != 0.0:
            return i
        out[0, i], out[1, i] = density, sound
    return -1


_atmosphere_state = bound(atmosphere_state)   # ``Atmosphere.state``: per stage where a canopy's apparent mass needs it

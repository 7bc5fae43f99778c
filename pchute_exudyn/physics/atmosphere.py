"""Atmosphere models: density as a function of geodetic altitude.

Each model has ``density(altitude)`` for one altitude, in plain floats (it runs in per-stage user functions). A model
with a validity range raises :class:`OutsideAtmosphereError` outside it. This module reads no files and imports
nothing from the rest of the package: ``case.tables`` reads atmosphere tables, the engine turns the exception into
the user's message.
"""

from __future__ import annotations

import math
from bisect import bisect_right
from dataclasses import dataclass

from .interpolation import bracket


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


class Atmosphere:
    """Base class: subclasses implement ``density(altitude)`` (kg/m^3 at geodetic altitude in m)."""

    name = "atmosphere"

    def density(self, altitude: float) -> float:  # pragma: no cover - interface
        raise NotImplementedError


@dataclass(frozen=True)
class MarsGRC(Atmosphere):
    """NASA Glenn Research Center's Mars atmosphere (``docs/models/mer.md``, "Atmosphere").

    T [deg C] = -31 - 0.000998 h below 7000 m, -23.4 - 0.00222 h above; p [kPa] = 0.699 exp(-0.00009 h);
    rho [kg/m^3] = p / (0.1921 (T + 273.1)), with h the geodetic altitude in m.
    """

    name = "mars_grc"

    def temperature(self, altitude: float) -> float:
        """Temperature (deg C) at ``altitude`` (m)."""
        if altitude < 7000.0:
            return -31.0 - 0.000998 * altitude
        return -23.4 - 0.00222 * altitude

    def pressure(self, altitude: float) -> float:
        """Pressure (kPa) at ``altitude`` (m)."""
        return 0.699 * math.exp(-0.00009 * altitude)

    def density(self, altitude: float) -> float:
        """Density (kg/m^3) at geodetic ``altitude`` (m)."""
        return self.pressure(altitude) / (0.1921 * (self.temperature(altitude) + 273.1))


@dataclass(frozen=True)
class TabulatedAtmosphere(Atmosphere):
    """Density tabulated against altitude, interpolated linearly in log(density).

    Log-linear interpolation is exact for an exponential atmosphere between the points, which linear interpolation
    is not. Outside the table the model refuses to extrapolate: ``density`` raises :class:`OutsideAtmosphereError`.
    ``case.tables.read_atmosphere_table`` builds one from a CSV file.

    Parameters
    ----------
    altitude : sequence of float
        Strictly increasing geodetic altitudes (m), at least 2; stored as a tuple of floats.
    density_values : sequence of float
        Densities (kg/m^3) at those altitudes, all > 0; stored as a tuple of floats.
    source : str
        Where the table came from (file path), for messages.

    Raises
    ------
    AtmosphereTableError
        (a ValueError) if the columns differ in length, have fewer than 2 rows, the altitudes do not increase
        strictly or a density is not > 0.
    """

    altitude: tuple
    density_values: tuple
    source: str = "table"
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
        object.__setattr__(self, "altitude", altitude)
        object.__setattr__(self, "density_values", density)
        object.__setattr__(self, "_log_density", tuple(math.log(r) for r in density))

    def density(self, altitude: float) -> float:
        """Density (kg/m^3) at geodetic ``altitude`` (m); raises OutsideAtmosphereError outside the table."""
        alt = self.altitude
        if not (alt[0] <= altitude <= alt[-1]):
            raise OutsideAtmosphereError(altitude, alt[0], alt[-1], f"atmosphere table {self.source}",
                                         "extend the table")
        i, w = bracket(alt, altitude)
        return math.exp(self._log_density[i - 1] + w * (self._log_density[i] - self._log_density[i - 1]))


# U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562), part 1, constants in SI units.
US76_R0 = 6356766.0               # m, effective Earth radius of the geopotential conversion H = R0 h / (R0 + h)
US76_G0 = 9.80665                 # m/s^2, standard gravity (with the geopotential metre: m'^2/s^2 per m')
US76_R_STAR = 8314.32             # J/(kmol K), gas constant as the standard defines it
US76_M0 = 28.9644                 # kg/kmol, sea-level mean molecular weight of air
US76_R = US76_R_STAR / US76_M0    # J/(kg K), specific gas constant of air: 287.05287
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
_US76_BASES = tuple(row[0] for row in _US76)


@dataclass(frozen=True)
class US76(Atmosphere):
    """U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562, NOAA/NASA/USAF, 1976), part 1 (the seven layers of the
    lower atmosphere, to 86 km geometric), ``docs/models/cev_pa1.md``; the first layer extended down to -5 km.

    The layers are defined on geopotential altitude H = r0 h / (r0 + h) (m'), r0 = 6 356 766 m, from the geometric
    (geodetic) altitude h (m). In layer b with base H_b, base temperature T_b and lapse rate L_b (K/m': -6.5, 0, +1,
    +2.8, 0, -2.8, -2.0 K/km from H_b = 0, 11, 20, 32, 47, 51, 71 km'; top 84.852 km'):
    T = T_b + L_b (H - H_b) (K); p = p_b (T_b / T)^(g0 M0 / (R* L_b)) for L_b != 0,
    p = p_b exp(-g0 M0 (H - H_b) / (R* T_b)) for L_b = 0 (Pa); rho = p M0 / (R* T) (kg/m^3). Constants: T0 = 288.15 K,
    p0 = 101 325 Pa, g0 = 9.80665 m/s^2, R* = 8 314.32 J/(kmol K), M0 = 28.9644 kg/kmol (R*/M0 = 287.05287 J/(kg K)).
    The layer base values are computed once, at import; ``density`` uses plain floats.

    Outside -5 000 to 86 000 m geometric altitude the methods raise :class:`OutsideAtmosphereError`.
    """

    name = "us76"
    floor = -5000.0       # m, geometric
    ceiling = 86000.0     # m, geometric

    def _layer(self, altitude: float):
        """(geopotential altitude m', layer row) for geometric ``altitude`` (m), after the range check."""
        if not (self.floor <= altitude <= self.ceiling):
            raise OutsideAtmosphereError(altitude, self.floor, self.ceiling, "US76 atmosphere")
        geopotential = self.geopotential_altitude(altitude)
        i = bisect_right(_US76_BASES, geopotential) - 1
        return geopotential, _US76[i if i > 0 else 0]

    def geopotential_altitude(self, altitude: float) -> float:
        """Geopotential altitude H (m') of geometric ``altitude`` h (m): H = r0 h / (r0 + h)."""
        return US76_R0 * altitude / (US76_R0 + altitude)

    def temperature(self, altitude: float) -> float:
        """Temperature (K) at geometric ``altitude`` (m)."""
        geopotential, (base, base_temperature, lapse, _, _, _) = self._layer(altitude)
        return base_temperature + lapse * (geopotential - base)

    def pressure(self, altitude: float) -> float:
        """Pressure (Pa) at geometric ``altitude`` (m)."""
        return self.density(altitude) * US76_R * self.temperature(altitude)

    def density(self, altitude: float) -> float:
        """Density (kg/m^3) at geometric (geodetic) ``altitude`` (m)."""
        # the range check and geopotential_altitude inlined: this runs at every solver stage (about 0.18 us a call)
        if not (-5000.0 <= altitude <= 86000.0):
            raise OutsideAtmosphereError(altitude, self.floor, self.ceiling, "US76 atmosphere")
        geopotential = 6356766.0 * altitude / (6356766.0 + altitude)
        i = bisect_right(_US76_BASES, geopotential) - 1
        base, base_temperature, lapse, _, base_density, k = _US76[i if i > 0 else 0]
        if lapse == 0.0:
            return base_density * math.exp(k * (geopotential - base))
        return base_density * (1.0 + lapse * (geopotential - base) / base_temperature) ** k


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

    def at(self, altitude: float):
        """(east, north) wind (m/s) at ``altitude`` (m)."""
        if not self.altitude:
            return self.east[0], self.north[0]
        i, w = bracket(self.altitude, altitude)
        return (self.east[i - 1] + w * (self.east[i] - self.east[i - 1]),
                self.north[i - 1] + w * (self.north[i] - self.north[i - 1]))

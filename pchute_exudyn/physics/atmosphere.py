"""Atmosphere models: density as a function of geodetic altitude.

Each model has ``density(altitude)`` for one altitude (plain floats: it runs in per-stage user functions) and
``density_profile(altitudes)`` for arrays.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import CaseError, SimulationError
from .interpolation import bracket


class Atmosphere:
    """Base class: subclasses implement ``density(altitude)`` (kg/m^3 at geodetic altitude in m)."""

    name = "atmosphere"

    def density(self, altitude: float) -> float:  # pragma: no cover - interface
        raise NotImplementedError

    def density_profile(self, altitudes) -> np.ndarray:
        """Density (kg/m^3) at each of ``altitudes`` (m)."""
        return np.array([self.density(float(h)) for h in np.ravel(altitudes)]).reshape(np.shape(altitudes))


@dataclass(frozen=True)
class MarsGRC(Atmosphere):
    """NASA Glenn Research Center's Mars atmosphere (``shared/models/mer.md``, "Atmosphere").

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
    is not. Outside the table the model refuses to extrapolate: a run that leaves the table stops with an error.

    Parameters
    ----------
    altitude : tuple of float
        Strictly increasing altitudes (m).
    density_values : tuple of float
        Densities (kg/m^3), all > 0.
    source : str
        Where the table came from (file path), for messages.
    """

    altitude: tuple
    density_values: tuple
    source: str = "table"
    name = "table"

    def __post_init__(self):
        object.__setattr__(self, "_log_density", tuple(math.log(r) for r in self.density_values))

    @classmethod
    def from_csv(cls, path) -> "TabulatedAtmosphere":
        """Read a CSV file with a header row holding columns ``altitude`` (m) and ``density`` (kg/m^3)."""
        path = Path(path)
        if not path.is_file():
            raise CaseError(str(path), "", "atmosphere table file not found")
        with path.open(newline="") as handle:
            rows = list(csv.reader(row for row in handle if row.strip() and not row.lstrip().startswith("#")))
        if not rows:
            raise CaseError(str(path), "", "atmosphere table is empty")
        header = [h.strip().lower() for h in rows[0]]
        if "altitude" not in header or "density" not in header:
            raise CaseError(str(path), "", f"header {rows[0]} must name the columns 'altitude' (m) and 'density' (kg/m^3)")
        ia, idens = header.index("altitude"), header.index("density")
        altitude, density = [], []
        for number, row in enumerate(rows[1:], start=2):
            try:
                altitude.append(float(row[ia]))
                density.append(float(row[idens]))
            except (ValueError, IndexError):
                raise CaseError(str(path), f"row {number}", "altitude and density must be numbers", value=row) from None
        return cls.checked(altitude, density, str(path))

    @classmethod
    def checked(cls, altitude, density, source: str) -> "TabulatedAtmosphere":
        """Build a table after checking it: >= 2 rows, altitudes strictly increasing, densities > 0."""
        if len(altitude) < 2:
            raise CaseError(source, "", f"atmosphere table needs at least 2 rows, got {len(altitude)}")
        if any(b <= a for a, b in zip(altitude, altitude[1:])):
            raise CaseError(source, "altitude", "altitudes must be strictly increasing", value=list(altitude))
        if any(not (r > 0.0) for r in density):
            raise CaseError(source, "density", "densities must all be > 0 (kg/m^3)", value=list(density))
        return cls(tuple(float(a) for a in altitude), tuple(float(r) for r in density), source)

    def density(self, altitude: float) -> float:
        """Density (kg/m^3) at ``altitude`` (m); raises SimulationError outside the table."""
        alt = self.altitude
        if not (alt[0] <= altitude <= alt[-1]):
            raise SimulationError(
                f"altitude {altitude:.1f} m is outside the atmosphere table {self.source} "
                f"({alt[0]:g} to {alt[-1]:g} m); extend the table")
        i, w = bracket(alt, altitude)
        return math.exp(self._log_density[i - 1] + w * (self._log_density[i] - self._log_density[i - 1]))


@dataclass(frozen=True)
class US76Lower(Atmosphere):
    """U.S. Standard Atmosphere 1976 below 11 km (``shared/models/cev_pa1.md``), geometric altitude h used directly:

    T = 288.15 - 0.0065 h K, p = 101 325 (T / 288.15)^5.25588 Pa, rho = p / (287.053 T).
    A run that leaves -500 to 11 000 m stops with an error (the next layer is not modelled).
    """

    name = "us76"
    floor = -500.0
    ceiling = 11000.0

    def temperature(self, altitude: float) -> float:
        """Temperature (K) at ``altitude`` (m)."""
        return 288.15 - 0.0065 * altitude

    def pressure(self, altitude: float) -> float:
        """Pressure (Pa) at ``altitude`` (m)."""
        return 101325.0 * (self.temperature(altitude) / 288.15) ** 5.25588

    def density(self, altitude: float) -> float:
        """Density (kg/m^3) at geodetic ``altitude`` (m)."""
        if not (self.floor <= altitude <= self.ceiling):
            raise SimulationError(f"altitude {altitude:.1f} m is outside the US76 lower atmosphere "
                                  f"({self.floor:g} to {self.ceiling:g} m)")
        return self.pressure(altitude) / (287.053 * self.temperature(altitude))


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
    def constant(cls, east: float, north: float) -> "Wind":
        return cls((), (float(east),), (float(north),))

    def at(self, altitude: float):
        """(east, north) wind (m/s) at ``altitude`` (m)."""
        if not self.altitude:
            return self.east[0], self.north[0]
        i, w = bracket(self.altitude, altitude)
        return (self.east[i - 1] + w * (self.east[i] - self.east[i - 1]),
                self.north[i - 1] + w * (self.north[i] - self.north[i - 1]))

"""Tables that a case file names by path, read into physics objects; every problem becomes a CaseError naming the file.

The physics package reads no files: this module does it for it.
"""

from __future__ import annotations

import csv
from pathlib import Path

from ..errors import CaseError
from ..physics.atmosphere import AtmosphereTableError, TabulatedAtmosphere

AIR_GAMMA = TabulatedAtmosphere.__dataclass_fields__["gamma"].default
"""A table's ratio of specific heats (-) when the case gives none: Earth's air, as the atmosphere's own default."""
AIR_GAS_CONSTANT = TabulatedAtmosphere.__dataclass_fields__["gas_constant"].default
"""A table's specific gas constant (J/(kg K)) when the case gives none: Earth's air."""


def read_atmosphere_table(path, gamma: float = AIR_GAMMA, gas_constant: float = AIR_GAS_CONSTANT,
                          speed_of_sound: float | None = None) -> TabulatedAtmosphere:
    """Read a CSV atmosphere table: a header row naming the columns ``altitude`` (m, geodetic) and ``density``
    (kg/m^3), and optionally ``temperature`` (K, for the speed of sound sqrt(``gamma`` ``gas_constant`` T) with
    gamma in - and R in J/(kg K)), in any order and case, then one row per altitude; blank lines and lines starting
    with ``#`` are skipped. Without temperatures, ``speed_of_sound`` (m/s) is the constant speed of sound, if given.

    Raises
    ------
    CaseError
        Naming ``path``: the file is missing, empty, lacks a column, holds a non-number, or the table is invalid
        (fewer than 2 rows, altitudes not strictly increasing, a density not > 0).
    """
    path = Path(path)
    source = str(path)
    if not path.is_file():
        raise CaseError(source, "", "atmosphere table file not found")
    with path.open(newline="") as handle:
        rows = list(csv.reader(row for row in handle if row.strip() and not row.lstrip().startswith("#")))
    if not rows:
        raise CaseError(source, "", "atmosphere table is empty")
    header = [h.strip().lower() for h in rows[0]]
    if "altitude" not in header or "density" not in header:
        raise CaseError(source, "", f"header {rows[0]} must name the columns 'altitude' (m) and 'density' (kg/m^3)")
    ia, idens = header.index("altitude"), header.index("density")
    itemp = header.index("temperature") if "temperature" in header else None
    altitude, density, temperature = [], [], []
    for number, row in enumerate(rows[1:], start=2):
        try:
            altitude.append(float(row[ia]))
            density.append(float(row[idens]))
            if itemp is not None:
                temperature.append(float(row[itemp]))
        except (ValueError, IndexError):
            columns = "altitude, density and temperature" if itemp is not None else "altitude and density"
            raise CaseError(source, f"row {number}", f"{columns} must be numbers", value=row) from None
    try:
        return TabulatedAtmosphere(altitude, density, source, tuple(temperature), gamma, gas_constant,
                                   speed_of_sound if not temperature else None)
    except AtmosphereTableError as exc:
        if exc.field:
            raise CaseError(source, exc.field, str(exc), value=exc.value) from None
        raise CaseError(source, "", str(exc)) from None

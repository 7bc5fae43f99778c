"""``[systems.<name>.inflation.supersonic]``: the supersonic opening of a disk-gap-band (``physics.supersonic_opening``,
docs/models/supersonic_opening.md)."""

from __future__ import annotations

from ..physics.supersonic_opening import MachTable, OpeningError, SupersonicOpening
from .fields import Table


def read_supersonic(t: Table) -> SupersonicOpening:
    """The opening-load factor against Mach number and the forebody's wake, the fill constant against Mach number and
    the breathing, as the table gives them."""
    keys = {key: t.number(key, unit, default) for key, unit, default in
            (("load_factor", "", None), ("reference_mach", "", 1.8), ("mach_slope", "", 0.0),
             ("wake_coefficient", "", 0.0), ("forebody_diameter", "m", 0.0), ("breathing_strouhal", "", 0.2))}
    if keys["load_factor"] is None:
        raise t.error("load_factor", "required (-): the opening-load factor C_k at reference_mach, >= 1")
    mach_range = t.vector("mach_range", "", length=2, default=(1.0, 2.5))
    tables = {key: _mach_table(t, key) for key in ("fill_constant", "breathing_amplitude")}
    t.finish()
    try:
        return SupersonicOpening(mach_range=tuple(mach_range), **keys, **tables)
    except OpeningError as exc:
        raise t.error(exc.field, str(exc), exc.value) from None


def _mach_table(t: Table, key: str) -> MachTable | None:
    """``key = { mach = [...], value = [...] }`` (None when absent): strictly increasing Mach numbers, two or more."""
    table = t.table(key, None)
    if table is None:
        return None
    mach = table.sequence("mach", "", min_length=2)
    value = table.vector("value", "", length=len(mach))
    table.finish()
    if any(b <= a for a, b in zip(mach, mach[1:])) or mach[0] < 0.0:
        raise table.error("mach", "must be Mach numbers >= 0, increasing strictly", list(mach))
    return MachTable(tuple(mach), tuple(value))

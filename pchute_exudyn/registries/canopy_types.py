"""The canopy types ``pchute new`` writes, one record each (``CanopyType``): the drag coefficient with its source and
range, and how a released vehicle's canopy of that type opens (``physics.inflation``). A new type is one record here
(its sources in docs/models/sources.md, its opening in docs/tutorial.md's table)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class CanopyType:
    """A canopy type ``pchute new`` writes (docs/tutorial.md; docs/models/sources.md gives the sources).

    Attributes
    ----------
    name : str
        Its ``--canopy-type`` value.
    drag_coefficient : float
        C_D0 on S0 (-), subsonic: the middle of the published range.
    drag_source : str
        Where that range comes from (the written case's comment names it).
    drag_range : str
        The published range.
    fill_constant, opening_exponent, overinflation : float
        How a released vehicle's canopy opens (``physics.inflation``): the fill time n D0 / V (n, -), the drag area
        growing as (t / t_fill)^exponent (-) and overshooting to C_x times the full drag area (-).
    opening_source : str
        Where those come from, or what is assumed.
    """

    name: str
    drag_coefficient: float
    drag_source: str
    drag_range: str
    fill_constant: float
    opening_exponent: float
    overinflation: float
    opening_source: str


CANOPY_TYPE_LIST = (
    CanopyType("disk_gap_band", 0.55, "Maydew, AGARD-AG-319", "0.53-0.58", 8.0, 2.0, 1.0,
               "assumed: no handbook value found (the solid flat canopy's n and exponent)"),
    CanopyType("ringsail", 0.80, "Knacke, Table 5-2", "0.75-0.85", 7.0, 2.0, 1.10,
               "n, C_x: Knacke; exponent assumed (solid cloth's, as the PA1 mains)"),
    CanopyType("ribbon", 0.50, "Knacke, Table 5-2", "where flat ribbon (0.45-0.50) meets conical ribbon (0.50-0.55)",
               14.0, 1.0, 1.05, "Knacke: n, linear growth of a slotted canopy, C_x"),
    CanopyType("flat_circular", 0.77, "Knacke, Table 5-1", "0.75-0.80 (solid textile)", 8.0, 2.0, 1.7,
               "Knacke: n, quadratic growth of solid cloth, C_x"),
    CanopyType("cross", 0.72, "Knacke, Table 5-1", "0.60-0.85", 11.7, 2.0, 1.15,
               "Knacke: n, C_x (1.1-1.2); exponent assumed (solid cloth's)"),
)
"""The canopy types, one record each. C_D0 sources: Knacke's type tables (NWC TP 6575, March 1991: 5-1 solid
textile, 5-2 slotted canopies); for the disk-gap-band, whose row there we have not seen, Maydew and Peterson,
AGARD-AG-319. Openings: n from Knacke's Table 5-6 unreefed column (p. 5-43), Pflanz's exponents (Knacke Fig. 5-51: 2
for solid cloth, 1 for slotted canopies), C_x the opening-force coefficient at infinite mass (Knacke Tables 5-1 and
5-2), read from secondary transcriptions of the manual: typical, not a design's."""
CANOPY_TYPES = {canopy.name: canopy for canopy in CANOPY_TYPE_LIST}
"""Canopy type name -> CanopyType."""

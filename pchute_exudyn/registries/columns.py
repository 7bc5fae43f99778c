"""The output columns: one record per kind of column (name template, unit, meaning, what it belongs to).

Every column name a run writes, a study records or a report, a comparison or a figure reads is made here
(``column``) and its unit read here (``unit``), so that a new column is one record. Templates name their parts:
``{owner}`` is a body, a confluence label (``Case.confluence_label``), a system, a canopy or a line label
(``Case.line_label``), as ``of`` says; ``{other}`` the second canopy of a pair. A method adds the columns of its own
outputs with ``register`` (``methods.base.Method.outputs``); a column it writes is ``method_column``'s.

Conventions: altitudes above the reference surface, heights above the case's ground
(``SimulationSettings.ground_altitude``), east and north along the start point's axes from it (m), latitude and
longitude geodetic on the case's ellipsoid relative to the ground (deg, east positive), velocities
relative to the ground (m/s, start-point axes, down positive), attitude angles in degrees (``physics.rotations``),
rates in body axes (rad/s), tensions positive (N).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property, lru_cache

from .quantities import QUANTITIES


@dataclass(frozen=True)
class Column:
    """A kind of output column.

    Attributes
    ----------
    template : str
        The name with its parts in braces: ``{owner}_altitude``.
    unit : str
        SI unit ('-' for a ratio, 'count' for a count).
    meaning : str
        One line.
    of : str
        What ``{owner}`` names: body, point (a body or a confluence), aerodynamic body, line, system, canopy, pair,
        run (a single column of a run), study run (a study's record of a run).
    derive : callable, optional
        For a column of each body computed from its sampled states alone: ``derive(body)`` with ``body`` the body's
        histories as ``engine.state.RawHistory`` holds them ({'position', 'velocity', 'rotation',
        'angular_velocity'}: (n, 3), (n, 3), (n, 3, 3), (n, 3) in the start frame, SI) returns the column (n,);
        ``run.outputs`` writes it for every body. A column without one is written by the code that computes it.
    """

    template: str
    unit: str
    meaning: str
    of: str
    derive: Callable | None = field(default=None, compare=False)

    @cached_property
    def pattern(self) -> re.Pattern:
        """The regular expression of the names this template makes (``{owner}``, ``{other}``: a group each),
        compiled at its first use (the table's 90 compiled at import cost a run's start 10 ms)."""
        parts = re.split(r"(\{owner\}|\{other\})", self.template)
        regex = "".join("(.+)" if part in ("{owner}", "{other}") else re.escape(part) for part in parts)
        return re.compile(f"^{regex}$")

    @cached_property
    def _fixed(self) -> list:
        """The template's fixed text around its ``{owner}`` and ``{other}`` (first, middles, last)."""
        return re.split(r"\{owner\}|\{other\}", self.template)

    def could_match(self, name: str) -> bool:
        """False where ``pattern`` cannot match ``name`` (its fixed text not there, in order): a check without
        compiling the pattern, so that describing a run's columns compiles only the few that could."""
        fixed = self._fixed
        if len(fixed) == 1:
            return name == fixed[0]
        head, tail = fixed[0], fixed[-1]
        if len(name) < len(head) + len(tail) + len(fixed) - 1 or not name.startswith(head) or not name.endswith(tail):
            return False
        position, end = len(head) + 1, len(name) - len(tail)
        for piece in fixed[1:-1]:
            found = name.find(piece, position, end)
            if found < 0:
                return False
            position = found + len(piece) + 1
        return True

    def name(self, owner: str = "", other: str = "") -> str:
        """The column of ``owner`` (and ``other``, a pair's second)."""
        return self.template.format(owner=owner, other=other)


def _each(template: str, unit: str, meaning: str, of: str, axes=("x", "y", "z")) -> list:
    return [Column(template.replace("{axis}", axis), unit, meaning.replace("{axis}", axis), of) for axis in axes]


UNNAMED_VEHICLE = "vehicle"
"""The vehicle's name (the owner of its columns) where nothing names it: a case without ``case.vehicle``, another
tool's file read without a summary (``Result.vehicle``), and ``summary.json``'s ``final``, which names the vehicle's
altitude, east and north by this owner whatever the vehicle is called (``results.summary.FinalState``)."""

DEPLOY_CONDITIONS = {q.name: f"deploy_{q.name}_{{owner}}" for q in QUANTITIES if q.studied}
"""The template of the column of each recorded quantity at a system's triggered deployment
(``registries.quantities.Quantity.studied``: altitude, mach, dynamic_pressure), by the quantity's name."""

POINT_TEMPLATES = ("{owner}_altitude", "{owner}_height", "{owner}_east", "{owner}_north", "{owner}_velocity_north",
                 "{owner}_velocity_east", "{owner}_velocity_down")
"""The templates of the columns of every body and confluence, in the order a run writes them."""
GEODETIC_TEMPLATES = ("{owner}_latitude", "{owner}_longitude")
"""The templates of every body's and confluence's geodetic latitude and longitude (deg) on an ellipsoidal planet,
written after all other columns of a run (the columns before them keep their places in ``timeseries.csv``)."""

COLUMNS = (
    Column("time", "s", "run time since the start", "run"),
    # every body and confluence
    Column("{owner}_altitude", "m", "centre of mass (a confluence: its point) above the reference surface", "point"),
    Column("{owner}_height", "m", "the same above the ground: altitude minus the case's ground altitude", "point"),
    Column("{owner}_east", "m", "east of the start point, along its axes", "point"),
    Column("{owner}_north", "m", "north of the start point, along its axes", "point"),
    Column("{owner}_latitude", "deg", "geodetic latitude on the case's ellipsoid, north positive (not on a flat "
           "planet)", "point"),
    Column("{owner}_longitude", "deg", "longitude on the case's ellipsoid, east positive, -180 to 180 (not on a flat "
           "planet)", "point"),
    *_each("{owner}_velocity_{axis}", "m/s", "velocity {axis} relative to the ground, start-point axes", "point",
           ("north", "east", "down")),
    *_each("{owner}_relative_position_{axis}", "m", "position relative to the vehicle, vehicle body axis {axis}",
           "point"),
    *_each("{owner}_relative_velocity_{axis}", "m/s", "velocity relative to the vehicle, vehicle body axis {axis}",
           "point"),
    # bodies
    Column("{owner}_yaw_deg", "deg", "yaw of the body axes (physics.rotations)", "body"),
    Column("{owner}_pitch_deg", "deg", "pitch of the body axes", "body"),
    Column("{owner}_roll_deg", "deg", "roll of the body axes", "body"),
    Column("{owner}_tilt_deg", "deg", "body +x from nadir", "body"),
    *_each("{owner}_rate_{axis}", "rad/s", "angular rate about body axis {axis}", "body"),
    Column("{owner}_pendulum_deg", "deg", "the vehicle's +x from the line to its canopies' centre, against down",
           "body"),
    Column("{owner}_pendulum_airspeed_deg", "deg", "the same against the air-relative velocity", "body"),
    Column("{owner}_apparent_mass_axial", "kg", "air carried along the body axis (apparent mass)", "body"),
    Column("{owner}_apparent_mass_lateral", "kg", "air carried across the body axis", "body"),
    Column("{owner}_apparent_inertia", "kg m^2", "apparent moment of inertia across the axis", "body"),
    # aerodynamic bodies
    Column("{owner}_angle_of_attack_deg", "deg", "total angle of attack of the air-relative velocity",
           "aerodynamic body"),
    Column("{owner}_alpha_deg", "deg", "atan2(w, u) of the air-relative velocity in body axes", "aerodynamic body"),
    Column("{owner}_beta_deg", "deg", "asin(v / |V|) of the air-relative velocity in body axes", "aerodynamic body"),
    Column("{owner}_dynamic_pressure", "Pa", "1/2 rho V^2 at the aerodynamic centre", "aerodynamic body"),
    Column("{owner}_mach", "-", "Mach number at the aerodynamic centre", "aerodynamic body"),
    *_each("{owner}_wind_{axis}", "m/s", "steady wind and gusts at the aerodynamic centre, {axis}", "aerodynamic body",
           ("east", "north", "up")),
    *_each("{owner}_turbulence_{axis}", "m/s", "turbulence at the aerodynamic centre, {axis}", "aerodynamic body",
           ("east", "north", "up")),
    Column("{owner}_aerodynamic_force", "N", "magnitude of an opening canopy's aerodynamic force", "canopy"),
    Column("{owner}_drag_area_fraction", "-", "drag area open, of the full (reefing, opening)", "canopy"),
    Column("{owner}_flyout_deg", "deg", "a cluster canopy's riser from the cluster's axis", "canopy"),
    Column("{owner}_{other}_overlap", "m", "two cluster canopies' overlap (positive: in contact)", "pair"),
    # lines and systems
    Column("tension_{owner}", "N", "line tension (positive: pulling)", "line"),
    Column("{owner}_load_share", "-", "largest canopy's share of a cluster's riser load", "system"),
    # a study's record of each run (study.runner)
    *[Column(name, unit, meaning, "study run") for name, unit, meaning in (
        ("final_time", "s", "end of the run"), ("final_altitude", "m", "the vehicle's altitude at the end"),
        ("final_east", "m", "the vehicle's east at the end"), ("final_north", "m", "the vehicle's north at the end"),
        ("final_lateral", "m", "horizontal distance from the start at the end"),
        ("final_latitude", "deg", "the vehicle's latitude at the end (an ellipsoidal planet)"),
        ("final_longitude", "deg", "the vehicle's longitude at the end (an ellipsoidal planet)"),
        ("touchdown_time", "s", "time of touchdown"),
        ("touchdown_speed", "m/s", "the vehicle's total speed over the ground at touchdown (all three components)"),
        ("touchdown_descent_rate", "m/s", "its vertical speed at touchdown, along the local vertical, down positive"),
        ("touchdown_horizontal_speed", "m/s", "its horizontal speed over the ground at touchdown"),
        ("wall_time", "s", "the engine's solve"), ("steps", "count", "integration steps"),
        ("descent_rate", "m/s", "the vehicle's steady descent rate"),
        ("pendulum_max_deg", "deg", "largest pendulum angle"), ("pendulum_rms_deg", "deg", "rms pendulum angle"),
        ("pendulum_amplitude_deg", "deg", "pendulum amplitude"))],
    *[Column(template, unit, meaning, of) for template, unit, meaning, of in (
        ("peak_tension_{owner}", "N", "a line's peak tension", "line"),
        ("rms_tension_{owner}", "N", "a line's rms tension", "line"),
        ("peak_load_share_{owner}", "-", "a cluster's peak load share", "system"),
        ("max_flyout_{owner}", "deg", "a canopy's largest flyout", "canopy"),
        ("mean_flyout_{owner}", "deg", "a canopy's mean flyout", "canopy"),
        ("deploy_time_{owner}", "s", "time of a system's deployment", "system"),
        ("snatch_load_{owner}", "N", "a deployment's snatch (its load's first peak: a system's or a tether's)",
         "system"),
        ("opening_load_{owner}", "N", "a deployment's opening load (its largest)", "system"),
        ("knacke_opening_load_{owner}", "N", "Knacke's hand estimate of a system's opening load", "system"),
        ("breaking_strength_{owner}", "N", "the lowest rated breaking strength of a deployment's lines", "system"),
        ("separation_time_{owner}", "s", "time of a separation", "run"),
        ("separation_clearance_{owner}", "m", "clearance after a separation", "run"))],
    *[Column(DEPLOY_CONDITIONS[q.name], q.unit, f"the vehicle's {q.meaning} at a system's triggered deployment",
             "system") for q in QUANTITIES if q.studied],
)
"""Every kind of column (a method's own: ``register``)."""

_REGISTERED: dict = {}


def derived(of: str) -> list:
    """The columns of kind ``of`` that carry their own ``derive``."""
    return [entry for entry in _table().values() if entry.derive is not None and entry.of == of]


def register(*columns: Column) -> None:
    """Add a method's columns (its confluence outputs) to the registry; a template already there stays."""
    for entry in columns:
        _REGISTERED.setdefault(entry.template, entry)
    describe.cache_clear()


def method_outputs(outputs: dict) -> tuple:
    """The columns of a method's confluence outputs ({output: unit}, ``Method.outputs``): the bare output with one
    system, ``<system>_<output>`` with several (``method_column``)."""
    return tuple(Column(template, unit, f"the confluence method's {output}", "system")
                 for output, unit in outputs.items() for template in (output, "{owner}_" + output))


def _table() -> dict:
    return {**{entry.template: entry for entry in COLUMNS}, **_REGISTERED}


def column(template: str, owner: str = "", other: str = "") -> str:
    """The name of column ``template`` (a key of the registry: ``'{owner}_altitude'``) for ``owner``."""
    try:
        entry = _table()[template]
    except KeyError:
        raise KeyError(f"no output column {template!r} in the registry (pchute_exudyn.registries.columns)") from None
    return entry.name(owner, other)


def method_column(output: str, system: str, systems: int) -> str:
    """The column of a method's output ``output`` for ``system`` of a case with ``systems`` systems: the bare
    output with one system, ``<system>_<output>`` with several."""
    return output if systems == 1 else f"{system}_{output}"


@lru_cache(maxsize=8192)   # a study's runs name the same columns: each is matched once
def describe(name: str) -> Column | None:
    """The record of column ``name``: the one whose template matches it with the longest fixed text (so that
    ``drogue_wind_east`` is a wind column, not the east of a point named ``drogue_wind``); None for none."""
    found = [entry for entry in _table().values() if entry.could_match(name) and entry.pattern.match(name)]
    return max(found, key=lambda entry: len(entry.template.replace("{owner}", "").replace("{other}", "")),
               default=None)


def owner(name: str, template: str) -> str | None:
    """The owner of column ``name`` if it is of kind ``template`` ('tension_{owner}' -> the line label), else None."""
    entry = describe(name)
    if entry is None or entry.template != template:
        return None
    return entry.pattern.match(name).group(1)


def markdown_table() -> str:
    """The registry as the Markdown table docs/results.md holds (a test checks that it is this one)."""
    rows = ["| column | unit | of | meaning |", "|---|---|---|---|"]
    rows += [f"| `{entry.template}` | {entry.unit} | {entry.of} | {entry.meaning} |" for entry in COLUMNS]
    return "\n".join(rows)


def unit(name: str) -> str | None:
    """The unit of column ``name`` (None for a column the registry does not know)."""
    entry = describe(name)
    return None if entry is None else entry.unit

"""A new case from a few choices: ``pchute new`` and ``new_case`` write a complete, commented, runnable case file.

The vehicle hangs under one canopy (or a cluster) on ``bridles`` lines that meet at a confluence, and one riser per
canopy from the confluence to the canopy's suspension-line apex (the canopy body's ``riser`` point). Everything is
placed in the descent attitude, in steady descent: every line stretched by its share of the steady load (LINE_STRAIN),
the confluence where the stretched bridles put it, all moving with the air and straight down through it at
``speed``; or released from an aircraft, every system placed at line stretch at its deployment; or at line stretch at
flight conditions (``mach``, ``dynamic_pressure``; case.new_conditions). Sizing rules (each written into the file
beside its number, and in ``docs/tutorial.md``):

* canopy: reference area S0 = drag area / C_D0 of its type (or from the nominal diameter, S0 = pi D0^2 / 4); mass
  CANOPY_AREAL_MASS x S0 unless given; the inertia of a thin hemispherical shell of the projected radius
  R_p = 0.67 D0 / 2 about its own centre, but the centre of mass (and the aerodynamic centre) at the skirt's centre,
  where the suspension lines of length L_s from the apex end (sqrt(L_s^2 - R_p^2) from it): a simplification, the
  shell's own centre lies R_p / 2 higher; C_A(alpha') C_D0 to AXIAL_FLAT_TO_DEG, then to 0 edge-on, and C_N(alpha')
  the zero-trim canopy table of MER to 60 deg, then to EDGE_ON_NORMAL;
* vehicle: a solid cylinder of the given diameter, half as tall, the bridles on a circle of 0.35 diameters on its
  top face; no aerodynamic load (at flight conditions a table of C_A = 0, so that the run records its Mach number);
* lines: stiffness from LINE_STRAIN of stretch under the vehicle's weight in steady descent, damping
  LINE_DAMPING_TIME x stiffness (MER's ratio); the confluence CONFLUENCE_MASS_FRACTION of the vehicle's mass;
* the run: SP to touchdown on the reference surface, RK4 at adaptive steps (no ``[simulation.steps]``;
  docs/models/step_control.md); with one bridle and one light canopy (LIGHT_CANOPY_TIME), a reduced canopy
  (``canopy_model = "reduced"``) unless it opens by an inflation (a release).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, fields

import numpy as np

from ..errors import InputError
from ..physics.cluster import DEFAULT_DRAG_EFFICIENCY, drag_efficiency, spread_directions, touching_spread
from ..physics.inflation import nominal_diameter
from ..physics.rotations import attitude_angles_deg, attitude_matrix
from ..physics.shapes import hemispherical_shell_inertia, solid_cylinder_inertia
from ..registries.canopy_types import CANOPY_TYPES
from ..registries.columns import column
from .model import Contact
from .new_checks import check_choice, check_integer, check_needs, check_number, check_positive, check_reader_ranges
from .new_conditions import check_conditions, header_words, start_state, vehicle_rows
from .new_planets import PLANETS, gravity_at

MER_DRAG_AREA = 178.47 * 0.46
"""The default canopy's drag area (m^2): MER's parachute, S0 178.47 m^2 at C_A 0.46 (cases/mer/base.toml)."""
CANOPY_AREAL_MASS = 0.15
"""Canopy mass per reference area (kg/m^2) when none is given: canopy cloth, suspension lines and hardware
(assumed; light nylon canopies run about 0.1 to 0.3 kg/m^2)."""
LINE_STRAIN = 0.025
"""Stretch (-) of each line under its share of the vehicle's weight in steady descent (MER's riser: 2.6 %)."""
LINE_DAMPING_TIME = 0.01
"""Line damping / stiffness (s): MER's 470 N s/m on 47 000 N/m."""
LIGHT_CANOPY_TIME = 0.05
"""The drag time constant (s) below which a canopy is light: m_canopy / (rho C_D0 S0 V) at the start, rho and V the
density and the steady rate of descent there (a release: its airspeed). A light canopy's speed along its riser settles
faster than the steps its descent needs, so with one bridle (its riser in series with it) ``pchute new`` writes
``canopy_model = "reduced"`` (SP flies it as a massless drag point at the riser's end), removing its fast modes. Not
in a release: its canopy opens by an inflation, which a reduced canopy refuses."""
CONFLUENCE_MASS_FRACTION = 0.002
"""Confluence mass / vehicle mass (-) when none is given (assumed: links and swivel)."""
COMMENT_COLUMN = 44
"""Column at which the written file's comments start (the hand-written case files' layout)."""
ATTACH_RADIUS = 0.35
"""Bridle attach circle / vehicle diameter (-)."""
OVERINFLATION_DECAY = 0.25
"""The overshoot's fall (``overinflation_decay``) as a fraction of the fill time at the release airspeed (assumed)."""
AXIAL_FLAT_TO_DEG = 60.0
"""C_A(alpha') is C_D0 up to this angle (deg), then falls linearly to 0 at 90 deg (assumed shape): a canopy
symmetric fore and aft has no axial force edge-on, so the force is continuous as the canopy turns past 90 deg (a
constant C_A changes sign there: a jump no implicit step can cross, and an attitude the canopy slides along;
docs/models/aerodatabase.md, "Edge-on"). Measured canopy tables fall with the angle too (cases/cev_pa1_aero.toml)."""
EDGE_ON_NORMAL = 0.25
"""C_N at 90 deg (-, on S0), assumed: an edge-on canopy's side-on projected area (half the disc of its projected
diameter 0.67 D0, about 0.22 S0) at a bluff body's drag coefficient near 1.1: the cross-flow drag that slows a canopy
thrown edge-on by an opening or a gust, so that its riser pulls it back (MER's table ends at 0)."""
NORMAL_COEFFICIENT = ([0.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 90.0],
                      [0.0, 0.040, 0.080, 0.110, 0.130, 0.150, 0.140, 0.110, EDGE_ON_NORMAL])
"""C_N(alpha'): MER's zero-trim parachute table (docs/models/mer.md: a stable canopy's restoring force) to 60 deg,
then rising to the cross-flow drag of a canopy seen edge-on, EDGE_ON_NORMAL at 90 deg (MER's table ends at 0)."""


@dataclass(frozen=True)
class NewCase:
    """The choices of a new case; every other number follows from them (module docstring).

    Attributes
    ----------
    planet : {"mars", "earth", "flat"}
        Mars (IAU ellipsoid, normal gravity, NASA GRC atmosphere), Earth (WGS-84, normal gravity, US76) or a flat
        Earth (9.80665 m/s^2, US76).
    mass : float
        Vehicle mass (kg).
    diameter : float
        Vehicle diameter (m).
    drag_area : float or None
        Each canopy's drag area C_D0 S0 (m^2); give this or ``canopy_diameter``; neither: MER's, 82.1 m^2.
    canopy_diameter : float or None
        Each canopy's nominal diameter D0 (m).
    canopy_type : str
        The canopy type (``registries.canopy_types``): its drag coefficient C_D0 and how it opens.
    canopy_mass : float or None
        Each canopy's mass (kg); None: 0.15 kg per m^2 of S0 (CANOPY_AREAL_MASS).
    canopies : int
        1, or 2 to 8 for a cluster (each canopy its own body and riser, on the cone where they just touch).
    bridles : int
        Bridles from the vehicle to the confluence (1 to 12; 2 on opposite sides of the attach circle). With one
        bridle and one light canopy (LIGHT_CANOPY_TIME), the canopy is reduced (``canopy_model = "reduced"``).
    bridle_length, riser_length, suspension_line_length : float or None
        Free lengths (m); None: the vehicle's diameter, half the canopy's nominal diameter and one nominal diameter.
    altitude : float
        Start altitude of the vehicle's centre of mass (m).
    speed : float or None
        Start descent speed (m/s, down, relative to the air); None: the steady rate of descent at the start altitude.
    name : str
        The case's name.
    drag_coefficient : float or None
        Each canopy's C_D0 on its nominal area S0 (-); None: its type's (CANOPY_TYPES).
    wind_speed : float
        A constant wind's speed (m/s); 0: still air. The descent starts moving with the air either way
        (``[start] velocities_relative_to = "air"``), so a wind set later (``--set atmosphere.wind.east=6``) does too.
    wind_from_deg : float
        The direction the wind comes from, clockwise from north (deg).
    release_airspeed : float or None
        Release the vehicle from an aircraft flying at this airspeed (m/s) instead of starting in steady descent:
        its canopies deploy at line stretch after ``static_line_time`` and open by the fill-constant law of their
        type (CANOPY_TYPES).
    release_heading_deg, release_flight_path_deg : float
        The aircraft's heading (deg, clockwise from north) and flight-path angle (deg, climbing > 0, -90 to 90).
    static_line_time : float
        Time (s, >= 0) from the release to line stretch.
    mach : float or None
        Start at line stretch at this Mach number (-) and ``dynamic_pressure`` instead of in steady descent: the
        altitude solves rho(h) a(h)^2 M^2 / 2 = q in the planet's atmosphere, the speed through the air is M a(h),
        and the canopies deploy at the start and open as after a release (case.new_conditions).
    dynamic_pressure : float or None
        The start's dynamic pressure q = rho V^2 / 2 (Pa), with ``mach``.
    flight_path_deg, heading_deg : float
        The start's velocity through the air above the horizontal (deg, -90 to 90, descending < 0) and its
        direction clockwise from north (deg), with ``mach``.
    dual_deploy : bool
        A rocket's dual deploy instead (case.new_rocket): a slender cylinder of ``mass`` (kg, its packed recovery gear
        included), ``diameter`` and ``length``, a drogue on an apogee trigger and a main at ``main_height``.
    length : float or None
        The rocket's length (m, dual deploy).
    drogue_drag_area, main_drag_area : float or None
        The drogue's and the main's C_D0 S0 (m^2; dual deploy).
    drogue_mass, main_mass : float or None
        The drogue's and the main's canopy mass (kg); None: 0.15 kg per m^2 of S0.
    main_height : float or None
        The main's deployment height above the ground (m, dual deploy), below the start's.
    apogee_lag : float
        The drogue's delay after the first trigger sample past apogee (s, >= 0).
    latitude, longitude : float or None
        The start point (deg; dual deploy); None: 0.
    ground_elevation : float or None
        The ground's altitude (m, dual deploy); None: 0, or the RocketPy export's.
    height : float or None
        Start height above the ground (m), instead of ``altitude`` (dual deploy).
    velocity_east, velocity_north, velocity_up : float or None
        Start velocity over the ground (m/s, east, north, up; dual deploy); None: 0.
    nose_pitch_deg, nose_heading_deg : float or None
        The nose above the horizontal (deg, -90 to 90; None: 0, level) and clockwise from north (deg; None: along
        the horizontal velocity, north at none) (dual deploy).
    from_rocketpy : str or None
        A RocketPy flight export (CSV, FlightDataExporter) whose apogee (its first row if it only descends) is the
        start: position, velocity over the ground, nose (dual deploy; read by the command line).
    """

    planet: str = "mars"
    mass: float = 800.0
    diameter: float = 2.6
    drag_area: float | None = None
    canopy_diameter: float | None = None
    canopy_type: str = "disk_gap_band"
    canopy_mass: float | None = None
    canopies: int = 1
    bridles: int = 3
    bridle_length: float | None = None
    riser_length: float | None = None
    suspension_line_length: float | None = None
    altitude: float = 8000.0
    speed: float | None = None
    name: str = "new case"
    drag_coefficient: float | None = None
    wind_speed: float = 0.0
    wind_from_deg: float = 270.0
    release_airspeed: float | None = None
    release_heading_deg: float = 0.0
    release_flight_path_deg: float = 0.0
    static_line_time: float = 1.0
    mach: float | None = None
    dynamic_pressure: float | None = None
    flight_path_deg: float = 0.0
    heading_deg: float = 0.0
    dual_deploy: bool = False
    length: float | None = None
    drogue_drag_area: float | None = None
    main_drag_area: float | None = None
    drogue_mass: float | None = None
    main_mass: float | None = None
    main_height: float | None = None
    apogee_lag: float = 1.0
    latitude: float | None = None
    longitude: float | None = None
    ground_elevation: float | None = None
    height: float | None = None
    velocity_east: float | None = None
    velocity_north: float | None = None
    velocity_up: float | None = None
    nose_pitch_deg: float | None = None
    nose_heading_deg: float | None = None
    from_rocketpy: str | None = None

    def __post_init__(self):
        check_choice("planet", self.planet, PLANETS)
        check_choice("canopy_type", self.canopy_type, CANOPY_TYPES)
        for key in ("mass", "diameter", "drag_area", "canopy_diameter", "canopy_mass", "bridle_length",
                    "riser_length", "suspension_line_length", "altitude"):
            check_positive(key, getattr(self, key), optional=key not in ("mass", "diameter", "altitude"),
                           unit={"mass": "kg", "canopy_mass": "kg", "drag_area": "m^2"}.get(key, "m"))
        if self.speed is not None:
            check_number("speed", self.speed, self.speed >= 0.0, "must be >= 0 (m/s, downward)")
        check_positive("drag_coefficient", self.drag_coefficient, optional=True, unit="-")
        check_number("wind_speed", self.wind_speed, self.wind_speed >= 0.0, "must be >= 0 (m/s)")
        check_number("wind_from_deg", self.wind_from_deg, -360.0 <= self.wind_from_deg <= 360.0,
                "must be within -360..360 (deg, clockwise from north)")
        self._check_release()
        check_conditions(self)
        if self.drag_area is not None and self.canopy_diameter is not None:
            raise InputError(f"drag_area = {self.drag_area!r} and canopy_diameter = {self.canopy_diameter!r}: give "
                             "one of them, not both")
        check_integer("canopies", self.canopies, 1, 8)
        check_integer("bridles", self.bridles, 1, 12)
        if self.bridle_length is not None and self.bridle_length <= ATTACH_RADIUS * self.diameter:
            raise InputError(f"bridle_length = {self.bridle_length!r}: must exceed the attach circle's radius, "
                             f"{ATTACH_RADIUS * self.diameter:g} m (0.35 x diameter)")
        from . import new_rocket  # it builds on this module

        new_rocket.check_choices(self)
        check_reader_ranges(self)
        check_needs(self, [f.name for f in fields(self) if getattr(self, f.name) != f.default])

    def _check_release(self) -> None:
        if self.release_airspeed is not None:
            check_number("release_airspeed", self.release_airspeed, self.release_airspeed >= 0.0, "must be >= 0 (m/s)")
        check_number("release_heading_deg", self.release_heading_deg, -360.0 <= self.release_heading_deg <= 360.0,
                "must be within -360..360 (deg, clockwise from north)")
        check_number("release_flight_path_deg", self.release_flight_path_deg,
                -90.0 <= self.release_flight_path_deg <= 90.0, "must be within -90..90 (deg, climbing > 0)")
        check_number("static_line_time", self.static_line_time, self.static_line_time >= 0.0,
                "must be >= 0 (s from the release to line stretch)")
        if self.release_airspeed is not None and self.speed is not None:
            raise InputError(f"speed = {self.speed!r} and release_airspeed = {self.release_airspeed!r}: a released "
                             "vehicle starts at the aircraft's airspeed; give one of them")

    @property
    def released(self) -> bool:
        """Whether the vehicle is released from an aircraft (else it starts in steady descent)."""
        return self.release_airspeed is not None

    @property
    def deploys(self) -> bool:
        """Whether the canopies deploy during the run (a release, or a start at flight conditions) rather than
        fly from the start in steady descent."""
        return self.released or self.mach is not None

    @property
    def canopy_drag_coefficient(self) -> float:
        """Each canopy's C_D0 on S0 (-): the one given, else its type's."""
        return (CANOPY_TYPES[self.canopy_type].drag_coefficient if self.drag_coefficient is None
                else float(self.drag_coefficient))

    @property
    def reference_area(self) -> float:
        """S0 of each canopy (m^2)."""
        if self.canopy_diameter is not None:
            return math.pi * self.canopy_diameter**2 / 4.0
        drag_area = MER_DRAG_AREA if self.drag_area is None else self.drag_area
        return drag_area / self.canopy_drag_coefficient


@dataclass(frozen=True)
class _Layout:
    """Sizes and positions (m, kg, N/m; altitudes above the reference surface) derived from the choices."""

    choices: NewCase
    gravity: float          # at the surface (m/s^2): the lines' sizing
    reference_area: float
    canopy_mass: float
    confluence_mass: float
    bridle_length: float
    riser_length: float
    apex_distance: float    # canopy centre of mass to its riser point (m)
    projected_radius: float
    altitude: float         # the vehicle's centre of mass at the start (m; flight conditions: solved)
    airspeed: float | None = None   # the start's speed through the air at flight conditions (m/s); else None

    @property
    def total_mass(self) -> float:
        c = self.choices
        return c.mass + c.canopies * self.canopy_mass + self.confluence_mass

    @property
    def conditions_words(self) -> str:
        """`pchute new`'s words on a start at flight conditions (their altitude and airspeed), else none."""
        c = self.choices
        return "" if self.airspeed is None else (f"line stretch at Mach {c.mach:g} and {c.dynamic_pressure:g} Pa: "
                                                 f"{self.altitude:.1f} m, {self.airspeed:.2f} m/s through the air, ")

    @property
    def height(self) -> float:
        """The vehicle cylinder's height (m)."""
        return 0.5 * self.choices.diameter

    @property
    def attach_radius(self) -> float:
        """The bridles' attach circle's radius (m)."""
        return ATTACH_RADIUS * self.choices.diameter

    def rise(self, strain: float = LINE_STRAIN) -> float:
        """The bridles' height from their attach points to the confluence (m), every bridle stretched by ``strain``
        (-): its steady stretch, or 0 at line stretch."""
        length = self.bridle_length * (1.0 + strain)
        if self.choices.bridles == 1:
            return length
        return math.sqrt(length**2 - self.attach_radius**2)

    @property
    def canopy_reach(self) -> float:
        """Confluence to a canopy's centre in steady descent (m): its riser, stretched by LINE_STRAIN, and the
        apex-to-centre distance."""
        return self.riser_length * (1.0 + LINE_STRAIN) + self.apex_distance

    @property
    def spread(self) -> float:
        """The cluster cone's half-angle (rad): the canopies' envelopes just touch."""
        return touching_spread(self.projected_radius, self.canopy_reach, self.choices.canopies)

    @property
    def canopy_height(self) -> float:
        """Vehicle centre of mass to a canopy's centre of mass (where its drag acts), vertically (m)."""
        return 0.5 * self.height + self.rise() + self.canopy_reach * math.cos(self.spread)

    @property
    def drag_efficiency(self) -> float:
        """eta(n) of the cluster (``physics.cluster``; 1 for one canopy): what each canopy's C_A delivers."""
        return drag_efficiency(DEFAULT_DRAG_EFFICIENCY, self.choices.canopies)

    @property
    def vertical_coefficient(self) -> float:
        """Each canopy's force coefficient along the vertical (-) in steady descent: a cluster's canopies fly at
        its spread theta off the vertical (their envelopes touching), where eta C_D0 along their axis and C_N(theta)
        across it give eta C_D0 cos(theta) + C_N(theta) sin(theta); eta C_D0 for one canopy."""
        theta = self.spread
        normal = float(np.interp(math.degrees(theta), *NORMAL_COEFFICIENT))
        return self.drag_efficiency * self.choices.canopy_drag_coefficient * math.cos(theta) + normal * math.sin(theta)

    def canopy_drag_time(self, speed: float) -> float:
        """A canopy's drag time constant m_canopy / (rho C_D0 S0 V) (s) at ``speed`` V (m/s) at the start, rho where
        its drag acts then (``canopy_height`` above the vehicle); inf at rest."""
        c = self.choices
        density = PLANETS[c.planet][3]().density(self.altitude + self.canopy_height)
        drag = density * c.canopy_drag_coefficient * self.reference_area * speed
        return self.canopy_mass / drag if drag > 0.0 else math.inf

    def steady_rate(self, altitude: float) -> float:
        """The closed-form steady rate of descent (m/s) of the vehicle at ``altitude`` (m), sqrt(2 m g / (rho n C_V
        S0)): m the suspended mass (vehicle, canopies and confluence), g there, n canopies of vertical coefficient
        C_V (``vertical_coefficient``: eta C_D0 for one canopy), rho where their drag acts (``canopy_height`` above
        the vehicle)."""
        c = self.choices
        atmosphere = PLANETS[c.planet][3]
        gravity = gravity_at(c.planet, 0.0, altitude)   # the single-system case starts at latitude 0
        density = atmosphere().density(altitude + self.canopy_height)
        drag_area = c.canopies * self.vertical_coefficient * self.reference_area
        return math.sqrt(2.0 * self.total_mass * gravity / (density * drag_area))


def layout(choices: NewCase) -> _Layout:
    """The sizes (m, m^2, kg) the choices imply (module docstring); InputError where they cannot be built."""
    area = choices.reference_area
    nominal = nominal_diameter(area)
    canopy_mass = CANOPY_AREAL_MASS * area if choices.canopy_mass is None else choices.canopy_mass
    radius = Contact().projected_radius(area)   # the cluster contact model's envelope (0.67 D0 / 2)
    line = choices.suspension_line_length or nominal
    if line <= radius:
        raise InputError(f"suspension_line_length = {line!r}: must exceed the canopy's projected radius, {radius:g} m")
    plan = _Layout(choices, gravity_at(choices.planet), area, canopy_mass, CONFLUENCE_MASS_FRACTION * choices.mass,
                   choices.bridle_length or choices.diameter, choices.riser_length or 0.5 * nominal,
                   math.sqrt(line**2 - radius**2), radius, *start_state(choices))
    circle = radius if choices.canopies == 2 else radius / math.sin(math.pi / max(choices.canopies, 2))
    if choices.canopies > 1 and circle >= plan.canopy_reach:
        raise InputError(f"canopies = {choices.canopies}: their envelopes (radius {radius:.3g} m) cannot sit side by "
                         f"side on risers that reach {plan.canopy_reach:.3g} m; lengthen "
                         "riser_length or suspension_line_length")
    try:
        rate = plan.steady_rate(plan.altitude)
    except (ValueError, ZeroDivisionError):   # outside the model's range, or no air left
        rate = math.nan
    if not (math.isfinite(rate) and rate > 0.0):
        start = (f"altitude = {choices.altitude!r}" if plan.airspeed is None else f"mach = {choices.mach:g} and "
                 f"dynamic_pressure = {choices.dynamic_pressure:g} (a start at {plan.altitude:.1f} m)")
        raise InputError(f"{start}: outside the {PLANETS[choices.planet][1]} atmosphere "
                         "(no finite air density there); start lower")
    return plan


def _choices(choices: NewCase | None, kwargs: dict) -> NewCase:
    if choices is not None and kwargs:
        raise InputError(f"give a NewCase or its fields as keywords, not both (keywords: {', '.join(kwargs)})")
    return choices if choices is not None else NewCase(**kwargs)


def new_case_text(choices: NewCase | None = None, **kwargs) -> str:
    """The case file (TOML text) for ``choices`` (a NewCase, or its fields as keywords)."""
    choices = _choices(choices, kwargs)
    if choices.from_rocketpy is not None:
        raise InputError(f"from_rocketpy = {choices.from_rocketpy!r}: read by `pchute new`; from Python, start from "
                         "case.new_rocket.started_from(choices, results.rocketpy_export.apogee_state(path), path)")
    if choices.dual_deploy:
        from .new_rocket import dual_deploy_lines
        return "\n".join(_aligned(row) for row in dual_deploy_lines(choices)) + "\n"
    return "\n".join(_aligned(row) for row in _Writer(layout(choices)).lines()) + "\n"


def _aligned(row: str) -> str:
    """A key line with its comment at column COMMENT_COLUMN (the case files' layout)."""
    key, mark, comment = row.partition(" # ")
    if not mark or row.startswith("#") or '"' in key:   # a quoted value may hold " # " itself
        return row
    return f"{key.rstrip():<{COMMENT_COLUMN - 1}} # {comment.strip()}"


def new_case(choices: NewCase | None = None, **kwargs):
    """The loaded ``Case`` for ``choices`` (a NewCase, or its fields as keywords): the file ``new_case_text``
    writes, built in memory (for a notebook); ``pchute new`` writes the same text to a file."""
    from .files import tomllib
    from .loader import build_case

    choices = _choices(choices, kwargs)
    return build_case(tomllib.loads(new_case_text(choices)), {}, f"new_case({choices.name!r})")


def _n(value: float) -> str:
    """A number for the file: 12 significant digits (micrometres on kilometres), no float noise."""
    text = repr(float(f"{float(value):.12g}"))
    return "0.0" if text == "-0.0" else text


def _vector(values) -> str:
    return "[" + ", ".join(_n(v) for v in values) + "]"


class _Writer:
    """The case file's lines, section by section."""

    def __init__(self, plan: _Layout):
        self.plan, self.c = plan, plan.choices
        c = self.c
        self.height, self.attach_radius, self.rise = plan.height, plan.attach_radius, plan.rise()
        self.confluence_altitude = plan.altitude + 0.5 * self.height + self.rise
        self.speed = plan.steady_rate(plan.altitude) if c.speed is None else c.speed
        self.airspeed = c.release_airspeed if c.released else plan.airspeed   # at deployment (m/s); None: steady

    def lines(self) -> list:
        return self.header() + self.vehicle() + self.canopies() + self.system() + self.simulation()

    def header(self) -> list:
        c, p = self.c, self.plan
        planet_lines, atmosphere = PLANETS[c.planet][:2]
        canopy_altitude = column("{owner}_altitude", self.canopy_names()[0])
        return [f"# {c.name}: written by `pchute new` (pchute_exudyn.case.new; docs/tutorial.md). Units SI;",
                "# angles in degrees only where named _deg. " + self.start_words()[0], *self.start_words()[1:],
                f"# Suspended mass {_n(p.total_mass)} kg; steady rate of descent sqrt(2 m g / (rho n C_V S0)) = "
                f"{p.steady_rate(p.altitude):.3f} m/s at the start,", f"# {p.steady_rate(0.0):.3f} m/s at 0 m: "
                + ("C_V = C_D0 for one canopy" if c.canopies == 1 else
                   f"C_V = eta C_D0 cos(theta) + C_N(theta) sin(theta) = {p.vertical_coefficient:.5g}, the drag "
                   f"efficiency eta = {p.drag_efficiency:g}\n# of {c.canopies} canopies flying theta = "
                   f"{math.degrees(p.spread):.2f} deg off the vertical (where their envelopes touch)") + ".",
                "# Reported altitudes are each body's centre of mass (`vehicle_altitude`: the vehicle's); the canopy's",
                f"# drag acts {_n(self.plan.canopy_height)} m higher in steady descent, at its aerodynamic centre "
                f"(`{canopy_altitude}`).", "",
                "[case]", f"name = {json.dumps(c.name)}",
                f'description = "{c.mass:g} kg vehicle under {self.canopy_words()} ({c.planet})"',
                'vehicle = "vehicle"', "", "[planet]", *planet_lines, "",
                "[start]                                    # the start point", "latitude_deg = 0.0",
                "longitude_deg = 0.0", "# initial velocities relative to the air (the wind at the vehicle's "
                "start altitude): the descent starts moving with the wind", 'velocities_relative_to = "air"',
                *self.release(), "",
                "[atmosphere]", f'model = "{atmosphere}"', *self.wind(), ""]

    def start_words(self) -> list:
        """The header's lines on how the run starts."""
        c = self.c
        if c.mach is not None:
            return header_words(c, self.plan.altitude, self.airspeed)
        if c.released:
            return [f"Released from an aircraft at {_n(c.release_airspeed)} m/s through the air",
                    f"# (heading {c.release_heading_deg:g} deg, flight path {c.release_flight_path_deg:g} deg); the "
                    f"canopies deploy at line stretch {c.static_line_time:g} s later", f"# and open with the "
                    f"fill-constant law of a {c.canopy_type} canopy ([systems.main.inflation])."]
        rate = "the steady rate there" if c.speed is None else "as chosen"
        return [f"In steady descent: every line stretched {LINE_STRAIN:.1%} by its share of",
                "# the steady load, the confluence where the stretched bridles put it, everything moving with the air "
                "and down", f"# through it at {_n(self.speed)} m/s ({rate})."]

    def release(self) -> list:
        c = self.c
        if not c.released:
            return []
        return ["[start.release]                            # released from an aircraft: the vehicle leaves at the "
                "aircraft's velocity through the air",
                f"airspeed = {_n(c.release_airspeed)}   # m/s", f"heading_deg = {_n(c.release_heading_deg)}   # deg, "
                "clockwise from north", f"flight_path_deg = {_n(c.release_flight_path_deg)}   # deg, climbing > 0"]

    def wind(self) -> list:
        c = self.c
        if c.wind_speed == 0.0:
            return ["# [atmosphere.wind] (none): e.g. speed = 6.0 and from_deg = 270.0 for a 6 m/s west wind"]
        return ["[atmosphere.wind]                          # constant with altitude",
                f"speed = {_n(c.wind_speed)}   # m/s",
                f"from_deg = {_n(c.wind_from_deg)}   # deg: where it comes from, clockwise from north"]

    def canopy_words(self) -> str:
        c = self.c
        kind = c.canopy_type.replace("_", "-")
        return f"a {kind} canopy" if c.canopies == 1 else f"a cluster of {c.canopies} {kind} canopies"

    def vehicle(self) -> list:
        c = self.c
        rows = ["[bodies.vehicle]                           # a solid cylinder, half as tall as its diameter",
                f"mass = {_n(c.mass)}                             # kg",
                f"inertia = {_vector(solid_cylinder_inertia(c.mass, c.diameter, self.height))}   # kg m^2, "
                "principal, body axes",
                "[bodies.vehicle.points]                    # m, body axes from the centre of mass (+x down): "
                "the bridles' attach points"]
        for i, point in enumerate(self.attach_points(), start=1):
            rows.append(f"bridle{i} = {_vector(point)}")
        if c.deploys:
            rows.append(f"line_stretch = {_vector([-(0.5 * self.height + self.plan.rise(0.0)), 0.0, 0.0])}   # the "
                        "confluence at deployment: every bridle at its free length")
        if c.mach is not None:
            return rows + vehicle_rows(c, self.plan.altitude, self.airspeed) + [""]
        rows += ["[bodies.vehicle.initial]                   # attitude: body +x down (the descent attitude)",
                 f"altitude = {_n(c.altitude)}                        # m: the centre of mass"]
        if not c.released:
            rows.append(f"velocity_down = {_n(self.speed)}                  # m/s")
        return rows + [""]

    def attach_points(self) -> list:
        c = self.c
        if c.bridles == 1:
            return [[-0.5 * self.height, 0.0, 0.0]]
        angles = [2.0 * math.pi * i / c.bridles for i in range(c.bridles)]
        return [[-0.5 * self.height, self.attach_radius * math.cos(a), self.attach_radius * math.sin(a)]
                for a in angles]

    def canopy_names(self) -> list:
        return ["canopy"] if self.c.canopies == 1 else [f"canopy{i}" for i in range(1, self.c.canopies + 1)]

    def canopies(self) -> list:
        c, p = self.c, self.plan
        up = np.array([-1.0, 0.0, 0.0])    # descent frame (x down, y east, z south)
        directions = spread_directions(-up, np.array([0.0, 1.0, 0.0]), self.plan.spread, c.canopies)
        confluence = np.array([-self.confluence_altitude, 0.0, 0.0])
        rows = []
        for name, toward_confluence in zip(self.canopy_names(), directions):
            centre = confluence - self.plan.canopy_reach * toward_confluence
            yaw, pitch, roll = self.attitude(toward_confluence)
            rows += [f"[bodies.{name}]                            # {c.canopy_type}: a hemispherical shell of the "
                     "projected radius",
                     f"mass = {_n(p.canopy_mass)}                           # kg"
                     + (" (0.15 kg per m^2 of S0, assumed)" if c.canopy_mass is None else ""),
                     f"inertia = {_vector(hemispherical_shell_inertia(p.canopy_mass, p.projected_radius))}   # kg m^2",
                     f"points.riser = [{_n(p.apex_distance)}, 0.0, 0.0]   # m: the suspension lines' apex, "
                     f"{_n(c.suspension_line_length or nominal_diameter(p.reference_area))} m lines to the "
                     "skirt", *([] if c.deploys else self.canopy_initial(name, centre, yaw, pitch, roll)),
                     *self.aerodynamics(name), ""]
        return rows

    def canopy_initial(self, name: str, centre, yaw: float, pitch: float, roll: float) -> list:
        """A canopy's initial table in steady descent (a released one gets its state at line stretch)."""
        return [f"[bodies.{name}.initial]", f"altitude = {_n(-centre[0])}                  # m",
                *([] if self.c.canopies == 1 else [f"east = {_n(centre[1])}", f"north = {_n(-centre[2])}",
                                                   f"yaw_deg = {_n(yaw)}", f"pitch_deg = {_n(pitch)}",
                                                   f"roll_deg = {_n(roll)}"]),
                f"velocity_down = {_n(self.speed)}"]

    @staticmethod
    def attitude(toward_confluence) -> tuple:
        """Attitude angles (deg) that turn a canopy's +x onto ``toward_confluence`` (descent frame), no roll."""
        down = np.asarray(toward_confluence, float)
        yaw, pitch = math.atan2(down[1], down[0]), math.asin(-down[2])
        angles = attitude_angles_deg(attitude_matrix(math.degrees(yaw), math.degrees(pitch), 0.0))
        return tuple(float(a) for a in angles)

    def aerodynamics(self, name: str) -> list:
        c, p = self.c, self.plan
        alpha, value = NORMAL_COEFFICIENT
        return [f"[bodies.{name}.aerodynamics]",
                f"reference_area = {_n(p.reference_area)}               # m^2: S0, D0 = "
                f"{nominal_diameter(p.reference_area):.4f} m",
                f"axial_coefficient = {{ alpha_deg = [0.0, {AXIAL_FLAT_TO_DEG}, 90.0], value = "
                f"[{_n(c.canopy_drag_coefficient)}, {_n(c.canopy_drag_coefficient)}, 0.0] }}",
                "# C_A: C_D0 " + (f"of a {c.canopy_type} ({CANOPY_TYPES[c.canopy_type].drag_source}, mid-range)"
                                  if c.drag_coefficient is None
                                  else "as given") + f" to {AXIAL_FLAT_TO_DEG:g} deg, then to 0 edge-on (assumed)",
                "center = [0.0, 0.0, 0.0]                   # m: at the centre of mass",
                f"[bodies.{name}.aerodynamics.normal_coefficient]   # MER's zero-trim canopy table to 60 deg, "
                f"then the edge-on canopy's cross-flow drag ({EDGE_ON_NORMAL:g} at 90 deg, assumed)",
                f"alpha_deg = {alpha}", f"value = {value}"]

    def system(self) -> list:
        c, p = self.c, self.plan
        weight = c.mass * p.gravity
        bridle_tension = weight / max(c.bridles, 1) * (p.bridle_length * (1.0 + LINE_STRAIN) / self.rise)
        riser_tension = (weight + p.confluence_mass * p.gravity) / c.canopies / math.cos(self.plan.spread)
        rows = ["[systems.main]", f"canopies = {self.canopy_names()}".replace("'", '"') if c.canopies > 1
                else 'canopy = "canopy"', *self.canopy_model(), *self.deployment(), "[systems.main.confluence]",
                f"mass = {_n(p.confluence_mass)}                            # kg (0.2 % of the vehicle's, assumed)"]
        if not c.deploys:
            rows += ["[systems.main.confluence.initial]", f"altitude = {_n(self.confluence_altitude)}   # m: where "
                     "the stretched bridles put it", f"velocity_down = {_n(self.speed)}"]
        rows.append("")
        for i in range(1, c.bridles + 1):
            rows += self.line(f"bridle{i}", f"vehicle.bridle{i}", p.bridle_length, bridle_tension)
        for name in self.canopy_names():
            rows += self.line(f"riser_{name}" if c.canopies > 1 else "riser", f"{name}.riser", p.riser_length,
                              riser_tension)
        return rows

    def canopy_model(self) -> list:
        """``canopy_model = "reduced"`` for one light canopy on one bridle (LIGHT_CANOPY_TIME), unless it opens by an
        inflation (a release), which a reduced canopy refuses; nothing (rigid) otherwise."""
        c = self.c
        if c.bridles != 1 or c.canopies != 1:
            return []
        time = self.plan.canopy_drag_time(self.airspeed if c.deploys else self.speed)
        if time >= LIGHT_CANOPY_TIME:
            return []
        why = f"its drag time constant m / (rho C_D0 S0 V) = {time:.2g} s < {LIGHT_CANOPY_TIME:g} s"
        if c.deploys:
            return [f"# canopy_model: rigid (the default), though light ({why}): it opens by an inflation, which a "
                    "reduced canopy refuses"]
        return [f'canopy_model = "reduced"   # light ({why}): a drag point at the riser\'s end, without its fast '
                "modes (docs/models/reduced_canopy.md)"]

    def deployment(self) -> list:
        """A released vehicle's system: deployed at line stretch after the static line's time (at flight conditions:
        at the start), opening by its type's fill constant (CANOPY_TYPES)."""
        c = self.c
        if not c.deploys:
            return []
        canopy = CANOPY_TYPES[c.canopy_type]
        fill, exponent, overinflation = canopy.fill_constant, canopy.opening_exponent, canopy.overinflation
        fill_time = fill * nominal_diameter(self.plan.reference_area) / max(self.airspeed, 1.0)
        decay = OVERINFLATION_DECAY * fill_time if overinflation > 1.0 else 0.0
        when = (f"deploy_time = {_n(c.static_line_time)}   # s: the static line's time from the release to line "
                "stretch" if c.released else "deploy_time = 0.0   # s: line stretch at the start (flight conditions)")
        return [when, 'deploy_point = "vehicle.line_stretch"',
                f"[systems.main.inflation]                   # one stage from line stretch; {c.canopy_type} values "
                "(pchute_exudyn/registries/canopy_types.py, docs/tutorial.md)",
                "stage_start = [0.0]                        # s after line stretch", "fraction = [1.0]",
                f"fill_constant = [{_n(fill)}]   # -: fill time n D0 / V, V the canopy's speed at line stretch",
                f"exponent = [{_n(exponent)}]   # -: the drag area grows as (t / t_fill)^exponent",
                f"overinflation = {_n(overinflation)}   # -: the drag area's overshoot at the end of the fill",
                f"overinflation_decay = {_n(decay)}   # s: a quarter of the fill time at the "
                f"{'release' if c.released else 'start'} airspeed (assumed)"]

    @staticmethod
    def line(name: str, attach: str, length: float, tension: float) -> list:
        """A line's table: free ``length`` (m), stiffness from LINE_STRAIN under ``tension`` (N)."""
        stiffness = tension / (LINE_STRAIN * length)
        return [f"[systems.main.lines.{name}]", f'attach = "{attach}"', f"free_length = {_n(length)}   # m",
                f"stiffness = {_n(stiffness)}   # N/m: 2.5 % stretch under its share of the vehicle's weight",
                f"damping = {_n(LINE_DAMPING_TIME * stiffness)}   # N s/m: 0.01 s x stiffness", ""]

    def simulation(self) -> list:
        c, p = self.c, self.plan
        before = (c.static_line_time if c.released else 0.0) + 30.0 if c.deploys else 0.0   # the deployment, opening
        duration = 10.0 * math.ceil((1.25 * p.altitude / p.steady_rate(0.0) + 10.0 + before) / 10.0)
        return ["[simulation]", f"duration = {_n(duration)}   # s: an upper bound; the run ends at touchdown "
                "(the vehicle's centre of mass at 0 m)", "output_step = 0.02                         # s",
                'method = "sp"', 'integrator = "rk4"', "# No [simulation.steps]: RK4 takes adaptive steps "
                "(docs/models/step_control.md); to fix one, `[simulation.steps] sp = 0.01` or `--dt 0.01`."]

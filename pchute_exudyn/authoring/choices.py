"""The choices of a new case (``NewCase``), each checked when made: one InputError line naming the field, its value
and what is allowed. Everything a written case holds follows from them (``authoring.layout``, ``authoring.descent``,
``authoring.rocket``); their descriptions are also ``pchute new``'s help (``authoring.command_help``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from ..errors import InputError
from ..registries.canopy_types import CANOPY_TYPES
from .choice_checks import (
    check_choice,
    check_integer,
    check_needs,
    check_number,
    check_positive,
    check_reader_ranges,
    check_site,
)
from .flight_start import check_conditions
from .planets import PLANETS
from .rocket_start import check_choices as check_dual_deploy
from .rules import ATTACH_RADIUS, MER_DRAG_AREA


@dataclass(frozen=True)
class NewCase:
    """The choices of a new case; every other number follows from them (``authoring.descent``, ``authoring.rocket``).

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
    static_line_length : float or None
        A static line of this length (m) from the aircraft's anchor to the deployment bag instead of
        ``static_line_time``: the canopies deploy at the line stretch the flight reaches (the static line and the
        lines out), held back by the bag at the aircraft's velocity (docs/models/deployment_loads.md, "Static line").
    mach : float or None
        Start at line stretch at this Mach number (-) and ``dynamic_pressure`` instead of in steady descent: the
        altitude solves rho(h) a(h)^2 M^2 / 2 = q in the planet's atmosphere, the speed through the air is M a(h),
        and the canopies deploy at the start and open as after a release (authoring.flight_start).
    dynamic_pressure : float or None
        The start's dynamic pressure q = rho V^2 / 2 (Pa), with ``mach``.
    flight_path_deg, heading_deg : float
        The start's velocity through the air above the horizontal (deg, -90 to 90, descending < 0) and its
        direction clockwise from north (deg), with ``mach``.
    dual_deploy : bool
        A rocket's dual deploy instead (authoring.rocket): a slender cylinder of ``mass`` (kg, its packed recovery gear
        included), ``diameter`` and ``length``, a drogue on an apogee trigger and a main at ``main_height``.
    length : float or None
        The rocket's length (m, dual deploy).
    drogue_drag_area, main_drag_area : float or None
        The drogue's and the main's C_D0 S0 (m^2; dual deploy); give it or the canopy's diameter.
    drogue_mass, main_mass : float or None
        The drogue's and the main's canopy mass (kg); None: 0.15 kg per m^2 of S0.
    drogue_diameter, main_diameter : float or None
        The drogue's and the main's nominal diameter D0 (m, dual deploy): S0 = pi D0^2 / 4, C_D S = C_D S0; with the
        canopy's drag area instead its C_D is C_D S / S0 (then no drag coefficient).
    drogue_drag_coefficient, main_drag_coefficient : float or None
        The drogue's and the main's C_D0 on S0 (-, dual deploy); None: drag_coefficient, else the canopy type's.
    main_height : float or None
        The main's deployment height above the ground (m, dual deploy), below the start's.
    apogee_lag : float
        The drogue's delay after the first trigger sample past apogee (s, >= 0).
    main_lag : float
        The main's delay after the trigger sample below main_height (s, >= 0; the trigger's lag, dual deploy).
    harness_offset : float or None
        How far aft of the rocket's centre of mass its shock cords attach (m, dual deploy without shock_cord_length;
        None: HARNESS_FRACTION of its length, the bags a bridle's length aft of it). Given, the packed bags ride at
        the harness; at 0 the lines, the bags and the body's cross flow all act at the centre of mass and the rocket
        keeps the attitude it has at apogee, across the flow (a rocket hanging from the joint of its two sections);
        aft of it the rocket hangs nose down from its harness.
    main_opening_time : float or None
        The main's opening time (s, > 0, dual deploy): its drag area grows from 0 at deployment by the canopy type's
        opening exponent, (t / t_o)^j; None: fully open at deployment.
    body_drag : {"on", "off"}
        The rocket body's own drag as it hangs (dual deploy): a slender cylinder's cross flow at any angle of attack
        (Jorgensen, NASA TR R-474; physics.slender_body); off: none (as RocketPy's descent).
    drogue_after_main : {"attached", "cut"}
        The drogue after the main deploys (dual deploy): attached, on its harness to touchdown (a dual deploy as it
        flies); cut: cut away then (RocketPy's one C_D S at a time).
    shock_cord_length : float or None
        A rocket in two sections on one shock cord of this length (m, dual deploy; authoring.two_section): the nose cone
        thrown off at apogee (after apogee_lag) at ejection_speed, the drogue and the main hanging from its harness,
        each opening by its canopy type's fill law; None: one body with both systems packed in it.
    shock_cord_strength : float
        The shock cord's rated breaking strength (N, > 0; nylon's curve scaled by it).
    ejection_speed : float
        The nose cone's speed off the booster at the ejection (m/s, > 0).
    nose_mass : float or None
        The nose cone's mass (kg, below the rocket's); None: a tenth of the rocket's.
    latitude, longitude : float or None
        The start point (deg); None: 0. A descent's gravity is the planet's there.
    ground_elevation : float or None
        The ground's altitude (m); None: 0, or the RocketPy export's (dual deploy).
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
    static_line_length: float | None = None
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
    drogue_diameter: float | None = None
    main_diameter: float | None = None
    drogue_drag_coefficient: float | None = None
    main_drag_coefficient: float | None = None
    apogee_lag: float = 1.0
    main_lag: float = 0.0
    harness_offset: float | None = None
    main_opening_time: float | None = None
    body_drag: str = "on"
    drogue_after_main: str = "attached"
    shock_cord_length: float | None = None
    shock_cord_strength: float = 6000.0
    ejection_speed: float = 5.0
    nose_mass: float | None = None
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
        check_dual_deploy(self)
        check_site(self)
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
        if self.static_line_length is not None:
            check_number("static_line_length", self.static_line_length, 0.0 < self.static_line_length <= 100.0,
                         "must be > 0 and at most 100 (m, from the aircraft's anchor to the deployment bag)")
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

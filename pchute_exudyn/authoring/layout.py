"""The sizes and positions a NewCase implies (``layout``): canopy area and mass, line lengths, the cluster's spread,
the start altitude, and the steady rate of descent the written case states (``authoring.descent``'s sizing rules)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..case.canopy_choice import drag_time_constant
from ..case.model import Contact
from ..errors import InputError
from ..physics.cluster import DEFAULT_DRAG_EFFICIENCY, drag_efficiency, touching_spread
from ..physics.inflation import nominal_diameter
from .choices import NewCase
from .flight_start import start_state
from .planets import PLANETS, gravity_at
from .rules import ATTACH_RADIUS, CANOPY_AREAL_MASS, CONFLUENCE_MASS_FRACTION, LINE_STRAIN, NORMAL_COEFFICIENT


@dataclass(frozen=True)
class Layout:
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
        return drag_time_constant(self.canopy_mass, density, c.canopy_drag_coefficient, self.reference_area, speed)

    def steady_rate(self, altitude: float) -> float:
        """The closed-form steady rate of descent (m/s) of the vehicle at ``altitude`` (m), sqrt(2 m g / (rho n C_V
        S0)): m the suspended mass (vehicle, canopies and confluence), g there, n canopies of vertical coefficient
        C_V (``vertical_coefficient``: eta C_D0 for one canopy), rho where their drag acts (``canopy_height`` above
        the vehicle)."""
        c = self.choices
        atmosphere = PLANETS[c.planet][3]
        gravity = gravity_at(c.planet, c.latitude or 0.0, altitude)
        density = atmosphere().density(altitude + self.canopy_height)
        drag_area = c.canopies * self.vertical_coefficient * self.reference_area
        return math.sqrt(2.0 * self.total_mass * gravity / (density * drag_area))


def layout(choices: NewCase) -> Layout:
    """The sizes (m, m^2, kg) the choices imply (``authoring.descent``'s sizing rules); InputError where they
    cannot be built."""
    area = choices.reference_area
    nominal = nominal_diameter(area)
    canopy_mass = CANOPY_AREAL_MASS * area if choices.canopy_mass is None else choices.canopy_mass
    radius = Contact().projected_radius(area)   # the cluster contact model's envelope (0.67 D0 / 2)
    line = choices.suspension_line_length or nominal
    if line <= radius:
        raise InputError(f"suspension_line_length = {line!r}: must exceed the canopy's projected radius, {radius:g} m")
    gravity = gravity_at(choices.planet, choices.latitude or 0.0)
    plan = Layout(choices, gravity, area, canopy_mass, CONFLUENCE_MASS_FRACTION * choices.mass,
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

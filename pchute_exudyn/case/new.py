"""A new case from a few choices: ``pchute new`` and ``new_case`` write a complete, commented, runnable case file.

The vehicle hangs under one canopy (or a cluster) on ``bridles`` lines that meet at a confluence, and one riser per
canopy from the confluence to the canopy's suspension-line apex (the canopy body's ``riser`` point). Everything is
placed in the descent attitude, every line at its free length, the confluence where the lines' free lengths put it,
all moving straight down at ``speed``. Sizing rules (each written into the file beside its number, and in
``docs/tutorial.md``):

* canopy: reference area S0 = drag area / C_D0 of its type (or from the nominal diameter, S0 = pi D0^2 / 4); mass
  CANOPY_AREAL_MASS x S0 unless given; the inertia of a thin hemispherical shell of the projected radius
  R_p = 0.67 D0 / 2 about its own centre, but the centre of mass (and the aerodynamic centre) at the skirt's centre,
  where the suspension lines of length L_s from the apex end (sqrt(L_s^2 - R_p^2) from it): a simplification, the
  shell's own centre lies R_p / 2 higher; C_N(alpha) the zero-trim canopy table of MER;
* vehicle: a solid cylinder of the given diameter, half as tall, the bridles on a circle of 0.35 diameters on its
  top face;
* lines: stiffness from LINE_STRAIN of stretch under the vehicle's weight in steady descent, damping
  LINE_DAMPING_TIME x stiffness (MER's ratio); the confluence CONFLUENCE_MASS_FRACTION of the vehicle's mass;
* the run: SP, to touchdown on the reference surface; no ``[simulation.steps]``, so each method runs at half its
  stability limit (``simulation.stability_step``).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, fields

import numpy as np

from ..errors import InputError
from ..physics.atmosphere import US76, MarsGRC
from ..physics.cluster import spread_directions, touching_spread
from ..physics.inflation import nominal_diameter
from ..physics.rotations import attitude_angles_deg, attitude_matrix
from .model import Contact

CANOPY_TYPES = {   # C_D0 on S0, subsonic, mid-range of Knacke, Parachute Recovery Systems Design Manual, Table 5-1
    "disk_gap_band": 0.55,
    "ringsail": 0.85,
    "ribbon": 0.50,
    "flat_circular": 0.77,
    "cross": 0.70,
}
PLANETS = {   # name -> (planet table lines, atmosphere model, surface gravity m/s^2 for sizing, density model)
    "mars": (['name = "Mars"', "gravitational_parameter = 4.282828685e13   # m^3/s^2 (MER's, thesis Table 3.3)",
              "equatorial_radius = 3393940.0              # m", "polar_radius = 3376780.0                   # m",
              "rotation_rate = 0.0                        # rad/s"], "mars_grc", 4.282828685e13 / 3393940.0**2,
             MarsGRC),
    "earth": (['name = "Earth"', "gravitational_parameter = 3.986004418e14   # m^3/s^2 (WGS-84)",
               "equatorial_radius = 6378137.0              # m", "polar_radius = 6356752.314                # m",
               "rotation_rate = 0.0                        # rad/s (7.292115e-5 for a rotating Earth)"], "us76",
              3.986004418e14 / 6378137.0**2, US76),
    "flat": (['model = "flat"', "gravity = 9.80665                          # m/s^2"], "us76", 9.80665, US76),
}
MER_DRAG_AREA = 178.47 * 0.46
"""The default canopy's drag area (m^2): MER's parachute, S0 178.47 m^2 at C_A 0.46 (cases/mer/base.toml)."""
CANOPY_AREAL_MASS = 0.15
"""Canopy mass per reference area (kg/m^2) when none is given: canopy cloth, suspension lines and hardware
(assumed; light nylon canopies run about 0.1 to 0.3 kg/m^2)."""
LINE_STRAIN = 0.025
"""Stretch (-) of each line under its share of the vehicle's weight in steady descent (MER's riser: 2.6 %)."""
LINE_DAMPING_TIME = 0.01
"""Line damping / stiffness (s): MER's 470 N s/m on 47 000 N/m."""
CONFLUENCE_MASS_FRACTION = 0.002
"""Confluence mass / vehicle mass (-) when none is given (assumed: links and swivel)."""
COMMENT_COLUMN = 44
"""Column at which the written file's comments start (the hand-written case files' layout)."""
ATTACH_RADIUS = 0.35
"""Bridle attach circle / vehicle diameter (-)."""
NORMAL_COEFFICIENT = ([0.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 90.0],
                      [0.0, 0.040, 0.080, 0.110, 0.130, 0.150, 0.140, 0.110, 0.0])
"""C_N(alpha') of MER's parachute, zero trim (docs/models/mer.md): a stable canopy's restoring force."""


@dataclass(frozen=True)
class NewCase:
    """The choices of a new case; every other number follows from them (module docstring).

    Attributes
    ----------
    planet : {"mars", "earth", "flat"}
        Mars (MER's ellipsoid, NASA GRC atmosphere), Earth (WGS-84, US76) or a flat Earth (9.80665 m/s^2, US76).
    mass : float
        Vehicle mass (kg).
    diameter : float
        Vehicle diameter (m).
    drag_area : float or None
        Each canopy's drag area C_D0 S0 (m^2); give this or ``canopy_diameter``.
    canopy_diameter : float or None
        Each canopy's nominal diameter D0 (m).
    canopy_type : str
        A key of CANOPY_TYPES: its C_D0.
    canopy_mass : float or None
        Each canopy's mass (kg); None: CANOPY_AREAL_MASS x S0.
    canopies : int
        1, or 2 to 8 for a cluster (each canopy its own body and riser, on the cone where they just touch).
    bridles : int
        Bridles from the vehicle to the confluence (1 to 12).
    bridle_length, riser_length, suspension_line_length : float or None
        Free lengths (m); None: the vehicle's diameter, half the canopy's nominal diameter and one nominal diameter.
    altitude : float
        Start altitude of the vehicle's centre of mass (m).
    speed : float or None
        Start descent speed (m/s, down); None: the steady rate of descent at the start altitude.
    name : str
        The case's name.
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

    def __post_init__(self):
        _choice("planet", self.planet, PLANETS)
        _choice("canopy_type", self.canopy_type, CANOPY_TYPES)
        for key in ("mass", "diameter", "drag_area", "canopy_diameter", "canopy_mass", "bridle_length",
                    "riser_length", "suspension_line_length", "altitude"):
            _positive(key, getattr(self, key), optional=key not in ("mass", "diameter", "altitude"),
                      unit=_UNITS.get(key, "m"))
        if self.speed is not None:
            _number("speed", self.speed, self.speed >= 0.0, "must be >= 0 (m/s, downward)")
        if self.drag_area is not None and self.canopy_diameter is not None:
            raise InputError(f"drag_area = {self.drag_area!r} and canopy_diameter = {self.canopy_diameter!r}: give "
                             "one of them, not both")
        _integer("canopies", self.canopies, 1, 8)
        _integer("bridles", self.bridles, 1, 12)
        if self.bridles == 2:
            raise InputError("bridles = 2: two bridles cannot hold the vehicle's attitude; give 1 or 3 to 12")
        if self.bridle_length is not None and self.bridle_length <= ATTACH_RADIUS * self.diameter:
            raise InputError(f"bridle_length = {self.bridle_length!r}: must exceed the attach circle's radius, "
                             f"{ATTACH_RADIUS * self.diameter:g} m (0.35 x diameter)")

    @property
    def reference_area(self) -> float:
        """S0 of each canopy (m^2)."""
        if self.canopy_diameter is not None:
            return math.pi * self.canopy_diameter**2 / 4.0
        drag_area = MER_DRAG_AREA if self.drag_area is None else self.drag_area
        return drag_area / CANOPY_TYPES[self.canopy_type]


def _number(key, value, ok, allowed):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or not ok:
        raise InputError(f"{key} = {value!r}: {allowed}")


_UNITS = {"mass": "kg", "canopy_mass": "kg", "drag_area": "m^2"}


def _positive(key, value, optional, unit):
    if value is None and optional:
        return
    _number(key, value, isinstance(value, (int, float)) and value > 0.0, f"must be a number > 0 ({unit})")


def _integer(key, value, low, high):
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise InputError(f"{key} = {value!r}: must be a whole number from {low} to {high}")


def _choice(key, value, table):
    if value not in table:
        raise InputError(f"{key} = {value!r}: must be one of: {', '.join(table)}")


@dataclass(frozen=True)
class _Layout:
    """Sizes and positions (m, kg, N/m; altitudes above the reference surface) derived from the choices."""

    choices: NewCase
    gravity: float
    reference_area: float
    canopy_mass: float
    confluence_mass: float
    bridle_length: float
    riser_length: float
    apex_distance: float    # canopy centre of mass to its riser point (m)
    projected_radius: float

    @property
    def total_mass(self) -> float:
        c = self.choices
        return c.mass + c.canopies * self.canopy_mass + self.confluence_mass

    def steady_rate(self, altitude: float) -> float:
        """The closed-form steady rate of descent (m/s), sqrt(2 m g / (rho C_D S)) with m the suspended mass and
        rho at ``altitude`` (m)."""
        density = PLANETS[self.choices.planet][3]().density(altitude)
        drag_area = self.choices.canopies * CANOPY_TYPES[self.choices.canopy_type] * self.reference_area
        return math.sqrt(2.0 * self.total_mass * self.gravity / (density * drag_area))


def layout(choices: NewCase) -> _Layout:
    """The sizes (m, m^2, kg) the choices imply (module docstring); InputError where they cannot be built."""
    area = choices.reference_area
    nominal = nominal_diameter(area)
    canopy_mass = CANOPY_AREAL_MASS * area if choices.canopy_mass is None else choices.canopy_mass
    radius = Contact().projected_radius(area)   # the cluster contact model's envelope (0.67 D0 / 2)
    line = choices.suspension_line_length or nominal
    if line <= radius:
        raise InputError(f"suspension_line_length = {line!r}: must exceed the canopy's projected radius, {radius:g} m")
    plan = _Layout(choices, PLANETS[choices.planet][2], area, canopy_mass, CONFLUENCE_MASS_FRACTION * choices.mass,
                   choices.bridle_length or choices.diameter, choices.riser_length or 0.5 * nominal,
                   math.sqrt(line**2 - radius**2), radius)
    try:
        rate = plan.steady_rate(choices.altitude)
    except (ValueError, ZeroDivisionError):   # outside the model's range, or no air left
        rate = math.nan
    if not (math.isfinite(rate) and rate > 0.0):
        raise InputError(f"altitude = {choices.altitude!r}: outside the {PLANETS[choices.planet][1]} atmosphere "
                         "(no finite air density there); start lower")
    circle = radius if choices.canopies == 2 else radius / math.sin(math.pi / max(choices.canopies, 2))
    if choices.canopies > 1 and circle >= plan.riser_length + plan.apex_distance:
        raise InputError(f"canopies = {choices.canopies}: their envelopes (radius {radius:.3g} m) cannot sit side by "
                         f"side on risers that reach {plan.riser_length + plan.apex_distance:.3g} m; lengthen "
                         "riser_length or suspension_line_length")
    return plan


def _choices(choices: NewCase | None, kwargs: dict) -> NewCase:
    if choices is not None and kwargs:
        raise InputError(f"give a NewCase or its fields as keywords, not both (keywords: {', '.join(kwargs)})")
    return choices if choices is not None else NewCase(**kwargs)


def new_case_text(choices: NewCase | None = None, **kwargs) -> str:
    """The case file (TOML text) for ``choices`` (a NewCase, or its fields as keywords)."""
    choices = _choices(choices, kwargs)
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
    from .loader import build_case, tomllib

    choices = _choices(choices, kwargs)
    return build_case(tomllib.loads(new_case_text(choices)), {}, f"new_case({choices.name!r})")


def choice_fields() -> list:
    """The NewCase fields (name, default) in order, for the command line."""
    defaults = asdict(NewCase())
    return [(f.name, defaults[f.name]) for f in fields(NewCase)]


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
        self.height = 0.5 * c.diameter                      # the vehicle cylinder's height (m)
        self.attach_radius = ATTACH_RADIUS * c.diameter
        self.rise = math.sqrt(plan.bridle_length**2 - self.attach_radius**2) if c.bridles > 1 else plan.bridle_length
        self.confluence_altitude = c.altitude + 0.5 * self.height + self.rise
        self.speed = plan.steady_rate(c.altitude) if c.speed is None else c.speed

    def lines(self) -> list:
        return self.header() + self.vehicle() + self.canopies() + self.system() + self.simulation()

    def header(self) -> list:
        c, p = self.c, self.plan
        rate = "the steady rate there" if c.speed is None else "as chosen"
        planet_lines, atmosphere = PLANETS[c.planet][:2]
        return [f"# {c.name}: written by `pchute new` (pchute_exudyn.case.new; docs/tutorial.md). Units SI;",
                "# angles in degrees only where named _deg. Every line starts at its free length, the confluence",
                f"# where the lines' free lengths put it, everything moving down at {_n(self.speed)} m/s ({rate}).",
                f"# Suspended mass {_n(p.total_mass)} kg; steady rate of descent sqrt(2 m g / (rho C_D S)) = "
                f"{p.steady_rate(c.altitude):.3f} m/s at the start, {p.steady_rate(0.0):.3f} m/s at 0 m.",
                "# Reported altitudes are each body's centre of mass (`vehicle_altitude`: the vehicle's); the canopy's",
                f"# drag acts {_n(self.canopy_height())} m higher, at its aerodynamic centre "
                f"(`{self.canopy_names()[0]}_altitude`).", "",
                "[case]", f"name = {json.dumps(c.name)}",
                f'description = "{c.mass:g} kg vehicle under {self.canopy_words()} ({c.planet})"',
                'vehicle = "vehicle"', "", "[planet]", *planet_lines, "",
                "[start]                                    # the start point", "latitude_deg = 0.0",
                "longitude_deg = 0.0", "", "[atmosphere]", f'model = "{atmosphere}"', ""]

    def canopy_words(self) -> str:
        c = self.c
        kind = c.canopy_type.replace("_", "-")
        return f"a {kind} canopy" if c.canopies == 1 else f"a cluster of {c.canopies} {kind} canopies"

    def canopy_height(self) -> float:
        """Vehicle centre of mass to a canopy's centre of mass, vertically (m)."""
        return self.confluence_altitude - self.c.altitude + self.canopy_reach() * math.cos(self.spread())

    def canopy_reach(self) -> float:
        """Confluence to a canopy's centre (m): its riser and the apex-to-centre distance."""
        return self.plan.riser_length + self.plan.apex_distance

    def spread(self) -> float:
        """The cluster cone's half-angle (rad): the canopies' envelopes just touch."""
        return touching_spread(self.plan.projected_radius, self.canopy_reach(), self.c.canopies)

    def vehicle(self) -> list:
        c = self.c
        radius = 0.5 * c.diameter
        axial, lateral = c.mass * radius**2 / 2.0, c.mass * (3.0 * radius**2 + self.height**2) / 12.0
        rows = ["[bodies.vehicle]                           # a solid cylinder, half as tall as its diameter",
                f"mass = {_n(c.mass)}                             # kg",
                f"inertia = {_vector([axial, lateral, lateral])}   # kg m^2, principal, body axes",
                "[bodies.vehicle.points]                    # m, body axes from the centre of mass (+x down): "
                "the bridles' attach points"]
        for i, point in enumerate(self.attach_points(), start=1):
            rows.append(f"bridle{i} = {_vector(point)}")
        rows += ["[bodies.vehicle.initial]                   # attitude: body +x down (the descent attitude)",
                 f"altitude = {_n(c.altitude)}                        # m: the centre of mass",
                 f"velocity_down = {_n(self.speed)}                  # m/s", ""]
        return rows

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
        axial = 2.0 / 3.0 * p.canopy_mass * p.projected_radius**2
        lateral = 5.0 / 12.0 * p.canopy_mass * p.projected_radius**2
        up = np.array([-1.0, 0.0, 0.0])    # descent frame (x down, y east, z south)
        directions = spread_directions(-up, np.array([0.0, 1.0, 0.0]), self.spread(), c.canopies)
        confluence = np.array([-self.confluence_altitude, 0.0, 0.0])
        rows = []
        for name, toward_confluence in zip(self.canopy_names(), directions):
            centre = confluence - self.canopy_reach() * toward_confluence
            yaw, pitch, roll = self.attitude(toward_confluence)
            rows += [f"[bodies.{name}]                            # {c.canopy_type}: a hemispherical shell of the "
                     "projected radius",
                     f"mass = {_n(p.canopy_mass)}                           # kg"
                     + (" (0.15 kg per m^2 of S0, assumed)" if c.canopy_mass is None else ""),
                     f"inertia = {_vector([axial, lateral, lateral])}   # kg m^2",
                     f"points.riser = [{_n(p.apex_distance)}, 0.0, 0.0]   # m: the suspension lines' apex, "
                     f"{_n(c.suspension_line_length or nominal_diameter(p.reference_area))} m lines to the "
                     "skirt", f"[bodies.{name}.initial]",
                     f"altitude = {_n(-centre[0])}                  # m",
                     *([] if c.canopies == 1 else [f"east = {_n(centre[1])}", f"north = {_n(-centre[2])}",
                                                   f"yaw_deg = {_n(yaw)}", f"pitch_deg = {_n(pitch)}",
                                                   f"roll_deg = {_n(roll)}"]),
                     f"velocity_down = {_n(self.speed)}", *self.aerodynamics(name), ""]
        return rows

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
                f"axial_coefficient = {CANOPY_TYPES[c.canopy_type]}                  # C_D0 of a {c.canopy_type} "
                "(Knacke, Table 5-1, mid-range)",
                "center = [0.0, 0.0, 0.0]                   # m: at the centre of mass",
                f"[bodies.{name}.aerodynamics.normal_coefficient]   # MER's zero-trim canopy table; optional "
                "(absent: C_N = 0)", f"alpha_deg = {alpha}", f"value = {value}"]

    def system(self) -> list:
        c, p = self.c, self.plan
        weight = c.mass * p.gravity
        bridle_tension = weight / max(c.bridles, 1) * (p.bridle_length / self.rise)
        riser_tension = (weight + p.confluence_mass * p.gravity) / c.canopies / math.cos(self.spread())
        rows = ["[systems.main]", f"canopies = {self.canopy_names()}".replace("'", '"') if c.canopies > 1
                else 'canopy = "canopy"', "[systems.main.confluence]",
                f"mass = {_n(p.confluence_mass)}                            # kg (0.2 % of the vehicle's, assumed)",
                "[systems.main.confluence.initial]", f"altitude = {_n(self.confluence_altitude)}   # m: where the "
                "bridles' free lengths put it", f"velocity_down = {_n(self.speed)}", ""]
        for i in range(1, c.bridles + 1):
            rows += self.line(f"bridle{i}", f"vehicle.bridle{i}", p.bridle_length, bridle_tension)
        for name in self.canopy_names():
            rows += self.line(f"riser_{name}" if c.canopies > 1 else "riser", f"{name}.riser", p.riser_length,
                              riser_tension)
        return rows

    @staticmethod
    def line(name: str, attach: str, length: float, tension: float) -> list:
        """A line's table: free ``length`` (m), stiffness from LINE_STRAIN under ``tension`` (N)."""
        stiffness = tension / (LINE_STRAIN * length)
        return [f"[systems.main.lines.{name}]", f'attach = "{attach}"', f"free_length = {_n(length)}   # m",
                f"stiffness = {_n(stiffness)}   # N/m: 2.5 % stretch under its share of the vehicle's weight",
                f"damping = {_n(LINE_DAMPING_TIME * stiffness)}   # N s/m: 0.01 s x stiffness", ""]

    def simulation(self) -> list:
        c, p = self.c, self.plan
        duration = 10.0 * math.ceil((1.25 * c.altitude / p.steady_rate(0.0) + 10.0) / 10.0)
        return ["[simulation]", f"duration = {_n(duration)}   # s: an upper bound; the run ends at touchdown "
                "(the vehicle's centre of mass at 0 m)", "output_step = 0.02                         # s",
                'method = "sp"', 'integrator = "rk4"',
                "# No [simulation.steps]: each method runs at half its stability limit, rounded down (printed in "
                "the run", "# line); set e.g. `sp = 0.01` under [simulation.steps] to fix a step."]

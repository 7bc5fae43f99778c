"""``pchute new --dual-deploy``: a rocket's dual-deploy recovery from a state over the ground, as one case file's
lines (``dual_deploy_lines``; its choices and start: ``authoring.rocket_start``).

The rocket is a slender cylinder of the given length and diameter, its body +x the symmetry axis toward the nose.
Two systems ride packed in it (``packed = true``), each one bridle from the rocket's harness to a confluence and one
riser to its canopy, the canopies flown reduced (``canopy_model = "reduced"``: a light canopy as a massless drag
point at its riser's end; docs/models/reduced_canopy.md): the drogue deploys on an apogee trigger (sampled at
TRIGGER_RATE, after ``apogee_lag``), the main on a barometric trigger at ``main_height`` above the ground, and the
drogue is cut away when the main deploys (as RocketPy, where a second parachute's C_D S replaces the first's). The
rocket's stated mass, centre of mass and inertia include the packed gear (``mass_includes_packed``).
Sizing rules, each written beside its number:

* rocket: a solid cylinder, uniform (``physics.shapes.solid_cylinder_inertia``; a rocket's mass sits nearer its
  skin, so its axial inertia is larger); the harness HARNESS_FRACTION of the length aft of the centre of mass;
  bridle BRIDLE_FRACTION and riser RISER_FRACTION of the length unless given;
* canopies: as ``pchute new``'s (authoring.descent): S0 = C_D0 S0 / C_D0 of the canopy type, a hemispherical shell's
  inertia, CANOPY_AREAL_MASS x S0 unless a mass is given; lines stretched LINE_STRAIN under the rocket's weight;
* the start: position (latitude, longitude, altitude or height above the ground), velocity over the ground
  (``[start] velocities_relative_to = "ground"``: east, north, up) and the nose's pitch and heading.
"""

from __future__ import annotations

import json
import math

from ..case.model import Contact
from ..errors import InputError
from ..physics.inflation import nominal_diameter
from ..physics.shapes import hemispherical_shell_inertia, solid_cylinder_inertia
from ..registries.canopy_types import CANOPY_TYPES
from .planets import PLANETS, gravity_at
from .rocket_start import ground, nose_attitude_deg, nose_direction, start_altitude, start_height
from .rules import (
    AXIAL_FLAT_TO_DEG,
    CANOPY_AREAL_MASS,
    CONFLUENCE_MASS_FRACTION,
    LINE_DAMPING_TIME,
    LINE_STRAIN,
    NORMAL_COEFFICIENT,
)
from .text import number as _n
from .text import vector as _vector

TRIGGER_RATE = 100.0
"""Both triggers' sampling rate (Hz): RocketPy's usual 100 Hz."""
HARNESS_FRACTION = 0.12
"""The shock cords' harness aft of the centre of mass, as a fraction of the rocket's length (-, assumed)."""
BRIDLE_FRACTION = 0.4
"""A system's bridle (shock cord from the harness) per rocket length (-, assumed: 1 m on a 2.5 m rocket)."""
RISER_FRACTION = 2.0
"""A system's riser (confluence to the canopy) per rocket length (-, assumed: 5 m on a 2.5 m rocket)."""


def steady_rate(c, drag_area: float, altitude: float) -> float:
    """The rocket's steady rate of descent (m/s) under a drag area (m^2) at ``altitude`` (m): sqrt(2 m g / (rho
    C_D S)), m the rocket's mass (gear included), g the planet's surface gravity."""
    gravity, atmosphere = gravity_at(c.planet, c.latitude or 0.0, altitude), PLANETS[c.planet][3]
    return math.sqrt(2.0 * c.mass * gravity / (atmosphere().density(altitude) * drag_area))


def dual_deploy_lines(c) -> list:
    """The dual-deploy case file's lines (module docstring) for a checked NewCase ``c`` (the two-section form:
    ``authoring.two_section``)."""
    return header_lines(c) + _rocket(c) + canopy_lines(c, "drogue") + canopy_lines(c, "main") \
        + _system(c, "drogue") + _system(c, "main") + simulation_lines(c)


def _sizes(c, which: str) -> tuple:
    """(S0 (m^2), mass (kg), projected radius (m), apex distance (m)) of the ``which`` canopy."""
    drag_coefficient = CANOPY_TYPES[c.canopy_type].drag_coefficient if c.drag_coefficient is None \
        else c.drag_coefficient
    area = getattr(c, f"{which}_drag_area") / drag_coefficient
    mass = getattr(c, f"{which}_mass")
    radius = Contact().projected_radius(area)
    lines = c.suspension_line_length or nominal_diameter(area)
    if lines <= radius:
        raise InputError(f"suspension_line_length = {lines!r}: must exceed the {which} canopy's projected radius, "
                         f"{radius:g} m")
    return area, CANOPY_AREAL_MASS * area if mass is None else mass, radius, math.sqrt(lines**2 - radius**2)


def header_lines(c) -> list:
    planet_lines, atmosphere = PLANETS[c.planet][:2]
    nose = nose_direction(c)
    drogue = steady_rate(c, c.drogue_drag_area, ground(c))
    main = steady_rate(c, c.main_drag_area, ground(c))
    return [f"# {c.name}: a rocket's dual deploy, written by `pchute new --dual-deploy` (pchute_exudyn.authoring."
            "rocket; docs/tutorial.md).", "# Units SI; angles in degrees only where named _deg.",
            f"# Start {_n(start_height(c))} m above a ground at {_n(ground(c))} m, velocity over the ground east "
            f"{_n(c.velocity_east or 0.0)}, north {_n(c.velocity_north or 0.0)}, up {_n(c.velocity_up or 0.0)} m/s, "
            f"nose {math.degrees(math.asin(nose[2])):.4g} deg above the horizontal.",
            f"# Drogue (C_D S {_n(c.drogue_drag_area)} m^2) on an apogee trigger at {TRIGGER_RATE:g} Hz, "
            f"{_n(c.apogee_lag)} s lag; main (C_D S {_n(c.main_drag_area)} m^2) at {_n(c.main_height)} m above the "
            + ("ground, the drogue cut away then." if c.shock_cord_length is None else
               f"ground; the nose cone ejected at apogee on a {_n(c.shock_cord_length)} m shock cord, both canopies on "
               "its harness, opening by their type's fill law (authoring.two_section)."),
            f"# Steady rates at the ground: {drogue:.2f} m/s under the drogue, "
            f"{main:.2f} m/s under the main (sqrt(2 m g / (rho C_D S)), m = {_n(c.mass)} kg).", "",
            "[case]", f"name = {json.dumps(c.name)}",
            f'description = "{c.mass:g} kg rocket: drogue at apogee, main at {c.main_height:g} m above the ground"',
            f'vehicle = "{"booster" if c.shock_cord_length is not None else "rocket"}"', "", "[planet]", *planet_lines,
            "",
            "[start]", f"latitude_deg = {_n(c.latitude or 0.0)}", f"longitude_deg = {_n(c.longitude or 0.0)}",
            'velocities_relative_to = "ground"          # the initial velocities are over the ground', "",
            "[atmosphere]", f'model = "{atmosphere}"', *_wind(c), ""]


def _wind(c) -> list:
    if c.wind_speed == 0.0:
        return ["# [atmosphere.wind] (none): e.g. speed = 6.0 and from_deg = 270.0 for a 6 m/s west wind"]
    return ["[atmosphere.wind]                          # constant with altitude",
            f"speed = {_n(c.wind_speed)}   # m/s",
            f"from_deg = {_n(c.wind_from_deg)}   # deg: where it comes from, clockwise from north"]


def _rocket(c) -> list:
    harness = -HARNESS_FRACTION * c.length
    bridle = c.bridle_length or BRIDLE_FRACTION * c.length
    yaw, pitch, roll = nose_attitude_deg(nose_direction(c))
    return ["[bodies.rocket]                            # a solid cylinder, body +x its axis toward the nose",
            f"mass = {_n(c.mass)}   # kg, its packed recovery gear included",
            "mass_includes_packed = true                # mass, centre of mass, inertia, points: with the gear aboard",
            f"inertia = {_vector(solid_cylinder_inertia(c.mass, c.diameter, c.length))}   # kg m^2: m r^2 / 2 about "
            f"its axis, m (3 r^2 + L^2) / 12 across ({_n(c.diameter)} m by {_n(c.length)} m)",
            "[bodies.rocket.points]                     # m, body axes from the centre of mass",
            f"harness = [{_n(harness)}, 0.0, 0.0]   # where both shock cords attach",
            f"line_stretch = [{_n(harness - bridle)}, 0.0, 0.0]   # a confluence at deployment: a bridle's length "
            "aft",
            "[bodies.rocket.initial]                    # the start state, over the ground",
            f"altitude = {_n(start_altitude(c))}   # m: the centre of mass, {_n(start_height(c))} m above the ground",
            f"velocity_east = {_n(c.velocity_east or 0.0)}   # m/s", f"velocity_north = {_n(c.velocity_north or 0.0)}"
            "   # m/s", f"velocity_down = {_n(-(c.velocity_up or 0.0))}   # m/s",
            f"yaw_deg = {_n(yaw)}   # the nose: pitch {_n(c.nose_pitch_deg or 0.0)} deg, heading "
            f"{_n(math.degrees(math.atan2(*nose_direction(c)[:2])) % 360.0)} deg", f"pitch_deg = {_n(pitch)}",
            f"roll_deg = {_n(roll)}", ""]


def canopy_lines(c, which: str) -> list:
    area, mass, radius, apex = _sizes(c, which)
    drag_coefficient = getattr(c, f"{which}_drag_area") / area
    alpha, value = NORMAL_COEFFICIENT
    name = f"{which}_canopy"
    return [f"[bodies.{name}]   # {c.canopy_type}, C_D0 S0 = {_n(getattr(c, f'{which}_drag_area'))} m^2: a "
            "hemispherical shell of the projected radius",
            f"mass = {_n(mass)}   # kg" + (f" ({CANOPY_AREAL_MASS:g} kg per m^2 of S0, assumed)"
                                           if getattr(c, f"{which}_mass") is None else ""),
            f"inertia = {_vector(hemispherical_shell_inertia(mass, radius))}   # kg m^2: (2/3) m R_p^2, (5/12) m "
            f"R_p^2, R_p = {radius:.4f} m",
            f"points.riser = [{_n(apex)}, 0.0, 0.0]   # m: the suspension lines' apex",
            f"[bodies.{name}.aerodynamics]", f"reference_area = {_n(area)}   # m^2: S0, D0 = "
            f"{nominal_diameter(area):.4f} m",
            f"axial_coefficient = {{ alpha_deg = [0.0, {AXIAL_FLAT_TO_DEG}, 90.0], value = [{_n(drag_coefficient)}, "
            f"{_n(drag_coefficient)}, 0.0] }}", "center = [0.0, 0.0, 0.0]   # m: at the centre of mass",
            f"normal_coefficient = {{ alpha_deg = {alpha}, value = {value} }}", ""]


def _system(c, which: str) -> list:
    trigger = (f'deploy_trigger = {{ quantity = "apogee", rate = {_n(TRIGGER_RATE)}, lag = {_n(c.apogee_lag)} }}'
               "   # after the first sample past apogee" if which == "drogue" else
               f'deploy_trigger = {{ quantity = "altitude", below = {_n(c.main_height)}, reference = "ground", '
               f"rate = {_n(TRIGGER_RATE)} }}   # m above the ground")
    rows = [f"[systems.{which}]", f'canopy = "{which}_canopy"',
            'canopy_model = "reduced"   # a light canopy: a drag point at the riser\'s end (docs/models/'
            "reduced_canopy.md)", "packed = true   # its canopy and confluence ride in the rocket until it deploys",
            'deploy_point = "rocket.line_stretch"', trigger]
    if which == "drogue":
        rows.append('cutaway_trigger = { after = "main.deploy" }   # cut away when the main deploys (RocketPy: the '
                    "main's C_D S replaces the drogue's)")
    rows += [f"[systems.{which}.confluence]", f"mass = {_n(CONFLUENCE_MASS_FRACTION * c.mass)}   # kg (0.2 % of the "
             "rocket's, assumed)"]
    return rows + line_rows(c, which, "rocket.harness") + [""]


def line_rows(c, which: str, harness: str) -> list:
    """The ``which`` system's bridle from ``harness`` ("<body>.<point>") and riser to its canopy: lengths as given
    or BRIDLE_FRACTION and RISER_FRACTION of the rocket's, stiffness for LINE_STRAIN under the rocket's weight,
    damping LINE_DAMPING_TIME x stiffness."""
    weight = c.mass * gravity_at(c.planet, c.latitude or 0.0, ground(c))
    rows = []
    for line, attach, free in (("bridle", harness, c.bridle_length or BRIDLE_FRACTION * c.length),
                               ("riser", f"{which}_canopy.riser", c.riser_length or RISER_FRACTION * c.length)):
        stiffness = weight / (LINE_STRAIN * free)
        rows += [f"[systems.{which}.lines.{line}]", f'attach = "{attach}"', f"free_length = {_n(free)}   # m",
                 f"stiffness = {_n(stiffness)}   # N/m: {LINE_STRAIN:.1%} stretch under the rocket's weight",
                 f"damping = {_n(LINE_DAMPING_TIME * stiffness)}   # N s/m: {LINE_DAMPING_TIME:g} s x stiffness"]
    return rows


def simulation_lines(c) -> list:
    drogue_time = (start_height(c) - c.main_height) / steady_rate(c, c.drogue_drag_area, ground(c))
    main_time = c.main_height / steady_rate(c, c.main_drag_area, ground(c))
    climb = max(c.velocity_up or 0.0, 0.0) / gravity_at(c.planet, c.latitude or 0.0, ground(c))
    duration = 10.0 * math.ceil((1.25 * (drogue_time + main_time) + 2.0 * climb + c.apogee_lag + 20.0) / 10.0)
    return ["[simulation]", f"duration = {_n(duration)}   # s: an upper bound; the run ends at touchdown",
            "output_step = 0.05                         # s", f"ground_altitude = {_n(ground(c))}   # m",
            'method = "sp"', 'integrator = "rk4"',
            "# No [simulation.steps]: adaptive steps (docs/models/step_control.md); e.g. `sp = 0.01` there fixes one."]

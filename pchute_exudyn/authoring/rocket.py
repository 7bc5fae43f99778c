"""``pchute new --dual-deploy``: a rocket's dual-deploy recovery from a state over the ground, as one case file's
lines (``dual_deploy_lines``; its choices and start: ``authoring.rocket_start``).

The rocket is a slender cylinder of the given length and diameter, its body +x the symmetry axis toward the nose.
Two systems ride packed in it (``packed = true``), each one bridle from the rocket's harness to a confluence and one
riser to its canopy, the canopies flown reduced (``canopy_model = "reduced"``: a light canopy as a massless drag
point at its riser's end; docs/models/reduced_canopy.md): the drogue deploys on an apogee trigger (sampled at
TRIGGER_RATE, after ``apogee_lag``), the main on a barometric trigger at ``main_height`` above the ground (after
``main_lag``, opening over ``main_opening_time`` if given), and the drogue stays on its harness to touchdown
(``drogue_after_main`` attached) or is cut away when the main deploys (cut: as RocketPy, where a second parachute's
C_D S replaces the first's). The rocket's own drag as it hangs (``body_drag`` on) is a slender cylinder's at every
angle of attack (``physics.slender_body``; docs/models/slender_body.md), written as its aerodynamics tables. Each
canopy is sized by two of its drag area, diameter and C_D (``rocket_start.canopy_drag``). The rocket's stated mass,
centre of mass and inertia include the packed gear (``mass_includes_packed``).
Sizing rules, each written beside its number:

* rocket: a solid cylinder, uniform (``physics.shapes.solid_cylinder_inertia``; a rocket's mass sits nearer its
  skin, so its axial inertia is larger); the harness ``harness_offset`` aft of the centre of mass, else
  HARNESS_FRACTION of the length;
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
from ..physics.inflation import Inflation, InflationStage, nominal_diameter
from ..physics.shapes import hemispherical_shell_inertia, solid_cylinder_inertia
from ..physics.slender_body import (
    axial_coefficient,
    axial_coefficients,
    crossflow_normal_coefficient,
    finite_length_factor,
)
from ..registries.canopy_types import CANOPY_TYPES
from .planets import PLANETS, gravity_at
from .rocket_start import canopy_drag, ground, nose_attitude_deg, nose_direction, start_altitude, start_height
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
BODY_ANGLES_DEG = tuple(5.0 * k for k in range(37))
"""The total angles of attack (deg) at which the body's coefficients are tabulated: 0 to 180 in 5 deg steps (the
engine interpolates linearly between them)."""
OPENING_POINTS = 8
"""Intervals of the main's opening schedule (``main_opening_time``): the fill law (t / t_o)^j at 9 points."""


def steady_rate(c, drag_area: float, altitude: float) -> float:
    """The rocket's steady rate of descent (m/s) under a drag area (m^2) at ``altitude`` (m): sqrt(2 m g / (rho
    C_D S)), m the rocket's mass (gear included), g the planet's surface gravity."""
    gravity, atmosphere = gravity_at(c.planet, c.latitude or 0.0, altitude), PLANETS[c.planet][3]
    return math.sqrt(2.0 * c.mass * gravity / (atmosphere().density(altitude) * drag_area))


def drag_area(c, which: str) -> float:
    """The ``which`` canopy's C_D S (m^2; ``rocket_start.canopy_drag``)."""
    return canopy_drag(c, which)[0]


def main_phase_drag_area(c) -> float:
    """C_D S (m^2) the rocket hangs under once the main is open: the main's, and the drogue's unless it is cut
    away."""
    return drag_area(c, "main") + (drag_area(c, "drogue") if c.drogue_after_main == "attached" else 0.0)


def dual_deploy_lines(c) -> list:
    """The dual-deploy case file's lines (module docstring) for a checked NewCase ``c`` (the two-section form:
    ``authoring.two_section``)."""
    return header_lines(c) + _rocket(c) + canopy_lines(c, "drogue") + canopy_lines(c, "main") \
        + _system(c, "drogue") + _system(c, "main") + simulation_lines(c)


def _sizes(c, which: str) -> tuple:
    """(S0 (m^2), mass (kg), projected radius (m), apex distance (m)) of the ``which`` canopy."""
    area = canopy_drag(c, which)[1]
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
    drogue = steady_rate(c, drag_area(c, "drogue"), ground(c))
    main = steady_rate(c, main_phase_drag_area(c), ground(c))
    return [f"# {c.name}: a rocket's dual deploy, written by `pchute new --dual-deploy` (pchute_exudyn.authoring."
            "rocket; docs/tutorial.md).", "# Units SI; angles in degrees only where named _deg.",
            f"# Start {_n(start_height(c))} m above a ground at {_n(ground(c))} m, velocity over the ground east "
            f"{_n(c.velocity_east or 0.0)}, north {_n(c.velocity_north or 0.0)}, up {_n(c.velocity_up or 0.0)} m/s, "
            f"nose {math.degrees(math.asin(nose[2])):.4g} deg above the horizontal.",
            f"# Drogue (C_D S {_n(drag_area(c, 'drogue'))} m^2) on an apogee trigger at {TRIGGER_RATE:g} Hz, "
            f"{_n(c.apogee_lag)} s lag; main (C_D S {_n(drag_area(c, 'main'))} m^2) at {_n(c.main_height)} m above "
            + _harness_words(c),
            f"# Steady rates at the ground: {drogue:.2f} m/s under the drogue, {main:.2f} m/s under the main"
            + (" and the drogue" if c.drogue_after_main == "attached" else "")
            + f" (sqrt(2 m g / (rho C_D S)), m = {_n(c.mass)} kg).", *_body_drag_words(c), "",
            "[case]", f"name = {json.dumps(c.name)}",
            f'description = "{c.mass:g} kg rocket: drogue at apogee, main at {c.main_height:g} m above the ground"',
            f'vehicle = "{"booster" if c.shock_cord_length is not None else "rocket"}"', "", "[planet]", *planet_lines,
            "",
            "[start]", f"latitude_deg = {_n(c.latitude or 0.0)}", f"longitude_deg = {_n(c.longitude or 0.0)}",
            'velocities_relative_to = "ground"          # the initial velocities are over the ground', "",
            "[atmosphere]", f'model = "{atmosphere}"', *_wind(c), ""]


def _harness_words(c) -> str:
    """The header's words on the main's deployment and what becomes of the drogue then."""
    lag = "" if c.main_lag == 0.0 else f" (after a {_n(c.main_lag)} s lag)"
    if c.shock_cord_length is None:
        return f"the ground{lag}, the drogue " + ("cut away then." if c.drogue_after_main == "cut" else
                                                  "staying on its harness.")
    return (f"the ground{lag}; the nose cone ejected at apogee on a {_n(c.shock_cord_length)} m shock cord, both "
            "canopies on its harness, opening by their type's fill law (authoring.two_section)"
            + (", the drogue cut away when the main deploys." if c.drogue_after_main == "cut" else "."))


def _body_drag_words(c) -> list:
    if c.body_drag == "off":
        return []
    area = math.pi * c.diameter**2 / 4.0
    nose_first, tail_first = axial_coefficients(c.length, c.diameter)
    broadside = crossflow_normal_coefficient(90.0, c.length, c.diameter)
    return [f"# The body's own drag (a slender cylinder's cross flow, physics.slender_body): C_D S "
            f"{area * nose_first:.4g} m^2 nose first, {area * tail_first:.4g} m^2 tail first, "
            f"{area * broadside:.4g} m^2 broadside."]


def _wind(c) -> list:
    if c.wind_speed == 0.0:
        return ["# [atmosphere.wind] (none): e.g. speed = 6.0 and from_deg = 270.0 for a 6 m/s west wind"]
    return ["[atmosphere.wind]                          # constant with altitude",
            f"speed = {_n(c.wind_speed)}   # m/s",
            f"from_deg = {_n(c.wind_from_deg)}   # deg: where it comes from, clockwise from north"]


def _rocket(c) -> list:
    harness = -(HARNESS_FRACTION * c.length if c.harness_offset is None else c.harness_offset)
    bridle = c.bridle_length or BRIDLE_FRACTION * c.length
    yaw, pitch, roll = nose_attitude_deg(nose_direction(c))
    return ["[bodies.rocket]                            # a solid cylinder, body +x its axis toward the nose",
            f"mass = {_n(c.mass)}   # kg, its packed recovery gear included",
            "mass_includes_packed = true                # mass, centre of mass, inertia, points: with the gear aboard",
            f"inertia = {_vector(solid_cylinder_inertia(c.mass, c.diameter, c.length))}   # kg m^2: m r^2 / 2 about "
            f"its axis, m (3 r^2 + L^2) / 12 across ({_n(c.diameter)} m by {_n(c.length)} m)",
            "[bodies.rocket.points]                     # m, body axes from the centre of mass",
            f"harness = [{_n(harness)}, 0.0, 0.0]   # where both shock cords attach",
            *_deploy_point(c, harness, bridle),
            "[bodies.rocket.initial]                    # the start state, over the ground",
            f"altitude = {_n(start_altitude(c))}   # m: the centre of mass, {_n(start_height(c))} m above the ground",
            f"velocity_east = {_n(c.velocity_east or 0.0)}   # m/s", f"velocity_north = {_n(c.velocity_north or 0.0)}"
            "   # m/s", f"velocity_down = {_n(-(c.velocity_up or 0.0))}   # m/s",
            f"yaw_deg = {_n(yaw)}   # the nose: pitch {_n(c.nose_pitch_deg or 0.0)} deg, heading "
            f"{_n(math.degrees(math.atan2(*nose_direction(c)[:2])) % 360.0)} deg", f"pitch_deg = {_n(pitch)}",
            f"roll_deg = {_n(roll)}", *body_drag_rows(c, "rocket", c.length), ""]


def body_drag_rows(c, body: str, length: float) -> list:
    """``body``'s aerodynamics as it hangs (``body_drag`` on): a cylinder ``length`` (m) by the rocket's diameter in
    cross flow at every angle of attack (physics.slender_body), its force at the planform's centroid."""
    if c.body_drag == "off":
        return []
    nose_first, tail_first = axial_coefficients(length, c.diameter)
    angles = [_n(a) for a in BODY_ANGLES_DEG]
    axial = [_n(axial_coefficient(a, length, c.diameter)) for a in BODY_ANGLES_DEG]
    normal = [_n(crossflow_normal_coefficient(a, length, c.diameter)) for a in BODY_ANGLES_DEG]
    return [f"[bodies.{body}.aerodynamics]   # its own drag as it hangs: a slender cylinder's cross flow (docs/models/"
            "slender_body.md)", f"reference_area = {_n(math.pi * c.diameter**2 / 4.0)}   # m^2: pi d^2 / 4",
            "center = [0.0, 0.0, 0.0]   # m: the planform's centroid, the uniform cylinder's centre of mass",
            f"[bodies.{body}.aerodynamics.axial_coefficient]   # C_A,0 {nose_first:.4g} nose first, C_A,180 "
            f"{tail_first:.4g} tail first (Hoerner 1965), on q cos^2(alpha)",
            f"alpha_deg = [{', '.join(angles)}]", f"value = [{', '.join(axial)}]",
            f"[bodies.{body}.aerodynamics.normal_coefficient]   # Jorgensen (NASA TR R-474): eta "
            f"{finite_length_factor(length, c.diameter):.4g} at this L/d, C_dc 1.2"
            , f"alpha_deg = [{', '.join(angles)}]", f"value = [{', '.join(normal)}]"]


def _deploy_point(c, harness: float, bridle: float) -> list:
    """The systems' deploy point, where their packed gear rides: a bridle's length aft of the harness, or with
    ``harness_offset`` given, the harness itself (the bags packed at the joint the harness is on), so that the gear
    leaving moves the centre of mass no further from the lines than the offset (at 0: the lines, the gear and the
    body's cross flow all act at the centre of mass, and the rocket keeps its attitude)."""
    if c.harness_offset is None:
        return [f"line_stretch = [{_n(harness - bridle)}, 0.0, 0.0]   # a confluence at deployment: a bridle's "
                "length aft"]
    return [f"line_stretch = [{_n(harness)}, 0.0, 0.0]   # the bags ride at the harness: a confluence at deployment "
            "there, its bridle slack"]


def canopy_lines(c, which: str) -> list:
    area, mass, radius, apex = _sizes(c, which)
    drag_coefficient = drag_area(c, which) / area
    alpha, value = NORMAL_COEFFICIENT
    name = f"{which}_canopy"
    return [f"[bodies.{name}]   # {c.canopy_type}, C_D0 S0 = {_n(drag_area(c, which))} m^2: a "
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
               main_trigger(c))
    rows = [f"[systems.{which}]", f'canopy = "{which}_canopy"',
            'canopy_model = "reduced"   # a light canopy: a drag point at the riser\'s end (docs/models/'
            "reduced_canopy.md)", "packed = true   # its canopy and confluence ride in the rocket until it deploys",
            'deploy_point = "rocket.line_stretch"', trigger, *harness_rows(c, which), *_opening_rows(c, which)]
    rows += [f"[systems.{which}.confluence]", f"mass = {_n(CONFLUENCE_MASS_FRACTION * c.mass)}   # kg (0.2 % of the "
             "rocket's, assumed)"]
    return rows + line_rows(c, which, "rocket.harness") + [""]


def main_trigger(c) -> str:
    """The main's barometric trigger at ``main_height`` above the ground, with its lag when one is given."""
    lag = "" if c.main_lag == 0.0 else f", lag = {_n(c.main_lag)}"
    return (f'deploy_trigger = {{ quantity = "altitude", below = {_n(c.main_height)}, reference = "ground", '
            f"rate = {_n(TRIGGER_RATE)}{lag} }}   # m above the ground")


def harness_rows(c, which: str) -> list:
    """The drogue's cutaway when the main deploys (``drogue_after_main`` cut); none when it stays attached."""
    if which != "drogue" or c.drogue_after_main == "attached":
        return []
    return ['cutaway_trigger = { after = "main.deploy" }   # cut away when the main deploys (RocketPy: the '
            "main's C_D S replaces the drogue's)"]


def _opening_rows(c, which: str) -> list:
    """The main's drag area growing over ``main_opening_time`` by its type's fill law from 0 (none: fully open at
    deployment)."""
    if which != "main" or c.main_opening_time is None:
        return []
    exponent = CANOPY_TYPES[c.canopy_type].opening_exponent
    opening = Inflation(stages=(InflationStage(0.0, 1.0, 1.0, exponent),))
    times = [c.main_opening_time * k / OPENING_POINTS for k in range(OPENING_POINTS + 1)]
    fractions = [opening.fraction(t, [c.main_opening_time]) for t in times]
    return [f"drag_area_schedule = {{ time = [{', '.join(_n(t) for t in times)}], fraction = "
            f"[{', '.join(_n(f) for f in fractions)}] }}   # opening in {_n(c.main_opening_time)} s, (t / t_o)^"
            f"{exponent:g} ({c.canopy_type})"]


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
    drogue_time = (start_height(c) - c.main_height) / steady_rate(c, drag_area(c, "drogue"), ground(c))
    main_time = c.main_height / steady_rate(c, drag_area(c, "main"), ground(c))
    climb = max(c.velocity_up or 0.0, 0.0) / gravity_at(c.planet, c.latitude or 0.0, ground(c))
    duration = 10.0 * math.ceil((1.25 * (drogue_time + main_time) + 2.0 * climb + c.apogee_lag + 20.0) / 10.0)
    return ["[simulation]", f"duration = {_n(duration)}   # s: an upper bound; the run ends at touchdown",
            "output_step = 0.05                         # s", f"ground_altitude = {_n(ground(c))}   # m",
            'method = "sp"', 'integrator = "rk4"',
            "# No [simulation.steps]: adaptive steps (docs/models/step_control.md); e.g. `sp = 0.01` there fixes one."]

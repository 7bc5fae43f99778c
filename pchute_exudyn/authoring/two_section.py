"""``pchute new --dual-deploy --shock-cord-length L``: the rocket in two sections on one shock cord (its lines replace
``authoring.rocket``'s single body and packed systems; docs/models/deployment_loads.md).

The booster (the vehicle) carries the nose cone until the apogee trigger fires the ejection charge: the nose leaves
along the rocket's axis at ``ejection_speed`` (momentum conserved), tied to the booster by the shock cord (a tether of
nylon rated at ``shock_cord_strength``; its damping DAMPING_RATIO of critical on the two sections). The drogue comes
out DROGUE_DELAY after the ejection and the main at ``main_height`` above the ground, both packed in the booster and
hanging from its eye bolt (the cord's booster end; one bridle and one riser each, reduced canopies), each opening by
its canopy type's fill law (n, exponent, C_x; CANOPY_TYPES) from line stretch; the drogue stays on its harness after
the main opens (``drogue_after_main`` attached; cut: cut away then), the booster's own drag that of a cylinder of its
length (``body_drag``; ``authoring.rocket.body_drag_rows``). Sizing:
the booster the rocket's length but NOSE_FRACTION, a solid cylinder; the nose a solid cone of NOSE_FRACTION of the
length and ``nose_mass`` (a tenth of the rocket's unless given); the canopies and lines as ``authoring.rocket``'s.
"""

from __future__ import annotations

import math

from ..physics.line_materials import LINE_MATERIALS
from ..physics.shapes import solid_cylinder_inertia
from ..registries.canopy_types import CANOPY_TYPES
from .rocket import (
    BRIDLE_FRACTION,
    TRIGGER_RATE,
    body_drag_rows,
    canopy_lines,
    harness_rows,
    header_lines,
    line_rows,
    main_trigger,
    simulation_lines,
)
from .rocket_start import nose_attitude_deg, nose_direction, start_altitude, start_height
from .rules import CONFLUENCE_MASS_FRACTION
from .text import number as _n
from .text import vector as _vector

NOSE_FRACTION = 0.2
"""The nose cone's share of the rocket's length (-, assumed)."""
NOSE_MASS_FRACTION = 0.1
"""The nose cone's share of the rocket's mass when no nose_mass is given (-, assumed)."""
DROGUE_DELAY = 0.5
"""s after the ejection at which the drogue comes out behind the nose cone (assumed)."""
DAMPING_RATIO = 0.05
"""The shock cord's damping as a share of its critical damping on the two sections at its first slope (-, assumed:
nylon webbing's hysteresis)."""
SHOCK_CORD_MATERIAL = "nylon"
"""The shock cord's material (``physics.line_materials``): tubular nylon, the usual high-power rocketry cord."""


def two_section_lines(c) -> list:
    """The two-section dual deploy's case file lines (module docstring) for a checked NewCase ``c``."""
    return header_lines(c) + sections_bodies(c) + canopy_lines(c, "drogue") + canopy_lines(c, "main") \
        + sections_system(c, "drogue") + sections_system(c, "main") + simulation_lines(c)


def _geometry(c) -> dict:
    """Lengths (m) and masses (kg) of the two sections."""
    nose_length = NOSE_FRACTION * c.length
    booster_length = c.length - nose_length
    nose_mass = c.nose_mass if c.nose_mass is not None else NOSE_MASS_FRACTION * c.mass
    return {"nose_length": nose_length, "booster_length": booster_length, "nose_mass": nose_mass,
            "booster_mass": c.mass - nose_mass, "seat": 0.5 * booster_length + 0.25 * nose_length,
            "harness": 0.45 * booster_length, "nose_harness": -0.25 * nose_length}


def sections_bodies(c) -> list:
    """The booster (the vehicle), the nose cone it carries, the ejection and the shock cord."""
    g = _geometry(c)
    radius = 0.5 * c.diameter
    cone_axial = 0.3 * g["nose_mass"] * radius ** 2
    cone_across = g["nose_mass"] * (3.0 * radius ** 2 / 20.0 + 3.0 * g["nose_length"] ** 2 / 80.0)
    bridle = c.bridle_length or BRIDLE_FRACTION * c.length
    yaw, pitch, roll = nose_attitude_deg(nose_direction(c))
    return ["[bodies.booster]                           # a solid cylinder, body +x its axis toward the nose",
            f"mass = {_n(g['booster_mass'])}   # kg: the rocket's {_n(c.mass)} kg but the nose cone, its packed "
            "recovery gear included",
            "mass_includes_packed = true                # mass, centre of mass, inertia, points: with the gear aboard",
            f"inertia = {_vector(solid_cylinder_inertia(g['booster_mass'], c.diameter, g['booster_length']))}   "
            f"# kg m^2 ({_n(c.diameter)} m by {_n(g['booster_length'])} m)",
            "[bodies.booster.points]                    # m, body axes from the centre of mass",
            f"harness = [{_n(g['harness'])}, 0.0, 0.0]   # the shock cord's and both bridles' eye bolt",
            f"nose_seat = [{_n(g['seat'])}, 0.0, 0.0]   # where the nose cone's centre of mass rides",
            f"line_stretch = [{_n(g['harness'] - bridle)}, 0.0, 0.0]   # a confluence at deployment: a bridle's "
            "length aft",
            "[bodies.booster.initial]                   # the start state, over the ground",
            f"altitude = {_n(start_altitude(c))}   # m: {_n(start_height(c))} m above the ground",
            f"velocity_east = {_n(c.velocity_east or 0.0)}   # m/s", f"velocity_north = {_n(c.velocity_north or 0.0)}"
            "   # m/s", f"velocity_down = {_n(-(c.velocity_up or 0.0))}   # m/s",
            f"yaw_deg = {_n(yaw)}", f"pitch_deg = {_n(pitch)}", f"roll_deg = {_n(roll)}",
            *body_drag_rows(c, "booster", g["booster_length"]), "",
            "[bodies.nose]                              # a solid cone, body +x toward its tip",
            f"mass = {_n(g['nose_mass'])}   # kg",
            f"inertia = [{_n(cone_axial)}, {_n(cone_across)}, {_n(cone_across)}]   # kg m^2: 3 m r^2 / 10, "
            "m (3 r^2 / 20 + 3 h^2 / 80)",
            "[bodies.nose.points]",
            f"harness = [{_n(g['nose_harness'])}, 0.0, 0.0]   # the shock cord's eye bolt", "",
            "[separations.nose]                         # the ejection charge at apogee",
            'point = "booster.nose_seat"', f"speed = {_n(c.ejection_speed)}   # m/s off the booster",
            "direction = [1.0, 0.0, 0.0]                # along the rocket's axis, forward",
            f'trigger = {{ quantity = "apogee", rate = {_n(TRIGGER_RATE)}, lag = {_n(c.apogee_lag)} }}', "",
            *_shock_cord(c, g), ""]


def _shock_cord(c, g) -> list:
    mu = g["nose_mass"] * g["booster_mass"] / c.mass
    table = LINE_MATERIALS[SHOCK_CORD_MATERIAL].table(c.shock_cord_strength)
    stiffness = table.slopes()[0] / c.shock_cord_length
    damping = 2.0 * DAMPING_RATIO * math.sqrt(stiffness * mu)
    return ["[tethers.shock_cord]                       # booster to nose cone: slack until it is paid out",
            'ends = ["booster.harness", "nose.harness"]', f"free_length = {_n(c.shock_cord_length)}   # m",
            f'material = "{SHOCK_CORD_MATERIAL}"', f"breaking_strength = {_n(c.shock_cord_strength)}   # N",
            f"damping = {_n(damping)}   # N s/m: {DAMPING_RATIO:g} of critical on the two sections (assumed)"]


def sections_system(c, which: str) -> list:
    """A system packed in the booster and hanging from its eye bolt, opening by its canopy type's law."""
    kind = CANOPY_TYPES[c.canopy_type]
    trigger = (f'deploy_trigger = {{ after = "nose.separation", delay = {_n(DROGUE_DELAY)} }}   # behind the nose'
               if which == "drogue" else
               main_trigger(c))
    rows = [f"[systems.{which}]", f'canopy = "{which}_canopy"',
            'canopy_model = "reduced"   # a light canopy: a drag point at the riser\'s end (docs/models/'
            "reduced_canopy.md)", "packed = true   # its canopy and confluence ride in the booster until it deploys",
            'deploy_point = "booster.line_stretch"', trigger, *harness_rows(c, which), f"[systems.{which}.confluence]",
            f"mass = {_n(CONFLUENCE_MASS_FRACTION * c.mass)}   # kg (0.2 % of the rocket's, assumed)",
            f"[systems.{which}.inflation]   # {c.canopy_type}: {kind.opening_source}",
            "stage_start = [0.0]", "fraction = [1.0]", f"fill_constant = [{_n(kind.fill_constant)}]",
            f"exponent = [{_n(kind.opening_exponent)}]", f"overinflation = {_n(kind.overinflation)}"]
    if kind.overinflation > 1.0:
        rows.append("overinflation_decay = 0.3   # s (assumed)")
    return rows + line_rows(c, which, "booster.harness") + [""]

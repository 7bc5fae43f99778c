"""The dual deploy's own choices (``pchute new --dual-deploy``; its rows: ``authoring.rocket``): their checks, the
ground and the start's altitude and height above it, the nose's direction and attitude, and a start taken from a
RocketPy export (``started_from``). NewCase checks them when made (``authoring.choices``)."""

from __future__ import annotations

import math
from dataclasses import fields, replace

import numpy as np

from ..errors import InputError
from .choice_checks import check_number, check_positive

ROCKET_ONLY = ("length", "drogue_drag_area", "main_drag_area", "main_height", "drogue_mass", "main_mass",
               "drogue_diameter", "main_diameter", "drogue_drag_coefficient", "main_drag_coefficient", "main_lag",
               "harness_offset", "main_opening_time", "body_drag", "drogue_after_main",
               "height", "velocity_east", "velocity_north",
               "velocity_up", "nose_pitch_deg", "nose_heading_deg", "from_rocketpy", "shock_cord_length",
               "nose_mass")
"""NewCase fields of the dual-deploy form only."""
WORDS = {"body_drag": ("on", "off"), "drogue_after_main": ("attached", "cut")}
"""The dual deploy's worded choices: field -> the words allowed (``pchute new``'s choices too)."""
NOT_DUAL = {"drag_area": "each canopy's: --drogue-drag-area, --main-drag-area",
            "canopy_diameter": "each canopy's: --drogue-diameter, --main-diameter",
            "canopy_mass": "each canopy's: --drogue-mass, --main-mass",
            "bridles": "a dual deploy hangs each system from one bridle"}
"""NewCase fields a dual deploy refuses, even given at their default value: field -> what it takes instead."""
CANOPY_DRAG_COEFFICIENT_MAX = 3.0
"""The largest C_D on S0 (-) a canopy's drag area and diameter may imply together: beyond it, one is a slip."""
START_FIELDS = ("altitude", "height", "latitude", "longitude", "velocity_east", "velocity_north", "velocity_up",
                "nose_pitch_deg", "nose_heading_deg")
"""The start state's NewCase fields, which a RocketPy export gives (``started_from``)."""


def check_choices(c) -> None:
    """InputError, one line naming the field, its value and what is allowed, for a NewCase's dual-deploy fields
    (or for any of them given without ``dual_deploy``)."""
    if not c.dual_deploy:
        defaults = {f.name: f.default for f in fields(c)}
        given = [key for key in ROCKET_ONLY + SECTION_ONLY if getattr(c, key) != defaults[key]]
        if given:
            raise InputError(f"{given[0]} = {getattr(c, given[0])!r}: only with dual_deploy (--dual-deploy)")
        return
    if c.planet == "mars":
        raise InputError("planet = 'mars': a dual deploy flies on Earth; give planet 'earth' (--planet earth) or "
                         "'flat'")
    check_not_dual(c, [f.name for f in fields(c) if getattr(c, f.name) != f.default])
    for key in ("length", "main_height"):
        if getattr(c, key) is None:
            raise InputError(f"{key}: required with dual_deploy ({_UNITS[key]})")
    for key in ("length", "drogue_drag_area", "main_drag_area", "main_height", "drogue_mass", "main_mass",
                "height", "drogue_diameter", "main_diameter", "drogue_drag_coefficient", "main_drag_coefficient",
                "main_opening_time"):
        check_positive(key, getattr(c, key), optional=True, unit=_UNITS[key])
    for key, words in WORDS.items():
        if getattr(c, key) not in words:
            raise InputError(f"{key} = {getattr(c, key)!r}: must be one of: {', '.join(words)}")
    check_canopies(c)
    check_number("main_lag", c.main_lag, c.main_lag >= 0.0, "must be a number >= 0 (s)")
    if c.harness_offset is not None and c.length is not None:
        check_number("harness_offset", c.harness_offset, abs(c.harness_offset) < 0.5 * c.length,
                     f"must be a number within half the rocket's length, {0.5 * c.length:g} m, of its centre of mass "
                     "(m aft of it)")
    for key, low, high, unit in (("nose_pitch_deg", -90.0, 90.0, "deg, above the horizontal"),
                                 ("nose_heading_deg", -360.0, 360.0, "deg, clockwise from north"),
                                 *((key, -3000.0, 3000.0, "m/s, over the ground") for key in
                                   ("velocity_east", "velocity_north", "velocity_up"))):
        value = getattr(c, key)
        if value is not None:
            check_number(key, value, low <= value <= high, f"must be a number from {low:g} to {high:g} ({unit})")
    check_number("apogee_lag", c.apogee_lag, c.apogee_lag >= 0.0, "must be a number >= 0 (s)")
    check_sections(c)
    for key, value in (("canopies", c.canopies != 1), ("release_airspeed", c.release_airspeed is not None),
                       ("speed", c.speed is not None)):
        if value:
            raise InputError(f"{key} = {getattr(c, key)!r}: not with dual_deploy (one drogue, one main, a start "
                             "state over the ground)")
    height = start_height(c)
    if height <= 0.0:
        raise InputError(f"altitude = {c.altitude!r}: must be above the ground ({ground(c):g} m)")
    if c.main_height >= height:
        raise InputError(f"main_height = {c.main_height!r}: must be below the start's height above the ground, "
                         f"{height:g} m (the main deploys on the way down)")


def check_not_dual(c, given) -> None:
    """InputError for a field of ``given`` (names) that a dual deploy has no use for (NOT_DUAL): one line naming it
    and what the dual deploy takes instead, rather than a file that silently leaves it out."""
    for key in given:
        if c.dual_deploy and key in NOT_DUAL:
            raise InputError(f"{key} = {getattr(c, key)!r}: not with dual_deploy (--dual-deploy): {NOT_DUAL[key]}")


def check_canopies(c) -> None:
    """Each canopy's size: its drag area or diameter (or both, then no drag coefficient), one drag coefficient."""
    for which in ("drogue", "main"):
        area, diameter, coefficient = (getattr(c, f"{which}_{key}") for key in
                                       ("drag_area", "diameter", "drag_coefficient"))
        if area is None and diameter is None:
            raise InputError(f"{which}_drag_area: required with dual_deploy (m^2), or {which}_diameter (m)")
        if coefficient is not None and c.drag_coefficient is not None:
            raise InputError(f"{which}_drag_coefficient = {coefficient!r} and drag_coefficient = "
                             f"{c.drag_coefficient!r}: give one (--{which}-drag-coefficient or --drag-coefficient, "
                             "which sets both canopies')")
        if area is not None and diameter is not None:
            given = coefficient if coefficient is not None else c.drag_coefficient
            if given is not None:
                name = f"{which}_drag_coefficient" if coefficient is not None else "drag_coefficient"
                raise InputError(f"{name} = {given!r}: not with both {which}_drag_area and {which}_diameter "
                                 f"(--{which}-drag-area, --{which}-diameter: they give C_D = C_D S / S0); give two "
                                 "of the three")
            implied = area / (math.pi * diameter**2 / 4.0)
            if implied > CANOPY_DRAG_COEFFICIENT_MAX:
                raise InputError(f"{which}_drag_area = {area!r} and {which}_diameter = {diameter!r}: imply C_D = "
                                 f"{implied:.3g} on S0 = pi D0^2 / 4, above {CANOPY_DRAG_COEFFICIENT_MAX:g}")


def canopy_drag(c, which: str) -> tuple:
    """(C_D S (m^2), S0 (m^2)) of the ``which`` ("drogue" or "main") canopy: from its drag area and its C_D (its
    own, else drag_coefficient, else the canopy type's), or from its diameter, S0 = pi D0^2 / 4, and either."""
    area, diameter, coefficient = (getattr(c, f"{which}_{key}") for key in ("drag_area", "diameter",
                                                                            "drag_coefficient"))
    if coefficient is None:
        coefficient = c.canopy_drag_coefficient
    if diameter is None:
        return area, area / coefficient
    reference = math.pi * diameter**2 / 4.0
    return (coefficient * reference if area is None else area), reference


def check_sections(c) -> None:
    """The two-section form's choices (``shock_cord_length`` and what goes with it)."""
    check_positive("shock_cord_length", c.shock_cord_length, optional=True, unit="m")
    check_positive("nose_mass", c.nose_mass, optional=True, unit="kg")
    for key, unit in (("shock_cord_strength", "N"), ("ejection_speed", "m/s")):
        check_positive(key, getattr(c, key), optional=False, unit=unit)
    if c.nose_mass is not None and c.nose_mass >= c.mass:
        raise InputError(f"nose_mass = {c.nose_mass!r}: must be below the rocket's mass, {c.mass:g} kg")
    if c.shock_cord_length is not None and c.shock_cord_length < 0.3 * c.length:
        raise InputError(f"shock_cord_length = {c.shock_cord_length!r}: must be at least the nose cone's reach out of "
                         f"the booster, {0.3 * c.length:g} m (0.3 x length)")
    if c.shock_cord_length is not None and c.main_opening_time is not None:
        raise InputError(f"main_opening_time = {c.main_opening_time!r}: not with shock_cord_length "
                         "(--shock-cord-length): the two-section form opens each canopy by its type's fill law")
    if c.shock_cord_length is not None and c.harness_offset is not None:
        raise InputError(f"harness_offset = {c.harness_offset!r}: not with shock_cord_length (--shock-cord-length): "
                         "the two-section form's harness is the booster's eye bolt")
    if c.shock_cord_length is None:
        defaults = {f.name: f.default for f in fields(c)}
        given = [key for key in SECTION_ONLY if getattr(c, key) != defaults[key]]
        if given:
            raise InputError(f"{given[0]} = {getattr(c, given[0])!r}: only with shock_cord_length "
                             "(--shock-cord-length)")


SECTION_ONLY = ("nose_mass", "shock_cord_strength", "ejection_speed")
"""NewCase fields of the two-section form only (``authoring.two_section``)."""


_UNITS = {"length": "m", "drogue_drag_area": "m^2", "main_drag_area": "m^2", "main_height": "m",
          "drogue_mass": "kg", "main_mass": "kg", "height": "m", "drogue_diameter": "m", "main_diameter": "m",
          "drogue_drag_coefficient": "-", "main_drag_coefficient": "-", "main_opening_time": "s"}


def ground(c) -> float:
    """The ground's altitude (m)."""
    return 0.0 if c.ground_elevation is None else float(c.ground_elevation)


def start_altitude(c) -> float:
    """The rocket's start altitude (m): the ground's plus ``height``, else ``altitude``."""
    return ground(c) + c.height if c.height is not None else float(c.altitude)


def start_height(c) -> float:
    """The start's height above the ground (m)."""
    return start_altitude(c) - ground(c)


def started_from(c, state, source: str):
    """``c`` (a NewCase) with its start from a RocketPy export's ``state`` (``results.rocketpy_export
    .RocketPyStart``; ``source`` its file, for messages): position, velocity over the ground, the nose's pitch and
    heading where exported, the ground's altitude where the export has it and ``c`` does not. InputError if ``c``
    gives a start field too."""
    defaults = {field.name: field.default for field in fields(c)}
    given = [key for key in START_FIELDS if getattr(c, key) != defaults[key]]
    if given:
        raise InputError(f"{given[0]} = {getattr(c, given[0])!r}: the start comes from from_rocketpy ({source}); "
                         "give one or the other")
    start = {"altitude": state.altitude, "latitude": state.latitude_deg, "longitude": state.longitude_deg,
              "velocity_east": state.velocity_east, "velocity_north": state.velocity_north,
              "velocity_up": state.velocity_up, "nose_pitch_deg": state.nose_pitch_deg,
              "nose_heading_deg": state.nose_heading_deg}
    if c.ground_elevation is None:
        start["ground_elevation"] = state.ground_elevation
    return replace(c, **start)


def no_ground_warning(source: str) -> str:
    """The warning for a RocketPy export (``source``) without Altitude AGL read with no ground given."""
    return (f"from_rocketpy = {source}: the export has no 'Altitude AGL' column, so the ground is put at 0 m (the "
            "ellipsoid); give the launch site's with --ground-elevation")


def nose_direction(c) -> np.ndarray:
    """The nose (body +x) as (east, north, up) (-): ``nose_pitch_deg`` above the horizontal (0 if not given),
    ``nose_heading_deg`` clockwise from north (if not given: along the horizontal velocity, north at none)."""
    pitch = math.radians(c.nose_pitch_deg or 0.0)
    east, north = c.velocity_east or 0.0, c.velocity_north or 0.0
    heading = (math.radians(c.nose_heading_deg) if c.nose_heading_deg is not None
               else math.atan2(east, north) if math.hypot(east, north) > 0.0 else 0.0)
    return np.array([math.cos(pitch) * math.sin(heading), math.cos(pitch) * math.cos(heading), math.sin(pitch)])


def nose_attitude_deg(nose) -> tuple:
    """Attitude angles (yaw, pitch, roll) (deg, relative to the descent frame x down, y east, z south;
    docs/case-format.md) that put body +x on ``nose`` (east, north, up; a unit vector), no roll (the rocket is
    symmetric about its axis)."""
    east, north, up = (float(v) for v in nose)
    yaw, pitch = math.degrees(math.atan2(east, -up)), math.degrees(math.asin(max(-1.0, min(1.0, north))))
    return round(yaw, 9) + 0.0, round(pitch, 9) + 0.0, 0.0   # no float noise (1e-15 deg) in the file


"""The checks of ``pchute new``'s choices (``authoring.choices``, ``authoring.flight_start``,
``authoring.rocket_start``): each refuses a value with one line naming the field, the value and what is allowed
(InputError)."""

from __future__ import annotations

import math

from ..errors import InputError, short_repr


def is_finite(value) -> bool:
    """Whether ``value`` is a finite int or float (an integer no float holds is not)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:   # an integer of hundreds of digits
        return False


def check_number(key, value, ok, allowed) -> None:
    """InputError unless ``value`` is a finite number and ``ok``; ``allowed`` says what is."""
    if not is_finite(value) or not ok:
        raise InputError(f"{key} = {short_repr(value)}: {allowed}")


def check_positive(key, value, optional, unit) -> None:
    """InputError unless ``value`` is a finite number > 0 (in ``unit``), or None where ``optional``."""
    if value is None and optional:
        return
    check_number(key, value, isinstance(value, (int, float)) and value > 0.0, f"must be a number > 0 ({unit})")


def check_integer(key, value, low, high) -> None:
    """InputError unless ``value`` is a whole number from ``low`` to ``high``."""
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise InputError(f"{key} = {short_repr(value)}: must be a whole number from {low} to {high}")


def check_choice(key, value, table) -> None:
    """InputError unless ``value`` is a key of ``table``."""
    if value not in table:
        raise InputError(f"{key} = {value!r}: must be one of: {', '.join(table)}")


READER_KEYS = {"mass": "bodies.vehicle.mass", "canopy_mass": "bodies.canopy.mass", "drogue_mass": "bodies.drogue.mass",
               "main_mass": "bodies.main.mass",
               "speed": "bodies.vehicle.initial.velocity_down", "wind_speed": "atmosphere.wind.speed",
               "release_airspeed": "start.release.airspeed",
               "velocity_east": "bodies.vehicle.initial.velocity_east",
               "velocity_north": "bodies.vehicle.initial.velocity_north",
               "velocity_up": "bodies.vehicle.initial.velocity_down",
               "apogee_lag": "systems.drogue.deploy_trigger.lag", "main_lag": "systems.main.deploy_trigger.lag",
               "main_opening_time": "systems.main.drag_area_schedule.time"}
"""A NewCase field -> the case key it becomes, whose range (``case.plausible.RANGES``) the case reader checks."""
NEEDS = {"static_line_time": ("release_airspeed", "a static line deploys the canopies of a release from an aircraft"),
         "static_line_length": ("release_airspeed", "a static line deploys the canopies of a release from an aircraft"),
         "release_heading_deg": ("release_airspeed", "the heading is the aircraft's at a release"),
         "release_flight_path_deg": ("release_airspeed", "the flight path is the aircraft's at a release"),
         "wind_from_deg": ("wind_speed", "the direction is a wind's"),
         "flight_path_deg": ("mach", "the flight path is the start's at flight conditions"),
         "heading_deg": ("mach", "the heading is the start's at flight conditions")}
"""A NewCase field that means something only with another: field -> (that field, what the first is)."""
EXCLUDES = (("altitude", "mach", "the flight conditions give the start altitude (authoring.flight_start)"),
            ("altitude", "height", "the start is the ground's altitude plus the height; give one of them"),
            ("static_line_time", "static_line_length", "the static line's length places line stretch where the "
                                                       "flight reaches it"))
"""A NewCase field given (even at its default) that another, when set, refuses: (field, that field, why)."""


def implausible_choices(c) -> tuple:
    """One warning line per NewCase field outside the plausible range the case reader warns of for the key it
    becomes (READER_KEYS; ``case.plausible.RANGES``): an apogee lag of 100 s, naming the option."""
    from ..case.plausible import IMPLAUSIBLE, check_value

    lines = []
    for field, key in READER_KEYS.items():
        value = getattr(c, field, None)
        _, warning = check_value(key, value) if is_finite(value) else (None, None)
        if warning is not None:
            lines.append(f"{field} = {short_repr(value)} (--{field.replace('_', '-')}) is implausible: "
                         f"{warning.partition(IMPLAUSIBLE)[2]}, the case reader's range of {key}")
    return tuple(lines)


def check_reader_ranges(c) -> None:
    """InputError for a NewCase field outside the range the case reader allows for the key it becomes (a mass of
    1e30 kg, a speed of 1e6 m/s): ``pchute new`` never writes a file ``pchute run`` refuses."""
    from ..case.plausible import check_value

    for field, key in READER_KEYS.items():
        value = getattr(c, field, None)
        if is_finite(value):
            error, _ = check_value(key, value)
            if error is not None:
                raise InputError(f"{field} = {short_repr(value)}: {error} (the case reader's range of {key})")
    if not isinstance(c.name, str) or not c.name.isprintable():
        raise InputError(f"name = {short_repr(c.name)}: must be one line of printable text (the case's name)")


SITE_RANGES = (("latitude", -90.0, 90.0, "deg"), ("longitude", -360.0, 360.0, "deg"),
               ("ground_elevation", -12000.0, 20000.0, "m"))
"""The start point's and the ground's allowed values, every form (field, low, high, unit)."""


def check_site(c) -> None:
    """The start point (latitude, longitude) and the ground's elevation within SITE_RANGES; a descent's start
    altitude above its ground."""
    for key, low, high, unit in SITE_RANGES:
        value = getattr(c, key)
        if value is not None:
            check_number(key, value, low <= value <= high, f"must be a number from {low:g} to {high:g} ({unit})")
    if not c.dual_deploy and c.ground_elevation is not None and not c.altitude > c.ground_elevation:
        raise InputError(f"altitude = {c.altitude!r}: must be above ground_elevation = {c.ground_elevation!r} (m)")


def check_needs(c, given) -> None:
    """InputError for a field of ``given`` (names) that means nothing without another (NEEDS): one line naming both
    (``--static-line-time`` without ``--release-airspeed`` would be dropped from the file); or that another field
    set refuses (EXCLUDES: ``--altitude`` beside ``--mach``)."""
    for field in given:
        for excluded, other, why in EXCLUDES:
            if field == excluded and getattr(c, other) is not None:
                raise InputError(f"{field} = {short_repr(getattr(c, field))}: not with {other} "
                                 f"(--{other.replace('_', '-')}): {why}")
        if field in NEEDS and not getattr(c, NEEDS[field][0]):
            needed, what = NEEDS[field]
            raise InputError(f"{field} = {short_repr(getattr(c, field))}: only with {needed} "
                             f"(--{needed.replace('_', '-')}): {what}; without it the file would drop it")


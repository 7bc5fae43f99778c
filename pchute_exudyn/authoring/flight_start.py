"""``pchute new --mach M --dynamic-pressure Q``: the vehicle starts at line stretch at flight conditions (a mortar
fire or a line stretch as flight reconstructions state it) instead of in steady descent.

The written case gives the vehicle's ``initial`` table as ``mach``, ``dynamic_pressure``, ``flight_path_deg`` and
``heading_deg`` (docs/case-format.md, "A start at flight conditions"), which the case reader turns into the altitude
where the planet's atmosphere has rho(h) a(h)^2 M^2 / 2 = q and the airspeed V = M a(h) (``physics.conditions``).
``pchute new`` solves the same equation here (``start_state``) for its checks, the sizes that depend on the start
(the fill time, the run's duration) and the comments it writes. The canopies deploy at the start and open by their
type's fill-constant law, as after a release; the vehicle gets a load-free aerodynamics table (C_A = 0, as every
``pchute new`` vehicle flies without drag) so that the run records its Mach number and dynamic pressure.
"""

from __future__ import annotations

import math

from ..case.start import SPEED_KEY, mach_refusal
from ..errors import InputError, short_repr
from ..physics.conditions import ConditionsError, altitude_and_speed
from .choice_checks import check_number, check_positive
from .planets import PLANETS
from .text import number as _n

GROUND = 0.0
"""m: the altitude where a case of ``pchute new`` ends (touchdown of the vehicle's centre of mass), which the start
must be above."""
EXCLUDED = {"speed": "a start at flight conditions moves at M a(h) along its flight path, not at a descent speed",
            "release_airspeed": "a start at flight conditions is at line stretch, not a release from an aircraft",
            "dual_deploy": "a dual deploy starts from a state over the ground (--velocity-east, ...)"}
"""NewCase fields (None or False when not given) that a start at flight conditions refuses: field -> why."""


def check_conditions(c) -> None:
    """InputError, one line naming the field, its value and what is allowed, for a NewCase's flight conditions:
    ``mach`` (-, > 0) and ``dynamic_pressure`` (Pa, > 0) together or not at all, ``flight_path_deg`` within -90..90
    and ``heading_deg`` within -360..360 (deg), no field of EXCLUDED beside them, and a pair the planet's atmosphere
    gives above the ground (``start_state``)."""
    check_positive("mach", c.mach, optional=True, unit="-")
    check_positive("dynamic_pressure", c.dynamic_pressure, optional=True, unit="Pa")
    check_number("flight_path_deg", c.flight_path_deg, -90.0 <= c.flight_path_deg <= 90.0,
                 "must be within -90..90 (deg, climbing > 0)")
    check_number("heading_deg", c.heading_deg, -360.0 <= c.heading_deg <= 360.0,
                 "must be within -360..360 (deg, clockwise from north)")
    if (c.mach is None) != (c.dynamic_pressure is None):
        given, missing, unit = (("mach", "dynamic_pressure", "Pa") if c.dynamic_pressure is None
                                else ("dynamic_pressure", "mach", "-"))
        raise InputError(f"{given} = {short_repr(getattr(c, given))}: needs {missing} too (--"
                         f"{missing.replace('_', '-')}, a number > 0 ({unit})): a start at flight conditions is a "
                         "Mach number and a dynamic pressure")
    if c.mach is None:
        return
    for field, why in EXCLUDED.items():
        if getattr(c, field):
            raise InputError(f"{field} = {short_repr(getattr(c, field))}: not with mach and dynamic_pressure: {why}")
    start_state(c)


def start_state(c) -> tuple:
    """(altitude (m), airspeed (m/s)) of the vehicle's centre of mass at the start of NewCase ``c``: where the
    planet's atmosphere gives ``c.mach`` and ``c.dynamic_pressure`` (rho(h) a(h)^2 M^2 / 2 = q, V = M a(h);
    ``physics.conditions``) when they are given, else ``c.altitude`` and None. InputError (one line) when no altitude
    of the atmosphere gives them, the one that does is not above the ground (GROUND), or the speed is beyond the
    case reader's range of a velocity (``case.plausible``)."""
    from ..case.plausible import check_value

    if c.mach is None:
        return c.altitude, None
    atmosphere = PLANETS[c.planet][3]()
    refusal = mach_refusal(atmosphere, c.mach)
    if refusal is not None:
        raise InputError(f"mach = {short_repr(c.mach)}: {refusal}")
    try:
        altitude, speed = altitude_and_speed(atmosphere, c.mach, c.dynamic_pressure)
    except ConditionsError as exc:
        raise InputError(f"dynamic_pressure = {short_repr(c.dynamic_pressure)}: with mach = {c.mach:g}: "
                         f"{exc}") from None
    if not altitude > GROUND:
        raise InputError(f"dynamic_pressure = {short_repr(c.dynamic_pressure)}: with mach = {c.mach:g} the "
                         f"{atmosphere.name} atmosphere puts the start at {altitude:.1f} m, not above the ground "
                         f"({GROUND:g} m, where the run ends); give a lower dynamic pressure or a higher Mach number")
    error, _ = check_value(SPEED_KEY, speed)
    if error is not None:
        raise InputError(f"mach = {short_repr(c.mach)}: {speed:.6g} m/s through the air at {altitude:.1f} m: {error} "
                         f"(the case reader's range of {SPEED_KEY})")
    return altitude, speed


def header_words(c, altitude: float, speed: float) -> list:
    """The written file's header lines on a start at flight conditions (the first continues the header's line)."""
    return [f"At line stretch at Mach {c.mach:g} and a dynamic pressure of {c.dynamic_pressure:g} Pa:",
            f"# {altitude:.1f} m and {speed:.2f} m/s through the air (flight path {c.flight_path_deg:g} deg, heading "
            f"{c.heading_deg:g} deg); the canopies deploy", "# there at the start and open with the fill-constant "
            f"law of a {c.canopy_type} canopy ([systems.main.inflation])."]


def vehicle_rows(c, altitude: float, speed: float) -> list:
    """The vehicle's ``initial`` table at flight conditions and its load-free ``aerodynamics`` table, which makes
    the run record ``vehicle_mach`` and ``vehicle_dynamic_pressure``."""
    atmosphere = PLANETS[c.planet][1]
    return ["[bodies.vehicle.initial]                   # attitude: body +x down (the descent attitude)",
            f"# Mach {c.mach:g} at {c.dynamic_pressure:g} Pa: {altitude:.1f} m, {speed:.2f} m/s through the air "
            f"({atmosphere}; the case reader", "# solves rho(h) a(h)^2 M^2 / 2 = q for the altitude h of the centre "
            "of mass again, and V = M a(h))",
            f"mach = {_n(c.mach)}   # -: the speed through the air over the speed of sound",
            f"dynamic_pressure = {_n(c.dynamic_pressure)}   # Pa: rho V^2 / 2",
            f"flight_path_deg = {_n(c.flight_path_deg)}   # deg: the velocity through the air above the horizontal",
            f"heading_deg = {_n(c.heading_deg)}   # deg: its direction, clockwise from north",
            "[bodies.vehicle.aerodynamics]              # no load (C_A = 0: every `pchute new` vehicle flies without "
            "drag),", "# so that the run records vehicle_mach and vehicle_dynamic_pressure; a capsule's drag goes here",
            f"reference_area = {_n(math.pi * c.diameter ** 2 / 4.0)}   # m^2: the vehicle's cross-section",
            "axial_coefficient = 0.0", "center = [0.0, 0.0, 0.0]                   # m: at the centre of mass"]

"""The planets ``pchute new`` writes a case for: each one's [planet] table lines, its atmosphere and the gravity the
written case flies with, which sizes the lines and states the steady rates (``gravity_at``)."""

from __future__ import annotations

import math

from ..physics.atmosphere import US76, MarsGRC
from ..physics.gravity import (
    MARS_A,
    MARS_B,
    MARS_GM,
    MARS_OMEGA,
    WGS84_A,
    WGS84_B,
    WGS84_GM,
    WGS84_OMEGA,
    NormalGravity,
)

PLANETS = {   # name -> (planet table lines, atmosphere model, its normal gravity (flat: g, m/s^2), density model)
    "mars": (['name = "Mars"', "gravitational_parameter = 4.282837e13      # m^3/s^2 (Konopliv et al. 2006)",
              "equatorial_radius = 3396190.0              # m (IAU/IAG, Seidelmann et al. 2002)",
              "polar_radius = 3376200.0                   # m (IAU/IAG)",
              "rotation_rate = 0.0                        # rad/s: the frame turns with Mars (7.088218e-5: inertial)",
              'gravity_model = "normal"                   # spin_rate 7.088218e-5 rad/s by default (gravity.md)'],
             "mars_grc", NormalGravity(MARS_GM, MARS_A, MARS_B, MARS_OMEGA), MarsGRC),
    "earth": (['name = "Earth"', "gravitational_parameter = 3.986004418e14   # m^3/s^2 (WGS-84)",
               "equatorial_radius = 6378137.0              # m", "polar_radius = 6356752.314245             # m",
               "rotation_rate = 0.0                        # rad/s: the frame turns with the Earth (7.292115e-5: "
               "inertial)", 'gravity_model = "normal"                   # spin_rate 7.292115e-5 rad/s by default '
               "(gravity.md)"], "us76", NormalGravity(WGS84_GM, WGS84_A, WGS84_B, WGS84_OMEGA), US76),
    "flat": (['model = "flat"', "gravity = 9.80665                          # m/s^2"], "us76", 9.80665, US76),
}


def gravity_at(planet: str, latitude_deg: float = 0.0, altitude: float = 0.0) -> float:
    """g (m/s^2) a case of ``planet`` flies with at geodetic ``latitude_deg`` (deg) and ``altitude`` (m): the
    planet's normal gravity there (``physics.gravity``, the model the written case names), the flat planet's g."""
    field = PLANETS[planet][2]
    return field if isinstance(field, float) else field.magnitude(math.radians(latitude_deg), altitude)

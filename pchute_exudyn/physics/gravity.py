"""Normal gravity: the gravity of a planet's level ellipsoid, the one home of its formulas.

The level ellipsoid is the ellipsoid of revolution (semi-axes a >= b, m) that is an equipotential surface of its own
gravitation (mass GM, m^3/s^2) plus the centrifugal potential of its spin (omega, rad/s). Its gravity ("normal
gravity") is the acceleration a body at rest relative to the planet feels: gravitation plus the centrifugal term,
along the ellipsoid normal (the geodetic vertical; the field's small curvature of the plumb line above the surface is
left out, as in NIMA TR8350.2 eq. 4-3).

* On the ellipsoid, Somigliana's closed form (Heiskanen & Moritz 1967, eq. 2-78; NIMA TR8350.2 eq. 4-1):
  gamma(phi) = gamma_e (1 + k sin^2 phi) / sqrt(1 - e^2 sin^2 phi), k = b gamma_p / (a gamma_e) - 1,
  phi the geodetic latitude, e^2 = 1 - b^2/a^2.
* gamma_e and gamma_p from GM, a, b and omega (Heiskanen & Moritz 1967 eqs. 2-141, 2-142 and 2-146 (q0, q0');
  NIMA TR8350.2 section 4 (eqs. 3-7/3-8 of its predecessor)): E = sqrt(a^2 - b^2), e' = E/b, m = omega^2 a^2 b/GM,
  q0 = 1/2 [(1 + 3/e'^2) atan e' - 3/e'], q0' = 3 (1 + 1/e'^2)(1 - atan(e')/e') - 1,
  gamma_e = GM/(a b) (1 - m - m e' q0' / (6 q0)), gamma_p = GM/a^2 (1 + m e' q0' / (3 q0)).
  q0 and q0' lose six digits to cancellation in this form for e' ~ 0.1: up to SERIES_LIMIT they are summed from
  their series (``_q0_series``, within 7 ulps of 60-digit values), beyond it taken in this closed form (within 35
  ulps; the series diverges for e' >= 1): ``q0_pair``.
* Above the ellipsoid, the height correction (NIMA TR8350.2 eq. 4-3), h the geodetic height (m):
  gamma_h = gamma [1 - 2/a (1 + f + m - 2 f sin^2 phi) h + 3 h^2/a^2].

In a frame that does not rotate with the planet (the model frame with the planet's rotation on,
``docs/models/conventions.md``) the applied acceleration is the gravitation alone, gamma_h - omega^2 r_perp
(= gamma_h + Omega x (Omega x r), r_perp the distance vector from the spin axis): relative to the turning ground a body
then feels normal gravity plus the Coriolis term. Normal gravity is axisymmetric about the spin axis, so in the
inertial start frame it needs no time.

The kernels are pure (no engine import); ``NORMAL_COLUMNS`` packs one planet's normal gravity for them
(``planet.StartFrame.normal_gravity_parameters``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .compiled import kernel
from .geodesy import bowring

WGS84_GM = 3.986004418e14
"""WGS-84 GM (m^3/s^2), NIMA TR8350.2 (3rd ed., 2000) table 3.1."""
WGS84_A = 6_378_137.0
"""WGS-84 semi-major axis (m), NIMA TR8350.2 table 3.1."""
WGS84_INVERSE_FLATTENING = 298.257223563
"""WGS-84 1/f (-), NIMA TR8350.2 table 3.1."""
WGS84_OMEGA = 7.292115e-5
"""WGS-84 angular velocity of the Earth (rad/s), NIMA TR8350.2 table 3.1."""
WGS84_B = WGS84_A * (1.0 - 1.0 / WGS84_INVERSE_FLATTENING)
"""WGS-84 semi-minor axis (m): 6 356 752.3142 (NIMA TR8350.2 table 3.3)."""
WGS84_GAMMA_E, WGS84_GAMMA_P = 9.7803253359, 9.8321849378
"""WGS-84's published normal gravity at the equator and at the poles (m/s^2), NIMA TR8350.2 table 3.4."""

MARS_GM = 4.282837e13
"""Mars GM (m^3/s^2): 42 828.37 km^3/s^2, Konopliv et al. (2006), Icarus 182, 23-50 (MGS/Odyssey gravity field)."""
MARS_A = 3_396_190.0
"""Mars equatorial radius (m), IAU/IAG ellipsoid: Seidelmann et al. (2002), Celest. Mech. Dyn. Astr. 82, 83-111
(kept by Archinal et al. 2011/2018)."""
MARS_B = 3_376_200.0
"""Mars polar radius (m), IAU/IAG ellipsoid (Seidelmann et al. 2002)."""
MARS_OMEGA = 7.088218e-5
"""Mars sidereal rotation rate (rad/s): 350.891982 deg/day, the IAU rotation model (Archinal et al. 2011: W-dot =
350.89198226 deg/d; 7.0882181e-5 rad/s)."""

PUBLISHED_SPIN = {"earth": (WGS84_A, WGS84_B, WGS84_OMEGA), "mars": (MARS_A, MARS_B, MARS_OMEGA)}
"""Planet name (lower case) -> (a in m, b in m, spin rate in rad/s) of the published ellipsoids: a case's spin rate
defaults to it when its ellipsoid is this one (within SPIN_MATCH)."""
SPIN_MATCH = 1.0
"""How close (m) a case's semi-axes must be to a published ellipsoid's for its spin rate to be the default."""


def published_spin(name: str, equatorial_radius: float, polar_radius: float) -> float | None:
    """The spin rate (rad/s) of the published planet ``name`` ("Earth", "Mars", any case) when the semi-axes (m)
    are its ellipsoid's within SPIN_MATCH, else None."""
    known = PUBLISHED_SPIN.get(name.strip().lower())
    if known is None:
        return None
    a, b, omega = known
    close = abs(equatorial_radius - a) <= SPIN_MATCH and abs(polar_radius - b) <= SPIN_MATCH
    return omega if close else None


def _q0_series(e_prime: float) -> tuple:
    """(q0, q0') of Heiskanen & Moritz eqs. 2-58/2-146 from their power series in e' (-), without cancellation:
    q0 = 2 sum_{n>=1} (-1)^(n+1) n e'^(2n+1) / ((2n+1)(2n+3)), q0' = 6 sum_{n>=1} (-1)^(n+1) e'^(2n) / ((2n+1)(2n+3))
    (from atan's series; the closed forms' leading terms cancel). Converges for e' < 1."""
    x2 = e_prime * e_prime
    q0 = q0p = 0.0
    power = x2   # e'^(2n)
    for n in range(1, 200):
        sign = 1.0 if n % 2 else -1.0
        denominator = (2.0 * n + 1.0) * (2.0 * n + 3.0)
        term_q0p = 6.0 * sign * power / denominator
        term_q0 = 2.0 * sign * n * power * e_prime / denominator
        q0, q0p = q0 + term_q0, q0p + term_q0p
        if abs(term_q0) <= 1e-18 * abs(q0) and abs(term_q0p) <= 1e-18 * abs(q0p):
            break
        power *= x2
    return q0, q0p


SERIES_LIMIT = 0.9
"""The second eccentricity e' (-) up to which ``q0_pair`` sums the series (Earth 0.082, Mars 0.109). Measured
against 60-digit values (mpmath) at 50 random e' per 0.02 wide bin: the series is within 7 ulps up to 0.92 (its 200
terms fall short beyond: 1.4e3 ulps at 0.93), the closed form within 35 ulps from 0.8 on (75 ulps at 0.5, 2e5 at
0.08)."""


def _q0_closed(e_prime: float) -> tuple:
    """(q0, q0') of Heiskanen & Moritz eqs. 2-58/2-146 in their closed (atan) forms, e' (-) > 0."""
    arctangent = math.atan(e_prime)
    return (0.5 * ((1.0 + 3.0 / e_prime ** 2) * arctangent - 3.0 / e_prime),
            3.0 * (1.0 + 1.0 / e_prime ** 2) * (1.0 - arctangent / e_prime) - 1.0)


def q0_pair(e_prime: float) -> tuple:
    """(q0, q0') (-) at the second eccentricity ``e_prime`` (-) > 0, within 35 ulps for any e': the series up to
    SERIES_LIMIT (where the shipped planets' e' lie, bit for bit as before), the closed forms beyond."""
    return _q0_series(e_prime) if e_prime <= SERIES_LIMIT else _q0_closed(e_prime)


@dataclass(frozen=True)
class NormalGravity:
    """The normal gravity field of a level ellipsoid.

    Parameters
    ----------
    gravitational_parameter : float
        GM (m^3/s^2).
    equatorial_radius : float
        a (m).
    polar_radius : float
        b (m), 0 < b < a (a sphere has no level-ellipsoid closed form: e' = 0).
    spin_rate : float
        omega (rad/s), the planet's rotation, >= 0.
    """

    gravitational_parameter: float
    equatorial_radius: float
    polar_radius: float
    spin_rate: float

    @property
    def flattening(self) -> float:
        """f = (a - b)/a (-)."""
        return (self.equatorial_radius - self.polar_radius) / self.equatorial_radius

    @property
    def m(self) -> float:
        """m = omega^2 a^2 b / GM (-), Heiskanen & Moritz eq. 2-70."""
        a, b = self.equatorial_radius, self.polar_radius
        return self.spin_rate ** 2 * a * a * b / self.gravitational_parameter

    @property
    def equator_and_pole(self) -> tuple:
        """(gamma_e, gamma_p) (m/s^2): Heiskanen & Moritz eqs. 2-141/2-142."""
        gm, a, b, m = self.gravitational_parameter, self.equatorial_radius, self.polar_radius, self.m
        e_prime = math.sqrt(a * a - b * b) / b
        q0, q0p = q0_pair(e_prime)
        ratio = m * e_prime * q0p / q0
        return gm / (a * b) * (1.0 - m - ratio / 6.0), gm / (a * a) * (1.0 + ratio / 3.0)

    @property
    def k(self) -> float:
        """Somigliana's k = b gamma_p / (a gamma_e) - 1 (-)."""
        gamma_e, gamma_p = self.equator_and_pole
        return self.polar_radius * gamma_p / (self.equatorial_radius * gamma_e) - 1.0

    def on_ellipsoid(self, latitude_rad: float) -> float:
        """Somigliana's gamma(phi) (m/s^2) at geodetic latitude ``latitude_rad`` (rad), on the ellipsoid."""
        gamma_e = self.equator_and_pole[0]
        e2 = 1.0 - (self.polar_radius / self.equatorial_radius) ** 2
        s2 = math.sin(latitude_rad) ** 2
        return gamma_e * (1.0 + self.k * s2) / math.sqrt(1.0 - e2 * s2)

    def magnitude(self, latitude_rad: float, height: float) -> float:
        """gamma_h (m/s^2) at geodetic latitude (rad) and height ``height`` (m): NIMA TR8350.2 eq. 4-3."""
        a, f = self.equatorial_radius, self.flattening
        s2 = math.sin(latitude_rad) ** 2
        return self.on_ellipsoid(latitude_rad) * (1.0 - 2.0 / a * (1.0 + f + self.m - 2.0 * f * s2) * height
                                                  + 3.0 * height * height / (a * a))


NORMAL_COLUMNS = 12
"""One planet's normal gravity as the kernels take it (``normal_gravity``'s first arguments): the planet centre
(3, m) and the unit spin axis (3) in start-frame components, a and b (m), gamma_e (m/s^2), Somigliana's k (-),
m (-) and the rate (rad/s) of the frame's own rotation whose centrifugal term is taken out (0: a frame turning with
the planet; the spin rate: an inertial frame)."""


@kernel
def normal_gravity(cx, cy, cz, ux, uy, uz, a, b, gamma_e, k, m, rate, x, y, z):
    """Acceleration (m/s^2, start-frame axes) at the start-frame point (x, y, z) (m): normal gravity gamma_h along
    the ellipsoid normal, less rate^2 r_perp (the centrifugal part of a frame that does not turn with the planet;
    rate in rad/s, 0 for none). (cx, cy, cz) is the planet centre (m), (ux, uy, uz) the unit spin axis, a and b the
    semi-axes (m), gamma_e (m/s^2), k and m as ``NormalGravity``. Geodetic latitude and height by two Bowring
    iterations (``geodesy.bowring``, as ``planet._geodetic``)."""
    rx, ry, rz = x - cx, y - cy, z - cz
    along = rx * ux + ry * uy + rz * uz            # distance along the spin axis (m)
    px, py, pz = rx - along * ux, ry - along * uy, rz - along * uz   # r_perp (m)
    p = math.sqrt(px * px + py * py + pz * pz)
    sl, cl, height = bowring(p, along, a, b, 2)
    e2 = 1.0 - (b * b) / (a * a)
    s2 = sl * sl
    f = (a - b) / a
    gamma = gamma_e * (1.0 + k * s2) / math.sqrt(1.0 - e2 * s2)                    # Somigliana
    gamma *= 1.0 - 2.0 / a * (1.0 + f + m - 2.0 * f * s2) * height + 3.0 * height * height / (a * a)   # eq. 4-3
    if p > 0.0:
        ex, ey, ez = px / p, py / p, pz / p       # horizontal outward from the axis
    else:
        ex, ey, ez = 0.0, 0.0, 0.0                # on the axis cos(phi) = 0
    nx, ny, nz = cl * ex + sl * ux, cl * ey + sl * uy, cl * ez + sl * uz   # the ellipsoid normal (up)
    w2 = rate * rate
    return -gamma * nx - w2 * px, -gamma * ny - w2 * py, -gamma * nz - w2 * pz


"""Planet: an ellipsoid of revolution with normal (level-ellipsoid, ``physics.gravity``) or spherical (point-mass)
gravity, and the start-point frame.

Frames (``docs/models/conventions.md``, "Frames, altitude and gravity"):

* planet-centred inertial frame: X through latitude 0 / longitude 0, Z through the north pole, Y completes it.
  With a rotating planet (Omega != 0) this frame coincides with the planet-fixed one at t = 0.
* start frame: the local east/north/up (ENU) axes of the start point, with its origin on the ellipsoid at the start
  latitude and longitude (altitude 0). It is fixed in inertial space and is the frame of the Exudyn model, so
  coordinates stay small (metres to kilometres) and keep full double precision.

Altitude is always geodetic: the height above the ellipsoid along its normal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np

from .compiled import JIT, bound, kernel
from .geodesy import bowring
from .gravity import NormalGravity, normal_gravity

_MATH = SimpleNamespace(sin=math.sin, cos=math.cos, atan2=math.atan2, hypot=math.hypot, sqrt=math.sqrt)
_NUMPY = SimpleNamespace(sin=np.sin, cos=np.cos, atan2=np.arctan2, hypot=np.hypot, sqrt=np.sqrt)


def _geodetic(x, y, z, a, b, m, iterations=3):
    """Geodetic latitude (rad) and height (m) of planet-centred points, by Bowring's iteration.

    Written once for both scalars (``m`` = math) and arrays (``m`` = numpy), and without trigonometric calls in the
    loop: the sine and cosine of each latitude come from normalising the vector whose atan2 it is. One iteration is
    exact to 2e-9 m for Mars heights from -1 to 50 km (measured on 10 000 random points); three reach machine
    precision far above.
    """
    e2 = 1.0 - (b * b) / (a * a)
    ep2 = (a * a) / (b * b) - 1.0
    p = m.hypot(x, y)
    sb, cb = a * z, b * p                      # reduced latitude beta, first guess: tan(beta) = a z / (b p)
    for _ in range(iterations):
        norm = m.sqrt(sb * sb + cb * cb)
        sb, cb = sb / norm, cb / norm
        sl = z + ep2 * b * sb * sb * sb        # geodetic latitude phi: tan(phi) = sl / cl
        cl = p - e2 * a * cb * cb * cb
        norm = m.sqrt(sl * sl + cl * cl)
        sl, cl = sl / norm, cl / norm
        sb, cb = b * sl, a * cl                # tan(beta) = (b / a) tan(phi)
    height = p * cl + z * sl - a * m.sqrt(1.0 - e2 * sl * sl)
    return m.atan2(sl, cl), height


SPLIT = 134217729.0
"""2^27 + 1: Veltkamp's splitting constant (a double into two halves whose products are exact)."""


@kernel
def hypot(a, b):
    """sqrt(a^2 + b^2) to the last bit as CPython's ``math.hypot`` gives it (its vector_norm: power-of-two scaling,
    exact squares by Veltkamp-Dekker splitting, compensated summation, a corrected square root), so that compiled
    kernels reproduce the per-stage Python they replace bit for bit (a plain sqrt can differ in the last bit)."""
    x0, x1 = abs(a), abs(b)
    if x0 != x0 or x1 != x1:
        return math.inf if math.isinf(x0) or math.isinf(x1) else math.nan
    big = x0 if x0 > x1 else x1
    if math.isinf(big) or big == 0.0:
        return big
    factor = 1.0
    exponent = math.frexp(big)[1]
    if exponent < -1023:   # subnormal: lift to normals first (CPython recurses once)
        tiny = 2.2250738585072014e-308
        x0, x1, big, factor = x0 / tiny, x1 / tiny, big / tiny, tiny
        exponent = math.frexp(big)[1]
    scale = math.ldexp(1.0, -exponent)
    csum, frac1, frac2 = 1.0, 0.0, 0.0
    for x in (x0 * scale, x1 * scale):
        csum, frac1, frac2 = _add_product(x, x, csum, frac1, frac2)
    h = math.sqrt(csum - 1.0 + (frac1 + frac2))
    csum, frac1, frac2 = _add_product(-h, h, csum, frac1, frac2)   # the square root's residual, for its correction
    h += (csum - 1.0 + (frac1 + frac2)) / (2.0 * h)
    return factor * (h / scale)


hypot_port = hypot
"""The port itself, whatever the form (the tests check it against ``math.hypot``)."""
if not JIT:   # Python callers get the same bits from the function ported (compiled code is built in the jit form)
    hypot = math.hypot  # noqa: F811


@kernel
def _split(x):
    """Veltkamp's split of ``x`` into (high, low) halves whose products are exact."""
    t = SPLIT * x
    high = t - (t - x)
    return high, x - high


@kernel
def _add_product(a, b, csum, frac1, frac2):
    """Add a b exactly (Dekker's product: the rounded product and its error) to CPython's compensated sum
    (csum, frac1, frac2)."""
    product = a * b
    a_high, a_low = _split(a)
    b_high, b_low = _split(b)
    error = ((a_high * b_high - product) + a_high * b_low + a_low * b_high) + a_low * b_low
    total = csum + product
    frac2 += (csum - total) + product
    return total, frac1 + error, frac2


@kernel
def geodetic_height(x, y, z, a, b):
    """Geodetic height (m) of the planet-centred point (x, y, z) (m) on the ellipsoid of semi-axes a, b (m): one
    Bowring iteration, the scalar form of ``_geodetic`` (whose array form the histories use; the tests check that
    they agree), compiled for the per-stage kernels."""
    return bowring(hypot(x, y), z, a, b, 1)[2]


FRAME_COLUMNS = 15
"""A start frame for the kernels (``StartFrame.kernel_frame``): its origin (3, m) and axes (9, row-major), the
planet's semi-axes a and b (m), and 1 for a flat planet (altitude = up) or 0 for an ellipsoid."""


@kernel
def start_altitude(frame, x, y, z):
    """Geodetic altitude (m) of the start-frame point (x, y, z) (m) in the start frame ``frame``
    (FRAME_COLUMNS)."""
    px = frame[0] + frame[3] * x + frame[4] * y + frame[5] * z
    py = frame[1] + frame[6] * x + frame[7] * y + frame[8] * z
    pz = frame[2] + frame[9] * x + frame[10] * y + frame[11] * z
    if frame[14] > 0.0:
        return pz
    return geodetic_height(px, py, pz, frame[12], frame[13])


@dataclass(frozen=True)
class Planet:
    """An ellipsoidal planet with normal or spherical gravity.

    Parameters
    ----------
    gravitational_parameter : float
        mu = G M (m^3/s^2).
    equatorial_radius : float
        Semi-major axis Re (m).
    polar_radius : float
        Semi-minor axis Rp (m), 0 < Rp <= Re.
    rotation_rate : float
        Omega (rad/s) about the +Z (north polar) axis of the model frame's rotation: the frame is inertial and the
        planet turns under it; 0 for a frame that turns with the planet (no Coriolis or centrifugal terms).
    name : str
        Label for output files.
    spin_rate : float
        The planet's physical rotation rate (rad/s, >= 0), whose centrifugal term normal gravity includes (whether
        or not the frame rotates); equal to |rotation_rate| when that is not 0.
    gravity_model : {"spherical", "normal"}
        "spherical": -mu r/|r|^3 toward the centre (the thesis's model); "normal": the level ellipsoid's gravity
        along the ellipsoid normal (``physics.gravity``). The dataclass's default is spherical (the thesis's
        planets below); a case file's is normal (``docs/models/gravity.md``).
    """

    gravitational_parameter: float
    equatorial_radius: float
    polar_radius: float
    rotation_rate: float = 0.0
    name: str = "planet"
    spin_rate: float = 0.0
    gravity_model: str = "spherical"

    @property
    def normal(self) -> NormalGravity | None:
        """The level ellipsoid's normal gravity when ``gravity_model`` is "normal", else None."""
        if self.gravity_model != "normal":
            return None
        return NormalGravity(self.gravitational_parameter, self.equatorial_radius, self.polar_radius, self.spin_rate)

    @property
    def eccentricity_squared(self) -> float:
        """First eccentricity squared of the ellipsoid (-)."""
        return 1.0 - (self.polar_radius / self.equatorial_radius) ** 2

    def gravity(self, position) -> np.ndarray:
        """Gravitational acceleration (m/s^2) at planet-centred positions (m), shape (..., 3): -mu r / |r|^3, or
        normal gravity (gravitation plus the spin's centrifugal term: what a body at rest on the planet feels)."""
        r = np.asarray(position, dtype=float)
        normal = self.normal
        if normal is not None:
            gamma_e, k = normal.equator_and_pole[0], normal.k
            flat = r.reshape(-1, 3)
            values = [normal_gravity(0.0, 0.0, 0.0, 0.0, 0.0, 1.0, self.equatorial_radius, self.polar_radius,
                                     gamma_e, k, normal.m, 0.0, *map(float, point)) for point in flat]
            return np.array(values, dtype=float).reshape(r.shape)
        norm = np.linalg.norm(r, axis=-1, keepdims=True)
        return -self.gravitational_parameter * r / norm**3

    def cartesian(self, latitude_deg, longitude_deg, altitude=0.0) -> np.ndarray:
        """Planet-centred position (m) of a geodetic latitude/longitude (deg) and altitude (m)."""
        lat = np.radians(latitude_deg)
        lon = np.radians(longitude_deg)
        a = self.equatorial_radius
        e2 = self.eccentricity_squared
        n = a / np.sqrt(1.0 - e2 * np.sin(lat) ** 2)
        return np.stack([(n + altitude) * np.cos(lat) * np.cos(lon),
                         (n + altitude) * np.cos(lat) * np.sin(lon),
                         (n * (1.0 - e2) + altitude) * np.sin(lat)], axis=-1)

    def geodetic(self, position):
        """Geodetic latitude (deg), longitude (deg) and altitude (m) of planet-centred positions (m), shape (..., 3)."""
        r = np.asarray(position, dtype=float)
        lat, height = _geodetic(r[..., 0], r[..., 1], r[..., 2], self.equatorial_radius, self.polar_radius, _NUMPY)
        return np.degrees(lat), np.degrees(np.arctan2(r[..., 1], r[..., 0])), height

    def altitude(self, position) -> np.ndarray:
        """Geodetic altitude (m) of planet-centred positions (m), shape (..., 3)."""
        return self.geodetic(position)[2]

    def altitude_scalar(self, x: float, y: float, z: float) -> float:
        """Geodetic altitude (m) of one planet-centred point (m); plain floats, for per-stage user functions.

        One Bowring iteration: exact to 1e-8 m within 50 km of the surface (see ``_geodetic``)."""
        return _geodetic(x, y, z, self.equatorial_radius, self.polar_radius, _MATH, iterations=1)[1]

    @staticmethod
    def enu_axes(latitude_deg: float, longitude_deg: float) -> np.ndarray:
        """Local east, north and up unit vectors (planet-centred components) as the columns of a 3x3 matrix."""
        lat, lon = math.radians(latitude_deg), math.radians(longitude_deg)
        east = [-math.sin(lon), math.cos(lon), 0.0]
        north = [-math.sin(lat) * math.cos(lon), -math.sin(lat) * math.sin(lon), math.cos(lat)]
        up = [math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon), math.sin(lat)]
        return np.column_stack([east, north, up])


@dataclass(frozen=True)
class FlatPlanet:
    """A flat, non-rotating ground with uniform gravity (test systems such as the thesis's chapter 2 model).

    Coordinates are east, north, up directly; altitude is the up coordinate.

    Parameters
    ----------
    gravity_acceleration : float
        g (m/s^2), pointing down; 0 for none.
    """

    gravity_acceleration: float
    name: str = "flat"
    rotation_rate: float = 0.0

    def gravity(self, position) -> np.ndarray:
        """Uniform gravity (m/s^2) at positions (..., 3)."""
        return np.broadcast_to(np.array([0.0, 0.0, -self.gravity_acceleration]), np.shape(position)).copy()

    def cartesian(self, latitude_deg, longitude_deg, altitude=0.0) -> np.ndarray:
        return np.array([0.0, 0.0, float(altitude)])

    def geodetic(self, position):
        r = np.asarray(position, dtype=float)
        return np.zeros(r.shape[:-1]), np.zeros(r.shape[:-1]), r[..., 2]

    def altitude(self, position) -> np.ndarray:
        return np.asarray(position, dtype=float)[..., 2]

    def altitude_scalar(self, x: float, y: float, z: float) -> float:
        return z

    @staticmethod
    def enu_axes(latitude_deg: float, longitude_deg: float) -> np.ndarray:
        return np.eye(3)


MARS = Planet(4.282828685e13, 3_393_940.0, 3_376_780.0, 0.0, "Mars")
"""Mars of thesis Table 3.3: non-rotating ellipsoid, spherical gravity, J2.. = 0."""

EARTH_WGS84 = Planet(3.986004418e14, 6_378_137.0, 6_356_752.314245, 0.0, "Earth")
"""Earth, WGS-84 ellipsoid with spherical gravity; set ``rotation_rate`` to 7.292115e-5 rad/s for a rotating Earth."""


@dataclass(frozen=True)
class StartFrame:
    """Local east/north/up frame at the start point: the coordinate frame of every simulation.

    Parameters
    ----------
    planet : Planet
    latitude_deg, longitude_deg : float
        Geodetic latitude and longitude of the start point (deg).
    """

    planet: Planet | FlatPlanet
    latitude_deg: float
    longitude_deg: float
    origin: np.ndarray = field(init=False, repr=False)
    axes: np.ndarray = field(init=False, repr=False)
    _plain: tuple = field(init=False, repr=False, compare=False)   # origin and axes as floats, for altitude_scalar
    _gravity_plain: tuple = field(init=False, repr=False, compare=False)  # (mu, centre) or (0, uniform g), floats
    _normal: tuple | None = field(init=False, repr=False, compare=False)  # normal_gravity_parameters (or None)
    _frame: np.ndarray = field(init=False, repr=False, compare=False)     # kernel_frame

    def __post_init__(self):
        object.__setattr__(self, "origin", self.planet.cartesian(self.latitude_deg, self.longitude_deg, 0.0))
        object.__setattr__(self, "axes", self.planet.enu_axes(self.latitude_deg, self.longitude_deg))
        object.__setattr__(self, "_plain", (*self.origin.tolist(), *self.axes.ravel().tolist()))
        if isinstance(self.planet, FlatPlanet):
            gravity = (0.0, (0.0, 0.0, -float(self.planet.gravity_acceleration)))
        else:
            gravity = (float(self.planet.gravitational_parameter), tuple(self.planet_center.tolist()))
        normal = None if isinstance(self.planet, FlatPlanet) else self.planet.normal
        if normal is not None:
            gravity = (0.0, (0.0, 0.0, 0.0))   # no spherical or uniform part
            axis = self.axes.T @ np.array([0.0, 0.0, 1.0])
            normal = (*self.planet_center.tolist(), *axis.tolist(), float(normal.equatorial_radius),
                      float(normal.polar_radius), float(normal.equator_and_pole[0]), float(normal.k), float(normal.m),
                      abs(float(self.planet.rotation_rate)))
        object.__setattr__(self, "_gravity_plain", gravity)
        object.__setattr__(self, "_normal", normal)
        flat = isinstance(self.planet, FlatPlanet)
        semi_axes = (1.0, 1.0) if flat else (self.planet.equatorial_radius, self.planet.polar_radius)
        object.__setattr__(self, "_frame", np.array([*self._plain, *semi_axes, 1.0 if flat else 0.0]))

    @property
    def planet_center(self) -> np.ndarray:
        """Position of the planet centre in start-frame coordinates (m)."""
        return -(self.axes.T @ self.origin)

    @property
    def rotation_vector(self) -> np.ndarray:
        """Planet angular velocity in start-frame components (rad/s)."""
        return self.planet.rotation_rate * self.axes.T @ np.array([0.0, 0.0, 1.0])

    def local_position(self, altitude: float, east: float, north: float) -> np.ndarray:
        """Start-frame position (m) of the point ``east``/``north`` (m) along the start point's axes whose geodetic
        altitude is ``altitude`` (m): the inverse of how results report east, north and altitude."""
        up = float(altitude)
        for _ in range(6):  # d(altitude)/d(up) = 1 - O(east/R): converges to machine precision in 2-3 passes
            up += altitude - float(self.altitude(np.array([east, north, up])))
        return np.array([east, north, up], dtype=float)

    def to_planet(self, local) -> np.ndarray:
        """Planet-centred inertial positions (m) of start-frame positions (m), shape (..., 3)."""
        return self.origin + np.asarray(local, dtype=float) @ self.axes.T

    def to_planet_fixed(self, local, time) -> np.ndarray:
        """Start-frame coordinates (m) of inertial start-frame positions ``local`` carried back by the planet's
        rotation over ``time`` (s): the position relative to the ground (identity for a non-rotating planet)."""
        local = np.asarray(local, dtype=float)
        if self.planet.rotation_rate == 0.0:
            return local
        return self.planet_center + _rotate(local - self.planet_center, self.rotation_vector,
                                            -np.asarray(time, dtype=float))

    def velocity_to_planet_fixed(self, local, velocity, time) -> np.ndarray:
        """Velocity relative to the ground (m/s) in start-frame axes, from inertial position and velocity."""
        velocity = np.asarray(velocity, dtype=float)
        if self.planet.rotation_rate == 0.0:
            return velocity
        relative = velocity - np.cross(self.rotation_vector, np.asarray(local, float) - self.planet_center)
        return _rotate(relative, self.rotation_vector, -np.asarray(time, dtype=float))

    def inertial_velocity(self, local, ground_velocity) -> np.ndarray:
        """Inertial velocity (m/s) at t = 0 of a point moving at ``ground_velocity`` (m/s) relative to the planet."""
        return np.asarray(ground_velocity, float) + np.cross(self.rotation_vector,
                                                             np.asarray(local, float) - self.planet_center)

    def altitude(self, local) -> np.ndarray:
        """Geodetic altitude (m) of start-frame positions (m), shape (..., 3)."""
        return self.planet.altitude(self.to_planet(local))

    def down(self, local) -> np.ndarray:
        """Unit vectors along gravity (start-frame axes) at start-frame positions (m), shape (..., 3): the plumb
        line a hanging body settles to (toward the planet centre; straight down on a flat planet). The planet's
        rotation is left out (0.1 deg on Earth); with normal gravity it is the ellipsoid normal, rotation included."""
        local = np.asarray(local, dtype=float)
        if isinstance(self.planet, FlatPlanet):
            return np.broadcast_to(np.array([0.0, 0.0, -1.0]), local.shape).copy()
        if self._normal is not None:   # along normal gravity: the plumb line of a body at rest on the ground
            at_rest = (*self._normal[:-1], 0.0)
            flat = local.reshape(-1, 3)
            g = np.array([normal_gravity(*at_rest, *map(float, point)) for point in flat]).reshape(local.shape)
            return g / np.linalg.norm(g, axis=-1, keepdims=True)
        toward = self.planet_center - local
        return toward / np.linalg.norm(toward, axis=-1, keepdims=True)

    def altitude_scalar(self, x: float, y: float, z: float) -> float:
        """Geodetic altitude (m) of one start-frame position (m) (``start_altitude``: what the per-stage kernels
        compute)."""
        return _start_altitude(self.kernel_frame, float(x), float(y), float(z))

    @property
    def kernel_frame(self) -> np.ndarray:
        """The frame as the compiled kernels take it (FRAME_COLUMNS)."""
        return self._frame


    def gravity_scalar(self, x: float, y: float, z: float) -> tuple:
        """Gravitational acceleration (m/s^2, start-frame axes) at one start-frame position (m), in plain floats:
        -mu r / |r|^3 with r from the planet centre, the flat planet's uniform g (``gravity_acceleration``), or
        normal gravity (``gravity.normal_gravity``, less the frame's centrifugal term when the frame is inertial)."""
        if self._normal is not None:
            return _normal_gravity(*self._normal, float(x), float(y), float(z))
        mu, vector = self._gravity_plain
        return gravity_acceleration(mu, *vector, x, y, z)

    def gravity_parameters(self) -> tuple:
        """(mu in m^3/s^2, planet centre in m) or (0, uniform g in m/s^2): ``gravity_acceleration``'s first
        arguments; (0, 0, 0, 0) with normal gravity (``normal_gravity_parameters`` then)."""
        mu, vector = self._gravity_plain
        return mu, *vector

    def normal_gravity_parameters(self) -> tuple | None:
        """Normal gravity as ``gravity.normal_gravity``'s first arguments (``gravity.NORMAL_COLUMNS`` floats), the
        frame rotation's rate last; None with spherical or uniform gravity."""
        return self._normal


@kernel
def gravity_acceleration(mu, vx, vy, vz, x, y, z):
    """Gravitational acceleration (m/s^2) at the start-frame point (x, y, z) (m): -mu r / |r|^3 with r from the
    planet centre (vx, vy, vz) when mu (m^3/s^2) > 0, else the uniform (vx, vy, vz)."""
    if mu == 0.0:
        return vx, vy, vz
    rx, ry, rz = x - vx, y - vy, z - vz
    scale = -mu / (rx * rx + ry * ry + rz * rz) ** 1.5
    return rx * scale, ry * scale, rz * scale


@kernel
def engine_gravity_force(mu, mass, cx, cy, cz, x, y, z):
    """The gravitational force (N) on a mass ``mass`` (kg) at (x, y, z) (m) from a planet of ``mu`` (m^3/s^2)
    centred at (cx, cy, cz) (m), -mu m r / |r|^3, in the order of operations of the engine's own gravity connector
    (Exudyn's ObjectConnectorGravity with masses 1 and m): a kernel that applies it in the connector's stead adds
    the same bits (``engine.stage.Stage``, tests/integration/test_fast_path.py)."""
    rx, ry, rz = x - cx, y - cy, z - cz
    length = math.sqrt(rx * rx + ry * ry + rz * rz)
    length2_inverse = 1.0 / (length * length)
    length_inverse = 1.0 / length
    force = mu * (1.0 * mass) * length2_inverse
    return -(force * (length_inverse * rx)), -(force * (length_inverse * ry)), -(force * (length_inverse * rz))


def _rotate(vectors, axis_rate, time):
    """Rotate ``vectors`` (..., 3) about the axis of ``axis_rate`` by the angle |axis_rate| * time (Rodrigues)."""
    rate = np.linalg.norm(axis_rate)
    k = axis_rate / rate
    angle = rate * np.asarray(time)[..., None]
    c, s = np.cos(angle), np.sin(angle)
    kv = np.cross(k, vectors)
    kdot = (vectors @ k)[..., None]
    return vectors * c + kv * s + kdot * k * (1.0 - c)


_start_altitude = bound(start_altitude)   # ``StartFrame.altitude_scalar``: per stage for a canopy's apparent mass
_normal_gravity = bound(normal_gravity)   # ``StartFrame.gravity_scalar``: the engine's normal-gravity loads per stage

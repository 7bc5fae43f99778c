"""The computed air release point: the release position (east, north of the start frame, at the release altitude)
from which the full simulation lands the load on a target.

The landing point is L(x) = x + d(x), x the release position and d the drift from it. Winds vary with height only,
so d hardly depends on x (on a curved planet by O(|x| / R)), and the miss m(x) = L(x) - target has a Jacobian close
to the identity. The solve is Broyden's method on m(x) = 0 from J = I: the first step is the fixed point
x1 = target - d(x0), and each later run corrects J by its secant (the "good" update), so that a few runs suffice.
Every run is a full simulation of the case moved to x (``placement.moved``); its landing point is the vehicle's
centre of mass at the ground, interpolated in time at the run's touchdown (``touchdown_point``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field

import numpy as np

from ..boundary import check_overrides, load_case
from ..errors import CaseError, InputError
from ..registries.columns import column
from ..run.simulation import simulate
from .placement import (
    check_site,
    has_site,
    local_to_site,
    merged_data,
    moved,
    parsed_overrides,
    site_to_local,
    vehicle_start,
)

DEFAULT_TOLERANCE = 0.1   # m: the miss distance at which the solve stops
DEFAULT_MAX_RUNS = 10     # full runs at most


@dataclass(frozen=True)
class Iteration:
    """One run of the solve: its release position, landing point (m, start frame) and miss distance (m)."""

    run: int
    release_east: float
    release_north: float
    landing_east: float
    landing_north: float
    miss: float


@dataclass(frozen=True)
class ReleasePoint:
    """The solved release point (lengths in m in the start frame, angles in deg, speeds in m/s).

    ``release_east``/``release_north`` is the vehicle's centre of mass at the release, at ``altitude`` (m,
    geodetic); ``drift_east``/``drift_north`` its landing point's offset from there on the last run; ``miss`` that
    run's distance from the target; ``overrides`` the case keys that start the case there (with the user's own);
    ``latitude_deg``/``longitude_deg`` of the release and of the target when the case has a site.
    """

    case: str
    target_east: float
    target_north: float
    release_east: float
    release_north: float
    altitude: float
    airspeed: float
    heading_deg: float
    flight_path_deg: float
    drift_east: float
    drift_north: float
    miss: float
    tolerance: float
    converged: bool
    touchdown_time: float
    iterations: tuple
    overrides: dict = field(repr=False)
    latitude_deg: float | None = None
    longitude_deg: float | None = None
    target_latitude_deg: float | None = None
    target_longitude_deg: float | None = None

    def to_dict(self) -> dict:
        """The JSON form (strict: every number finite or null)."""
        data = asdict(self)
        data["iterations"] = [asdict(i) for i in self.iterations]
        del data["overrides"]
        return data


def touchdown_point(result) -> tuple:
    """(east, north) (m, start frame) of the vehicle's centre of mass at the run's touchdown time: its history
    interpolated linearly between the samples around the crossing (the run stops at the end of the step that
    reached the ground, up to a step's travel beyond it); InputError for a run that did not land."""
    touchdown = result.summary.touchdown
    if touchdown is None:
        raise InputError(f"the run of case {result.summary.case!r} ended at {result.summary.final.time:g} s without "
                         "reaching the ground: raise simulation.duration (--set simulation.duration=...)")
    time = result.time
    return tuple(float(np.interp(touchdown.time, time, result[column(name, result.vehicle)]))
                 for name in ("{owner}_east", "{owner}_north"))


AIRCRAFT_FLAGS = {"start.release.airspeed": "--airspeed", "start.release.heading_deg": "--heading-deg"}


def _check_aircraft(path, overrides: dict, given: dict) -> None:
    """The case with the aircraft's options (``given``: flag -> value) loads; else InputError naming the flag."""
    try:
        load_case(path, overrides)
    except CaseError as exc:
        flag = AIRCRAFT_FLAGS.get(exc.field)
        if flag is None or given.get(flag) is None:
            raise
        raise InputError(f"{flag} = {given[flag]:g}: {exc.detail}") from None


class _Problem:
    """The case, its aircraft and the runs of the solve."""

    def __init__(self, path, entries, airspeed, heading_deg, altitude):
        self.path = path
        entries = check_overrides(entries)
        self.user = dict(entries) if isinstance(entries, Mapping) else parsed_overrides(entries)
        base = load_case(path, dict(self.user))
        if base.release is None:
            raise InputError(f"case {path}: no [start.release]: a release point is for a load released from an "
                             "aircraft (give [start.release] airspeed and heading_deg)")
        self.base = base
        aircraft = {key: float(value) for key, value in (("start.release.airspeed", airspeed),
                                                           ("start.release.heading_deg", heading_deg))
                    if value is not None}
        data = merged_data(path, {**self.user, **aircraft})
        east, north, start_altitude = vehicle_start(data, base.vehicle)
        if altitude is not None and start_altitude is None:
            raise InputError(f"--altitude: case {path} starts its vehicle from flight conditions, not an altitude")
        if altitude is not None and not (math.isfinite(altitude) and altitude > base.simulation.ground_altitude):
            raise InputError(f"--altitude = {altitude:g}: must be a finite altitude (m) above the ground "
                             f"({base.simulation.ground_altitude:g} m, simulation.ground_altitude)")
        self.aircraft = {**aircraft, **moved(data, 0.0, 0.0, 0.0 if altitude is None else
                                             float(altitude) - float(start_altitude))}
        _check_aircraft(path, {**self.user, **self.aircraft}, {"--airspeed": airspeed, "--heading-deg": heading_deg})
        self.data = merged_data(path, {**self.user, **self.aircraft})
        self.origin = np.array([east, north])
        self.runs = 0

    def overrides(self, release) -> dict:
        """The case keys that release the vehicle at ``release`` (east, north; m)."""
        shift = np.asarray(release, float) - self.origin
        return {**self.user, **self.aircraft, **moved(self.data, float(shift[0]), float(shift[1]))}

    def landing(self, release) -> tuple:
        """(landing point (east, north; m), the run's Result) of a run released at ``release``."""
        case = load_case(self.path, self.overrides(release))
        self.runs += 1
        result = simulate(case)
        return np.array(touchdown_point(result)), result


def solve_release_point(path, target_east: float | None = None, target_north: float | None = None, *,
                        target_latitude_deg: float | None = None, target_longitude_deg: float | None = None,
                        overrides=(), airspeed: float | None = None, heading_deg: float | None = None,
                        altitude: float | None = None, tolerance: float = DEFAULT_TOLERANCE,
                        max_runs: int = DEFAULT_MAX_RUNS, report=None) -> ReleasePoint:
    """Solve the release point of case file ``path`` for a target on the ground.

    Parameters
    ----------
    path : path
        A case file with a ``[start.release]``.
    target_east, target_north : float
        The target (m, start frame); or ``target_latitude_deg``, ``target_longitude_deg`` (deg) for a case with a
        site.
    overrides : list of "key=value" str, or a mapping of dotted keys to values
        As ``pchute run --set`` (``load_case``'s).
    airspeed, heading_deg, altitude : float, optional
        The aircraft's airspeed (m/s), heading (deg clockwise from north) and the release altitude (m, geodetic, of
        the vehicle's centre of mass); default: the case's.
    tolerance : float
        Miss distance (m, > 0) at which the solve stops.
    max_runs : int
        Full runs at most (>= 1).
    report : callable, optional
        Receives each ``Iteration`` as its run ends (the command prints it).

    Returns
    -------
    ReleasePoint
        ``converged`` False when ``max_runs`` runs left a miss above ``tolerance``.
    """
    if not (isinstance(tolerance, (int, float)) and math.isfinite(tolerance) and tolerance > 0.0):
        raise InputError(f"tolerance = {tolerance!r}: must be a distance in m > 0")
    if isinstance(max_runs, bool) or not isinstance(max_runs, int) or max_runs < 1:
        raise InputError(f"max_runs = {max_runs!r}: must be an integer >= 1")
    problem = _Problem(path, overrides, airspeed, heading_deg, altitude)
    target = _target(problem, target_east, target_north, target_latitude_deg, target_longitude_deg)
    release, jacobian, iterations = problem.origin.copy(), np.eye(2), []
    landing, result = problem.landing(release)
    miss = landing - target
    while True:
        iterations.append(Iteration(problem.runs, *release.tolist(), *landing.tolist(), float(np.hypot(*miss))))
        if report is not None:
            report(iterations[-1])
        if iterations[-1].miss <= tolerance or problem.runs >= max_runs:
            break
        step = -np.linalg.solve(jacobian, miss)
        release = release + step
        landing, result = problem.landing(release)
        new_miss = landing - target
        jacobian = jacobian + np.outer(new_miss - miss - jacobian @ step, step) / float(step @ step)
        miss = new_miss
    return _release_point(problem, target, release, landing, result, iterations, tolerance)


def _target(problem: _Problem, east, north, latitude, longitude) -> np.ndarray:
    """The target (east, north; m) from one complete pair of the given coordinates."""
    pairs = {"--target-east/--target-north": (east, north),
             "--target-latitude/--target-longitude": (latitude, longitude)}
    given = [name for name, pair in pairs.items() if any(v is not None for v in pair)]
    if not given:
        raise InputError("no target: give --target-east and --target-north (m, start frame) or, for a case with a "
                         "site, --target-latitude and --target-longitude (deg)")
    if len(given) > 1:
        raise InputError("give the target once: --target-east/--target-north or --target-latitude/"
                         "--target-longitude, not both")
    pair = pairs[given[0]]
    names = given[0].split("/")
    for name, value in zip(names, pair):
        if value is None:
            raise InputError(f"{name} is missing: the target needs {' and '.join(names)}")
        if not (isinstance(value, (int, float)) and math.isfinite(value)):
            raise InputError(f"{name} = {value!r}: must be a finite number")
    if latitude is None:
        return np.array([float(east), float(north)])
    check_site(problem.base, problem.data, names[0])
    if not -90.0 <= latitude <= 90.0:
        raise InputError(f"--target-latitude = {latitude:g}: must be from -90 to 90 deg")
    ground = problem.base.simulation.ground_altitude
    return np.array(site_to_local(problem.base.start, float(latitude), float(longitude), ground))


def _release_point(problem: _Problem, target, release, landing, result, iterations, tolerance) -> ReleasePoint:
    start = problem.base.start
    loaded = load_case(problem.path, problem.overrides(release))
    altitude = loaded.bodies[loaded.vehicle].initial.altitude
    site = {}
    if has_site(problem.base, problem.data):
        ground = problem.base.simulation.ground_altitude
        site = dict(zip(("latitude_deg", "longitude_deg"), local_to_site(start, *release.tolist(), altitude)))
        site.update(zip(("target_latitude_deg", "target_longitude_deg"), local_to_site(start, *target.tolist(),
                                                                                       ground)))
    drift = landing - release
    return ReleasePoint(
        case=str(problem.path), target_east=float(target[0]), target_north=float(target[1]),
        release_east=float(release[0]), release_north=float(release[1]), altitude=float(altitude),
        airspeed=loaded.release.airspeed, heading_deg=loaded.release.heading_deg,
        flight_path_deg=loaded.release.flight_path_deg, drift_east=float(drift[0]), drift_north=float(drift[1]),
        miss=iterations[-1].miss, tolerance=float(tolerance), converged=iterations[-1].miss <= tolerance,
        touchdown_time=float(result.summary.touchdown.time), iterations=tuple(iterations),
        overrides=problem.overrides(release), **site)

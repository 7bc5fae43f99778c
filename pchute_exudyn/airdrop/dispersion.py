"""The landing footprint around a release point: a Monte Carlo study (``study``: its runner, its footprint
statistics, its bootstrap) of the case started at the release point.

The dispersions are study parameters on the release case's keys: each wind key of [atmosphere.wind] (east, north or
speed) scaled by a normal factor (1, ``wind``), a ``from_deg`` turned by a normal angle (0, ``direction``), each
canopy's axial coefficient (its drag area) by a normal factor (1, ``drag``), and the vehicle's release east and
north drawn normal about the release point (``release``, m; a timing error dt at ground speed V belongs in it as
V dt along the track). Or a study file of the user's, run with the release case in place of its own.

Each run's touchdown point is the solve's: interpolated at its touchdown time from its history, which the study keeps.
The footprint's centre is the mean touchdown point; its 95 % interval is the percentile bootstrap of that mean
(``study.statistics.bootstrap_mean_interval``), per axis; the target is inside it when it lies within both,
each widened by the solve's tolerance (the undispersed run lands only that close to the target).
"""

from __future__ import annotations

import math
import shutil
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..boundary import load_case
from ..errors import InputError
from ..registries.columns import column
from ..results.io import atomic_write_text
from ..results.result import Result
from ..study.footprint import MINIMUM_RUNS, footprint_statistics
from ..study.report import load_table
from ..study.runner import run_study
from ..study.spec import SAMPLINGS, load_study
from ..study.statistics import bootstrap_mean_interval
from .placement import initial_tables, merged_data
from .release_files import CASE_FILE
from .release_point import touchdown_point

DEFAULT_WIND_ERROR = 0.15
"""Relative 1-sigma scale of each wind key by default (-)."""
DEFAULT_DIRECTION_ERROR = 10.0
"""1-sigma turn (deg) of a wind given as speed and from_deg, by default."""
WIND_KEYS = ("east", "north", "speed")
"""Keys of [atmosphere.wind] a dispersion scales (a from_deg is turned)."""
STUDY_FILE = "footprint_study.toml"
STUDY_FOLDER = "monte_carlo"


@dataclass(frozen=True)
class Dispersion:
    """The Monte Carlo's spread (one standard deviation each; 0 leaves the input alone).

    Attributes
    ----------
    runs : int
        Runs (>= MINIMUM_RUNS).
    wind : float
        Relative scale of each wind key (-; 0.15: 15 %); None: DEFAULT_WIND_ERROR where the case has a wind, else
        none (a scale given for a case without wind is refused: it would disperse nothing).
    drag : float
        Relative scale of each canopy's axial coefficient, i.e. its drag area (-).
    release : float
        Release position error per horizontal axis (m).
    seed : int
        The study's seed (>= 0).
    sampling : str
        How the draws are spread (``study.spec.SAMPLINGS``): a Latin hypercube by default, whose every marginal is
        stratified, so that a few runs give the centre (the bootstrap, which treats the runs as independent, is then
        on the safe side).
    direction : float or None
        The 1-sigma turn (deg) of a wind given as ``speed`` and ``from_deg``; None: DEFAULT_DIRECTION_ERROR where the
        case's wind has them, else none (given for a case without them: refused).
    """

    runs: int
    wind: float | None = None
    drag: float = 0.05
    release: float = 5.0
    seed: int = 1
    sampling: str = "latin_hypercube"
    direction: float | None = None

    def check(self) -> None:
        """InputError naming the option of the first value out of its range."""
        if isinstance(self.runs, bool) or not isinstance(self.runs, int) or self.runs < MINIMUM_RUNS:
            raise InputError(f"--runs = {self.runs!r}: must be an integer >= {MINIMUM_RUNS} (a footprint needs a "
                             "covariance)")
        for flag, value in (("--wind-error", DEFAULT_WIND_ERROR if self.wind is None else self.wind),
                            ("--wind-direction-error", DEFAULT_DIRECTION_ERROR if self.direction is None
                             else self.direction), ("--drag-error", self.drag),
                            ("--release-error", self.release)):
            if isinstance(value, bool) or not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise InputError(f"{flag} = {value!r}: must be a finite standard deviation >= 0")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise InputError(f"--seed = {self.seed!r}: must be an integer >= 0")
        if self.sampling not in SAMPLINGS:
            raise InputError(f"--sampling = {self.sampling!r}: must be one of {', '.join(SAMPLINGS)}")


    def wind_parameters(self, data: dict, case) -> list:
        """The study parameters (key, distribution, relative, description) of the case's [atmosphere.wind] (merged
        ``data`` of case file ``case``): a factor on each key not zero, a turn of a ``from_deg``; InputError when an
        error was given for a case without what it disperses."""
        wind = data.get("atmosphere", {}).get("wind", {})
        blowing = [key for key in WIND_KEYS if np.any(np.asarray(wind.get(key, 0.0), float) != 0.0)]
        turning = "from_deg" in wind and "speed" in blowing
        for flag, value, found, what in (("--wind-error", self.wind, blowing, "wind to scale"),
                                         ("--wind-direction-error", self.direction, turning, "from_deg to turn")):
            if value is not None and value > 0.0 and not found:
                raise InputError(f"{flag} = {value:g}: case {case} has no {what} ([atmosphere.wind] absent, zero or "
                                 f"without it; a sounding's wind is not dispersed): give {flag} 0")
        scale = DEFAULT_WIND_ERROR if self.wind is None else self.wind
        turn = DEFAULT_DIRECTION_ERROR if self.direction is None else self.direction
        parameters = [(f"atmosphere.wind.{key}", {"mean": 1.0, "std": scale}, True, f"wind {key} x N(1, {scale:g})")
                      for key in blowing if scale > 0.0]
        if turning and turn > 0.0:
            parameters.append(("atmosphere.wind.from_deg", {"mean": float(wind["from_deg"]), "std": turn}, False,
                               f"wind from_deg + N(0, {turn:g} deg)"))
        return parameters


@dataclass(frozen=True)
class Footprint:
    """The touchdown points' statistics (``study.footprint.footprint_statistics``: mean, covariance, ellipses, in
    m and m^2), the bootstrap 95 % interval of the centre (m, per axis: ((east low, east high), (north low, north
    high))), whether the target lies in it, the touchdown points (m), the run counts and the study's folder
    (relative to the release point's)."""

    statistics: dict
    centre_interval: tuple
    target_inside: bool
    points: tuple
    runs: int
    failed: int
    folder: str
    dispersions: tuple

    def to_dict(self) -> dict:
        """The JSON form: the centre and its interval (m) first, then the statistics and the points."""
        (east_low, east_high), (north_low, north_high) = self.centre_interval
        return {"centre_east": self.statistics["mean_east"], "centre_north": self.statistics["mean_north"],
                "centre_interval_95": {"east": [east_low, east_high], "north": [north_low, north_high]},
                "target_inside_interval": self.target_inside, "runs": self.runs, "failed": self.failed,
                "dispersions": list(self.dispersions), "statistics": self.statistics,
                "touchdown_points": [list(p) for p in self.points], "study_folder": self.folder}


def dispersion_study_text(case_file: Path, dispersion: Dispersion, release) -> tuple:
    """(study file text, the dispersed keys described) for ``dispersion`` of the release case ``case_file`` whose
    vehicle is released at ``release`` (a ``ReleasePoint``)."""
    case = load_case(case_file)
    data = merged_data(case_file, {})
    parameters = []   # (key, distribution keys, description)
    parameters += dispersion.wind_parameters(data, release.case)
    if dispersion.drag > 0.0:
        for canopy in dict.fromkeys(c for system in case.systems.values() for c in system.canopies):
            if "axial_coefficient" in data["bodies"][canopy].get("aerodynamics", {}):
                parameters.append((f"bodies.{canopy}.aerodynamics.axial_coefficient",
                                   {"mean": 1.0, "std": dispersion.drag}, True,
                                   f"{canopy} drag area x N(1, {dispersion.drag:g})"))
    if dispersion.release > 0.0:
        others = [prefix for prefix in initial_tables(data) if prefix != f"bodies.{case.vehicle}.initial"]
        if others:
            raise InputError(f"--release-error: case {release.case} also places {others[0]} at the start; a "
                             "release error moves the vehicle alone: give --release-error 0")
        for axis, mean in (("east", release.release_east), ("north", release.release_north)):
            parameters.append((f"bodies.{case.vehicle}.initial.{axis}", {"mean": mean, "std": dispersion.release},
                               False, f"release {axis} + N(0, {dispersion.release:g} m)"))
    if not parameters:
        raise InputError("the Monte Carlo has nothing to disperse: no wind to scale, no canopy drag and no release "
                         "error (give --wind-error, --drag-error or --release-error > 0)")
    lines = ["# the landing footprint around the release point (pchute release-point)", "[study]",
             'name = "release point footprint"', f'case = "{case_file.name}"', f"runs = {dispersion.runs}",
             f"seed = {dispersion.seed}", f'sampling = "{dispersion.sampling}"',
             "histories = true   # read for each run's touchdown point, then removed", ""]
    for key, values, relative, _ in parameters:
        lines += [f'[parameters."{key}"]', 'distribution = "normal"',
                  *(f"{name} = {float(value)!r}" for name, value in values.items()),
                  f"relative = {'true' if relative else 'false'}", ""]
    return "\n".join(lines), tuple(p[3] for p in parameters)


def landing_points(study_folder: Path) -> np.ndarray:
    """(n, 2) touchdown points (east, north; m) of the study's ok runs that landed, each interpolated at its
    touchdown time from its kept history (``release_point.touchdown_point``: the solve's own landing point, not the
    end of the step that reached the ground, which runs.csv's final_east and final_north hold)."""
    rows = [row for row in load_table(study_folder) if row.get("status") == "ok"
            and isinstance(row.get(column("touchdown_time")), float)]
    histories = study_folder / "histories"
    points = np.array([touchdown_point(Result.load(histories / f"run_{int(row['run']):05d}")) for row in rows],
                      float).reshape(-1, 2)
    shutil.rmtree(histories, ignore_errors=True)   # 1-2 MB a run, and the points are kept in the JSON
    return points


def one_case_study(study_file):
    """The study file ``study_file`` read (``study.spec.load_study``), refused (InputError) unless it runs one case
    file, which the release case replaces."""
    spec = load_study(study_file)
    if len(spec.cases) != 1:
        raise InputError(f"--monte-carlo {study_file}: the study runs {len(spec.cases)} case files; a release "
                         "point's footprint runs one, the release case")
    return spec


def release_footprint(folder, release, dispersion: Dispersion | None = None, study_file=None, workers=None,
                      progress: bool = False) -> Footprint:
    """Run the Monte Carlo around ``release`` (a ``ReleasePoint``) in ``folder``, which holds its release case
    (``release_files.CASE_FILE``): the ``dispersion`` study, or the study file ``study_file`` with the release case
    as its case; its folder is ``folder``/monte_carlo."""
    folder = Path(folder)
    case_file = folder / CASE_FILE
    if study_file is not None:
        spec = replace(one_case_study(study_file), cases=(case_file.resolve(),), histories=True)
        described = tuple(p.key for p in spec.parameters)
    elif isinstance(dispersion, Dispersion):
        dispersion.check()
        text, described = dispersion_study_text(case_file, dispersion, release)
        atomic_write_text(folder / STUDY_FILE, text)
        spec = load_study(folder / STUDY_FILE)
    else:
        raise InputError(f"dispersion = {dispersion!r}: give a Dispersion, or a study file (study_file)")
    outcome = run_study(spec, folder / STUDY_FOLDER, workers=workers, progress=progress)
    points = landing_points(folder / STUDY_FOLDER)
    if len(points) < MINIMUM_RUNS:
        raise InputError(f"only {len(points)} of the {outcome.planned} Monte Carlo runs touched down: a footprint "
                         f"needs {MINIMUM_RUNS} (see {folder / STUDY_FOLDER / 'runs.csv'})")
    interval = bootstrap_mean_interval(points)
    target = (release.target_east, release.target_north)
    # widened by the solve's tolerance: the undispersed run itself lands only that close
    inside = all(low - release.tolerance <= t <= high + release.tolerance for (low, high), t in zip(interval, target))
    return Footprint(footprint_statistics(points), tuple(tuple(map(float, axis)) for axis in interval), bool(inside),
                     tuple(tuple(map(float, p)) for p in points), int(outcome.planned), int(outcome.failed),
                     STUDY_FOLDER, described)

"""Recorded reference runs: numbers written once from real runs, which the tests compare real runs with.

* The runs whose results must not change when the canopy physics beyond the thesis is absent or switched off:
  MER cases 1-6 (SP, equilibrium point and implicit full mass over 10 s) and PA1 (SP to touchdown, implicit full mass
  for 20 s), in tests/data/reference_runs.json. ``python tests/reference_runs.py OUT.json`` records them with the
  code it imports (run it from a checkout of the version to keep as the reference);
  ``tests/acceptance/test_canopy_physics.py`` reruns them and asks for the same events and numbers within 1e-9
  relative (``largest_difference``).
* MER case 1 over 60 s, full mass, RK4 at the thesis's step 1e-4 s (``CASE1_RK4``): the reference SP, the
  equilibrium point, implicit full mass and RK4 at twice the step are compared with (tests/acceptance/test_sp.py,
  test_full_model.py, test_chapter2_engine.py; the ``case1_rk4_reference`` fixture). Its time series are read back,
  not rerun (the run takes 20-40 s). ``python tests/reference_runs.py --case1-rk4`` records it again with the code it
  imports; the slow test ``test_the_recorded_case1_reference_is_what_the_code_computes`` (tests/acceptance/
  test_full_model.py, ``python -m pytest -m slow``) reruns it and asks for the recorded numbers within 1e-9.
* The shipped rocket from apogee to 8 s past its drogue's deployment, full mass, RK4 at 1e-4 s, the canopy rigid
  (``ROCKET_DROGUE``): the figures the reduced drogue is compared with (tests/acceptance/test_reduced_canopy.py), read
  back instead of rerun (10-20 s). ``python tests/reference_runs.py --rocket-drogue`` records them again; the slow test
  ``test_the_recorded_rigid_drogue_reference_is_what_the_code_computes`` reruns it and asks for them within 1e-9.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np

if __name__ == "__main__":   # run as a script (python tests/reference_runs.py OUT.json): the repository root first
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.helpers import ROOT  # noqa: E402

RUNS = [(f"mer{c}_{method}_{integrator}", f"cases/mer/case{c}.toml", method, integrator, 10.0)
        for c in range(1, 7) for method, integrator in (("sp", "rk4"), ("equilibrium", "rk4"), ("full", "implicit"))]
RUNS += [("pa1_sp", "cases/cev_pa1.toml", "sp", "rk4", None), ("pa1_full_implicit", "cases/cev_pa1.toml", "full",
                                                                "implicit", 20.0)]
# full-mass RK4 runs added for issue 14, also recorded from commit 53493ef (6085d44, the commit before issue 14,
# gives the same numbers: checked when they were added)
RUNS += [("mer1_full_rk4", "cases/mer/case1.toml", "full", "rk4", 3.0),
         ("mer4_full_rk4", "cases/mer/case4.toml", "full", "rk4", 3.0),
         ("pa1_full_rk4", "cases/cev_pa1.toml", "full", "rk4", 12.0)]

TOLERANCE = {"rk4": 1e-9, "implicit": 1e-7}
"""Largest relative difference allowed from the recorded numbers. RK4 (the thesis's integrator, and SP): 1e-9, the
round-off of the compiled kernels and the one force item grown over a run. Implicit: 1e-7, because round-off in
the residual moves where Newton's iteration stops within its own tolerance (seen: 4.6e-9 in MER case 4)."""


PINNED = {"pa1_sp": ["simulation.sp.kappa_max=5.0"]}
"""Settings the reference was recorded with where the case's default has moved since (PA1's SP preset, issue 14)."""


def record(name, case_file, method, integrator, duration, overrides=()) -> dict:
    """The run's final values, peak tensions and events, as plain JSON values."""
    from pchute_exudyn import load_case, simulate
    overrides = [*PINNED.get(name, []), *overrides]
    result = simulate(load_case(ROOT / case_file, list(overrides)), method, integrator, duration=duration)
    return summary_record(result.summary)


def summary_record(summary, keys=("final", "peak_tension", "events")) -> dict:
    """``keys`` of a run's summary (``RunSummary``) as ``summary.json`` holds them, plain JSON values."""
    from pchute_exudyn.results.io import _finite
    written = summary.to_dict()   # the file's form: what the recording holds
    # NaN (a quantity absent at the end, e.g. a cut-away system) as None: strict JSON, as the result files write it
    return _finite({key: written[key] for key in keys})


def _leaves(value, path=""):
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _leaves(item, f"{path}/{key}")
    elif isinstance(value, list):
        for i, item in enumerate(value):
            yield from _leaves(item, f"{path}[{i}]")
    else:
        yield path, value


ADDED_SINCE = ("descent_rate", "horizontal_speed_over_ground")
"""Entries the code added after the recording (issue 48: the touchdown event's split along the local vertical): a
new record's leaf so named is left out where the recording has none; every recorded entry is still compared."""
ADDED_SINCE += ("altitude", "east", "north")
"""Issue 59: the touchdown event's interpolated place (the ground's altitude, east and north), left out alike."""
ADDED_SUFFIXES = ("_latitude", "_longitude")
"""Endings of entries added after the recording (issue 57: each body's latitude and longitude), left out alike."""


def _added_since(leaf: str) -> bool:
    return leaf in ADDED_SINCE or leaf.endswith(ADDED_SUFFIXES)


def largest_difference(got: dict, want: dict) -> tuple[float, str]:
    """The largest relative difference between two records (relative to max(|want|, 1) for numbers; infinite where
    the structure, a name or a missing value differs) and where it is; ``ADDED_SINCE`` entries of ``got`` that
    ``want`` lacks are not differences."""
    want_leaves = dict(_leaves(want))
    got_leaves = {path: value for path, value in _leaves(got)
                  if path in want_leaves or not _added_since(path.rsplit("/", 1)[-1])}
    if got_leaves.keys() != want_leaves.keys():
        return math.inf, f"keys {sorted(got_leaves.keys() ^ want_leaves.keys())}"
    worst = (0.0, "")
    for path, expected in want_leaves.items():
        value = got_leaves[path]
        numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (value, expected))
        difference = abs(value - expected) / max(abs(expected), 1.0) if numbers else \
            (0.0 if value == expected else math.inf)
        worst = max(worst, (difference, path))
    return worst


CASE1_RK4 = ROOT / "tests" / "data" / "mer1_full_rk4_1e-4_60s.npz"
"""MER case 1, 60 s, full mass, RK4 at 1e-4 s: time, vehicle altitude and every line tension on the 0.01 s output grid
(float64, as the run computed them), and in ``recorded`` (JSON) the summary's final values, peak tensions, events,
steps, versions, and the commit whose package code wrote it."""
CASE1_RK4_RUN = ("cases/mer/case1.toml", "full", "rk4", 1e-4)
CASE1_RK4_COLUMNS = ("time", "vehicle_altitude", "tension_bridle1", "tension_bridle2", "tension_bridle3",
                     "tension_riser")


def case1_rk4_run():
    """The real run the recording holds (20-40 s of wall time), with the code imported."""
    from pchute_exudyn import load_case, simulate
    case_file, method, integrator, step = CASE1_RK4_RUN
    return simulate(load_case(ROOT / case_file), method, integrator, step)


def _package_commit() -> str:
    """The last commit of pchute_exudyn/ in this checkout, '+modified' when its files differ from it."""
    def git(*args):
        return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    commit = git("log", "-1", "--format=%h", "--", "pchute_exudyn") or "unknown"
    return commit + ("+modified" if git("status", "--porcelain", "--", "pchute_exudyn") else "")


def record_case1_rk4(path=CASE1_RK4) -> None:
    """Run MER case 1 (``case1_rk4_run``) and write its columns and summary to ``path``."""
    result = case1_rk4_run()
    recorded = summary_record(result.summary, ("final", "peak_tension", "events", "steps", "versions"))
    recorded["package_commit"] = _package_commit()
    recorded["command"] = "python tests/reference_runs.py --case1-rk4"
    np.savez_compressed(path, **{name: np.asarray(result[name], dtype=float) for name in CASE1_RK4_COLUMNS},
                        recorded=np.array(json.dumps(recorded, allow_nan=False)))


class RecordedRun:
    """A recorded run read back with the part of ``Result``'s interface the tests use: ``time``, ``run[name]``,
    ``final(name)``, ``tension_names()``; ``recorded`` holds its summary."""

    def __init__(self, path):
        with np.load(path) as data:
            self.columns = {name: data[name] for name in data.files if name != "recorded"}
            self.recorded = json.loads(str(data["recorded"]))
        for column in self.columns.values():
            column.flags.writeable = False   # shared by the whole session: no test may change it

    @property
    def time(self) -> np.ndarray:
        return self.columns["time"]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    def __contains__(self, name: str) -> bool:
        return name in self.columns

    def final(self, name: str) -> float:
        return float(self.columns[name][-1])

    def tension_names(self) -> list:
        return [name for name in self.columns if name.startswith("tension_")]


@lru_cache(maxsize=1)
def case1_rk4_reference() -> RecordedRun:
    """The recorded MER case 1 full-mass RK4 1e-4 s run (``CASE1_RK4``)."""
    return RecordedRun(CASE1_RK4)


ROCKET_DROGUE = ROOT / "tests" / "data" / "rocket_drogue_full_rk4_1e-4_9s.json"
"""The shipped rocket (``ROCKET_DROGUE_RUN``), full mass, RK4 at 1e-4 s for 9 s, its drogue deployed at 1.01 s:
``rocket_drogue_figures`` of the run and the commit whose package code wrote them."""
ROCKET_DROGUE_RUN = ("cases/rocket/dual_deploy.toml", {"systems.drogue.deploy_trigger": {"time": 1.01}}, "full",
                     "rk4", 1e-4, 9.0)   # the deployment time as sampled at 100 Hz


def rocket_drogue_case():
    """The rocket case of ``ROCKET_DROGUE_RUN`` (the reduced drogue's test runs SP on it)."""
    from pchute_exudyn import load_case
    return load_case(ROOT / ROCKET_DROGUE_RUN[0], ROCKET_DROGUE_RUN[1])


def rocket_drogue_full_run():
    """The real full-mass run the recording holds (10-20 s of wall time), with the code imported."""
    from pchute_exudyn import simulate
    return simulate(rocket_drogue_case(), *ROCKET_DROGUE_RUN[2:])


def rocket_drogue_figures(result) -> dict:
    """What the reduced drogue is compared on: steps, the rocket's final descent rate (m/s) and altitude (m), the
    drogue riser's peak tension (N)."""
    return {"steps": int(result.summary.steps),
            "rocket_velocity_down": result.final("rocket_velocity_down"),
            "rocket_altitude": result.final("rocket_altitude"),
            "peak_tension_drogue_riser": float(np.nanmax(result["tension_drogue_riser"]))}


def record_rocket_drogue(path=ROCKET_DROGUE) -> None:
    """Run ``rocket_drogue_full_run`` and write its figures to ``path``."""
    recorded = {**rocket_drogue_figures(rocket_drogue_full_run()), "package_commit": _package_commit(),
                "command": "python tests/reference_runs.py --rocket-drogue"}
    path.write_text(json.dumps(recorded, indent=1, allow_nan=False) + "\n")


@lru_cache(maxsize=1)
def rocket_drogue_reference() -> dict:
    """The recorded figures of the rigid drogue's full-mass run (``ROCKET_DROGUE``)."""
    return json.loads(ROCKET_DROGUE.read_text())


if __name__ == "__main__":
    if sys.argv[1:2] == ["--rocket-drogue"]:
        record_rocket_drogue(Path(sys.argv[2]) if len(sys.argv) > 2 else ROCKET_DROGUE)
    elif sys.argv[1:2] == ["--case1-rk4"]:
        record_case1_rk4(Path(sys.argv[2]) if len(sys.argv) > 2 else CASE1_RK4)
    else:
        out = {name: record(name, *rest) for name, *rest in RUNS}
        Path(sys.argv[1]).write_text(json.dumps(out, indent=1, allow_nan=False) + "\n")

"""The result of a run: named time histories with units, a summary, and the files they are saved to.

Files written by ``Result.save`` (each atomically):

* ``timeseries.csv``: a header row of column names, first column ``time`` (s), then one row per sample;
* ``result.npz``: the same arrays plus ``units`` and ``summary`` (JSON strings), and the scene an animation draws
  (``scene/<name>`` arrays and ``scene`` JSON: ``outputs.scene``), when the run made one;
* ``summary.json``: case, method, integrator, step, duration, steps, wall time, final vehicle state, peak tensions,
  column units and the versions of this package, Exudyn, numpy and Python; and ``result_files``, the files of the
  folder the run wrote (all that a later ``overwrite`` replaces: ``io.result_files``);
* ``exudyn_solution_phase<k>.txt``: Exudyn's own solution file of each phase, when the run kept them
  (``simulate(engine_solution=True)``, ``pchute run --exudyn-solution``);
* ``overview.png``: line tensions, vehicle altitude and (when the run has them) its Mach number and dynamic pressure
  against time, with the run's events marked, and the rate of descent against altitude;
* ``ground_track.png``: the vehicle's track over the ground, north against east of the start point, events marked;
* ``loads.png``: each deployment's load (a system's risers, a tether) against time at every step kept, its snatch,
  opening load, Knacke's estimate and breaking strength marked (``plotting.plot_deployment_loads``), when the run
  has deployments; their histories are ``loads/<name>/time`` and ``loads/<name>/load`` in ``result.npz``.

``pchute map`` adds ``map.kml``, ``map.geojson``, ``map.gpx`` and ``map.html`` to a result folder later
(``run_map.write_run_map``), listed in its ``result_files`` with the rest.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..registries.columns import UNNAMED_VEHICLE, owner
from . import rocketpy_export
from .csv_dialects import map_columns, parse_column_map  # noqa: F401  (parse_column_map: API)
from .io import (
    FILES_KEY,
    BackgroundSyncs,
    atomic_write_text,
    atomic_writer,
    check_result_folder,
    json_text,
    staged_folder,
)
from .number_text import table_text
from .summary import RunSummary

CSV_NAME, NPZ_NAME, SUMMARY_NAME, PLOT_NAME = "timeseries.csv", "result.npz", "summary.json", "overview.png"
LOADS_NAME, LOADS = "loads.png", "loads"
"""The loads figure's file, and the prefix of the load histories' arrays in ``result.npz`` (``loads/<name>/...``)."""
TRACK_NAME = "ground_track.png"
SCENE = "scene"
"""Key of the scene description in ``result.npz``; its arrays are ``scene/<name>``."""


def load_scene(folder) -> tuple[np.ndarray, dict, dict]:
    """Sample times (s), scene arrays and description from a result folder's ``result.npz`` (InputError when the
    folder has none: a result saved before scenes were stored, a study's scalar record, or a CSV)."""
    path = Path(folder) / NPZ_NAME
    if not Path(folder).is_dir():
        raise InputError(f"{folder}: not a folder: give the result folder of `pchute run`")
    if not path.is_file():
        raise InputError(f"{folder}: no {NPZ_NAME}: not a result folder of `pchute run`")
    data = read_npz(path, lambda key: key in ("time", SCENE) or key.startswith(SCENE + "/"))
    if SCENE not in data:
        raise InputError(f"{folder}: {NPZ_NAME} holds no scene (body attitudes and attach points); rerun the case "
                         "with this version to animate it")
    arrays = {k[len(SCENE) + 1:]: v for k, v in data.items() if k.startswith(SCENE + "/")}
    try:
        description = json.loads(str(data[SCENE]))
    except (ValueError, RecursionError):
        description = None
    missing = _scene_gap(description, arrays) if "time" in data else "the time array"
    if missing:
        raise InputError(f"{path}: its scene is not one pchute run wrote (no {missing}); rerun the case")
    return data["time"], arrays, description


def _scene_gap(description, arrays: dict) -> str | None:
    """What a scene (``outputs.scene``) lacks that an animation reads, or None when it is whole."""
    if not isinstance(description, dict):
        return "description as a JSON object"
    for key, kind in (("vehicle", str), ("bodies", dict), ("systems", dict)):
        if not isinstance(description.get(key), kind):
            return f"{key!r} in its description"
    if description["vehicle"] not in description["bodies"]:
        return f"body {description['vehicle']!r}, the vehicle"
    needed = [f"{name}/{kind}" for name in description["bodies"] for kind in ("position", "rotation")]
    for name, system in description["systems"].items():
        lines = system.get("lines") if isinstance(system, dict) else None
        if not isinstance(lines, list) or not all(isinstance(line, dict) and "name" in line for line in lines):
            return f"lines of system {name!r}"
        needed += [f"{name}/confluence"] + [f"{name}/{line['name']}" for line in lines]
    return next((f"array {SCENE}/{key}" for key in needed if key not in arrays), None)


def read_npz(path, wanted=None) -> dict:
    """The arrays of ``path`` (a result.npz) whose names ``wanted(name)`` accepts (default all), read whole;
    InputError naming the file when it is truncated or not an npz archive (no traceback from zipfile or numpy)."""
    try:
        with np.load(path, allow_pickle=False) as data:
            return {key: data[key] for key in data.files if wanted is None or wanted(key)}
    except OSError as exc:
        reason = exc.strerror or str(exc).splitlines()[0]
    except Exception as exc:   # zipfile.BadZipFile, EOFError, ValueError, zlib.error: a truncated or foreign file
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    raise InputError(f"{path}: cannot be read ({reason}): truncated or not a {NPZ_NAME} written by pchute run; rerun "
                     "the case")


def read_summary(folder) -> dict:
    """A result folder's summary.json ({} without one), without the list of the folder's files; InputError naming
    the file when it is empty, not JSON or not a JSON object."""
    path = Path(folder) / SUMMARY_NAME
    if not path.is_file():
        return {}
    try:
        text = path.read_text(encoding="utf-8")
        summary = json.loads(text)
    except OSError as exc:
        raise InputError(f"{path}: cannot be read: {exc.strerror}") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not UTF-8 text: not a summary written by pchute run") from None
    except (ValueError, RecursionError) as exc:
        what = "empty" if not text.strip() else f"not JSON ({getattr(exc, 'msg', type(exc).__name__)})"
        raise InputError(f"{path}: {what}: not a summary written by pchute run; rerun the case") from None
    if not isinstance(summary, dict):
        raise InputError(f"{path}: a JSON {type(summary).__name__}, not an object: not a summary written by pchute "
                         "run; rerun the case")
    summary.pop(FILES_KEY, None)
    return summary


class Result:
    """Named time histories of a run.

    Parameters
    ----------
    columns : dict of str to ndarray
        Time histories, ``time`` (s) first; see ``pchute_exudyn.run.outputs`` for the names.
    units : dict of str to str
        Unit of each column.
    summary : summary.RunSummary, optional
        What the run was and how it ended (``summary.json``, read back by ``RunSummary.from_dict``); None for a
        result without one (a CSV file of another tool).
    scene : (dict, dict), optional
        Arrays and description of the bodies and lines in the start frame (``outputs.scene``), for animations.
    attachments : dict of str to str, optional
        Further text files of the run (Exudyn's own solution files), saved beside the others under their names.
    loads : dict, optional
        Each deployment's load history: name -> (times in s, loads in N) (``results.deployments``).
    """

    def __init__(self, columns: dict, units: dict | None = None, summary: RunSummary | None = None, scene=None,
                 attachments=None, loads=None):
        if "time" not in columns:
            raise InputError("a result needs a 'time' column")
        if summary is not None and not isinstance(summary, RunSummary):
            raise InputError(f"summary: a RunSummary (RunSummary.from_dict reads a summary.json's), not "
                             f"{type(summary).__name__}")
        self.columns = {k: np.asarray(v, dtype=float) for k, v in columns.items()}
        self.units = dict(units or {})
        self.summary = summary
        self.scene_arrays, self.scene = scene if scene is not None else ({}, None)
        self.attachments = dict(attachments or {})
        self.loads = {name: (np.asarray(t, float), np.asarray(v, float)) for name, (t, v) in (loads or {}).items()}

    @property
    def time(self) -> np.ndarray:
        """Sample times (s)."""
        return self.columns["time"]

    @property
    def vehicle(self) -> str:
        """The vehicle's name, the owner of its columns (``registries.columns``): its summary's, else
        ``UNNAMED_VEHICLE`` (a file of another tool)."""
        return self.summary.vehicle if self.vehicle_named else UNNAMED_VEHICLE

    @property
    def vehicle_named(self) -> bool:
        """Whether the result's summary names its vehicle (a CSV file of another tool has no summary)."""
        return isinstance(getattr(self.summary, "vehicle", None), str)

    @property
    def names(self) -> list:
        """Column names, ``time`` first."""
        return list(self.columns)

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.columns[name]
        except KeyError:
            raise KeyError(f"no column {name!r}; columns are: {', '.join(self.columns)}") from None

    def __contains__(self, name: str) -> bool:
        return name in self.columns

    def final(self, name: str) -> float:
        """Last sample of column ``name``."""
        return float(self[name][-1])

    def tension_names(self) -> list:
        """Names of the line tension columns."""
        return list(self.tensions().values())

    def tensions(self) -> dict:
        """{line label: its tension column} (``registries.columns``)."""
        found = {name: owner(name, "tension_{owner}") for name in self.columns}
        return {label: name for name, label in found.items() if label is not None}

    def to_pandas(self):
        """The time histories as a pandas DataFrame indexed by time (pandas is imported only here)."""
        import pandas as pd
        return pd.DataFrame(self.columns).set_index("time")

    def plot(self, **kwargs):
        """Overview figure (line tensions and vehicle altitude); see ``plotting.plot_overview``."""
        from ..views.plotting import plot_overview
        return plot_overview(self, **kwargs)

    # -- files ---------------------------------------------------------------------------------------------------

    def save(self, folder, plot: bool = True, csv: bool = True, overwrite: bool = False, draw=None) -> dict:
        """Write the result files into ``folder``; returns their paths. ``csv=False`` keeps the time histories in
        ``result.npz`` only (a study's many runs); ``draw(result, path, track)``, when given, writes the overview
        figure and the ground track (True when it did: ``figure_process.FigureProcess.draw``), else this process
        draws them.

        The files are written into a fresh folder beside ``folder``, then put in its place. ``folder`` may be absent
        or empty; an earlier result is replaced only with ``overwrite``, and then only its own files (the user's
        other files stay); any other non-empty folder is refused (InputError), as is a failed write (a full disk:
        nothing of this run is left, an earlier result is untouched)."""
        for flag, value in (("plot", plot), ("csv", csv), ("overwrite", overwrite)):
            if not isinstance(value, bool):
                raise InputError(f"{flag} = {value!r}: must be True or False")
        folder = check_result_folder(_checked_path(folder, "folder"), overwrite)
        with staged_folder(folder) as staging:
            written = self._write(staging, plot, csv, draw)
        return {key: folder / path.name for key, path in written.items()}

    def _write(self, folder: Path, plot: bool, csv: bool, draw=None) -> dict:
        syncs = BackgroundSyncs()   # the large timeseries.csv goes to disk while the other files are written
        try:
            paths = self._write_files(folder, plot, csv, draw, syncs)
        except BaseException:
            syncs.wait(raising=False)
            raise
        syncs.wait()
        return paths

    def _write_files(self, folder: Path, plot: bool, csv: bool, draw, syncs: BackgroundSyncs) -> dict:
        summary = {} if self.summary is None else self.summary.to_dict()   # the files' form of the summary
        paths = {"npz": folder / NPZ_NAME, "summary": folder / SUMMARY_NAME}
        if csv:
            paths["csv"] = folder / CSV_NAME
            atomic_write_text(paths["csv"], table_text(self.names, [self.columns[n] for n in self.names]), syncs)
        scene = {f"{SCENE}/{k}": v for k, v in self.scene_arrays.items()}
        if self.scene is not None:
            scene[SCENE] = json_text(self.scene)
        loads = {f"{LOADS}/{name}/{key}": array for name, pair in self.loads.items()
                 for key, array in zip(("time", "load"), pair)}
        with atomic_writer(paths["npz"], "wb") as handle:
            # not compressed: deflate takes 40 times longer to write a history (0.1 s for MER's 60 s) and saves 20 %
            np.savez(handle, **self.columns, units=json_text(self.units), summary=json_text(summary), **scene,
                     **loads)
        figures = ([PLOT_NAME, TRACK_NAME] + ([LOADS_NAME] if self.loads else [])) if plot else []
        written = [p.name for p in paths.values()] + list(self.attachments) + figures
        # the folder's own summary.json lists its files: all that a later --overwrite replaces (io.result_files)
        atomic_write_text(paths["summary"], json_text({**summary, FILES_KEY: written}, indent=2) + "\n")
        for name, text in self.attachments.items():
            paths[name] = folder / name
            atomic_write_text(paths[name], text)
        if plot:
            paths["plot"], paths["ground_track"] = folder / PLOT_NAME, folder / TRACK_NAME
            if self.loads:
                paths["loads"] = folder / LOADS_NAME
            if draw is None or not draw(self, paths["plot"], paths["ground_track"], paths.get("loads")):
                from ..views.plotting import plot_deployment_loads, plot_ground_track, save_figure
                save_figure(self.plot(), paths["plot"])
                save_figure(plot_ground_track(self), paths["ground_track"])
                if self.loads:
                    save_figure(plot_deployment_loads(self), paths["loads"])
        return paths

    @classmethod
    def load(cls, path, column_map: dict | None = None, vehicle: str = UNNAMED_VEHICLE) -> Result:
        """Read a result folder (its ``timeseries.csv`` and ``summary.json``) or any CSV file.

        ``column_map`` (``csv_dialects.parse_column_map``) renames and rescales another tool's columns to this
        package's names before the ``time`` column (s) is required; ``csv_dialects`` lists the CSV dialects read.
        A RocketPy export read without a column map is mapped as ``rocketpy_export.column_map(vehicle)`` does.
        """
        path = _checked_path(path, "path")
        summary: dict = {}
        if path.is_dir():
            summary = read_summary(path)
            if not (path / CSV_NAME).is_file() and (path / NPZ_NAME).is_file():
                data = read_npz(path / NPZ_NAME, lambda key: key not in ("summary", SCENE)
                                and not key.startswith(SCENE + "/"))
                loads = _loads(data)
                columns = {k: v for k, v in data.items() if k != "units" and not k.startswith(LOADS + "/")}
                units = _units(data, path / NPZ_NAME)
                if "time" not in columns:
                    raise InputError(f"{path / NPZ_NAME}: holds no time array: not a {NPZ_NAME} written by pchute run")
                return cls(map_columns(columns, column_map or {}, path)[0], units, typed_summary(summary),
                           loads=loads)
            if not (path / CSV_NAME).is_file():
                raise InputError(f"{path}: a folder without {CSV_NAME} or {NPZ_NAME}: not a result folder of "
                                 "`pchute run` (a study folder is read by `pchute study-report`)")
            path = path / CSV_NAME
        if not path.is_file():
            raise InputError(f"result not found: {str(path)!r} is neither a result folder nor a CSV file")
        raw, raw_units, headers = rocketpy_export.read_columns(path)
        if not column_map and rocketpy_export.is_rocketpy(headers):
            column_map = rocketpy_export.column_map(vehicle, raw)
        columns, units = map_columns(raw, column_map or {}, path, headers, raw_units)
        if "time" not in columns:
            raise InputError(f"{path}: no 'time' column (name it with a column map, e.g. --map t=time); columns "
                             f"are: {', '.join(columns)}")
        typed = typed_summary(summary)
        file_units = typed.units if typed is not None and isinstance(typed.units, dict) else None
        return cls(columns, file_units or {n: u for n, u in units.items() if u}, typed)


def _loads(data: dict) -> dict:
    """The load histories of a result.npz's arrays (``loads/<name>/time`` and ``/load``): name -> (times, loads)."""
    names = {key.split("/")[1] for key in data if key.startswith(LOADS + "/") and key.count("/") == 2}
    return {name: (data[f"{LOADS}/{name}/time"], data[f"{LOADS}/{name}/load"]) for name in sorted(names)
            if f"{LOADS}/{name}/time" in data and f"{LOADS}/{name}/load" in data}


def typed_summary(summary: dict) -> RunSummary | None:
    """The ``summary.RunSummary`` of a result folder's ``summary.json`` (``read_summary``), of this version or an
    earlier one (what it lacks is None); None for no summary."""
    return RunSummary.from_dict(summary) if summary else None


def _units(data: dict, path: Path) -> dict:
    """The units a result.npz stores (JSON text), {} without them; InputError when they are not a JSON object."""
    if "units" not in data:
        return {}
    try:
        units = json.loads(str(data["units"]))
    except (ValueError, RecursionError):
        units = None
    if not isinstance(units, dict):
        raise InputError(f"{path}: its units are not a JSON object: not a {NPZ_NAME} written by pchute run")
    return units


def _checked_path(value, name: str) -> Path:
    """``value`` as a Path; InputError naming argument ``name`` unless it is a str or os.PathLike."""
    if isinstance(value, (str, os.PathLike)) and str(value) != "":
        return Path(value)
    raise InputError(f"{name} = {value!r}: must be a path (a non-empty str or a pathlib.Path), not "
                     f"{type(value).__name__}")

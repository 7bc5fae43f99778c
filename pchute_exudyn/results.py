"""The result of a run: named time histories with units, a summary, and the files they are saved to.

Files written by :meth:`Result.save` (each atomically):

* ``timeseries.csv``: a header row of column names, first column ``time`` (s), then one row per sample;
* ``result.npz``: the same arrays plus ``units`` and ``summary`` (JSON strings), and the scene an animation draws
  (``scene/<name>`` arrays and ``scene`` JSON: ``outputs.scene``), when the run made one;
* ``summary.json``: case, method, integrator, step, duration, steps, wall time, final vehicle state, peak tensions,
  column units and the versions of this package, Exudyn, numpy and Python;
* ``exudyn_solution_phase<k>.txt``: Exudyn's own solution file of each phase, when the run kept them
  (``simulate(engine_solution=True)``, ``pchute run --exudyn-solution``);
* ``overview.png``: line tensions and vehicle altitude against time.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .csv_dialects import map_columns, parse_column_map, read_csv_columns  # noqa: F401  (parse_column_map: API)
from .errors import InputError
from .io import atomic_write_text, atomic_writer, check_result_folder, json_text, staged_folder
from .number_text import table_text

CSV_NAME, NPZ_NAME, SUMMARY_NAME, PLOT_NAME = "timeseries.csv", "result.npz", "summary.json", "overview.png"
SCENE = "scene"
"""Key of the scene description in ``result.npz``; its arrays are ``scene/<name>``."""


def load_scene(folder) -> tuple[np.ndarray, dict, dict]:
    """Sample times (s), scene arrays and description from a result folder's ``result.npz`` (InputError when the
    folder has none: a result saved before scenes were stored, a study's scalar record, or a CSV)."""
    path = Path(folder) / NPZ_NAME
    if not path.is_file():
        raise InputError(f"{folder}: no {NPZ_NAME}: not a result folder of `pchute run`")
    with np.load(path) as data:
        if SCENE not in data.files:
            raise InputError(f"{folder}: {NPZ_NAME} holds no scene (body attitudes and attach points); rerun the case "
                             "with this version to animate it")
        arrays = {k[len(SCENE) + 1:]: data[k] for k in data.files if k.startswith(SCENE + "/")}
        return data["time"], arrays, json.loads(str(data[SCENE]))


class Result:
    """Named time histories of a run.

    Parameters
    ----------
    columns : dict of str to ndarray
        Time histories, ``time`` (s) first; see ``pchute_exudyn.outputs`` for the names.
    units : dict of str to str
        Unit of each column.
    summary : dict
        Run metadata (see the module docstring), as ``summary.json`` holds it.
    run_summary : summary.RunSummary, optional
        The same as a typed object, for a result just simulated (None for one loaded from files).
    scene : (dict, dict), optional
        Arrays and description of the bodies and lines in the start frame (``outputs.scene``), for animations.
    attachments : dict of str to str, optional
        Further text files of the run (Exudyn's own solution files), saved beside the others under their names.
    """

    def __init__(self, columns: dict, units: dict | None = None, summary: dict | None = None, run_summary=None,
                 scene=None, attachments=None):
        if "time" not in columns:
            raise InputError("a result needs a 'time' column")
        self.columns = {k: np.asarray(v, dtype=float) for k, v in columns.items()}
        self.units = dict(units or {})
        self.summary = dict(summary or {})
        self.run_summary = run_summary
        self.scene_arrays, self.scene = scene if scene is not None else ({}, None)
        self.attachments = dict(attachments or {})

    @property
    def time(self) -> np.ndarray:
        """Sample times (s)."""
        return self.columns["time"]

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
        return [n for n in self.columns if n.startswith("tension_")]

    def to_pandas(self):
        """The time histories as a pandas DataFrame indexed by time (pandas is imported only here)."""
        import pandas as pd
        return pd.DataFrame(self.columns).set_index("time")

    def plot(self, **kwargs):
        """Overview figure (line tensions and vehicle altitude); see ``plotting.plot_overview``."""
        from .plotting import plot_overview
        return plot_overview(self, **kwargs)

    # -- files ---------------------------------------------------------------------------------------------------

    def save(self, folder, plot: bool = True, csv: bool = True, overwrite: bool = False, draw=None) -> dict:
        """Write the result files into ``folder``; returns their paths. ``csv=False`` keeps the time histories in
        ``result.npz`` only (a study's many runs); ``draw(result, path)``, when given, writes the overview figure
        (True when it did: ``figure_process.FigureProcess.draw``), else this process draws it.

        The files are written into a fresh folder beside ``folder`` that then takes its place, so ``folder`` holds
        exactly this run's files. ``folder`` may be absent or empty; an earlier result folder is replaced only with
        ``overwrite``; any other non-empty folder is refused (InputError)."""
        folder = check_result_folder(folder, overwrite)
        with staged_folder(folder) as staging:
            written = self._write(staging, plot, csv, draw)
        return {key: folder / path.name for key, path in written.items()}

    def _write(self, folder: Path, plot: bool, csv: bool, draw=None) -> dict:
        paths = {"npz": folder / NPZ_NAME, "summary": folder / SUMMARY_NAME}
        if csv:
            paths["csv"] = folder / CSV_NAME
            atomic_write_text(paths["csv"], table_text(self.names, [self.columns[n] for n in self.names]))
        scene = {f"{SCENE}/{k}": v for k, v in self.scene_arrays.items()}
        if self.scene is not None:
            scene[SCENE] = json_text(self.scene)
        with atomic_writer(paths["npz"], "wb") as handle:
            # not compressed: deflate takes 40 times longer to write a history (0.1 s for MER's 60 s) and saves 20 %
            np.savez(handle, **self.columns, units=json_text(self.units), summary=json_text(self.summary), **scene)
        atomic_write_text(paths["summary"], json_text(self.summary, indent=2) + "\n")
        for name, text in self.attachments.items():
            paths[name] = folder / name
            atomic_write_text(paths[name], text)
        if plot:
            paths["plot"] = folder / PLOT_NAME
            if draw is None or not draw(self, paths["plot"]):
                from .plotting import save_figure
                save_figure(self.plot(), paths["plot"])
        return paths

    @classmethod
    def load(cls, path, column_map: dict | None = None) -> Result:
        """Read a result folder (its ``timeseries.csv`` and ``summary.json``) or any CSV file.

        ``column_map`` (``csv_dialects.parse_column_map``) renames and rescales another tool's columns to this
        package's names before the ``time`` column (s) is required; ``csv_dialects`` lists the CSV dialects read.
        """
        path = Path(path)
        summary: dict = {}
        if path.is_dir():
            if (path / SUMMARY_NAME).is_file():
                summary = json.loads((path / SUMMARY_NAME).read_text())
            if not (path / CSV_NAME).is_file() and (path / NPZ_NAME).is_file():
                with np.load(path / NPZ_NAME) as data:
                    columns = {k: data[k] for k in data.files if k not in ("units", "summary", SCENE)
                               and not k.startswith(SCENE + "/")}
                    units = json.loads(str(data["units"])) if "units" in data.files else {}
                return cls(map_columns(columns, column_map or {}, path)[0], units, summary)
            path = path / CSV_NAME
        if not path.is_file():
            raise InputError(f"result not found: {str(path)!r} is neither a result folder nor a CSV file")
        raw, raw_units, headers = read_csv_columns(path)
        columns, units = map_columns(raw, column_map or {}, path, headers, raw_units)
        if "time" not in columns:
            raise InputError(f"{path}: no 'time' column (name it with a column map, e.g. --map t=time); columns "
                             f"are: {', '.join(columns)}")
        return cls(columns, summary.get("units") or {n: u for n, u in units.items() if u}, summary)

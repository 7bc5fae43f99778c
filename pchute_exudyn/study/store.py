"""The result store of a study: one folder, nothing lost, nothing twice.

* ``study.toml``: a copy of the study file; ``manifest.json``: the study's fingerprint and run count;
* ``inputs.csv``: every planned run and its inputs, written before the first run;
* ``runs.jsonl``: one line per finished run (inputs, outputs, status, error), appended and flushed to disk as each
  run finishes: the record that survives a crash (a torn last line is ignored, so that run simply runs again);
* ``runs.csv``: the same as a table: a row appended as each run finishes (in the order they finish; the whole table
  rewritten, atomically, only when a run brings a column the table lacks), rewritten in run order when the study
  ends or is interrupted;
* ``histories/run_NNNNN/``: time histories, when the study keeps them.

Rerunning a study into the same folder skips the runs in ``runs.jsonl``; a study whose file, cases or inputs changed
is refused (start it in a new folder).
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from pathlib import Path

from ..errors import InputError
from ..io import atomic_write_text, ensure_writable_dir, json_text
from .table import write_parquet

FIRST_COLUMNS = ["run", "sample", "case", "reference", "reference_run", "method", "integrator", "step"]


class StudyStore:
    """Append-only record of a study's runs in ``folder``."""

    def __init__(self, folder, spec, runs: list):
        self.folder = Path(folder)
        self.spec = spec
        self.runs = runs
        self.records: dict = {}
        self._columns = None   # runs.csv's header as last written

    # -- set up and resume --------------------------------------------------------------------------------------

    def open(self) -> None:
        ensure_writable_dir(self.folder)
        manifest = self.folder / "manifest.json"
        fingerprint = self.spec.fingerprint()
        saved = json.loads(manifest.read_text()) if manifest.is_file() else None
        if saved is not None and saved.get("fingerprint") != fingerprint:
            raise InputError(f"{self.folder} holds a study whose file, cases or inputs differ from "
                             f"{self.spec.source}: resume only the same study (use another --out)")
        if saved is None:
            atomic_write_text(self.folder / "study.toml", self.spec.text)
            atomic_write_text(self.folder / "inputs.csv", self._csv([self._input_row(r) for r in self.runs]))
        if saved is None or "parameter_units" not in saved:   # (folders from before the units were kept)
            atomic_write_text(manifest, json.dumps({"name": self.spec.name, "fingerprint": fingerprint,
                                                    "runs": len(self.runs),
                                                    "study_file": os.path.relpath(self.spec.source, self.folder),
                                                    "parameter_units": self.spec.parameter_units},
                                                   indent=2) + "\n")
        self.records = self.load_records(self.folder)
        self.write_table()   # the runs recorded so far (none for a new study): the header the rows append to

    @staticmethod
    def load_records(folder) -> dict:
        """Finished runs from ``runs.jsonl`` by run index (a torn line is skipped). An index appears twice only when a
        failed run was retried (``--retry-failed``): the later record wins."""
        records = {}
        path = Path(folder) / "runs.jsonl"
        if path.is_file():
            for line in path.read_text().splitlines():
                try:
                    record = json.loads(line)
                except json.JSONDecodeError:
                    continue
                records[record["run"]] = record
        return records

    def done(self, retry_failed: bool = False) -> set:
        return {i for i, r in self.records.items() if not (retry_failed and r.get("status") != "ok")}

    # -- recording ------------------------------------------------------------------------------------------------

    def record(self, record: dict) -> None:
        """Append one finished run to disk at once: its line in ``runs.jsonl`` (flushed to the disk) and its row in
        ``runs.csv`` (nothing is read back: a study of thousands of runs records each in the same time)."""
        line = json_text(record) + "\n"
        with open(self.folder / "runs.jsonl", "a", encoding="utf-8") as handle:
            handle.write(line)
            handle.flush()
            os.fsync(handle.fileno())
        self.records[record["run"]] = record
        row = {**self._input_row(self.runs[record["run"]]), **record}
        if self._columns is None or any(key not in self._columns for key in row):
            self.write_table()   # a new column: the whole table with it
            return
        with open(self.folder / "runs.csv", "a", encoding="utf-8", newline="") as handle:
            handle.write(self._rows_text([row], self._columns))

    def write_table(self, final: bool = False) -> None:
        """Rewrite ``runs.csv`` in run order; ``final`` (the study's end, or its interruption) also
        ``runs.parquet``."""
        rows = [{**self._input_row(self.runs[i]), **self.records[i]} for i in sorted(self.records)]
        self._columns = self._keys(rows)
        atomic_write_text(self.folder / "runs.csv", self._csv(rows, self._columns))
        if final:
            write_parquet(self.folder)

    # -- helpers ----------------------------------------------------------------------------------------------------

    def _input_row(self, run) -> dict:
        return run.row(Path(run.case_file).stem)

    def _keys(self, rows: list) -> list:
        keys = list(FIRST_COLUMNS) + [p.key for p in self.spec.parameters]
        for row in rows:
            for key in row:
                if key not in keys:
                    keys.append(key)
        return keys

    def _csv(self, rows: list, keys: list | None = None) -> str:
        keys = keys or self._keys(rows)
        return ",".join(keys) + "\n" + self._rows_text(rows, keys)

    @staticmethod
    def _rows_text(rows: list, keys: list) -> str:
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=keys, extrasaction="ignore", lineterminator="\n")
        for row in rows:
            writer.writerow({k: _cell(v) for k, v in row.items()})
        return buffer.getvalue()


def _cell(value):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, float):
        return f"{value:.12g}"
    return value

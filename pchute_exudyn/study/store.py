"""The result store of a study: one folder, nothing lost, nothing twice.

* ``study.toml``: a copy of the study file; ``manifest.json``: the study's fingerprint, run count and the digest of
  every file the study reads (its cases and their ``extends`` chains);
* ``.pchute.lock``: locked while a study works in the folder (``journal.FolderLock``): a second one is refused;
* ``inputs.csv``: every planned run and its inputs, written before the first run;
* ``runs.jsonl``: one line per finished run (inputs, outputs, status, error; its warnings, ``JOURNAL_ONLY``),
  appended and flushed to disk as each run finishes, each line with its checksum (``journal``): the record that
  survives a crash (a torn or corrupt line is reported and set aside in ``runs.jsonl.rejected``, so that run simply
  runs again);
* ``runs.csv``: the same as a table: a row appended as each run finishes (in the order they finish; the whole table
  rewritten, atomically, only when a run brings a column the table lacks), rewritten in run order when the study
  ends or is interrupted;
* ``histories/run_NNNNN/``: time histories, when the study keeps them.

Rerunning a study into the same folder skips the runs in ``runs.jsonl``; a study whose file, cases (or a file they
extend) or inputs changed is refused (start it in a new folder). A failed write (a full disk) is one line; the
journal never keeps half a line, and the same command resumes once there is space.
"""

from __future__ import annotations

import csv
import io
import math
import os
import shutil
import sys
from dataclasses import dataclass, field, fields
from pathlib import Path

from ..results import journal as journal
from ..results.io import atomic_write_text, json_text
from ..results.journal import RUN_INDEX, RecordFolder, digests, writing
from .table import PARQUET_NAME, write_parquet

FIRST_COLUMNS = ["run", "sample", "case", "reference", "reference_run", "method", "integrator", "step"]
JOURNAL_ONLY = ("warnings", "site")
"""Record entries kept in ``runs.jsonl`` alone (lists of text lines, the run's site): not columns of ``runs.csv``."""


@dataclass(frozen=True)
class RunRecord:
    """What a study records of one run: a line of ``runs.jsonl`` (``to_dict``; ``from_dict`` reads it back), a row
    of ``runs.csv`` and ``runs.parquet`` beside the run's inputs.

    Attributes
    ----------
    run : int
        The run's index in the study.
    status : str
        "ok" or "failed".
    error : str or None
        Why the run failed ("" for an ok run; None in a record that has no entry for it).
    outputs : dict
        The run's scalar outputs by column (``registries.columns``, kind "study run" and the per line, system,
        canopy and body ones: m, s, N, m/s, deg, -; None: no value, an empty cell).
    never_fired : str or None
        For a case with triggers, the triggered events that did not happen, space-separated ("" when all fired).
    warnings : tuple of str
        The run's warnings (``RunSummary.warnings``): in ``runs.jsonl`` only (``JOURNAL_ONLY``).
    wall_time : float or None
        The engine's solve (s; a failed run: the time until it failed).
    steps : int or None
        Integration steps taken.
    run_time : float or None
        The whole run in its worker (s): loading the case, the run and its outputs.
    write_error : str or None
        Why a worker could not save the run's histories (the study stops with it; never recorded).
    site : dict or None
        The run's start point on its planet (``RunSummary.site``: what a map of the footprint needs); in
        ``runs.jsonl`` only; None on a flat planet, for a failed run and in records written before it was kept.
    """

    run: int
    status: str
    error: str | None = ""
    outputs: dict = field(default_factory=dict)
    never_fired: str | None = None
    warnings: tuple = ()
    wall_time: float | None = None
    steps: int | None = None
    run_time: float | None = None
    write_error: str | None = None
    site: dict | None = None

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def to_dict(self) -> dict:
        """The record's line of ``runs.jsonl``: run, status, error, the outputs, then what is set of the rest."""
        rest = {"never_fired": self.never_fired, "warnings": list(self.warnings) or None,
                "wall_time": self.wall_time, "steps": self.steps, "write_error": self.write_error,
                "run_time": self.run_time, "site": self.site}
        return {"run": self.run, "status": self.status, **({"error": self.error} if self.error is not None else {}),
                **self.outputs, **{key: value for key, value in rest.items() if value is not None}}

    @classmethod
    def from_dict(cls, data: dict) -> RunRecord:
        """A line of ``runs.jsonl`` (``journal.read``), of this version or an earlier one: every entry that is none
        of the record's fields is an output."""
        named = {f.name for f in fields(cls)} - {"outputs"}
        return cls(**{k: v for k, v in data.items() if k in named and k not in ("error", "warnings")},
                   error=data.get("error"), warnings=tuple(data.get("warnings") or ()),
                   outputs={k: v for k, v in data.items() if k not in named})


class StudyStore(RecordFolder):
    """Append-only record of a study's runs in ``folder``."""

    what, journal_name = "study", "runs.jsonl"

    def __init__(self, folder, spec, runs: list):
        super().__init__(folder)
        self.spec = spec
        self.runs = runs
        self.records: dict = {}
        self._columns = None   # runs.csv's header as last written

    # -- set up and resume --------------------------------------------------------------------------------------

    def _open_locked(self) -> None:
        manifest = self.folder / "manifest.json"
        files, fingerprint = digests(self.spec.source_files()), self.spec.fingerprint()
        saved = self.saved_manifest(self.spec.source, fingerprint, files)
        if saved is None:
            with writing(self.folder / "study.toml"):
                atomic_write_text(self.folder / "study.toml", self.spec.text)
            with writing(self.folder / "inputs.csv"):
                atomic_write_text(self.folder / "inputs.csv", self._csv([self._input_row(r) for r in self.runs]))
        if saved is None or "parameter_units" not in saved or "files" not in saved:   # (folders of earlier versions)
            with writing(manifest):
                atomic_write_text(manifest, json_text({"name": self.spec.name, "fingerprint": fingerprint,
                                                       "runs": len(self.runs),
                                                       "study_file": os.path.relpath(self.spec.source, self.folder),
                                                       "parameter_units": self.spec.parameter_units,
                                                       "files": files}, indent=2) + "\n")
        self.records = self.load_records(self.folder, len(self.runs), _note)
        _remove_half_written_histories(self.folder / "histories")
        if saved is not None:
            _note_unreadable_tables(self.folder)
        self.write_table()   # the runs recorded so far (none for a new study): the header the rows append to

    @staticmethod
    def load_records(folder, runs: int | None = None, note=None) -> dict:
        """Finished runs (``RunRecord``) from ``runs.jsonl`` by run index. A line that is torn, fails its checksum or
        is not a record of one of the ``runs`` planned runs is skipped (with ``note``, a resume: reported and set
        aside, its run runs again). An index appears twice only when a failed run was retried (``--retry-failed``):
        the later record wins."""
        finished = set()   # runs recorded ok so far: only a failed run is recorded again (--retry-failed)

        def check(record):
            run = record.get("run")
            if not isinstance(run, int) or isinstance(run, bool) or not isinstance(record.get("status"), str):
                return "is not a run record"
            if runs is not None and not 0 <= run < runs:
                return f"records run {run} of a study of {runs} runs (0 to {runs - 1})"
            if run in finished:
                return f"records run {run} again, already recorded as ok"
            if record["status"] == "ok":
                finished.add(run)
            return None

        def label(record, line):
            match = RUN_INDEX.match(line)   # a torn line still starts with its run index
            index = record.get("run") if isinstance(record, dict) else int(match.group(1)) if match else None
            if not isinstance(index, int) or isinstance(index, bool) or not (runs is None or 0 <= index < runs):
                return "skipped"
            return "the earlier record counts" if index in finished else f"run {index} runs again"

        records = {}
        for record in journal.read(Path(folder) / "runs.jsonl", check, label, note):
            records[record["run"]] = RunRecord.from_dict(record)
        return records

    def done(self, retry_failed: bool = False) -> set:
        return {i for i, r in self.records.items() if not (retry_failed and not r.ok)}

    # -- recording ------------------------------------------------------------------------------------------------

    def record(self, record: RunRecord) -> None:
        """Append one finished run to disk at once: its line in ``runs.jsonl`` (flushed to the disk) and its row in
        ``runs.csv`` (nothing is read back: a study of thousands of runs records each in the same time)."""
        line = record.to_dict()
        journal.append(self.folder / "runs.jsonl", line)
        self.records[record.run] = record
        row = {**self._input_row(self.runs[record.run]), **line}
        if self._columns is None or any(key not in self._columns and key not in JOURNAL_ONLY for key in row):
            self.write_table()   # a new column: the whole table with it
            return
        journal.append_text(self.folder / "runs.csv", self._rows_text([row], self._columns))

    def write_table(self, final: bool = False) -> None:
        """Rewrite ``runs.csv`` in run order; ``final`` (the study's end, or its interruption) also
        ``runs.parquet``."""
        rows = [{**self._input_row(self.runs[i]), **self.records[i].to_dict()} for i in sorted(self.records)]
        self._columns = self._keys(rows)
        with writing(self.folder / "runs.csv"):
            atomic_write_text(self.folder / "runs.csv", self._csv(rows, self._columns))
        if final:
            with writing(self.folder / "runs.parquet"):
                write_parquet(self.folder)

    # -- helpers ----------------------------------------------------------------------------------------------------

    def _input_row(self, run) -> dict:
        return run.row(Path(run.case_file).stem)

    def _keys(self, rows: list) -> list:
        keys = list(FIRST_COLUMNS) + [p.key for p in self.spec.parameters]
        for row in rows:
            for key in row:
                if key not in keys and key not in JOURNAL_ONLY:
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


def _remove_half_written_histories(folder: Path) -> None:
    """The staging folders (``.run_NNNNN.*.tmp``, ``.*.old``) of histories whose run was stopped while they were
    saved (an interrupt kills the workers): never a run's result; that run runs again."""
    for path in [*folder.glob(".*.tmp"), *folder.glob(".*.old")]:
        shutil.rmtree(path, ignore_errors=True)


def _cell(value):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, float):
        return f"{value:.12g}"
    return value


def _note(text: str) -> None:
    print(f"pchute study: {text}", file=sys.stderr)


def _note_unreadable_tables(folder: Path) -> None:
    """Say so when the derived tables of a resumed folder cannot be read: they are rebuilt from ``runs.jsonl``."""
    table = folder / "runs.csv"
    if table.is_file():
        try:
            table.read_bytes().decode("utf-8")
        except UnicodeDecodeError:
            _note("runs.csv is not UTF-8 text: rebuilt from runs.jsonl")
    parquet = folder / PARQUET_NAME
    if parquet.is_file():
        with parquet.open("rb") as handle:   # a Parquet file starts and ends with its magic bytes
            head = handle.read(4)
            handle.seek(max(0, parquet.stat().st_size - 4))
            tail = handle.read(4)
        if parquet.stat().st_size < 8 or head != b"PAR1" or tail != b"PAR1":
            _note(f"{PARQUET_NAME} is not a Parquet file: rebuilt from runs.jsonl when the study ends")

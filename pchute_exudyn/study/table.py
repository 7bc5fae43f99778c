"""A study's results as one table a data scientist loads in one line: ``runs.parquet`` beside ``runs.csv`` (the
always-available format), and ``load(DIR)`` returning a pandas DataFrame. pandas and pyarrow are the ``data``
extra (``pip install -e ".[data]"``); without them the study writes the CSV alone."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..results.io import atomic_writer

PARQUET_NAME = "runs.parquet"


def _pandas():
    try:
        import pandas
        import pyarrow  # noqa: F401  (the Parquet engine)
    except ImportError:
        return None
    return pandas


def write_parquet(folder) -> Path | None:
    """Write ``runs.parquet`` from ``runs.csv`` atomically; None when pandas or pyarrow is missing."""
    pandas = _pandas()
    folder = Path(folder)
    if pandas is None or not (folder / "runs.csv").is_file():
        return None
    frame = pandas.read_csv(folder / "runs.csv")
    path = folder / PARQUET_NAME
    with atomic_writer(path, "wb") as handle:
        frame.to_parquet(handle, index=False)
    return path


def load(folder):
    """The study folder's runs as a pandas DataFrame (one row per run: inputs and scalar outputs, as runs.csv)."""
    pandas = _pandas()
    if pandas is None:
        raise InputError("loading a study as a DataFrame needs pandas and pyarrow: pip install -e \".[data]\"")
    folder = Path(folder)
    for name, read in ((PARQUET_NAME, pandas.read_parquet), ("runs.csv", pandas.read_csv)):
        if (folder / name).is_file():
            try:
                return read(folder / name)
            except Exception as exc:  # pyarrow's ArrowInvalid, a decode error ...: a torn or foreign file, one line
                raise InputError(f"{folder / name}: not a {'Parquet' if name == PARQUET_NAME else 'CSV'} table "
                                 f"pchute wrote ({type(exc).__name__}); rerun `pchute study` into the folder to "
                                 "rewrite it from runs.jsonl") from None
    raise InputError(f"{folder}: no runs.csv: not a study folder (run `pchute study` into it first)")

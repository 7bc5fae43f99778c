"""File output that never leaves a half-written file: write beside the target, flush to disk, then rename."""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

from .errors import InputError

_UMASK = os.umask(0)
os.umask(_UMASK)  # read once: mkstemp creates 0600 files, results should get the user's usual permissions


@contextmanager
def atomic_writer(path, mode: str = "w", **kwargs):
    """Open a temporary file beside ``path``; on success it replaces ``path`` in one rename, on error it vanishes."""
    path = Path(path)
    fd, temp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.chmod(temp, 0o666 & ~_UMASK)
        with os.fdopen(fd, mode, **kwargs) as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temp, path)
    except BaseException:
        try:
            os.unlink(temp)
        except FileNotFoundError:
            pass
        raise


def atomic_write_text(path, text: str) -> None:
    """Write ``text`` to ``path`` atomically (UTF-8)."""
    with atomic_writer(path, "w", encoding="utf-8", newline="") as handle:
        handle.write(text)


def ensure_writable_dir(path) -> Path:
    """Create folder ``path`` if needed and check a file can be written there; InputError otherwise."""
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path, prefix=".pchute-write-test-"):
            pass
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise InputError(f"output folder {str(path)!r} cannot be written: {reason}") from None
    return path


def _finite(value):
    """``value`` with every non-finite float (NaN, inf) replaced by None, recursively; numpy scalars as Python's."""
    if isinstance(value, dict):
        return {key: _finite(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(item) for item in value]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):   # numpy scalar
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def json_text(data, indent: int | None = None) -> str:
    """Strict JSON (RFC 8259 has no NaN or Infinity): non-finite numbers are written as null, so that every parser
    reads the file. In summaries and reports a null number means "not defined here" (a system not present, no
    sample)."""
    return json.dumps(_finite(data), indent=indent, allow_nan=False)


RESULT_MARKER = "summary.json"
"""The file that makes a folder a result folder (one run's files)."""


def check_result_folder(folder, overwrite: bool = False) -> Path:
    """Check that a run's files may go to ``folder``: absent, empty, or (with ``overwrite``) an earlier result
    folder, under a writable folder. InputError otherwise. Nothing is created."""
    folder = Path(folder)
    if folder.exists():
        if not folder.is_dir():
            raise InputError(f"output folder {str(folder)!r} is a file; choose another --out")
        if any(folder.iterdir()):
            if not (folder / RESULT_MARKER).is_file():
                raise InputError(f"output folder {str(folder)!r} is not empty and holds no result; choose another "
                                 "--out (a result folder holds exactly one run's files)")
            if not overwrite:
                raise InputError(f"output folder {str(folder)!r} holds an earlier result; pass --overwrite to "
                                 "replace it, or choose another --out")
    existing = folder.absolute().parent
    while not existing.exists():
        existing = existing.parent
    if not (existing.is_dir() and os.access(existing, os.W_OK | os.X_OK)):
        raise InputError(f"output folder {str(folder)!r} cannot be written: {str(existing)!r} is not a writable folder")
    return folder


@contextmanager
def staged_folder(folder):
    """A fresh hidden folder beside ``folder`` to write a run's files into; on success it replaces ``folder`` (an
    earlier folder is moved aside and deleted), so ``folder`` holds exactly those files; on error it vanishes."""
    folder = Path(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.", suffix=".tmp"))
    try:
        os.chmod(staging, 0o777 & ~_UMASK)
        yield staging
        old = None
        if folder.exists():
            old = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.", suffix=".old"))
            os.replace(folder, old / "previous")
        os.replace(staging, folder)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise

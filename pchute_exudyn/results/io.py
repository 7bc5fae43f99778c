"""File output that never leaves a half-written file: write beside the target, flush to disk, then rename."""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path

from ..errors import InputError

_UMASK = os.umask(0)
os.umask(_UMASK)  # read once: mkstemp creates 0600 files, results should get the user's usual permissions


@contextmanager
def atomic_writer(path, mode: str = "w", later: BackgroundSyncs | None = None, **kwargs):
    """Open a temporary file beside ``path``; on success it replaces ``path`` in one rename, on error it vanishes.
    With ``later``, the flush to disk and the rename run in a thread of ``later`` (its ``wait`` reports a failure)."""
    path = Path(path)
    fd, temp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.chmod(temp, 0o666 & ~_UMASK)
        with os.fdopen(fd, mode, **kwargs) as handle:
            yield handle
            handle.flush()
            if later is None:
                os.fsync(handle.fileno())
            else:
                duplicate = os.dup(handle.fileno())
        if later is None:
            os.replace(temp, path)
            return
    except BaseException:
        _unlink(temp)
        raise
    later.start(duplicate, temp, path)


def _unlink(temp) -> None:
    try:
        os.unlink(temp)
    except FileNotFoundError:
        pass


class BackgroundSyncs:
    """Written files whose flush to disk (fsync: 10 ms for a 7 MB timeseries.csv) and rename into place run in
    threads while the writer goes on with the next file; ``wait`` joins them and raises the first failure (its
    temporary file removed, as ``atomic_writer`` does)."""

    def __init__(self):
        self._threads: list = []
        self._errors: list = []

    def start(self, fd: int, temp: str, path: Path) -> None:
        thread = threading.Thread(target=self._sync, args=(fd, temp, path), daemon=True)
        thread.start()
        self._threads.append(thread)

    def _sync(self, fd: int, temp: str, path: Path) -> None:
        try:
            os.fsync(fd)
            os.replace(temp, path)
        except OSError as exc:
            self._errors.append(exc)
            _unlink(temp)
        finally:
            os.close(fd)

    def wait(self, raising: bool = True) -> None:
        """Join every thread; with ``raising``, raise the first failure (each failure is reported once)."""
        for thread in self._threads:
            thread.join()
        self._threads.clear()
        errors, self._errors = self._errors, []
        if raising and errors:
            raise errors[0]


def atomic_write_text(path, text: str, later: BackgroundSyncs | None = None) -> None:
    """Write ``text`` to ``path`` atomically (UTF-8); ``later``: see ``atomic_writer``."""
    with atomic_writer(path, "w", later=later, encoding="utf-8", newline="") as handle:
        handle.write(text)


def ensure_writable_dir(path) -> Path:
    """Create folder ``path`` if needed and check a file can be written there; InputError otherwise."""
    path = Path(path)
    blocking = next((p for p in [path, *path.parents] if p.exists() and not p.is_dir()), None)
    if blocking is not None:
        where = "is a file" if blocking == path else f"is under {str(blocking)!r}, a file"
        raise InputError(f"output folder {str(path)!r} {where}: an output folder must be a folder or a path to create "
                         "(choose another --out)")
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
FILES_KEY = "result_files"
"""Key of summary.json (in the folder, not in result.npz) listing the files of the folder the run wrote: all that
``--overwrite`` replaces; the user's other files in the folder stay."""
LEGACY_FILES = ("timeseries.csv", "result.npz", "summary.json", "overview.png")
"""The files of a result written before summary.json listed them (with ``exudyn_solution_phase<k>.txt``)."""
LEGACY_KEYS = ("case", "method", "integrator", "step")
"""Keys a summary.json written before the list of files must all have to count as a result of this tool."""


def result_files(folder) -> list | None:
    """The names of the files an earlier run of this tool wrote into ``folder`` (its summary.json's list, or for an
    older result the files it writes), or None when ``folder`` holds no such result: no summary.json, or one that is
    empty, not JSON, not an object, or lacks the keys a result has (a file of someone else's that happens to bear
    the name)."""
    try:
        summary = json.loads((Path(folder) / RESULT_MARKER).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError, RecursionError):
        return None
    if not isinstance(summary, dict):
        return None
    listed = summary.get(FILES_KEY)
    if isinstance(listed, list) and all(isinstance(n, str) and n == Path(n).name and n not in ("", ".", "..")
                                        for n in listed):
        return [n for n in listed if (Path(folder) / n).is_file()]
    if not all(key in summary for key in LEGACY_KEYS):
        return None
    return sorted(p.name for p in Path(folder).iterdir() if p.is_file() and _result_name(p.name))


def _result_name(name: str) -> bool:
    """Whether a run of this tool may write a file of this name into a result folder."""
    return name in LEGACY_FILES or (name.startswith("exudyn_solution_phase") and name.endswith(".txt"))


def _not_a_result(folder: Path) -> str:
    """Why ``folder`` (not empty, no result of this tool) is refused."""
    if not (folder / RESULT_MARKER).exists():
        return (f"output folder {str(folder)!r} is not empty and holds no result; choose another --out (a result "
                "folder holds one run's files)")
    return (f"output folder {str(folder)!r} holds a {RESULT_MARKER} that is not a result of pchute run (empty, not "
            "a JSON object, or without the keys a run's summary has); nothing in it is replaced: choose another --out")


def _probe_writable(folder: Path, target: Path) -> None:
    """InputError unless a file can be created in ``folder`` (a real try: permission bits do not stop root, a
    read-only file system does)."""
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".pchute-write-test-"):
            pass
    except OSError as exc:
        raise InputError(f"output folder {str(target)!r} cannot be written: {str(folder)!r}: "
                         f"{exc.strerror or type(exc).__name__}") from None


def check_result_folder(folder, overwrite: bool = False) -> Path:
    """Check that a run's files may go to ``folder``: absent, empty, or (with ``overwrite``) a result folder of this
    tool (``result_files``), under a writable folder. InputError otherwise. Nothing is left behind (a probe file is
    created and removed)."""
    folder = Path(folder)
    if folder.exists():
        if not folder.is_dir():
            raise InputError(f"output folder {str(folder)!r} is a file; choose another --out")
        if any(folder.iterdir()):
            if result_files(folder) is None:
                raise InputError(_not_a_result(folder))
            if not overwrite:
                raise InputError(f"output folder {str(folder)!r} holds an earlier result; pass --overwrite to "
                                 "replace it, or choose another --out")
            earlier = result_files(folder)
            clash = sorted(p.name for p in folder.iterdir() if p.name not in earlier and _result_name(p.name))
            if clash:   # a file of the user's that a run's file would replace
                raise InputError(f"output folder {str(folder)!r}: {clash[0]} is not a file of the earlier result: "
                                 "this run would replace it; move it away or choose another --out")
            _probe_writable(folder, folder)   # its earlier files are moved out of it
    existing = folder.absolute().parent
    while not existing.exists():
        existing = existing.parent
    if not (existing.is_dir() and os.access(existing, os.W_OK | os.X_OK)):
        raise InputError(f"output folder {str(folder)!r} cannot be written: {str(existing)!r} is not a writable folder")
    _probe_writable(existing, folder)
    return folder


def write_failure(folder, exc: OSError) -> InputError:
    """A failed write (a full disk, a file-size limit, a read-only file system) as one line naming the file and the
    reason; ``staged_folder`` has removed everything of the run by then."""
    name = Path(exc.filename).name if exc.filename else ""
    where = f"{str(folder)!r}" + (f" ({name})" if name and not name.startswith(".") else "")
    kept = "; its earlier files are untouched" if Path(folder).is_dir() and any(Path(folder).iterdir()) else ""
    return InputError(f"output folder {where} cannot be written: {exc.strerror or type(exc).__name__}; nothing of "
                      f"this run was kept{kept}")


@contextmanager
def staged_folder(folder):
    """A fresh hidden folder beside ``folder`` to write a run's files into; on success its files replace the files
    of the earlier result in ``folder`` (``result_files``: the whole folder when it holds nothing else, in one
    rename), the user's other files stay; on error it vanishes and ``folder`` is untouched. An OSError (a full disk)
    becomes InputError (``write_failure``)."""
    folder = Path(folder)
    try:
        folder.parent.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.", suffix=".tmp"))
    except OSError as exc:
        raise write_failure(folder, exc) from None
    try:
        os.chmod(staging, 0o777 & ~_UMASK)
        yield staging
        _replace_result(folder, staging)
    except OSError as exc:
        shutil.rmtree(staging, ignore_errors=True)
        raise write_failure(folder, exc) from None
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


def _swap_files(folder: Path, staging: Path, old: Path, earlier: list, new: list) -> None:
    """The earlier result's files moved from ``folder`` into ``old``, then the staged ones moved in; a move that
    fails puts every earlier file back (and takes the new ones out) before it is raised: the folder holds one run's
    files, never a mix and never none."""
    moved, placed = [], []
    try:
        for name in earlier:
            os.replace(folder / name, old / name)
            moved.append(name)
        for name in new:
            os.replace(staging / name, folder / name)
            placed.append(name)
        staging.rmdir()
    except OSError:
        for name in placed:
            os.replace(folder / name, staging / name)
        for name in moved:
            os.replace(old / name, folder / name)
        raise


def _replace_result(folder: Path, staging: Path) -> None:
    """Put the staged files in ``folder``: one rename of the whole folder when ``folder`` is absent or holds only an
    earlier result; else file by file, the earlier result's files moved aside first, summary.json last."""
    earlier = result_files(folder) or [] if folder.exists() else []
    others = [p.name for p in folder.iterdir() if p.name not in earlier] if folder.exists() else []
    old = None
    if folder.exists():
        old = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.", suffix=".old"))
    if not others:
        if old is not None:
            os.replace(folder, old / "previous")
        os.replace(staging, folder)
    else:
        new = sorted((p.name for p in staging.iterdir()), key=lambda n: n == RESULT_MARKER)
        clash = sorted(set(new) & set(others))
        if clash:
            shutil.rmtree(old, ignore_errors=True)
            raise InputError(f"output folder {str(folder)!r}: {clash[0]} is not a file of the earlier result: "
                             "this run would replace it; move it away or choose another --out")
        _swap_files(folder, staging, old, earlier, new)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)

"""What a study or fit folder survives: a checksummed append-only journal, a lock on the folder, the digests of the
files a resume depends on, and one-line errors for a full disk.

* A journal line is the record's strict JSON with a last key ``"crc32"``: the CRC-32 (8 hex digits) of the line's
  text before that key (closed by ``}``). A line is appended in one write, flushed to the disk, and cut back if the
  write fails half way. Lines without the key (journals of earlier versions) are read as they are.
* Reading a journal keeps the valid lines and sets the others aside in ``<journal>.rejected`` (the journal is
  rewritten without them, atomically): a torn last line (power loss), a line failing its checksum, a line that is
  not a record of this folder. Each is reported in one line; its run simply runs again.
* ``FolderLock``: ``fcntl.flock`` on ``<folder>/.pchute.lock``, which holds the holder's pid, host and start time.
  The kernel drops the lock when its holder dies, however it dies: a lock left by a dead process never blocks.
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
import re
import socket
import time
import zlib
from contextlib import contextmanager
from pathlib import Path

import tomllib

from ..errors import InputError
from .io import atomic_writer, ensure_writable_dir, json_text

try:
    import fcntl
except ImportError:   # (Windows: folders are not locked)
    fcntl = None

CHECK_KEY = "crc32"
LOCK_NAME = ".pchute.lock"
_CHECK_TAIL = re.compile(r', "crc32": "([0-9a-f]{8})"}$')
RUN_INDEX = re.compile(r'^\{"run": (\d+),')
"""The run index at the start of a study record's line, readable even when the rest of the line is torn."""
MAX_NOTES = 10
"""Lines set aside that a resume reports one by one (the rest in one line)."""
_NO_SPACE = (errno.ENOSPC, errno.EFBIG, errno.EDQUOT)


class WriteFailed(InputError):
    """Writing a folder's file failed (a full disk, a file size limit, an I/O error): one line naming the file."""


def write_error(path, exc: OSError) -> WriteFailed:
    """The one-line error of an ``OSError`` writing ``path``: what to do to resume."""
    if exc.errno in _NO_SPACE:   # no space left on device, file too large (a size limit), disk quota exceeded
        return WriteFailed(f"{os.strerror(exc.errno).lower()} writing {path}: free space and rerun the same command "
                           "to resume")
    return WriteFailed(f"could not write {path} ({exc.strerror or type(exc).__name__}): fix it and rerun the same "
                       "command to resume")


# -- journal lines ------------------------------------------------------------------------------------------------

def encode(record: dict) -> str:
    """The journal line of ``record`` (without its newline): strict JSON ending with its checksum."""
    text = json_text(record)   # a record is never empty: its text ends '...}'
    return f'{text[:-1]}, "{CHECK_KEY}": "{zlib.crc32(text.encode()):08x}"}}'


def decode(line: str) -> tuple:
    """(record, problem): the record of one journal line, or None and why it is not one."""
    try:
        record = json.loads(line)
    except (json.JSONDecodeError, RecursionError):   # (nested thousands deep: no record of ours)
        return None, "is not JSON (corrupt)" if line.strip() else "empty"
    if not isinstance(record, dict):
        return None, "not a record"
    if CHECK_KEY in record:
        match = _CHECK_TAIL.search(line.rstrip("\r\n"))
        text = line.rstrip("\r\n")[:match.start()] + "}" if match else ""
        if not match or f"{zlib.crc32(text.encode()):08x}" != match.group(1):
            return None, "fails its checksum"
        del record[CHECK_KEY]
    return record, None


def append(path, record: dict) -> None:
    """Append ``record``'s line to journal ``path``, flushed to the disk; a failed write is cut back (nothing half
    written stays) and raised as ``WriteFailed``."""
    _append(path, (encode(record) + "\n").encode(), sync=True)


def append_text(path, text: str) -> None:
    """Append ``text`` to a derived file (a table), cut back if the write fails."""
    _append(path, text.encode(), sync=False)


def _append(path, data: bytes, sync: bool) -> None:
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)
    try:
        start = os.fstat(fd).st_size
        try:
            written = 0
            while written < len(data):
                written += os.write(fd, data[written:])
            if sync:
                os.fsync(fd)
        except OSError as exc:
            _cut_back(fd, start)
            raise write_error(path, exc) from None
    finally:
        os.close(fd)


def _cut_back(fd: int, size: int) -> None:
    try:
        os.ftruncate(fd, size)
    except OSError:   # nothing more can be done: the next read sets the torn line aside
        pass


def read(path, check, label, note=None) -> list:
    """The valid records of journal ``path`` in file order. ``check(record)`` returns None or why the record does not
    belong here; ``label(record, line)`` names what runs again. With ``note`` (a function reporting each line set
    aside: a resume) the journal is rewritten without those lines (kept in ``<path>.rejected``), so that the next
    line appended starts a line of its own."""
    path = Path(path)
    if not path.is_file():
        return []
    lines = path.read_bytes().split(b"\n")
    torn_tail = lines[-1] != b""
    lines = lines if torn_tail else lines[:-1]
    records, kept, rejected = [], [], []
    for number, raw in enumerate(lines, 1):
        try:
            line = raw.decode("utf-8")
        except UnicodeDecodeError:
            line = raw.decode("utf-8", "replace")
        record, problem = decode(line)
        if number == len(lines) and torn_tail:
            problem = "torn (power loss?)"   # no newline: the last write did not finish (not checked: not kept)
        elif record is not None:
            problem = check(record)
        if problem is None:
            records.append(record)
            kept.append(raw)
            continue
        rejected.append(raw)
        if line.strip() and note is not None and len(rejected) <= MAX_NOTES:
            note(f"{path.name}: line {number} {problem}: {label(record, line)}")
    if rejected and note is not None:
        if len(rejected) > MAX_NOTES:
            note(f"{path.name}: {len(rejected) - MAX_NOTES} more lines set aside in {path.name}.rejected")
        _set_aside(path, kept, rejected)
    return records


def _set_aside(path: Path, kept: list, rejected: list) -> None:
    with writing(path):
        with open(path.with_name(path.name + ".rejected"), "ab") as handle:
            handle.write(b"".join(line + b"\n" for line in rejected))
        with atomic_writer(path, "wb") as handle:
            handle.write(b"".join(line + b"\n" for line in kept))


@contextmanager
def writing(path):
    """Turn an ``OSError`` while writing ``path`` into its one-line ``WriteFailed``."""
    try:
        yield
    except OSError as exc:
        raise write_error(path, exc) from None


# -- the folder lock -----------------------------------------------------------------------------------------------

_HELD: set = set()
"""Descriptors of the folder locks this process holds."""


def _drop_held_in_child() -> None:
    """In a forked child (a pool's worker): close the copies of the held locks' descriptors, so that the child, which
    may outlive the study or fit (a pool passed in by the caller), does not keep the folder locked. Closing a copy
    leaves the parent's lock in place (``flock`` belongs to the open file, released when its last descriptor
    closes)."""
    for fd in list(_HELD):
        try:
            os.close(fd)
        except OSError:
            pass
    _HELD.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_drop_held_in_child)


class FolderLock:
    """An exclusive lock on a study or fit folder, held while this process works in it (``what``: 'study', 'fit')."""

    def __init__(self, folder, what: str):
        self.path = Path(folder) / LOCK_NAME
        self.what = what
        self.fd: int | None = None

    def acquire(self) -> None:
        if fcntl is None:
            return
        try:
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o666)
        except OSError as exc:
            raise write_error(self.path, exc) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            holder = _holder(fd)
            os.close(fd)
            raise InputError(f"{self.path.parent} is in use ({holder}): wait for it to end, or use another "
                             "--out") from None
        stamp = time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())
        holder = f"pchute {self.what}, pid {os.getpid()} on {socket.gethostname()}, started {stamp}"
        try:   # written over the last holder's line, then cut to length: never empty while held
            os.pwrite(fd, holder.encode(), 0)
            os.ftruncate(fd, len(holder.encode()))
        except OSError:   # a full disk: the lock holds all the same, only its holder goes unnamed
            pass
        self.fd = fd
        _HELD.add(fd)

    def release(self) -> None:
        if self.fd is not None:
            _HELD.discard(self.fd)
            os.close(self.fd)   # closing the descriptor drops the lock
            self.fd = None


def _holder(fd: int) -> str:
    """The holder's line of a lock file (waiting a moment for a holder that has just taken the lock to write it)."""
    for _ in range(50):
        text = os.pread(fd, 400, 0).decode("utf-8", "replace").strip()
        if text:
            return text
        time.sleep(0.01)
    return "another pchute process"


# -- what a resume depends on ----------------------------------------------------------------------------------------

def case_files(case) -> list:
    """The files case ``case`` reads: itself, its ``extends`` chain and an atmosphere table (absolute paths; a file
    that cannot be read is listed as it is, its loader names the problem)."""
    found: list = []
    _collect(Path(case).resolve(), found)
    return found


def _collect(path: Path, found: list) -> None:
    if path in found:
        return
    found.append(path)
    try:
        with path.open("rb") as handle:
            data = tomllib.load(handle)
    except (OSError, ValueError):
        return
    extends = data.get("extends", [])
    for base in [extends] if isinstance(extends, str) else extends if isinstance(extends, list) else []:
        if isinstance(base, str):
            _collect((path.parent / base).resolve(), found)
    atmosphere = data.get("atmosphere")
    if isinstance(atmosphere, dict) and isinstance(atmosphere.get("file"), str):
        table = (path.parent / atmosphere["file"]).resolve()
        if table not in found:
            found.append(table)


def digests(paths) -> dict:
    """Path text -> SHA-256 of its content (None for a file that cannot be read)."""
    out = {}
    for path in paths:
        try:
            out[str(path)] = hashlib.sha256(Path(path).read_bytes()).hexdigest()
        except OSError:
            out[str(path)] = None
    return out


def changed_file(saved: dict, now: dict) -> str | None:
    """The first file whose content differs between two ``digests`` (or that was added or removed)."""
    for path in sorted(saved.keys() | now.keys()):
        if saved.get(path) != now.get(path):
            return path
    return None


def read_manifest(path, what: str) -> dict | None:
    """The manifest of a folder (None when absent); one-line InputError when it is not a valid one."""
    path = Path(path)
    if not path.is_file():
        return None
    advice = (f"the folder was not written completely by pchute {what}, or was changed since: use another --out "
              "(or remove the folder to start again)")
    try:
        data = json.loads(path.read_bytes().decode("utf-8"))
    except UnicodeDecodeError:
        raise InputError(f"{path}: not UTF-8 text: {advice}") from None
    except (json.JSONDecodeError, RecursionError):
        problem = "empty" if not path.read_bytes().strip() else "not JSON"
        raise InputError(f"{path}: {problem}: {advice}") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror}): {advice}") from None
    if not isinstance(data, dict):
        raise InputError(f"{path}: a JSON {type(data).__name__}, not the manifest's object: {advice}")
    if not isinstance(data.get("fingerprint"), str):
        raise InputError(f"{path}: no 'fingerprint' key: {advice}")
    return data


# -- a study's or fit's folder -----------------------------------------------------------------------------------------

class RecordFolder:
    """A study's or fit's folder (``what``: 'study', 'fit'; its journal ``journal_name``): locked from ``open`` to
    ``close``; a resume is checked against the manifest (``saved_manifest``) before any record is read."""

    what = ""
    journal_name = ""

    def __init__(self, folder):
        self.folder = Path(folder)
        self.journal = self.folder / self.journal_name
        self.lock = FolderLock(self.folder, self.what)

    def open(self) -> None:
        """Lock the folder (until ``close``), check that it holds this study or fit (or nothing), read its records."""
        ensure_writable_dir(self.folder)
        self.lock.acquire()
        try:
            self._open_locked()
        except BaseException:
            self.lock.release()
            raise

    def close(self) -> None:
        self.lock.release()

    def _open_locked(self) -> None:
        raise NotImplementedError

    def saved_manifest(self, source, fingerprint: str, files: dict) -> dict | None:
        """The folder's manifest (None for a new folder), once it is shown to be of the same study or fit as
        ``source`` (its ``fingerprint``) reading the same ``files`` (their ``digests``); InputError otherwise."""
        saved = read_manifest(self.folder / "manifest.json", self.what)
        if saved is None and self.journal.is_file():
            raise InputError(f"{self.folder} holds {self.journal_name} but no manifest.json: its runs cannot be "
                             f"matched to {source}; use another --out")
        if saved is None:
            return None
        old = saved["files"] if isinstance(saved.get("files"), dict) else None
        if old is not None and old.keys() == files.keys() and changed_file(old, files) is not None:
            raise InputError(f"{changed_file(old, files)} changed since the {self.what} in {self.folder} started (its "
                             f"content differs): resuming would mix two models in one {self.what}; use another --out")
        if saved["fingerprint"] != fingerprint:
            raise InputError(f"{self.folder} holds a {self.what} whose file, cases or data differ from {source}: "
                             f"resume only the same {self.what} (use another --out)")
        if old is not None and sorted(map(str, old.values())) != sorted(map(str, files.values())):
            # other files (not the same files moved): a file of an extends chain added, removed or edited
            raise InputError(f"the files the {self.what} reads differ from those it read when it started in "
                             f"{self.folder}: resuming would mix two models in one {self.what}; use another --out")
        return saved

"""The compiled code of the package's dataclass methods, kept between processes.

``dataclasses`` writes the ``__init__``, ``__eq__``, ``__hash__``, ``__repr__`` and ``__setattr__`` of every class it
decorates as Python source and compiles it when the class is defined: about 520 small compilations for the 94
classes a ``pchute run`` imports, 0.1 s of each start-up (a quarter of the package's import time). Python keeps the
compiled code of modules in ``__pycache__``; this keeps the compiled code of those generated methods beside the
compiled kernels (``selection.cache_directory``), one file per Python version (code objects are version-specific),
keyed by the source text the dataclasses module wrote: the same text gives the same code, so a class defined with a
cached code object is the class ``dataclasses`` would have made (the methods' globals, closures and defaults are
still bound at definition, as always). Only classes of this package use it; any other module's dataclasses compile
as usual. Nothing is written where Python writes no bytecode (``sys.dont_write_bytecode``, PYTHONDONTWRITEBYTECODE).
"""

from __future__ import annotations

import atexit
import builtins
import dataclasses
import marshal
import os
import sys
from pathlib import Path

PACKAGE = __name__.split(".")[0]
LIMIT = 5000
"""Entries at most: a cache grown past it (edited classes leave their old texts behind) starts again."""

_code: dict = {}
_state = {"new": False, "file": None, "loaded": True}


def cache_file(folder: Path) -> Path:
    """The cache of this Python in ``folder``."""
    return folder / f"dataclass_code.{sys.implementation.cache_tag}.{sys.hexversion:x}.marshal"


def install(folder: Path) -> None:
    """Compile this package's dataclass methods through the cache in ``folder`` from now on (read at the first)."""
    _state["file"], _state["loaded"] = cache_file(folder), False
    dataclasses.exec = _exec   # the dataclasses module's own name lookup finds this before the builtin
    atexit.register(save)      # a script's or a test's process; the command saves before its fast exit


def _exec(source, globals=None, locals=None):
    """``exec`` as ``dataclasses`` calls it, with the compiled code of a package class's method source remembered.
    A text is always compiled here with ``dont_inherit``: ``exec`` of a text would take this module's future features
    (``annotations``: every other module's dataclass ``__init__`` would carry its annotations as strings)."""
    if not isinstance(source, str):
        return builtins.exec(source, globals, locals)
    if not (isinstance(globals, dict) and str(globals.get("__name__", "")).startswith(PACKAGE + ".")):
        return builtins.exec(compile(source, "<string>", "exec", dont_inherit=True), globals, locals)
    if not _state["loaded"]:
        _load()
    code = _code.get(source)
    if code is None:   # as exec compiles a text: file name <string>, no future features of this module inherited
        code = _code[source] = compile(source, "<string>", "exec", dont_inherit=True)
        _state["new"] = True
    return builtins.exec(code, globals, locals)


def _load() -> None:
    """Read the cache file (4 ms: not before a class needs it, so `pchute --help` does not)."""
    _state["loaded"] = True
    try:
        loaded = marshal.loads(_state["file"].read_bytes())
        if isinstance(loaded, dict) and len(loaded) <= LIMIT:
            _code.update(loaded)
    except (OSError, EOFError, ValueError, TypeError):   # none yet, or damaged: compiled afresh and rewritten
        pass


def warm_and_save() -> None:
    """Define every class a run defines (its modules imported) and save their code: the install's kernel build
    ends with this, so that the first run after it starts as fast as the later ones."""
    from importlib import import_module

    for name in ("cli", "run.simulation", "results.result", "results.run_line", "methods", "views.progress"):
        import_module(f"{PACKAGE}.{name}")
    save()


def save() -> None:
    """Write the cache when this process compiled anything new (atomically; silently not where it cannot)."""
    path = _state["file"]
    if not _state["new"] or path is None or sys.dont_write_bytecode:
        return
    _state["new"] = False
    entries = _code if len(_code) <= LIMIT else {}
    import tempfile  # here only: most processes have nothing new to save

    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, temp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
        try:
            os.chmod(temp, 0o644)   # readable as the module beside it is (mkstemp makes 0600)
            with os.fdopen(fd, "wb") as handle:
                handle.write(marshal.dumps(entries))
            os.replace(temp, path)
        except BaseException:
            Path(temp).unlink(missing_ok=True)
            raise
    except OSError:   # a read-only kernel folder: each start compiles them, as without the cache
        pass

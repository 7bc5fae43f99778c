"""Which form of the per-stage kernels (``physics.compiled``) this process runs, and where the compiled form is found.

Three forms of the same functions:

* ``compiled``: one extension module, built ahead of time from the kernels by numba's AOT compiler
  (``pchute_exudyn.kernels.build``): when the package is installed (``setup.py``) and again whenever the kernels'
  source changes. Importing it costs milliseconds and neither numba nor LLVM; the module is named after a digest of
  the kernels' source (``source_key``), so a module built from other source is never used.
* ``jit``: numba compiles each kernel at its first call and caches the machine code on disk (about 0.6 s of numba
  start-up per process, more for a first compile); the module builder itself runs in it.
* ``python``: the functions as written (the same results, several times slower per stage).

``PCHUTE_KERNELS`` in the environment chooses: ``compiled`` (the compiled module, or ``jit`` when no module of the
current source exists: the test suite), ``jit`` or ``python``; any other value is an input error
(``rejected_choice``). Unset: ``compiled`` when the module exists, else ``python``. Chosen once per process, before
``physics`` is imported (``pchute_exudyn/__init__.py``); child processes inherit the choice.

Where no module exists, the commands that run simulations (``pchute run``, ``study``, ``fit``) start a background
build for the runs after theirs, or build first for a long run (``kernels.lock``). ``simulate`` from Python starts
none: an API user's runs take the Python form until ``python -m pchute_exudyn.kernels.build`` (or a command) has
built the module.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import json
import os
import sys
import sysconfig
from pathlib import Path

from ..environment import KERNEL_DIR, KERNELS_AUTO, KERNELS_NUMBA_BASE, NUMBA_CACHE_DIR, XDG_CACHE_HOME
from .form import BUILDER, EXPORTS, VARIABLE

MODES = ("compiled", "jit", "python")
PACKAGE = Path(__file__).resolve().parents[1]
PHYSICS = PACKAGE / "physics"
SP_KERNELS = ("memory", "balance", "stepping", "canopy_kernels")
"""The modules of SP's package (``methods/sp``) that hold its compiled kernels and their named memory."""
KERNEL_MODULES = ("pchute_exudyn.physics.", "pchute_exudyn.results.number_text",
                  *(f"pchute_exudyn.methods.sp.{name}" for name in SP_KERNELS))
"""The modules whose functions are kernels (``physics.compiled.kernel``): the physics, SP's kernels and the number
formatter."""


def kernel_sources() -> list:
    """The files the kernels are compiled from (``source_key``): every physics module, SP's kernel modules and the
    number formatter."""
    return [*sorted(PHYSICS.glob("*.py")), *(PACKAGE / "methods" / "sp" / f"{name}.py" for name in SP_KERNELS),
            PACKAGE / "results" / "number_text.py"]
SIGNATURES = PACKAGE / "kernels" / "signatures.json"
"""The argument types each kernel is compiled for: the ones the package calls it with from Python
(``python -m pchute_exudyn.tools.record_signatures`` writes it)."""


def _sha256():
    """A SHA-256 hash object: Python's own implementation where it has one (``hashlib`` loads OpenSSL: 7 ms of every
    start-up), the same digest."""
    try:
        from _sha256 import sha256  # CPython 3.11
    except ImportError:
        try:
            from _sha2 import sha256  # CPython 3.12 and later
        except ImportError:
            from hashlib import sha256
    return sha256()


def source_key() -> str:
    """A digest of the kernels' source, the signatures they are compiled for, and the Python that loads them."""
    digest = _sha256()
    for path in kernel_sources():
        digest.update(path.name.encode() + path.read_bytes())
    digest.update(SIGNATURES.read_bytes() if SIGNATURES.is_file() else b"")
    digest.update(sys.version.encode() + sysconfig.get_platform().encode())
    return digest.hexdigest()[:16]


def cache_directory() -> Path:
    """Where the compiled module is built: ``PCHUTE_KERNEL_DIR`` when set, else the package's ``_compiled`` folder
    (where the install puts it), else, when the package cannot be written, the user's cache."""
    if os.environ.get(KERNEL_DIR):
        return Path(os.environ[KERNEL_DIR])
    beside = PACKAGE / "_compiled"
    if os.access(beside if beside.is_dir() else PACKAGE, os.W_OK):
        return beside
    return Path(os.environ.get(XDG_CACHE_HOME, Path.home() / ".cache")) / "pchute_exudyn"


def module_name(key: str | None = None) -> str:
    return f"kernels_{key or source_key()}"


def table_path(key: str | None = None, folder: Path | None = None) -> Path:
    """The compiled module's table (which export serves which kernel): written after the module, so its presence
    means the module is complete."""
    return (folder or cache_directory()) / f"{module_name(key)}.json"


def load_compiled(folder: Path | None = None) -> dict | None:
    """The compiled module of the current source, as {kernel name: [(argument types, function)]}; None when there
    is none (or it cannot be loaded). Looks in ``folder``, else in ``PCHUTE_KERNEL_DIR`` alone when that is set,
    else in the kernel folder and the package's ``_compiled`` folder."""
    key = source_key()
    places = [folder] if folder else [cache_directory()]
    if folder is None and not os.environ.get(KERNEL_DIR):
        places.append(PACKAGE / "_compiled")
    for place in dict.fromkeys(places):
        table = table_path(key, place)
        if not table.is_file():
            continue
        try:
            entries = json.loads(table.read_text())
            path = place / entries["file"]
            loader = importlib.machinery.ExtensionFileLoader(module_name(key), str(path))
            spec = importlib.util.spec_from_file_location(module_name(key), path, loader=loader)
            module = importlib.util.module_from_spec(spec)
            loader.exec_module(module)
            exports = {name: [(tuple(export["arguments"]), getattr(module, export["export"]))
                              for export in exports] for name, exports in entries["kernels"].items()}
            BUILDER.update(numba=entries.get("numba"))
            return exports
        except (OSError, ImportError, KeyError, ValueError, AttributeError):   # damaged or foreign: not used
            continue
    return None


REJECTED: list = []
"""A value of ``PCHUTE_KERNELS`` that names no form, when one was given (the process chose as if unset)."""


def rejected_choice() -> str | None:
    """One line naming a ``PCHUTE_KERNELS`` value that is not a form, or None. Not raised at import: the command
    line prints it as its error, ``simulate`` raises it."""
    if not REJECTED:
        return None
    return f"{VARIABLE}={REJECTED[0]!r} in the environment: allowed {', '.join(MODES)}, or unset (automatic)"


def select() -> str:
    """Decide the form for this process (and its children): see the module docstring. Sets the environment
    variable so every later import agrees; the compiled module's exports go to ``kernels.form.EXPORTS``."""
    asked = os.environ.get(VARIABLE)
    mode = asked if asked in MODES else None
    if asked and mode is None:   # reported by rejected_choice (the command line and simulate), not at import
        REJECTED.append(asked)
    if mode in (None, "compiled"):
        exports = load_compiled()
        if exports is not None:
            EXPORTS.update(exports)
            mode = "compiled"
        elif mode == "compiled":
            mode = "jit"         # asked for compiled kernels: numba compiles them in this process
        else:
            mode = "python"
            os.environ[KERNELS_AUTO] = "1"   # chosen here, not asked for: a background build may help
    os.environ[VARIABLE] = mode
    if mode == "jit":
        use_jit_cache_of_this_source()
    return mode


JIT_CACHE_BASE = KERNELS_NUMBA_BASE
"""The folder the jit form's per-source caches go in (set for child processes, so that they agree)."""


def use_jit_cache_of_this_source() -> None:
    """Point numba's on-disk cache at a folder of this kernel source (``jit_<source_key>``), under the folder a user
    gave in ``NUMBA_CACHE_DIR`` or the kernel folder. numba keys a cached kernel by its own file only: a kernel that
    calls one in another file that was edited would otherwise be loaded as compiled before the edit (an edited
    aerodynamic law reached the full-mass kernels but not SP's, and the module built from them)."""
    base = os.environ.get(JIT_CACHE_BASE) or os.environ.get(NUMBA_CACHE_DIR) or str(cache_directory())
    os.environ[JIT_CACHE_BASE] = base
    os.environ[NUMBA_CACHE_DIR] = str(Path(base) / f"jit_{source_key()}")


def chosen_automatically() -> bool:
    """Whether this process runs the Python form because no module was found (``select``), not because it was asked."""
    return os.environ.get(KERNELS_AUTO) == "1"

"""Whether this process runs the per-stage kernels compiled (numba) or as the Python they are written in.

Numba compiles the kernels (``physics.compiled``) on their first call and caches the machine code on disk; compiling
all of them takes several seconds, which the first run on a machine would otherwise pay on top of its own time. So
the package imports them compiled only when a complete cache is known to exist (a marker file written after every
kernel was compiled, keyed by the kernels' source, numba's and Python's versions). Without it the run uses the same
functions as Python (about six times slower per stage, still faster than the whole compilation for one run) and
starts a background process that compiles them for the runs after it (``pchute_exudyn.kernel_cache``).

``PCHUTE_KERNELS=compiled`` or ``=python`` in the environment decides instead (the test suite compiles; a test runs
the Python form). Chosen once, before ``physics`` is imported (``pchute_exudyn/__init__.py``).
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import sysconfig
import time
from pathlib import Path

LOCK_AGE = 300.0
"""Seconds after which a compile lock is taken to be left by a process that died."""
VARIABLE = "PCHUTE_KERNELS"
MODES = ("compiled", "python")
PHYSICS = Path(__file__).resolve().parent / "physics"


def source_key() -> str:
    """A digest of the kernels' source files and of the numba and Python versions that compile them."""
    digest = hashlib.sha256()
    for path in sorted(PHYSICS.glob("*.py")):
        digest.update(path.name.encode() + path.read_bytes())
    try:
        from importlib.metadata import version
        digest.update(version("numba").encode())
    except Exception:  # noqa: BLE001 - no numba metadata: the key still covers the sources
        pass
    digest.update(sys.version.encode() + sysconfig.get_platform().encode())
    return digest.hexdigest()[:16]


def cache_directory() -> Path:
    """Where numba caches the kernels and where the marker goes: NUMBA_CACHE_DIR when set, else beside the sources
    (numba's own default when the package directory is writable), else the user's cache directory."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"])
    beside = PHYSICS / "__pycache__"
    if os.access(PHYSICS, os.W_OK):
        return beside
    return Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "pchute_exudyn"


def marker() -> Path:
    return cache_directory() / f"pchute_exudyn_kernels_{source_key()}.ok"


def select() -> str:
    """Decide the mode for this process (and its children): the environment's, else compiled when the marker
    exists, else python. Sets the environment variable so every later import agrees."""
    mode = os.environ.get(VARIABLE)
    if mode not in MODES:
        mode = "compiled" if marker().exists() else "python"
        os.environ[VARIABLE] = mode
        os.environ[VARIABLE + "_AUTO"] = "1"   # chosen here, not asked for: a background compile may help
    return mode


def chosen_automatically() -> bool:
    return os.environ.get(VARIABLE + "_AUTO") == "1"


def lock() -> Path:
    return marker().with_suffix(".compiling")


def start_background_compile() -> bool:
    """Spawn ``python -m pchute_exudyn.kernel_cache``, detached, when this process runs the Python kernels because
    no compiled ones were found (not when a mode was asked for), unless another process is compiling them; True when
    it spawned one."""
    if os.environ.get(VARIABLE) == "compiled" or not chosen_automatically() or marker().exists():
        return False
    path = lock()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.exists() and time.time() - path.stat().st_mtime < LOCK_AGE:
            return False
        path.write_text(str(os.getpid()))
        env = {**os.environ, VARIABLE: "compiled"}
        env.pop(VARIABLE + "_AUTO", None)
        subprocess.Popen([sys.executable, "-m", "pchute_exudyn.kernel_cache"], env=env, start_new_session=True,
                         stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return True
    except OSError:   # a read-only cache directory: the runs keep the Python kernels
        return False

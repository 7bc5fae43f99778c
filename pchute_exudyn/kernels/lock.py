"""The build lock, and when a process builds the compiled kernel module: first (a long run), in the background (the
runs after this one) or not at all.

The module's folder holds, beside the module of the current source (``selection.table_path``), a lock while a process
builds it (``lock``: the builder's process id) and a mark left by a build that failed (``failed``). The commands that
run simulations (``pchute run``, ``study``, ``fit``) call ``start_background_build``, and ``pchute run`` builds
first when its run would take longer with the kernels' Python form than the build (``worth_building_first``,
``build_then_restart``). ``simulate`` from Python builds nothing: an API user's runs take the Python form until
``python -m pchute_exudyn.kernels.build`` (or a command) has built the module.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

from .form import VARIABLE
from .selection import chosen_automatically, table_path

LOCK_AGE = 600.0
"""Seconds after which a build lock is taken to be left by a process that died."""
BUILD_SECONDS = 12.0
"""About what building the compiled module takes (9 to 10 s measured on a 2-core machine; setup.py prints it)."""
PYTHON_STEP_SECONDS = 4.5e-4
"""About what an integration step costs with the kernels' Python form (an SP step of MER case 1 or of a
single-canopy descent, aerodynamics included: validation/startup_budget.py's first runs without a module)."""


def worth_building_first(steps: float) -> bool:
    """Whether a run of ``steps`` integration steps, in a process that runs the Python form because no module was
    found, would take longer that way than building the module first (a foreground build pays for itself when the
    Python form would take over 1.5 times the build: about 40 000 steps, a 400-s descent at 1e-2 s)."""
    return build_would_help() and steps * PYTHON_STEP_SECONDS > 1.5 * BUILD_SECONDS


def build_would_help() -> bool:
    """Whether this process runs the Python form because no module was found (not because a form was asked for),
    and no build of this source failed."""
    return (os.environ.get(VARIABLE) == "python" and chosen_automatically() and not table_path().exists()
            and not failed().exists())


def building() -> bool:
    """Whether another process is building the module now: its lock is younger than LOCK_AGE and the process whose
    id it holds (the builder's, once started) is alive: a builder killed outright leaves a lock nobody waits for."""
    path = lock()
    try:
        if time.time() - path.stat().st_mtime >= LOCK_AGE:
            return False
        holder = int(path.read_text() or 0)
    except (OSError, ValueError):
        return False
    return holder == 0 or alive(holder)   # 0: the lock is being written


def alive(pid: int) -> bool:
    if os.name == "nt":   # os.kill would end the process there; the lock's age decides alone
        return True
    try:
        os.kill(pid, 0)
    except PermissionError:   # alive, another user's
        return True
    except OSError:
        return False
    return True


def build_now() -> bool:
    """The compiled module of this source, built in the foreground (``python -m pchute_exudyn.kernels.build``), or
    the build another process is making, waited for; True when it exists."""
    import subprocess

    if building():
        deadline = time.monotonic() + LOCK_AGE
        while building() and not table_path().exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        if table_path().exists():
            return True
    command = builder_command()
    if command is None:
        return False
    done = subprocess.run(command, env=fresh_environment(), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return done.returncode == 0 and table_path().exists()


def builder_command() -> list | None:
    """The command that builds the module, with the build lock taken for it (the builder removes it); None when the
    kernel folder cannot be written."""
    path = lock()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(str(os.getpid()))
    except OSError:
        return None
    return [sys.executable, "-m", "pchute_exudyn.kernels.build", "--lock", str(path)]


def fresh_environment() -> dict:
    """The environment for a process that should choose the form anew (after a build)."""
    return {key: value for key, value in os.environ.items() if not key.startswith(VARIABLE)}


def lock() -> Path:
    return table_path().with_suffix(".building")


def failed() -> Path:
    """Written by a build of this source that failed (no C compiler, say): runs then stop starting builds that would
    fail the same way; ``python -m pchute_exudyn.kernels.build`` still tries, and removes it when it succeeds."""
    return table_path().with_suffix(".failed")


def start_background_build() -> bool:
    """Spawn ``python -m pchute_exudyn.kernels.build``, detached, when this process runs the Python kernels because
    no compiled module was found (not when a form was asked for), unless another process is building it; True when
    it spawned one."""
    if not build_would_help() or building():
        return False
    command = builder_command()
    if command is None:   # a read-only kernel folder: the runs keep the Python kernels
        return False
    import subprocess  # here only: most processes never start a build

    try:
        subprocess.Popen(command, env=fresh_environment(), start_new_session=True, stdin=subprocess.DEVNULL,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except OSError:
        lock().unlink(missing_ok=True)
        return False
    return True


def build_then_restart(steps: float, quiet: bool) -> None:
    """A long ``pchute run`` with no compiled module: build it first, then run this command again in a process that
    loads it (the kernels' form is chosen once per process). A failed build leaves the run to the Python form."""
    if not quiet:
        print(f"pchute run: note: no compiled kernels for this source yet: building them first (about "
              f"{BUILD_SECONDS:.0f} s, once); with their Python form these {steps:.0f} steps would take "
              f"about {steps * PYTHON_STEP_SECONDS:.0f} s", file=sys.stderr, flush=True)
    if build_now():
        sys.stdout.flush()
        os.execve(sys.executable, [sys.executable, "-m", "pchute_exudyn", *sys.argv[1:]], fresh_environment())


BACKGROUND_NOTE = ("pchute run: note: this machine has no compiled kernels yet; this run uses their Python form "
                   "(slower) while a background process compiles them for the next runs")
"""What ``pchute run`` prints when it started a background build."""

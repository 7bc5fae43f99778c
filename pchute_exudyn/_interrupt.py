"""Ctrl-C in the ``pchute`` command at any moment, its start-up included: an interrupt (exit 130), never a traceback.

Python's own SIGINT handler raises KeyboardInterrupt wherever the main thread is. Inside an import that leaves a
module half imported, and some imports turn the interrupt into another error (Exudyn's reports an ImportError about
its wheel, numpy an AttributeError), so a Ctrl-C in the first 0.3 s of a command ended in a traceback or a wrong
message. The command's handler raises it as Python's does, except inside an import: there it waits for the import to
finish (looking again every ``RETRY`` s) and raises it then; one raised where Python can only print it (``__del__``,
an at-fork callback) is raised again. SIGTERM is taken the same way, as ``Terminated`` (exit 143). It is installed
when the package is imported by the ``pchute`` command (the console script, ``python -m pchute_exudyn``), before
anything heavy is imported; a program that imports the package keeps its own handlers.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from pathlib import Path

RETRY = 0.02
"""Seconds between looks at whether a deferred Ctrl-C may be raised."""


def _importing(frame) -> bool:
    """Whether ``frame``'s stack runs an import."""
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame = frame.f_back
    return False


class Terminated(KeyboardInterrupt):
    """SIGTERM to the command: the same clean stop as Ctrl-C, exit status 143."""

    def __init__(self, message: str = "terminated (SIGTERM)"):
        super().__init__(message)


_PENDING = [KeyboardInterrupt]
"""What the next raise is: KeyboardInterrupt (SIGINT) or Terminated (SIGTERM), kept while an import defers it."""


RECEIVED = [None]
"""The interrupt this command was sent (KeyboardInterrupt or Terminated), None before any: an engine call that the
raise lands in may turn it into an error of its own (Exudyn's AddObject a RuntimeError), which the command then
reports as the interrupt it was (``cli.main``)."""


def interrupt(signum, frame) -> None:
    """SIGINT, SIGTERM (and the timer that retries them): KeyboardInterrupt, or Terminated for SIGTERM, once no
    import is running."""
    if signum == signal.SIGTERM:
        _PENDING[0] = Terminated
    elif signum == signal.SIGINT:
        _PENDING[0] = KeyboardInterrupt
    RECEIVED[0] = _PENDING[0]
    if _importing(frame):
        _retry()
        return
    raised, _PENDING[0] = _PENDING[0], KeyboardInterrupt
    raise raised()


def pending_is_termination() -> bool:
    """Whether the signal a deferred raise stands for is SIGTERM (``Terminated``), and forget it: a solve takes it
    over (``engine.solver``)."""
    pending, _PENDING[0] = _PENDING[0], KeyboardInterrupt
    return pending is Terminated


terminate = interrupt
"""The command's SIGTERM handler (the one function: a solve takes both over, ``engine.solver``)."""


def _retry() -> None:
    signal.signal(signal.SIGALRM, interrupt)
    signal.setitimer(signal.ITIMER_REAL, RETRY)


def _unraisable(unraisable) -> None:
    """``sys.unraisablehook``: a KeyboardInterrupt raised where Python cannot raise it (a ``__del__``, an at-fork
    callback: logging's runs at every fork of a pool's worker) would be printed and lost, and the command would go on
    as if never interrupted: it is raised again a moment later instead. Anything else goes to the previous hook."""
    if issubclass(unraisable.exc_type, KeyboardInterrupt) and threading.current_thread() is threading.main_thread():
        _PENDING[0] = Terminated if issubclass(unraisable.exc_type, Terminated) else KeyboardInterrupt
        _retry()
        return
    _PREVIOUS_HOOK[0](unraisable)


_PREVIOUS_HOOK = [sys.unraisablehook]


def launched_as_command() -> bool:
    """Whether this process is the ``pchute`` command (its original command line)."""
    argv = list(getattr(sys, "orig_argv", ()))
    if "-m" in argv and argv[argv.index("-m") + 1:argv.index("-m") + 2] == ["pchute_exudyn"]:
        return True
    return len(argv) > 1 and Path(argv[1]).name in ("pchute", "pchute.exe", "pchute-script.py")


def asks_only_about_the_command() -> bool:
    """Whether this command line names no command (``pchute --help``, ``--version``, or nothing): such a process
    runs no physics, and chooses no kernel form (loading the compiled module imports numpy: 0.1 s)."""
    return all(argument.startswith("-") for argument in sys.argv[1:])


def install() -> None:
    """Use ``interrupt`` for SIGINT and ``terminate`` for SIGTERM in this process (the main thread only; where
    SIGINT is not ignored, where SIGTERM is at its default)."""
    if not hasattr(signal, "setitimer"):
        return
    installed = False
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, interrupt)
        installed = True
    if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
        signal.signal(signal.SIGTERM, terminate)
        installed = True
    if installed and sys.unraisablehook is not _unraisable:
        _PREVIOUS_HOOK[0] = sys.unraisablehook
        sys.unraisablehook = _unraisable


@contextlib.contextmanager
def signals_interrupt():
    """While a run, a study, a fit or a release point goes on, SIGTERM stops it as Ctrl-C does (``terminate``): a
    study's workers stopped, finished runs kept, one line, exit status 143 (signals reach only the main thread:
    elsewhere nothing changes)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)

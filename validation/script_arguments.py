"""The validation scripts' command lines and endings, under the package's own rule for bad input: every argument is
checked before anything is computed or written; an error is one line '<script>: <message>' with exit status 1 (never
a traceback); Ctrl-C ends with status 130, SIGTERM with 143.

A script reads its command line (``arguments``) before its heavy imports, so ``--help`` and a bad value cost no
import of numpy, Exudyn or the package; its ``__main__`` block hands ``main`` to ``run_script``."""

from __future__ import annotations

import argparse
import math
import os
import signal
import sys
from pathlib import Path

EXIT_INTERRUPTED = 130   # 128 + SIGINT, as the package's command line and shells report it
EXIT_TERMINATED = 143    # 128 + SIGTERM


class OneLineParser(argparse.ArgumentParser):
    """argparse with its errors as one line '<script>: <message>' and exit status 1 (not the usage and status 2)."""

    def __init__(self, script: str | None = None, description: str | None = None, **kwargs):
        if script is not None:   # (a sub-command's parser comes from argparse itself, with its own prog)
            kwargs.setdefault("prog", Path(script).name)
        if description:
            kwargs["description"] = " ".join(description.strip().split("\n\n")[0].split())   # the first paragraph
        super().__init__(**kwargs)

    def error(self, message):
        raise SystemExit(f"{self.prog}: {' '.join(message.split())}")

    def refuse(self, message: str):
        """Stop with one line about an argument argparse accepted but the script cannot use."""
        raise SystemExit(f"{self.prog}: {message}")

    def check_counts(self, args) -> None:
        """``--runs`` at least 1 and ``--workers`` from 1 to the machine's limit."""
        if args.runs < 1:
            self.refuse(f"--runs = {args.runs}: must be >= 1")
        if args.workers < 1 or args.workers > most_workers():   # (0 refused without importing the package)
            self.refuse(f"--workers = {args.workers}: must be from 1 to {most_workers()}")


def most_workers() -> int:
    """The package's limit of local worker processes (imported here: a script may choose the kernels first)."""
    from pchute_exudyn.boundary import most_workers as limit

    return limit()


def count(text: str) -> int:
    """argparse type: a whole number >= 1 (runs, rounds, repeats)."""
    try:
        value = int(text)
    except ValueError:
        value = None
    if value is None or value < 1:
        raise argparse.ArgumentTypeError(f"must be a whole number >= 1, not {text!r}")
    return value


def workers(text: str) -> int:
    """argparse type: a number of local worker processes, from 1 to the package's limit for this machine."""
    value = count(text)
    if value > most_workers():
        raise argparse.ArgumentTypeError(f"must be from 1 to {most_workers()} (this machine's limit), not {text!r}")
    return value


def _number(text: str, allowed: str, holds) -> float:
    """``text`` as a finite float for which ``holds`` is true, else an argparse error saying what is ``allowed``."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and holds(value)):
        raise argparse.ArgumentTypeError(f"must be a finite number {allowed}, not {text!r}")
    return value


def positive(text: str) -> float:
    """argparse type: a finite number > 0 (a duration in s, a step in s, a tolerance)."""
    return _number(text, "> 0", lambda value: value > 0.0)


def non_negative(text: str) -> float:
    """argparse type: a finite number >= 0 (a tolerance)."""
    return _number(text, ">= 0", lambda value: value >= 0.0)


def existing_folder(text: str) -> Path:
    """argparse type: a folder that exists (a checkout of the code before, a folder of logs)."""
    path = Path(text)
    if not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is not a folder (must be an existing folder)")
    return path


def output_path(text: str) -> Path:
    """argparse type: a file or folder to write, whose nearest existing parent is a writable folder."""
    path = Path(text)
    parent = next((p for p in path.absolute().parents if p.exists()), None)
    if parent is None or not parent.is_dir() or not os.access(parent, os.W_OK):
        raise argparse.ArgumentTypeError(f"{text!r} cannot be written (its folder {str(parent)!r} is not writable)")
    return path


def output_file(text: str) -> Path:
    """argparse type: a file to write (``output_path``), not an existing folder."""
    path = output_path(text)
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is a folder (must be a file to write, e.g. a .md table)")
    return path


def no_arguments(script: str, doc: str, argv=None) -> None:
    """The command line of a script that takes none: ``--help`` (before anything runs) and nothing else."""
    OneLineParser(script, doc).parse_args(argv)


def module_of(module: str, doc: str, script: str, argv=None) -> None:
    """The command line of a module a script imports (``script``, its name): ``--help`` says what it is, anything
    else (even nothing) stops in one line pointing at the script, rather than exit 0 having done nothing."""
    parser = OneLineParser(module, doc)
    parser.parse_args(argv)
    parser.refuse(f"a module that validation/{script} imports, not a script: run python validation/{script}")


class Terminated(KeyboardInterrupt):
    """SIGTERM to a script: the same clean stop as Ctrl-C, every ``finally`` run (a staged folder removed), exit
    status 143. (The package's own handler is not used: importing the package first would choose the kernels before
    a script that sets them.)"""


_TERMINATED = []
"""Set when SIGTERM came: a solve it landed in may turn it into an error of its own (Exudyn stops the integration)."""


def _terminate(signum, frame) -> None:
    _TERMINATED.append(signum)
    raise Terminated("terminated (SIGTERM)")


def run_script(main, *args) -> None:
    """Run ``main(*args)`` as the script and exit with its status: an error as one line (status 1), Ctrl-C as 130,
    SIGTERM as 143."""
    if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
        signal.signal(signal.SIGTERM, _terminate)
    prog = Path(sys.argv[0]).name
    try:
        status = main(*args)
    except KeyboardInterrupt as exc:   # (a run's solve raises the package's own Terminated, or one marked so)
        terminated = _TERMINATED or getattr(exc, "terminated", False) or any(c.__name__ == "Terminated"
                                                                             for c in type(exc).__mro__)
        status = _stopped(prog, bool(terminated))
    except Exception as exc:   # every error of a script ends as one line (SystemExit passes: it is one already)
        status = _stopped(prog, True) if _TERMINATED else f"{prog}: {one_line(exc)}"
    sys.exit(status)


def _stopped(prog: str, terminated: bool) -> int:
    print(f"{prog}: {'terminated' if terminated else 'interrupted'}", file=sys.stderr)
    return EXIT_TERMINATED if terminated else EXIT_INTERRUPTED


def one_line(exc: BaseException, limit: int = 300) -> str:
    """An exception as one line: a failed file operation names the file; an unexpected one its type."""
    if isinstance(exc, OSError) and exc.strerror:
        text = f"{exc.filename}: {exc.strerror}" if exc.filename else exc.strerror
    else:
        lines = str(exc).strip().splitlines()
        text = lines[0] if lines else ""
        if not _is_package_error(exc):
            text = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _is_package_error(exc: BaseException) -> bool:
    """Whether ``exc`` is one of the package's own one-line errors (checked without importing the package)."""
    return any(cls.__module__ == "pchute_exudyn.errors" for cls in type(exc).__mro__)

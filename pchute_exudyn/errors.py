"""User-facing errors.

Every mistake a user can make (a bad case file, an unknown method, a step that makes the solver diverge) raises a
subclass of ``PchuteError`` whose message is one line that names what is wrong and what is allowed. The command
line prints that line and exits non-zero; it never shows a traceback for these.
"""

from __future__ import annotations

LARGEST_DIGITS = 12
"""Digits of an oversized integer shown in a message (the rest counted)."""


def short_repr(value, limit: int = 60) -> str:
    """``repr(value)`` cut to ``limit`` characters (an integer of 400 digits, a long list), so a message stays one
    readable line."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10 ** LARGEST_DIGITS:
        try:
            text = str(value)
        except ValueError:   # beyond Python's 4300 digits for int to str
            return f"an integer of about {value.bit_length() * 0.30103:.0f} digits"
        return f"{text[:LARGEST_DIGITS]}... ({len(text.lstrip('-'))} digits)"
    text = repr(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


class PchuteError(Exception):
    """Base class of every error this package raises on purpose."""


class CaseError(PchuteError):
    """A case (or study) file, or an override of one, is invalid.

    Parameters
    ----------
    source : str
        Where the bad value came from: a file path, or ``--set key=value``.
    field : str
        The dotted key of the field, e.g. ``bodies.vehicle.mass``; empty for file-level problems.
    message : str
        What is wrong and what is allowed.
    value : object, optional
        The offending value, shown with ``repr`` when given.
    """

    _NO_VALUE = object()

    def __init__(self, source: str, field: str, message: str, value: object = _NO_VALUE):
        self.source = source
        self.field = field
        self.value = value
        self.detail = message
        where = source if not field else f"{source}: {field}"
        if value is not CaseError._NO_VALUE:
            where = f"{where} = {short_repr(value, 200)}"
        super().__init__(f"{where}: {message}")


class InputError(PchuteError):
    """A bad argument to the API or the command line (unknown method, step <= 0, unwritable folder, ...)."""


class SimulationError(PchuteError):
    """The integration failed: the state became NaN or infinite, a line broke or was over-stretched, or the engine
    stopped.

    Parameters
    ----------
    message : str
        What happened and what to try.
    time : float or None
        Simulation time (s) at which the failure was detected.
    """

    def __init__(self, message: str, time: float | None = None):
        self.time = time
        super().__init__(message)


class Interrupted(KeyboardInterrupt):
    """The user interrupted a run (Ctrl-C, SIGINT; SIGTERM when ``terminated``): not an error of the model. ``time``
    (s) is the simulation time the run had reached; ``cause``: what interrupted it when not a signal to the process
    (a KeyboardInterrupt a user trigger function raised). Nothing of the run is written."""

    def __init__(self, time: float, end: float, cause: str = "", terminated: bool = False):
        self.time, self.end, self.cause, self.terminated = time, end, cause, terminated
        what = "terminated (SIGTERM)" if terminated else "interrupted"
        because = f" ({cause})" if cause else ""
        super().__init__(f"{what} at t = {time:.3f} s of {end:g} s{because}; no result files were written")

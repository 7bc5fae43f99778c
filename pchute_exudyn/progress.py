"""Progress of a long run on a terminal: simulated time, the rate and the time left, on one line of standard error.

Shown only when standard error is a terminal (never in a pipe, a file or CI) and not with ``--quiet``; the line is
cleared when the run ends, so the run's one-line summary or error follows on a clean line.
"""

from __future__ import annotations

import sys
import time


class TerminalProgress:
    """A callable receiving the simulation time ``t`` (s) of a run of ``duration`` (s); redraws at most every
    ``interval`` s of wall time."""

    def __init__(self, duration: float, stream=None, interval: float = 0.25):
        self.duration, self.stream, self.interval = duration, stream or sys.stderr, interval
        self.started = self.last = time.perf_counter()
        self.shown = False

    @staticmethod
    def wanted(quiet: bool = False, stream=None) -> bool:
        """Whether to show progress: not ``quiet`` and the stream (default standard error) is a terminal."""
        stream = stream or sys.stderr
        return not quiet and hasattr(stream, "isatty") and stream.isatty()

    def __call__(self, t: float) -> None:
        now = time.perf_counter()
        if now - self.last < self.interval:
            return
        self.last = now
        elapsed = now - self.started
        fraction = min(max(t / self.duration, 0.0), 1.0) if self.duration > 0 else 1.0
        left = elapsed * (1.0 - fraction) / fraction if fraction > 0 else float("inf")
        rate = t / elapsed if elapsed > 0 else 0.0
        self.stream.write(f"\r  t = {t:.2f} of {self.duration:g} s ({100 * fraction:.0f} %), {rate:.3g} s simulated "
                          f"per s, {elapsed:.0f} s elapsed, about {left:.0f} s left ")
        self.stream.flush()
        self.shown = True

    def close(self) -> None:
        """Clear the line (if anything was drawn)."""
        if self.shown:
            self.stream.write("\r\033[K")
            self.stream.flush()

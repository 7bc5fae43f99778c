"""Progress of a long run on a terminal: simulated time, the rate and the time left, on one line of standard error.

Shown only when standard error is a terminal (never in a pipe, a file or CI) and not with ``--quiet``; the line is
cleared when the run ends, so the run's one-line summary or error follows on a clean line. A study's progress
(``run_progress``) is a bar on a terminal and one line per tenth of its runs elsewhere.
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


class LogProgress:
    """Progress of a study or fit when standard error is not a terminal (a log file, a pipe, CI): one line per tenth
    of the runs done, never a redrawn bar (a carriage-return flood in a log). The subset of ``tqdm``'s interface
    the study uses: ``update``, ``set_postfix``, ``close``."""

    def __init__(self, total: int, initial: int = 0, stream=None, name: str = "study"):
        self.total, self.done, self.stream, self.name = total, initial, stream or sys.stderr, name
        self.postfix: dict = {}
        self.shown_tenth = self._tenth()

    def _tenth(self) -> int:
        return 10 * self.done // self.total if self.total > 0 else 10

    def set_postfix(self, **values) -> None:
        """Counts shown after the runs done; a line due from ``update`` is written with them."""
        self.postfix = values
        self._write_due()

    def update(self, count: int = 1) -> None:
        """``count`` more runs done (the line for a tenth crossed follows the next ``set_postfix`` or ``close``,
        so that it carries the counts of the run just done)."""
        self.done += count

    def _write_due(self) -> None:
        if self._tenth() > self.shown_tenth:
            self.shown_tenth = self._tenth()
            extra = "".join(f", {key} {value}" for key, value in self.postfix.items())
            self.stream.write(f"{self.name}: {self.done} of {self.total} runs done{extra}\n")
            self.stream.flush()

    def close(self) -> None:
        """Write the line due, if any (every line is complete: nothing to clear)."""
        self._write_due()


def run_progress(total: int, initial: int, failed: int, stream=None):
    """A study's progress on standard error (or ``stream``): a ``tqdm`` bar on a terminal, else ``LogProgress``."""
    stream = stream or sys.stderr
    if TerminalProgress.wanted(stream=stream):
        from tqdm import tqdm
        bar = tqdm(total=total, initial=initial, unit="run", desc="study", dynamic_ncols=True, file=stream)
    else:
        bar = LogProgress(total, initial, stream)
    bar.set_postfix(failed=failed)
    return bar

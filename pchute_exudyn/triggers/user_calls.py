"""A user's trigger function called in a thread of its own, so that the thread that waits for it stays free.

The function runs inside Exudyn's post-step hook. Called there directly, a Ctrl-C could not stop it: the solve's
SIGINT handler only sets a flag (``engine.solver``), so a ``time.sleep(100)`` resumed after the handler and the run
went on for as long as the function took. Here the calling thread hands the call to a worker thread and waits for
its answer in slices of ``POLL`` s, looking between them whether the run was asked to stop (``stopped``: Ctrl-C,
SIGTERM) and whether the call has passed its time limit: either ends the wait at once, the worker left to finish
(or not) on its own. A worker that has had nothing to do for ``IDLE`` s ends. Cost: about 13 us per call.
"""

from __future__ import annotations

import queue
import threading
import time

POLL = 0.05
"""s: how often the waiting thread looks at ``stopped`` and the time limit."""
IDLE = 1.0
"""s: a worker with no call for this long ends (the next call starts another)."""


class CallTimedOut(Exception):
    """The call took longer than its time limit (s)."""


class CallInterrupted(Exception):
    """The run was asked to stop (Ctrl-C, SIGTERM) while the call ran."""


class UserCalls:
    """Calls user functions in one worker thread at a time. ``stopped()``: whether the run was asked to stop."""

    def __init__(self, stopped=lambda: False):
        self.stopped = stopped
        self._lock = threading.Lock()
        self._worker = None   # (requests, answers) of the live worker, None when there is none

    def __reduce__(self):
        """A copy (a watch copied, pickled) is a new caller: no worker, not stopped (its feeder sets ``stopped``)."""
        return UserCalls, ()

    def call(self, function, args: tuple, limit: float):
        """``function(*args)``'s answer; its exception (any BaseException, SystemExit and KeyboardInterrupt
        included) is raised here. Raises CallTimedOut after ``limit`` s, CallInterrupted when ``stopped()`` or a
        KeyboardInterrupt arrives while waiting."""
        with self._lock:
            if self._worker is None:
                self._worker = (queue.SimpleQueue(), queue.SimpleQueue())
                threading.Thread(target=self._serve, args=self._worker, daemon=True,
                                 name="pchute-user-function").start()
            requests, answers = self._worker
            requests.put((function, args))
        deadline = time.monotonic() + limit
        try:
            while True:
                try:
                    ok, value = answers.get(timeout=max(min(POLL, deadline - time.monotonic()), 0.0))
                    break
                except queue.Empty:
                    pass
                if self.stopped():
                    raise CallInterrupted()
                if time.monotonic() >= deadline:
                    raise CallTimedOut()
        except KeyboardInterrupt:   # a SIGINT handler that raises (outside a solve, the API's default)
            self._abandon()
            raise CallInterrupted() from None
        except (CallInterrupted, CallTimedOut):
            self._abandon()
            raise
        if not ok:
            raise value
        return value

    def _abandon(self) -> None:
        """Leave the busy worker to itself (a daemon thread): the next call starts another."""
        with self._lock:
            if self._worker is not None:
                self._worker[0].put(None)   # it ends once the call it runs returns
            self._worker = None

    def _serve(self, requests, answers) -> None:
        while True:
            try:
                item = requests.get(timeout=IDLE)
            except queue.Empty:
                with self._lock:   # no call put while it decides (a call puts under the lock)
                    if not requests.empty():
                        continue
                    if self._worker is not None and self._worker[0] is requests:
                        self._worker = None
                    return
            if item is None:
                return
            function, args = item
            try:
                answers.put((True, function(*args)))
            except BaseException as exc:   # noqa: BLE001 - handed to the caller, which says what it was
                answers.put((False, exc))

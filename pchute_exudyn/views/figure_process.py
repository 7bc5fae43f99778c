"""The run's figures drawn by a process of its own, started with the command, so that matplotlib's import (0.3 s,
most of what the figures cost) runs on another core while the case is loaded and run.

``FigureProcess()`` starts ``python -m pchute_exudyn.views.figure_process``, which imports the plotting module and
waits; ``draw(result, path, track, loads)`` sends it the columns the figures show, the run's summary and its load
histories, and waits for ``path`` (the overview), ``track`` (the ground track) and ``loads`` (the loads figure), each
when given, to be written (``plotting.plot_overview``,
``plotting.plot_ground_track``, ``plotting.save_figure``: the same figures as drawn in the command's own process).
Where it cannot (one core, the process failed), ``draw`` returns False and the caller draws the figure itself.
"""

from __future__ import annotations

import os
import pickle
import subprocess
import sys

from ..registries.columns import column

VEHICLE_COLUMNS = ("{owner}_altitude", "{owner}_velocity_down", "{owner}_east", "{owner}_north", "{owner}_mach",
                   "{owner}_dynamic_pressure")
"""The vehicle's columns the figures draw (those the run has)."""


def cores() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


class FigureProcess:
    """A process that draws one run's figures (see the module docstring); ``close`` ends it if still running."""

    def __init__(self):
        self.process = None
        if cores() < 2:   # nothing to overlap with: the command draws it
            return
        try:
            self.process = subprocess.Popen([sys.executable, "-m", "pchute_exudyn.views.figure_process"],
                                            stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                            stderr=subprocess.DEVNULL, start_new_session=True)
        except OSError:
            self.process = None

    def draw(self, result, path, track=None, loads=None) -> bool:
        """Have the process draw ``result``'s overview figure into ``path`` and, with ``track``, its ground track
        there, with ``loads`` its loads figure there; True when it did."""
        if self.process is None:
            return False
        names = ["time", *result.tension_names()]
        names += [name for name in (column(template, result.vehicle) for template in VEHICLE_COLUMNS)
                  if name in result]
        # the typed summary whole (a few kB): the figures read its titles, the vehicle's name and the events
        message = {"columns": {name: result[name] for name in names}, "summary": result.summary,
                   "path": str(path), "track": None if track is None else str(track),
                   "loads": None if loads is None else str(loads), "histories": result.loads if loads else {}}
        try:
            self.process.stdin.write(pickle.dumps(message, protocol=pickle.HIGHEST_PROTOCOL))
            self.process.stdin.close()
            return self.process.wait() == 0 and all(os.path.isfile(p) for p in (path, track, loads) if p is not None)
        except OSError:   # the process ended early (a broken pipe): the command draws the figures
            return False
        finally:
            self.close()

    def close(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        self.process = None


def main() -> int:
    from ..results.result import Result
    from .plotting import (  # the import this process exists for
        plot_deployment_loads,
        plot_ground_track,
        plot_overview,
        save_figure,
    )

    message = pickle.load(sys.stdin.buffer)
    result = Result(message["columns"], {}, message["summary"], loads=message.get("histories"))
    save_figure(plot_overview(result), message["path"])
    if message.get("track") is not None:
        save_figure(plot_ground_track(result), message["track"])
    if message.get("loads") is not None:
        save_figure(plot_deployment_loads(result), message["loads"])
    return 0


if __name__ == "__main__":
    try:
        code = main()
    except Exception:   # the command sees the exit status and draws the figure itself
        code = 1
    os._exit(code)   # the file is written and closed: no interpreter teardown (0.1 s with matplotlib loaded)

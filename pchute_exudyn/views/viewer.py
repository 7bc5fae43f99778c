"""Replay a finished run in Exudyn's SolutionViewer (``pchute view``), from its result folder alone.

The run's stored scene drives a display model (``engine.display``); its coordinates go to an Exudyn text solution
file, which the viewer loads. The viewer needs a display: without one, ``pchute view`` stops with a one-line error
(``pchute animate`` draws the same scene without a display).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import io
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

from ..engine.display import DisplayModel, open_viewer
from ..environment import DISPLAY, WAYLAND_DISPLAY
from ..errors import InputError
from ..results.io import atomic_write_text
from ..results.result import load_scene

SOLUTION_NAME = "display_solution.txt"


def solution_text(time: np.ndarray, coordinates: np.ndarray) -> str:
    """``coordinates`` (n, nODE2) at ``time`` (s) in Exudyn's text solution-file format (displacements only)."""
    n = coordinates.shape[1]
    # Exudyn's reader expects the written-coordinates line fifth, as the engine's own files have it
    header = ["#Exudyn solution file written by pchute-exudyn", "#display model of a finished run",
              "#columns contain: time, ODE2 displacements",
              f"#number of system coordinates [nODE2, nODE1, nAlgebraic, nData] = [{n},0,0,0]",
              f"#number of written coordinates [nODE2, nVel2, nAcc2, nODE1, nVel1, nAlgebraic, nData] = "
              f"[{n},0,0,0,0,0,0]", f"#total columns exported  (excl. time) = {n}",
              f"#number of time steps (planned) = {len(time)}", "#"]
    buffer = io.StringIO()
    buffer.write("\n".join(header) + "\n")
    np.savetxt(buffer, np.column_stack([time, coordinates]), delimiter=",", fmt="%.10g")
    return buffer.getvalue()


def prepare(folder, solution_path, scene=None) -> DisplayModel:
    """The display model of result folder ``folder`` (or of its ``scene``, already loaded), with its solution file
    written to ``solution_path``."""
    time, arrays, description = load_scene(folder) if scene is None else scene
    model = DisplayModel(description)
    atomic_write_text(solution_path, solution_text(np.asarray(time, float), model.coordinates(arrays)))
    return model


def has_display() -> bool:
    """Whether a window can open: always on Windows and macOS, on Linux only with an X11 or Wayland display."""
    return not sys.platform.startswith("linux") or bool(os.environ.get(DISPLAY) or os.environ.get(WAYLAND_DISPLAY))


def display_problem() -> str | None:
    """Why no window can open here, or None. On Linux with X11 the display is opened and closed once first:
    Exudyn's renderer aborts the whole process (no exception) when it cannot open it."""
    if not has_display():
        return "DISPLAY is not set"
    display = os.environ.get(DISPLAY)
    if not sys.platform.startswith("linux") or not display:
        return None
    library = ctypes.util.find_library("X11")
    if library is None:   # cannot check: the viewer tries
        return None
    x11 = ctypes.CDLL(library)
    x11.XOpenDisplay.restype, x11.XOpenDisplay.argtypes = ctypes.c_void_p, [ctypes.c_char_p]
    x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
    handle = x11.XOpenDisplay(display.encode())
    if not handle:
        return f"the X display DISPLAY={display!r} cannot be opened (no X server there?)"
    x11.XCloseDisplay(handle)
    return None


def view(folder) -> None:
    """Open the run in result folder ``folder`` in Exudyn's SolutionViewer (InputError without a display, or when
    the viewer fails to open)."""
    scene = load_scene(folder)   # a folder that is no result is told first
    problem = display_problem()
    if problem is not None:
        raise InputError(f"no display to open Exudyn's viewer in ({problem}); `pchute animate {folder}` draws the "
                         "run into a GIF or MP4 without one")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / SOLUTION_NAME
        model = prepare(folder, path, scene)
        try:
            open_viewer(model, path, f"pchute-exudyn: {folder}")
        except Exception as exc:   # the engine's own text stays out of the message's first words
            first = (str(exc).strip().splitlines() or [type(exc).__name__])[0][:120]
            raise InputError(f"Exudyn's viewer could not open ({type(exc).__name__}: {first}); `pchute animate "
                             f"{folder}` draws the run into a GIF or MP4 without a window") from None

"""Calibration: fit free case keys to measured event times, final values and time histories (``pchute fit``)."""

from .solve import run_fit
from .spec import FitSpec, load_fit

__all__ = ["FitSpec", "load_fit", "run_fit"]

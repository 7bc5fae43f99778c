"""Calibration: fit free case keys to measured event times, final values and time histories (``pchute fit``)."""

from .evaluate import Evaluation
from .solve import FitOutcome, run_fit
from .spec import FitSpec, load_fit

__all__ = ["Evaluation", "FitOutcome", "FitSpec", "load_fit", "run_fit"]

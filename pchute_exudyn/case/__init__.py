"""Case files: the model of a run as validated, frozen data."""

from .loader import apply_override, load_case, parse_override
from .model import INTEGRATORS, METHODS, Case

__all__ = ["Case", "INTEGRATORS", "METHODS", "apply_override", "load_case", "parse_override"]

"""Case files: the model of a run as validated, frozen data."""

from .loader import Scale, apply_override, load_case, parse_override
from .model import INTEGRATORS, METHODS, Case

__all__ = ["Case", "INTEGRATORS", "METHODS", "Scale", "apply_override", "load_case", "parse_override"]

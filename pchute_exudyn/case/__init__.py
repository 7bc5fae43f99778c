"""Case files: the model of a run as validated, frozen data, and the table of methods a case can name."""

from ..registries.methods import INTEGRATORS, METHODS, OptionError
from .loader import load_case
from .model import Case
from .overrides import Scale, apply_override, parse_override

__all__ = ["Case", "INTEGRATORS", "METHODS", "OptionError", "Scale", "apply_override", "load_case",
           "parse_override"]

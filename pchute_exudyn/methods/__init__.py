"""The confluence methods, one class each, registered in the method table (``case.method_table.METHODS``).

Adding a method: write its class (a ``base.Method`` subclass with a name, its integrators, its Options type, a
``build`` and, if it has confluence dynamics, a ``step_limit``) and add it to ``_BUILT_IN`` below.
"""

from ..case.method_table import METHODS
from .base import Method, StepLimit, unstable_step_message
from .equilibrium import EquilibriumPoint
from .full import FullMass
from .sp import SingularPerturbation

_BUILT_IN = (FullMass, SingularPerturbation, EquilibriumPoint)
for _method in _BUILT_IN:
    METHODS.register(_method)

__all__ = ["METHODS", "EquilibriumPoint", "FullMass", "Method", "SingularPerturbation", "StepLimit",
           "unstable_step_message"]

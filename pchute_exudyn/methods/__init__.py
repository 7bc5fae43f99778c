"""The confluence methods, one module each, registered in the method table (``registries.methods.METHODS``).

Adding a method: a module in this package with its class (a ``base.Method`` subclass with a name, its integrators,
its Options type, a ``build`` of its model and, if it has confluence dynamics, a ``step_limit``), its model's
confluence, and its kernels in ``physics/``. Every ``Method`` subclass defined in a module of this package is
registered when the table is first read, in the order of ``ORDER`` and then by module name.
"""

import importlib
import pkgutil

from ..registries.methods import METHODS
from .base import Method, StepLimit, unstable_step_message

ORDER = ("full", "sp", "equilibrium")
"""The built-in methods' order in the table (the command line's choices and the docs' tables list them so)."""


def _discovered() -> list:
    found = []
    for module in pkgutil.iter_modules(__path__):
        loaded = importlib.import_module(f"{__name__}.{module.name}")
        found += [value for value in vars(loaded).values() if isinstance(value, type) and issubclass(value, Method)
                  and value is not Method and value.__module__ == loaded.__name__ and value.name]
    return sorted(found, key=lambda m: (ORDER.index(m.name) if m.name in ORDER else len(ORDER), m.__module__))


for _method in _discovered():
    METHODS.register(_method)

__all__ = ["METHODS", "Method", "StepLimit", "unstable_step_message"]

"""The confluence methods, one module or package each, registered in the method table
(``registries.methods.METHODS``).

Adding a method: a module (or a package, as ``sp``) in this package with its class: a ``base.Method`` subclass with a
name, its integrators, its Options type, a ``build`` of its model and, if it has confluence dynamics, its step limits
(``confluence_limits``, ``lumped_limit``); its model's confluence; its kernels (pure, compiled: in ``physics/`` or in
its own package, listed in ``kernels.selection.SP_KERNELS`` for SP's). ``register_builtin`` registers every ``Method``
subclass a module of this package defines, or a package exports in ``__all__``, when the table is first read
(``pchute_exudyn.__init__``), in the order of ``ORDER`` and then by module name: importing this package registers
nothing and imports no engine, so that a method's kernel modules can be imported alone (the kernels' build).
"""

import importlib
import pkgutil

from ..registries.methods import METHODS
from .base import Method, StepLimit, unstable_step_message

ORDER = ("full", "sp", "equilibrium")
"""The built-in methods' order in the table (the command line's choices and the docs' tables list them so)."""


def _defined(loaded) -> list:
    """The method classes a module defines, or a package exports (``__all__``, imported when asked for)."""
    if hasattr(loaded, "__path__"):
        values = [getattr(loaded, name) for name in getattr(loaded, "__all__", ())]
    else:
        values = [value for value in vars(loaded).values() if getattr(value, "__module__", None) == loaded.__name__]
    return [value for value in values if isinstance(value, type) and issubclass(value, Method)
            and value is not Method and value.name]


def _discovered() -> list:
    found = []
    for module in pkgutil.iter_modules(__path__):
        found += _defined(importlib.import_module(f"{__name__}.{module.name}"))
    return sorted(found, key=lambda m: (ORDER.index(m.name) if m.name in ORDER else len(ORDER), m.__module__))


def register_builtin() -> None:
    """Register the built-in methods (``METHODS.fill_with`` calls it when the table is first read)."""
    for method in _discovered():
        METHODS.register(method)


__all__ = ["METHODS", "Method", "StepLimit", "register_builtin", "unstable_step_message"]

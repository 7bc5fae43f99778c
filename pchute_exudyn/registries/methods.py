"""The table of confluence methods, as scipy's ``solve_ivp`` keeps ``METHODS``: name -> method class.

The classes themselves live in ``pchute_exudyn.methods`` (they build Exudyn models, so they sit above the engine)
and register here when the package is imported; the case loader, the Python API, the command line and study files
all resolve a method and validate its options through this one table. Nothing else compares method names.

A method class has a ``name``, the ``integrators`` it supports (a subset of INTEGRATORS), a one-line ``summary`` and
an ``Options`` type: a frozen dataclass whose fields are the method's options with their defaults, validated in
``__post_init__`` by raising ``OptionError``.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, fields, replace
from typing import Any


@dataclass(frozen=True)
class Integrator:
    """An integrator of the engine: ``explicit`` (a fixed-step explicit scheme whose step stability limits) or not
    (implicit: stable at any step, the step is for accuracy)."""

    name: str
    explicit: bool

    def step_key(self, method_name: str) -> str:
        """The key of ``[simulation.steps]`` for method ``method_name`` with this integrator: the method's name for
        rk4, ``<method>_<integrator>`` for any other."""
        return method_name if self.name == "rk4" else f"{method_name}_{self.name}"


ADAPTIVE_STEP = "auto"
"""The step that asks for adaptive steps (``--dt auto``, ``step = "auto"``, a study's ``steps = ["auto"]``): an RK4
run without a step gets them anyway (``physics.step_rule``)."""

INTEGRATORS = {integrator.name: integrator for integrator in (Integrator("rk4", explicit=True),
                                                               Integrator("implicit", explicit=False))}
"""Integrator name -> Integrator, in the order of the choices. ``rk4``: Exudyn's explicit RK44, fixed step;
``implicit``: Exudyn's generalized-alpha."""


class OptionError(ValueError):
    """A method option (or a method name) is invalid: ``field``, ``value`` and what is allowed (``allowed``)."""

    def __init__(self, field: str, value: Any, allowed: str, message: str | None = None):
        self.field, self.value, self.allowed = field, value, allowed
        super().__init__(message or f"{field} = {value!r}: {allowed}")


@dataclass(frozen=True)
class NoOptions:
    """Options of a method that has none."""


def option_names(options_type) -> tuple:
    """The option names of an options type, in declaration order."""
    return tuple(f.name for f in fields(options_type))


def make_options(options_type, values: Mapping[str, Any], base=None):
    """An options object of ``options_type`` from ``values`` on top of ``base`` (default: the type's defaults);
    an unknown name or a bad value raises OptionError."""
    names = option_names(options_type)
    for name, value in values.items():
        if name not in names:
            allowed = f"options are: {', '.join(names)}" if names else "this method has no options"
            raise OptionError(name, value, f"not an option of this method; {allowed}")
    base = options_type() if base is None else base
    return replace(base, **dict(values)) if values else base


class MethodTable(Mapping):
    """Method name -> method class; ``register`` adds one (also as a class decorator)."""

    def __init__(self):
        self._registered: dict = {}
        self._fill = None   # called once before the first lookup (``fill_with``)

    def fill_with(self, fill) -> None:
        """Call ``fill`` (which registers the built-in methods) before the table is first read: the package wires
        it, so that the methods and the engine below them are imported only by a process that uses them."""
        self._fill = fill

    @property
    def _classes(self) -> dict:
        if self._fill is not None:
            fill, self._fill = self._fill, None
            fill()
        return self._registered

    def register(self, method_class):
        """Add ``method_class`` under its ``name``; a name already taken by another class is an error."""
        name = method_class.name
        if name in self._classes and self._classes[name] is not method_class:
            raise ValueError(f"a method named {name!r} is already registered ({self._classes[name].__name__})")
        unknown = [i for i in method_class.integrators if i not in INTEGRATORS]
        if unknown:
            raise ValueError(f"method {name!r} names unknown integrator(s) {unknown}; "
                             f"integrators are {tuple(INTEGRATORS)}")
        self._classes[name] = method_class
        from .columns import method_outputs, register  # here: the table's import (every command's) needs no numpy
        register(*method_outputs(getattr(method_class, "outputs", {})))   # its columns (``registries.columns``)
        return method_class

    def unregister(self, name: str) -> None:
        """Remove a method (tests register toy methods and remove them again)."""
        self._classes.pop(name, None)

    def resolve(self, method):
        """The class for a method name or class; an unknown name raises OptionError listing the methods."""
        if isinstance(method, type):   # a method class itself, registered or not (as solve_ivp takes a solver class)
            return method
        if method not in self._classes:
            methods = ", ".join(self._classes)
            raise OptionError("method", method, f"must be one of: {methods}",
                              f"unknown method {method!r}; methods are: {methods}")
        return self._classes[method]

    def __getitem__(self, name: str):
        return self._classes[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._classes)

    def __len__(self) -> int:
        return len(self._classes)


METHODS = MethodTable()
"""The method table (filled by ``pchute_exudyn.methods``)."""

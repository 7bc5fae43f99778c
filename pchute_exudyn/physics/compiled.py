"""Compiled per-stage kernels: the one place that says how physics functions are compiled.

The functions that run at every solver stage (body kinematics, the SP solve, small linear algebra, the line law of a
load-elongation table, the aerodynamics), and a few that run over whole histories (the air-relative outputs, the
numbers of timeseries.csv: ``number_text``), are written in the subset of Python that numba compiles (floats, ints,
bools, numpy arrays, loops) and decorated with ``kernel``. They are the only home of their formulas: Python callers
(tests, the equilibrium method, histories) call the same functions.

What ``kernel`` returns depends on the form this process runs (``pchute_exudyn.kernels.selection``):

* compiled: a ``CompiledKernel``, which calls the kernel's code in the ahead-of-time compiled module (no numba in
  the process) when the arguments have the types it was compiled for, and its Python form otherwise;
* jit: numba's dispatcher (nopython mode, cached on disk, GIL released); the compiled module is built in this form;
* python: the function as it is.

No ``fastmath``: results are IEEE-exact like the Python they replace, in every form. numpy's error model: a division
by zero gives inf or NaN as numpy does (the solver's NaN check stops such a run) instead of raising.
"""

from __future__ import annotations

import os
from array import array
from types import FunctionType

import numpy as np

from ..kernels.form import EXPORTS, VARIABLE

MODE = os.environ.get(VARIABLE, "compiled")
"""The form this process runs: 'compiled', 'jit' or 'python' (chosen by ``kernels.selection.select`` before this
import)."""
COMPILED = MODE != "python"
"""Whether the kernels run as machine code (either compiled form)."""
JIT = MODE == "jit"
FALLBACKS: dict = {}
"""Compiled form: calls that ran a kernel's Python form because no compiled code takes their argument types, by
(kernel name, argument types). Empty in every run the package makes (``tests/integration/test_kernels.py``)."""

_SCALARS = {float: "f8", int: "i8", bool: "b1", np.float64: "f8", np.int64: "i8", np.bool_: "b1"}


def describe(value) -> str:
    """The type of an argument as the compiled module's table names it (as numba would type it): 'f8', 'i8', 'b1',
    '<f8:2:C' (an array's dtype, dimensions, layout, ':r' when read-only), 'array.d' (a typed array), '(...)' (a
    tuple); any other type by its Python name (never compiled)."""
    kind = _SCALARS.get(type(value))
    if kind is not None:
        return kind
    if type(value) is np.ndarray:
        flags = value.flags
        layout = "C" if flags.c_contiguous else "F" if flags.f_contiguous else "A"
        return f"{value.dtype.str}:{value.ndim}:{layout}" + ("" if flags.writeable else ":r")
    if type(value) is array:
        return f"array.{value.typecode}"
    if type(value) is tuple:
        return "(" + ",".join(describe(item) for item in value) + ")"
    return type(value).__name__


class CompiledKernel:
    """A kernel of the compiled module: called like the function, it runs the compiled code compiled for the
    arguments' types (``describe``), else the function's Python form (the same result, slower; counted in
    FALLBACKS)."""

    __slots__ = ("py_func", "name", "codes", "floats", "__wrapped__")

    def __init__(self, function, codes: list):
        self.py_func = self.__wrapped__ = function
        self.name = f"{function.__module__}.{function.__qualname__}"
        self.codes = {types: code for types, code in codes}
        # compiled for float arguments only: any number converts to a float exactly as the code reads it, so the
        # call needs no check (3x3 linear algebra called per stage by the equilibrium point, hypot, gust speed)
        only = len(codes) == 1 and all(kind == "f8" for kind in codes[0][0])
        self.floats = codes[0][1] if only else None

    def code_for(self, arguments):
        """The compiled code for arguments of these types, or the Python form."""
        types = tuple(describe(argument) for argument in arguments)
        code = self.codes.get(types)
        if code is None:
            FALLBACKS[(self.name, types)] = FALLBACKS.get((self.name, types), 0) + 1
            return self.py_func
        return code

    def __call__(self, *arguments):
        if self.floats is not None:
            return self.floats(*arguments)
        return self.code_for(arguments)(*arguments)

    def __repr__(self) -> str:
        return f"<compiled kernel {self.name}>"


def kernel(function):
    """``function`` in the form this process runs (see the module docstring)."""
    if MODE == "python":
        return function
    if MODE == "jit":
        import numba  # only when compiling: the other forms are spared its import (0.2 s) and start-up (0.4 s)

        return numba.njit(cache=True, nogil=True, error_model="numpy")(function)
    name = f"{function.__module__}.{function.__qualname__}"
    return CompiledKernel(function, EXPORTS.get(name, []))


def machine_code(function, *arguments):
    """The machine code of kernel ``function`` for the types of ``arguments``, callable without any per-call type
    check (a per-stage call saves about 0.25 us of its 1.5 us): the compiled module's export, or numba's compiled
    code for these types (loaded from its cache or compiled). Every call must pass arguments of exactly these types
    (arrays of the same dtype, dimensions and layout; float, int and bool scalars as Python floats, ints and bools):
    the code converts what it is given without checking. In the Python form, ``function`` itself."""
    if MODE == "python":
        return function
    if MODE == "jit":
        import numba

        return function.compile(tuple(numba.typeof(argument) for argument in arguments))
    return function.code_for(arguments)


def has_machine_code(function, *arguments) -> bool:
    """Whether kernel ``function`` runs as machine code for the types of ``arguments`` (in the compiled form: the
    compiled module has an export for them; the jit form compiles any; the Python form has none)."""
    if MODE == "python":
        return False
    if MODE == "jit":
        return True
    return tuple(describe(argument) for argument in arguments) in function.codes


def bound(function):
    """A caller of kernel ``function`` that runs the machine code for the types of its first call's arguments
    (``machine_code``) from then on: for a per-stage call site whose arguments always have the same types (a
    model's arrays), where a ``CompiledKernel``'s check of every call costs more than the kernel."""
    codes = []

    def call(*arguments):
        if not codes:
            codes.append(machine_code(function, *arguments))
        return codes[0](*arguments)
    return call


_PYTHON_FORMS: dict = {}
"""Each kernel's Python form with its kernel calls rebound to theirs (``python_form``), made once."""


def python_form(function):
    """Kernel ``function`` as the Python it is written in, the kernels it calls as Python too: for a call from Python
    (a line's law in the equilibrium method, a step limit), where crossing into tiny compiled code costs more than
    the arithmetic it saves, at every inner call as much as at the outer one."""
    python = getattr(function, "py_func", function)
    if MODE == "python" or not hasattr(python, "__code__"):
        return python
    if python not in _PYTHON_FORMS:
        _PYTHON_FORMS[python] = python   # a kernel that calls itself keeps calling this form
        inner = {name: value for name, value in python.__globals__.items()
                 if name in python.__code__.co_names and hasattr(value, "py_func")}
        if inner:
            namespace = {**python.__globals__, **{name: python_form(value) for name, value in inner.items()}}
            _PYTHON_FORMS[python] = FunctionType(python.__code__, namespace, python.__name__, python.__defaults__,
                                                 python.__closure__)
    return _PYTHON_FORMS[python]

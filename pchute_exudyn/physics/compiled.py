"""Compiled per-stage kernels: the one place that says how physics functions are compiled.

The functions that run at every solver stage (body kinematics, the SP solve, small linear algebra, the line law of a
load-elongation table) are written in the subset of Python that numba compiles (floats, ints, bools, numpy arrays,
loops) and decorated with ``kernel``. They are the only home of their formulas: Python callers (tests, the
equilibrium method, histories) call the same compiled functions.

Compiled code is cached on disk (numba's ``cache=True``: beside the module, or in the user's cache directory when
the package directory is read-only). Until a machine's cache is complete the kernels run as the Python they are
(``pchute_exudyn._kernel_mode``), so no run pays the several seconds of compilation
(``validation/benchmark_sp.py`` measures both). No ``fastmath``: results are IEEE-exact like the Python they replace.
numpy's error model: a division by zero gives inf or NaN as numpy does (the solver's NaN check stops such a run)
instead of raising, which also spares every division a check.
"""

from __future__ import annotations

import os

COMPILED = os.environ.get("PCHUTE_KERNELS", "compiled") == "compiled"
"""Whether the kernels run compiled: chosen by ``pchute_exudyn._kernel_mode`` before this import (the Python form
on a machine whose kernels are not compiled yet, while a background process compiles them)."""


def kernel(function):
    """Compile ``function`` with numba (nopython mode, cached on disk, GIL released, numpy's error model); in the
    Python mode, the function as it is."""
    if not COMPILED:
        return function
    import numba  # only when compiling: the Python mode (a machine's first run) is spared its import (0.15 s)

    return numba.njit(cache=True, nogil=True, error_model="numpy")(function)


def machine_code(function, *arguments):
    """The compiled code of kernel ``function`` for the types of ``arguments`` (loaded from the cache or compiled),
    callable without numba's per-call type dispatch: a per-stage call saves about 0.25 us of its 1.5 us (measured
    in ``validation/benchmark_sp.py``). Every call must pass arguments of exactly these types (arrays of the same
    dtype, dimensions and layout; float, int and bool scalars as Python floats, ints and bools): the code converts
    what it is given without checking. In the Python mode, ``function`` itself."""
    if not COMPILED:
        return function
    import numba

    return function.compile(tuple(numba.typeof(argument) for argument in arguments))


def python_form(function):
    """Kernel ``function`` as the Python it is written in: for a check made from Python, where calling tiny
    compiled code costs more than the arithmetic it saves."""
    return getattr(function, "py_func", function)


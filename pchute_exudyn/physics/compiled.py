"""Compiled per-stage kernels: the one place that says how physics functions are compiled.

The functions that run at every solver stage (body kinematics, the SP solve, small linear algebra, the line law of a
load-elongation table) are written in the subset of Python that numba compiles (floats, ints, bools, numpy arrays,
loops) and decorated with ``kernel``. They are the only home of their formulas: Python callers (tests, the
equilibrium method, histories) call the same compiled functions.

Compiled code is cached on disk (numba's ``cache=True``: beside the module, or in the user's cache directory when
the package directory is read-only), so only the first run on a machine pays for compilation
(``validation/benchmark_sp.py`` measures it). No ``fastmath``: results are IEEE-exact like the Python they replace.
numpy's error model: a division by zero gives inf or NaN as numpy does (the solver's NaN check stops such a run)
instead of raising, which also spares every division a check.
"""

from __future__ import annotations

import numba


def kernel(function):
    """Compile ``function`` with numba (nopython mode, cached on disk, GIL released, numpy's error model)."""
    return numba.njit(cache=True, nogil=True, error_model="numpy")(function)

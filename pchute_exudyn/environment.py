"""Every environment variable the package reads or sets, by name: one place to look them up.

Each constant is the variable's name; the package reads ``os.environ`` only through these. Nothing of the package
is imported here (it sits below every other module, the physics kernels included).
"""

import os

KERNELS = "PCHUTE_KERNELS"
"""The kernels' form: ``compiled`` (the compiled module, or ``jit`` when none of the current source exists), ``jit``
or ``python``; unset: automatic (``kernels.selection``). Any other value is an input error. The process sets it to
the form it chose, so that child processes agree; names starting with it are dropped for a process that should
choose anew (``kernels.lock.fresh_environment``)."""
KERNELS_AUTO = KERNELS + "_AUTO"
"""Set to ``1`` by the process when it chose the Python form itself because no compiled module was found (not
because a form was asked for): only then may a build help (``kernels.lock.build_would_help``)."""
KERNELS_NUMBA_BASE = KERNELS + "_NUMBA_BASE"
"""Set by the jit form: the folder its per-source numba caches go in, so that child processes agree
(``kernels.selection.use_jit_cache_of_this_source``)."""
KERNEL_DIR = "PCHUTE_KERNEL_DIR"
"""A folder for the compiled kernel module, instead of the package's ``_compiled`` folder or the user's cache
(``kernels.selection.cache_directory``); when set, the module is looked for there alone."""
NUMBA_CACHE_DIR = "NUMBA_CACHE_DIR"
"""numba's on-disk cache: read as the base folder a user gave, then set by the jit form to a folder of this kernel
source under it (``jit_<source key>``)."""
XDG_CACHE_HOME = "XDG_CACHE_HOME"
"""The user's cache folder (default ``~/.cache``): the kernel module goes in its ``pchute_exudyn`` folder when the
package's own folder cannot be written."""
DISPLAY = "DISPLAY"
"""The X11 display (Linux): ``pchute view`` opens a window only with it or ``WAYLAND_DISPLAY`` set."""
WAYLAND_DISPLAY = "WAYLAND_DISPLAY"
"""The Wayland display (Linux): see ``DISPLAY``."""
SKIP_KERNEL_BUILD = "PCHUTE_SKIP_KERNEL_BUILD"
"""Read by the install (``setup.py``) alone: ``1`` installs without building the compiled kernel module, which
otherwise fails the install when it cannot be built (runs then use the Python form and build it in the background)."""
BLAS_THREADS = "OPENBLAS_NUM_THREADS"
"""OpenBLAS's thread count (numpy's BLAS): the ``pchute`` command sets it to 1 unless the user has set it
(``single_thread_blas``), before numpy is imported. The command's arrays are small (a body's 6x6, a line table),
so BLAS threads never pay for themselves, yet starting them costs every command about 60 ms of its start-up (numpy's
import 0.21 s against 0.15 s here); a study's worker processes inherit it, as they should (their parallelism is the
processes'). A program that imports the package keeps its own setting."""


def single_thread_blas() -> None:
    """Set ``BLAS_THREADS`` to 1 for this process and its children unless set (the command; see ``BLAS_THREADS``)."""
    os.environ.setdefault(BLAS_THREADS, "1")

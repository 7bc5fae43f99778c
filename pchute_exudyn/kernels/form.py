"""The form of the kernels this process runs, as the kernels see it: the environment variable that names it and the
compiled module's exports. ``kernels.selection.select`` fills it before ``physics`` is imported; ``physics.compiled``
reads it (without importing the file handling of ``kernels.selection``)."""

from ..environment import KERNELS

VARIABLE = KERNELS
"""The environment variable that names the form (``environment.KERNELS``)."""

EXPORTS: dict = {}
"""The loaded compiled module's exports: kernel name -> [(argument types, function)]; empty unless this process
runs the compiled form."""
BUILDER: dict = {}
"""What built the loaded compiled module ({"numba": version}); empty unless this process runs the compiled form."""

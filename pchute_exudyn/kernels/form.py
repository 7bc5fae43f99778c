"""The form of the kernels this process runs, as the kernels see it: the environment variable that names it and the
compiled module's exports. ``_kernel_mode.select`` fills it before ``physics`` is imported; ``physics.compiled``
reads it (without importing the file handling of ``_kernel_mode``)."""

VARIABLE = "PCHUTE_KERNELS"
EXPORTS: dict = {}
"""The loaded compiled module's exports: kernel name -> [(argument types, function)]; empty unless this process
runs the compiled form."""
BUILDER: dict = {}
"""What built the loaded compiled module ({"numba": version}); empty unless this process runs the compiled form."""

"""The compiled kernels: which form a process runs (``selection``), the build lock and when to build (``lock``),
building the module (``build``) and recording the signatures it is built for (``record``, a developer tool)."""

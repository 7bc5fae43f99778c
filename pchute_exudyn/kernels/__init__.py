"""The compiled kernels: which form a process runs, the build lock, building the module and recording its signatures."""

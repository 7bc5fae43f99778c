"""Integration tier: runs of the models through the engine, the command line, studies and fits (Dask included),
the files they read and write, and the faults around them."""

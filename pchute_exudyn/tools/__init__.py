"""Developer tools that run the whole package (the top layer, beside the command line): ``record_signatures``
records the argument types every compiled kernel is called with (``kernels/signatures.json``)."""

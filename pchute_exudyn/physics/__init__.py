"""Pure physics kernels: no Exudyn import, so they can be tested alone and reused by every method."""

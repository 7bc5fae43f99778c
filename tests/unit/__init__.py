"""Unit tier: the physics kernels, the readers and the small fast checks; no Exudyn run, or only tiny ones (seconds
for the whole tier: ``python -m pytest tests/unit``)."""

"""Acceptance tier: the thesis's numbers, the methods against full mass and the recorded reference runs, closed forms
over whole descents, the PA1 validation, the tutorial and the examples as written, and the README and architecture
checks."""

"""Triggers: when an event of a sequence happens, from what avionics sense (docs/case-format.md, "Triggers").

``definition``: a trigger's condition and sensor, the case data; ``sensors``: what a sensor reads (barometric
altitude, navigated speeds, seeded noise); ``crossing``: where a continuously sampled crossing lies between two
samples; ``watch``: one trigger through a run (sample, sense, decide); ``user_calls``: a user's trigger function in a
thread of its own. The quantities a sensor reads are ``registries.quantities``. Its own layer, between the case
reader above and the registries below: the physics layer runs no thread and no user code.
"""

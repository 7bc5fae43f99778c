"""Authoring: ``pchute new`` and ``new_case`` write a complete, commented, runnable case file from a few choices, and
read it back through the case layer to check it. A layer of its own above ``case`` (pyproject.toml's contracts).

Its modules, each importing only those listed before it (no circle, at module level or inside a function):

* ``rules``: the assumed numbers that size every written case; ``text``: numbers, vectors and aligned comments;
  ``planets``: the planets a case can fly on, their atmospheres and gravity;
* ``choice_checks``: the checks of the choices (one InputError line each); ``flight_start``: a start at flight
  conditions (Mach number and dynamic pressure), its checks and rows; ``rocket_start``: a dual deploy's own choices
  and start;
* ``choices``: ``NewCase``, the choices, checked when made;
* ``layout``: the sizes the choices imply; ``descent``: the lines of a vehicle under one canopy or a cluster;
  ``rocket``: the lines of a rocket's dual deploy;
* ``write``: ``new_case_text``, ``new_case`` and the text ``pchute new`` writes once the case reader accepts it;
  ``options``: ``pchute new``'s options and help, from NewCase's docstring.
"""

"""``pchute new``'s dry run of the case it is about to write: the text loaded by the case reader (its checks and
warnings: plausibility, triggers that cannot fire), the run planned as ``pchute run`` plans it (output size, step
count, trigger samples), and, where something deploys during the run, the flight flown up to that deployment and
SETTLE_TIME past it (leaving the atmosphere, a line over-stretched at a late deployment, the ground reached before
line stretch). A case its own run would refuse is an InputError naming the option behind it; nothing is written.
"""

from __future__ import annotations

from dataclasses import fields, replace

from ..authoring.choice_checks import implausible_choices
from ..authoring.layout import layout
from ..authoring.planets import gravity_at
from ..authoring.rocket_start import ground
from ..authoring.write import checked_case
from ..errors import InputError, SimulationError, short_repr
from .simulation import resolve_run, run

SETTLE_TIME = 0.5
"""s flown past the first deployment's line stretch: the snatch and the first of the opening, where a line
over-stretched by a deployment at too high a speed stops a run."""
DURATION_OPTIONS = ("apogee_lag", "static_line_time", "velocity_up", "main_lag", "height", "altitude")
"""The options that lengthen a written case's duration (``authoring.rocket``, ``authoring.descent``), most likely
first: what a plan refused for its size names."""


def dry_run(choices) -> tuple:
    """(the case text, its warning lines) for a NewCase ``choices``: InputError, one line naming the option, for a
    case whose own run would refuse it (module docstring)."""
    text, case = checked_case(choices)
    try:
        plan = resolve_run(case)
    except InputError as exc:
        raise InputError(f"{_option(choices, DURATION_OPTIONS)}: the written case's run would refuse it: {exc}") \
            from None
    horizon = _first_deployment(choices)
    if horizon is not None:
        _fly(choices, case, replace(plan, duration=min(plan.duration, horizon + SETTLE_TIME)), horizon)
    ours = implausible_choices(choices)
    keys = [line.rpartition("the case reader's range of ")[2] for line in ours]
    return text, ours + tuple(w for w in case.warnings if not any(w.startswith(f"{key} = ") for key in keys))


def _first_deployment(c) -> float | None:
    """The time (s) by which the written case's first line stretch comes, None when its canopies fly from the
    start: a dual deploy's drogue one lag after apogee (the climb in vacuum, v / g, is the longest), a release's
    canopies after its static line time (with a static line, twice the time its length and the canopy's reach take
    to fall at the planet's g), a start at flight conditions at once."""
    if c.dual_deploy:
        return _climb_time(c) + c.apogee_lag + 0.1   # + the trigger's first samples
    if c.static_line_length is not None:   # the static line and the canopy's reach fallen at g; twice that (drag)
        g = gravity_at(c.planet, c.latitude or 0.0, ground(c))
        return 2.0 * (2.0 * (c.static_line_length + layout(c).canopy_height) / g) ** 0.5 + 1.0
    if c.released:
        return float(c.static_line_time)
    return 0.0 if c.mach is not None else None


def _climb_time(c) -> float:
    """The longest a dual deploy's rocket climbs (s): v / g in vacuum (drag only shortens it)."""
    return max(c.velocity_up or 0.0, 0.0) / gravity_at(c.planet, c.latitude or 0.0, ground(c))


def _fly(c, case, plan, deployment: float) -> None:
    """Fly ``plan`` (the written case's, to SETTLE_TIME past its first line stretch at ``deployment``, s):
    InputError for a run that fails, or that lands with a system not yet deployed."""
    try:
        _, _, events, _, _, _ = run(case, plan)
    except SimulationError as exc:
        when = exc.time if exc.time is not None else deployment
        climbing = c.dual_deploy and when <= _climb_time(c)
        raise InputError(f"{_option(c, _shaping(c, climbing))}: the written case's run would fail "
                         f"{when:.4g} s into its flight: {exc}") from None
    landed = [e.time for e in events if e.kind == "touchdown"]
    deployed = {e.system for e in events if e.kind == "deploy"}
    waiting = [name for name in case.systems if name not in deployed and not case.systems[name].deployed_by(0.0)]
    if landed and waiting:
        raise InputError(f"{_option(c, _shaping(c, False))}: the written case's run reaches the ground at "
                         f"{landed[0]:.4g} s, before the line stretch of {', '.join(waiting)}: deploy earlier or "
                         "start higher")


def _shaping(c, climbing: bool) -> tuple:
    """The options that shape the flight to the first line stretch, most likely first."""
    if c.dual_deploy:
        return ("velocity_up", "height", "altitude") if climbing else ("apogee_lag", "velocity_up", "height",
                                                                       "altitude")
    if c.released:
        return ("static_line_time", "static_line_length", "release_airspeed", "altitude")
    return ("mach", "dynamic_pressure", "flight_path_deg")


def _option(c, candidates) -> str:
    """``field = value (--flag)`` of the first of ``candidates`` given another value than its default; "these
    choices" when none is."""
    defaults = {f.name: f.default for f in fields(c)}
    for name in candidates:
        value = getattr(c, name)
        if value != defaults[name]:
            return f"{name} = {short_repr(value)} (--{name.replace('_', '-')})"
    return "these choices"

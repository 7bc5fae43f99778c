"""Readers of triggers (``triggers.definition``; docs/case-format.md, "Triggers and sensors") and of
``[separations.<body>]``, and the check of the event graph (names, cycles)."""

from __future__ import annotations

import importlib
import importlib.util
import math
import sys
from pathlib import Path

import numpy as np

from ..registries.quantities import QUANTITY, THRESHOLD_QUANTITIES
from ..triggers.definition import After, AllOf, AnyOf, Apogee, At, Sensor, Threshold, Trigger, UserFunction, leaves
from .events import DISREEF, known_times
from .fields import Table, default_of
from .sections import Separation

FORMS = ("time", "after", "quantity", "function", "all", "any")
"""The keys that say what a trigger is; a trigger table has exactly one of them."""
QUANTITIES = tuple(THRESHOLD_QUANTITIES) + ("apogee",)
SENSOR_KEYS = {"rate": "Hz", "lag": "s", "pressure_noise": "Pa", "pressure_bias": "Pa", "correlation_time": "s",
               "speed_noise": "m/s", "speed_bias": "m/s"}


def read_trigger(t: Table, bodies: dict, sensed: bool = True) -> Trigger:
    """The trigger of table ``t`` (``sensed``: it may carry sensor keys; False for a part of ``all``/``any``)."""
    forms = [key for key in FORMS if key in t.data]
    if len(forms) != 1:
        raise t.error(None, "a trigger needs exactly one of: " + ", ".join(FORMS), sorted(t.data))
    condition = _read_condition(forms[0], t, bodies, case_folder(t))
    sensor = Sensor()
    if sensed and not isinstance(condition, (At, After)):
        sensor = _read_sensor(t, bodies)
    t.finish()
    return Trigger(condition, sensor, ".".join(str(p) for p in t.path))


def _read_condition(form: str, t: Table, bodies: dict, folder):
    if form == "time":
        return At(t.number("time", "s", minimum=0.0))
    if form == "after":
        return After(t.string("after"), t.number("delay", "s", default_of(After, "delay"), minimum=0.0))
    if form == "quantity":
        quantity = t.string("quantity", choices=QUANTITIES)
        if quantity == "apogee":
            return Apogee()
        bounds = [key for key in ("below", "above") if key in t.data]
        if len(bounds) != 1:
            raise t.error("below", f"the {quantity} trigger needs exactly one of below, above "
                                   f"({THRESHOLD_QUANTITIES[quantity]})")
        unit = THRESHOLD_QUANTITIES[quantity]
        value = t.number(bounds[0], unit, minimum=None if quantity == "altitude" else 0.0)
        low, high = QUANTITY[quantity].limits   # the range it can take: beyond it, a threshold cannot mean anything
        if not low <= value <= high:
            raise t.error(bounds[0], f"must be within {low:g}..{high:g} ({unit}), the {quantity} a run of this tool "
                                     "can have", value)
        reference = "geoid"
        if quantity == "altitude":
            reference = t.string("reference", "geoid", choices=("geoid", "ground"))
        return Threshold(quantity, bounds[0] == "below", value, reference)
    if form == "function":
        limit = t.number("time_limit", "s", default_of(UserFunction, "time_limit"), above=0.0)
        given = t.raw("function", None, "")
        if callable(given):   # through the Python API (load_case overrides)
            return UserFunction(getattr(given, "__qualname__", repr(given)), given, limit)
        name = t.string("function")
        return UserFunction(name, import_function(name, folder, lambda m: t.error("function", m, name)), limit)
    parts = t.raw(form, None, "table")
    if not isinstance(parts, list) or not parts:
        raise t.error(form, "must be a list of one or more trigger tables", parts)
    conditions = []
    for i, part in enumerate(parts):
        trigger = read_trigger(Table(part, t.path + (form, i), t.ctx), bodies, sensed=False)
        conditions.append(trigger.condition)
    return AllOf(tuple(conditions)) if form == "all" else AnyOf(tuple(conditions))


def _read_sensor(t: Table, bodies: dict) -> Sensor:
    values = {}
    for key, unit in SENSOR_KEYS.items():
        default = default_of(Sensor, key)
        if key == "rate":
            values[key] = t.number(key, unit, None, above=0.0)
        elif key.endswith("_bias"):
            values[key] = t.number(key, unit, default)
        else:
            values[key] = t.number(key, unit, default, minimum=0.0)
    body = t.string("body", None)
    if body is not None and (body not in bodies or bodies[body].fixed):
        raise t.error("body", "must name a moving body of the case: " + ", ".join(
            name for name, b in bodies.items() if not b.fixed), body)
    sensor = Sensor(**values, body=body)
    if sensor.noisy and sensor.rate is None:
        raise t.error("rate", "required (Hz) with pressure_noise or speed_noise: noise is drawn per sample")
    return sensor


def import_function(name: str, case_folder: Path | None, error):
    """The callable of ``"module:function"``: an importable module, else ``module.py`` next to the case file. The
    module is a plain (dotted) module name: no path, no leading dots, so no module outside the case's folder and the
    import path is reached."""
    if not isinstance(name, str) or name.count(":") != 1 or not all(name.split(":")):
        raise error('must be "module:function"')
    module_name, function_name = name.split(":")
    if not all(part.isidentifier() for part in module_name.split(".")) or not function_name.isidentifier():
        raise error('must be "module:function" with a plain module name (names joined by dots, no path, no '
                    'leading dot): a module.py in the case\'s folder or a module on the import path')
    try:
        module = _import(module_name, case_folder)
    except Exception as exc:   # the user's module: say what went wrong in one line
        raise error(f"cannot import module '{module_name}': {type(exc).__name__}: {exc}") from None
    function = getattr(module, function_name, None)
    if not callable(function):
        raise error(f"module '{module_name}' has no function '{function_name}'")
    return function


def _import(module_name: str, case_folder: Path | None):
    if module_name in sys.modules:
        return sys.modules[module_name]
    beside = None if case_folder is None else Path(case_folder) / (module_name.replace(".", "/") + ".py")
    if beside is not None and beside.is_file():
        spec = importlib.util.spec_from_file_location(module_name, beside)
        module = importlib.util.module_from_spec(spec)
        sys.modules[module_name] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            del sys.modules[module_name]
            raise
        return module
    return importlib.import_module(module_name)


def check_events(triggers: dict, fixed: set, error) -> None:
    """Every ``after`` names an event of the case (``triggers``: event -> Trigger; ``fixed``: events at a fixed time)
    and no chain of ``after`` and arming (``_waits_on``) comes back to itself; ``error(event, message, value)`` makes
    the error."""
    known = set(triggers) | fixed
    for event, trigger in triggers.items():
        for reference in trigger.references():
            if reference not in known:
                raise error(event, "names an event the case does not have; events: " + ", ".join(sorted(known)),
                            reference)
    for event in triggers:
        seen, pending = [event], [event]
        while pending:
            current = pending.pop()
            for reference in _waits_on(current, triggers, known):
                if _later_stage(event, reference):
                    raise error(event, f"waits on {reference}, a later stage of its inflation (through "
                                       f"{' -> '.join(seen + [reference])}): stages start in order, each armed by "
                                       "the one before", reference)
                if reference == event:
                    raise error(event, "waits on itself through " + " -> ".join(seen + [event]), reference)
                if reference not in seen:
                    seen.append(reference)
                    pending.append(reference)


def _waits_on(event: str, triggers: dict, known: set) -> list:
    """The events ``event`` waits on: those its ``after`` names, and the one that arms its trigger (a system's
    deployment for its cut-away and disreefs, ``case.events.armed_by``), so that a deployment after its own
    cut-away is a cycle too."""
    waits = list(triggers[event].references()) if event in triggers else []
    owner, kind = event.rsplit(".", 1)
    if (kind == "cutaway" or kind.startswith(DISREEF)) and f"{owner}.deploy" in known:
        waits.append(f"{owner}.deploy")
    return waits


def _later_stage(event: str, reference: str) -> bool:
    """Whether ``reference`` is a later disreef of the system of disreef ``event`` (``<system>.disreef<k>``)."""
    (owner, kind), (other, later) = event.rsplit(".", 1), reference.rsplit(".", 1)
    stage = [name[len(DISREEF):] for name in (kind, later) if name.startswith(DISREEF)]
    return owner == other and len(stage) == 2 and all(k.isdigit() for k in stage) and int(stage[1]) > int(stage[0])


def read_separations(t: Table | None, bodies: dict, vehicle: str, triggers: dict, systems: dict,
                     duration: float) -> dict:
    """``[separations.<body>]``: body -> Separation; each trigger goes into ``triggers`` (``<body>.separation``)."""
    if t is None:
        return {}
    separations = {}
    # a carried body may hold the lines of a system that deploys from it once it has separated, not a canopy or the
    # lines of a system present from the start (``run.phases.deploy`` refuses a deployment from a body still carried)
    on_lines = {c for system in systems.values() for c in system.canopies}
    on_lines |= {line.body for system in systems.values() if system.deploy_time is None for line in system.lines}
    t.allowed = list(t.data)
    for name, st in ((n, Table(v, t.path + (n,), t.ctx)) for n, v in t.data.items()):
        if name not in bodies or name == vehicle or bodies[name].fixed:
            raise t.error(name, "must name a body of the case other than the vehicle, carried by the vehicle "
                                "until it separates", name)
        if name in on_lines:
            raise t.error(name, f"body '{name}' hangs on a system's lines (a canopy): only a body with no line, or "
                                "the lines of a system that deploys after it separates, can ride with the vehicle "
                                "until it separates", name)
        if bodies[name].initial is not None:
            raise t.error(name, f"body '{name}' is carried by the vehicle until it separates: remove its "
                                "[bodies.<name>.initial] table")
        point = st.string("point")
        owner, _, point_name = point.partition(".")
        if owner != vehicle or point_name not in bodies[vehicle].points:
            raise st.error("point", f"must be a point of the vehicle \"{vehicle}.<point>\"; its points: "
                                    + ", ".join(bodies[vehicle].points), point)
        direction = np.array(st.vector("direction", ""), float)
        with np.errstate(over="ignore"):
            norm = float(np.linalg.norm(direction))
        if not (norm > 0.0 and math.isfinite(norm)):   # [1e308, 1e308, 0] overflows its norm: the push would vanish
            raise st.error("direction", "must be a non-zero vector of finite length (vehicle body axes)",
                           direction.tolist())
        speed = st.number("speed", "m/s", minimum=0.0)
        trigger = read_trigger(st.table("trigger"), bodies)
        time = trigger.condition.time if isinstance(trigger.condition, At) else math.inf
        if math.isfinite(time) and time >= duration:
            raise st.error("trigger", f"time must be before the end of the run (simulation.duration = {duration:g} s)",
                           time)
        if not isinstance(trigger.condition, At):
            triggers[f"{name}.separation"] = trigger
        st.finish()
        separations[name] = Separation(name, tuple(bodies[vehicle].points[point_name]), speed,
                                       tuple((direction / norm).tolist()), time)
    t.finish()
    return separations


def case_folder(t: Table) -> Path:
    """The folder of the case file (where a user trigger function's module may sit)."""
    return Path(t.ctx.top_source.split(" with ")[0]).parent


def check_triggers(top: Table, triggers: dict, systems: dict, failures, separations: dict, atmosphere) -> None:
    """Every ``after`` names an event of the case, without cycles; a sensed quantity has the atmosphere it needs."""
    fixed = set(known_times(systems, failures, separations))
    check_events(triggers, fixed, lambda event, message, value: top.error(triggers[event].key, message, value))
    for trigger in triggers.values():
        needs = {c.quantity for c in leaves(trigger.condition) if isinstance(c, Threshold)
                 and QUANTITY[c.quantity].needs_speed_of_sound}
        if trigger.sensor.pressure_noise or trigger.sensor.pressure_bias:
            needs.add("barometric altitude")
        if needs and (atmosphere is None or not atmosphere.has_speed_of_sound):
            raise top.error(trigger.key, f"senses {', '.join(sorted(needs))}, which needs an atmosphere with a "
                                         "temperature (speed of sound)")
        functions = [c.name for c in leaves(trigger.condition) if isinstance(c, UserFunction)]
        if functions and (atmosphere is None or not atmosphere.has_speed_of_sound):
            where = "the case has no atmosphere" if atmosphere is None else \
                f"the atmosphere '{atmosphere.name}' has no temperature"
            raise top.error(trigger.key, f"the function {functions[0]} is given pressure and mach, which need an "
                            f"atmosphere with a temperature (speed of sound): {where}; add a temperature column (K) "
                            "or give atmosphere.speed_of_sound (m/s)")

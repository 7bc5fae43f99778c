"""Run a case: choose the method, integrator and step, build the engine model, integrate, check, and name outputs."""

from __future__ import annotations

import math
import platform
import sys
from datetime import datetime, timezone

import numpy as np

from .case.model import IMPLICIT_METHODS, INTEGRATORS, METHODS, SLACK_RULES, Case
from .errors import InputError
from .outputs import check_history, derive_columns
from .physics.singular_perturbation import SP_ORDER_RULE, is_sp_order
from .results import Result


def resolve_run(case: Case, method: str | None, integrator: str | None, step: float | None,
                duration: float | None) -> tuple[str, str, float, float]:
    """Fill in the case's defaults and validate method, integrator, step (s) and duration (s)."""
    method = case.simulation.method if method is None else method
    integrator = case.simulation.integrator if integrator is None else integrator
    if method not in METHODS:
        raise InputError(f"unknown method {method!r}; methods are: {', '.join(METHODS)}")
    if integrator not in INTEGRATORS:
        raise InputError(f"unknown integrator {integrator!r}; integrators are: {', '.join(INTEGRATORS)}")
    if integrator != "rk4" and method not in IMPLICIT_METHODS:
        raise InputError(f"the {method} method runs with --integrator rk4 only: it couples first-order (ODE1) "
                         "user-function states to the bodies, and Exudyn's implicit solvers drop the ODE1/ODE2 "
                         "coupling from their Jacobian (first-order accurate, slow); use rk4, or --method full with "
                         "implicit")
    duration = case.simulation.duration if duration is None else float(duration)
    if not (math.isfinite(duration) and duration > 0.0):
        raise InputError(f"duration (--t-end) = {duration!r}: must be a number > 0 (s)")
    if step is None:
        step = case.simulation.default_step(method, integrator)
        if step is None:
            key = method if integrator == "rk4" else f"{method}_{integrator}"
            raise InputError(f"no step given and the case sets no simulation.steps.{key}: pass --dt")
    step = float(step)
    if not (math.isfinite(step) and step > 0.0):
        raise InputError(f"step (--dt) = {step!r}: must be a number > 0 (s)")
    if step > duration:
        raise InputError(f"step (--dt) = {step:g} s: must not exceed the duration ({duration:g} s)")
    return method, integrator, step, duration


def versions() -> dict:
    """Versions of this package and the libraries the numbers depend on."""
    import exudyn

    from . import __version__
    return {"pchute_exudyn": __version__, "exudyn": exudyn.__version__, "numpy": np.__version__,
            "python": sys.version.split()[0], "platform": platform.platform()}


def check_sp_settings(case: Case, kappa_max: float, slack_rule: str, sp_order: int = 0) -> None:
    """Refuse SP settings and cases the method cannot solve (InputError)."""
    if not (isinstance(kappa_max, (int, float)) and math.isfinite(kappa_max) and kappa_max > 3.0):
        raise InputError(f"kappa_max (--kappa-max) = {kappa_max!r}: must be > 3 (the Frobenius condition number "
                         "of Eq. 3.13 is at least 3 for any 3x3 matrix; the thesis used 5)")
    if slack_rule not in SLACK_RULES:
        raise InputError(f"unknown slack rule {slack_rule!r}; slack rules are: {', '.join(SLACK_RULES)}")
    if not is_sp_order(sp_order):
        raise InputError(f"sp_order (--sp-order) = {sp_order!r}: {SP_ORDER_RULE}")
    undamped = [f"{case.line_label(system, line)}" for system, line in case.lines() if line.damping <= 0.0]
    if undamped:
        every = "every line" if len(undamped) == len(case.lines()) else f"line(s) {', '.join(undamped)}"
        raise InputError(f"the sp method needs damping on every line, but {every} has zero damping: alpha of "
                         "Eq. 3.6 is built from the line damping and is singular whenever only undamped lines are "
                         "taut; use --method full (or the equilibrium method, which ignores damping)")


def _build(case: Case, phase, method: str, kappa_max, slack_rule, sp_order, line_law: str):
    if method == "sp":
        from .engine.sp import build_sp_model
        return build_sp_model(case, phase, kappa_max, slack_rule, sp_order)
    if method == "equilibrium":
        from .engine.equilibrium import build_equilibrium_model
        return build_equilibrium_model(case, phase)
    from .engine.full import build_full_model
    return build_full_model(case, phase, line_law=line_law)


def _end_state(items, phase) -> tuple[dict, dict]:
    """Body and confluence states at the end of a phase, read through the model's output channels."""
    from .phases import BodyState, ConfluenceState
    read = items.channels
    bodies = {name: BodyState(np.asarray(read[("body", name, "position")](), float),
                              np.asarray(read[("body", name, "rotation")](), float).reshape(3, 3),
                              np.asarray(read[("body", name, "velocity")](), float),
                              np.asarray(read[("body", name, "angular_velocity")](), float))
              for name in phase.bodies}
    confluences = {name: ConfluenceState(np.asarray(read[("confluence", name, "position")](), float)[:3],
                                         np.asarray(read[("confluence", name, "velocity")](), float),
                                         _acceleration(items.reduced.get(name)))
                   for name in phase.systems}
    return bodies, confluences


def _acceleration(confluence):
    """The acceleration a massless confluence carries into the next phase (SP order 1), else None."""
    acceleration = None if confluence is None else confluence.acceleration()
    return None if acceleration is None else np.asarray(acceleration, float)


def _merge_facts(settings: dict, facts: dict) -> None:
    """Add one phase's method facts to the run's (counts add up over phases)."""
    for key, value in facts.items():
        old = settings.get(key)
        if isinstance(old, dict) and "solves" in old:
            solves = old["solves"] + value["solves"]
            value = {"solves": solves, "failures": old["failures"] + value["failures"],
                     "mean_iterations": (old["mean_iterations"] * old["solves"]
                                         + value["mean_iterations"] * value["solves"]) / max(solves, 1),
                     "max_iterations": max(old["max_iterations"], value["max_iterations"])}
        settings[key] = value


def descent_rate_events(case: Case, time, descent_rate, after: float) -> list:
    """First downward crossings of ``case.simulation.descent_rate_events`` by the vehicle's descent rate (m/s)
    after time ``after`` (s), linearly interpolated."""
    events = []
    for threshold in case.simulation.descent_rate_events:
        finite = np.isfinite(descent_rate) & (time >= after)
        above = (descent_rate > threshold) & finite
        for i in range(1, len(time)):
            if above[i - 1] and finite[i] and descent_rate[i] <= threshold:
                w = (descent_rate[i - 1] - threshold) / (descent_rate[i - 1] - descent_rate[i])
                events.append({"event": "descent_rate", "value": threshold,
                               "time": float(time[i - 1] + w * (time[i] - time[i - 1]))})
                break
    return events


def run(case: Case, method: str, integrator: str, step: float, duration: float, *, kappa_max: float | None = None,
        slack_rule: str | None = None, sp_order: int | None = None, line_law: str = "symbolic"):
    """Build and integrate the engine models of ``case`` phase by phase (arguments resolved by ``resolve_run``).

    Returns the checked engine history of the whole run, the method's settings and facts, and the event log.
    """
    from .engine.full import add_rk4_step_monitor
    from .engine.items import Touchdown
    from .engine.solver import integrate
    from .outputs import concatenate
    from .phases import boundaries, initial_states, next_phase

    settings = {}
    if method == "sp":
        kappa_max = case.simulation.kappa_max if kappa_max is None else kappa_max
        slack_rule = case.simulation.slack_rule if slack_rule is None else slack_rule
        sp_order = case.simulation.sp_order if sp_order is None else sp_order
        check_sp_settings(case, kappa_max, slack_rule, sp_order)
        settings = {"kappa_max": kappa_max, "slack_rule": slack_rule, "sp_order": sp_order}
    output_step = min(case.simulation.output_step, duration)
    body_states, confluence_states = initial_states(case)
    events = [{"event": "start", "time": 0.0}]
    histories = []
    times = boundaries(case, duration)
    for start, end in zip(times, times[1:]):
        phase = next_phase(case, start, end, body_states, confluence_states)
        events.extend(phase.events)
        items = _build(case, phase, method, kappa_max, slack_rule, sp_order, line_law)
        if integrator == "rk4" and method in ("full", "sp"):   # the equilibrium method has no confluence dynamics
            add_rk4_step_monitor(items, case, step, method)
        touchdown = None
        if case.simulation.ground_altitude is not None:
            touchdown = Touchdown(items, case, case.simulation.ground_altitude)
            items.stop_conditions.append(touchdown)
        raw = integrate(items, integrator, step, end, output_step, case.simulation.spectral_radius, start=start)
        check_history(case, raw, step)
        histories.append(raw)
        for summarize in items.summaries:
            _merge_facts(settings, summarize())
        if touchdown is not None and touchdown.event is not None:
            events.append(touchdown.event)
            break
        body_states, confluence_states = _end_state(items, phase)
    raw = concatenate(case, histories)
    settings["output_step"] = output_step
    settings["end"] = "touchdown" if events[-1]["event"] == "touchdown" else "duration"
    return raw, settings, events


def simulate(case: Case, method: str | None = None, integrator: str | None = None, step: float | None = None,
             duration: float | None = None, *, kappa_max: float | None = None, slack_rule: str | None = None,
             sp_order: int | None = None, line_law: str = "symbolic") -> Result:
    """Simulate ``case``.

    Parameters
    ----------
    case : Case
        From :func:`pchute_exudyn.load_case`.
    method : {"full", "sp", "equilibrium"}, optional
        Confluence method; default from the case.
    integrator : {"rk4", "implicit"}, optional
        Default from the case; ``sp`` and ``equilibrium`` run with ``rk4`` only.
    step : float, optional
        Integration step (s); default from the case's ``simulation.steps``.
    duration : float, optional
        Simulated time (s); default from the case.
    kappa_max : float, optional
        SP: largest condition number while a line is slack (> 3); default from the case (5).
    slack_rule : {"stretch", "force"}, optional
        SP slack rule; default from the case (``stretch``, the thesis's).
    sp_order : {0, 1}, optional
        SP order in the confluence mass: 0 drops it (Eq. 3.10, the thesis), 1 keeps its weight and inertia to first
        order; default from the case (0).
    line_law : {"symbolic", "python"}
        How the full model's tension-only law runs in the engine (symbolic is faster; python exists to measure).

    Returns
    -------
    Result

    Raises
    ------
    InputError, SimulationError
    """
    method, integrator, step, duration = resolve_run(case, method, integrator, step, duration)
    raw, settings, events = run(case, method, integrator, step, duration, kappa_max=kappa_max, slack_rule=slack_rule,
                                sp_order=sp_order, line_law=line_law)
    columns, units = derive_columns(case, raw)
    last_deployment = max([e["time"] for e in events if e["event"] == "deploy"], default=0.0)
    events = sorted(events + descent_rate_events(case, columns["time"], columns[f"{case.vehicle}_velocity_down"],
                                                 last_deployment), key=lambda e: e["time"])
    vehicle = case.vehicle
    summary = {
        "case": case.name,
        "case_file": case.source,
        "description": case.description,
        "vehicle": vehicle,
        "method": method,
        "integrator": integrator,
        "step": step,
        "duration": duration,
        **settings,
        "steps": raw.steps,
        "wall_time": raw.wall_time,
        "steps_per_second": raw.steps / raw.wall_time if raw.wall_time > 0 else None,
        "final": {"time": float(columns["time"][-1]),
                  "vehicle_altitude": float(columns[f"{vehicle}_altitude"][-1]),
                  "vehicle_east": float(columns[f"{vehicle}_east"][-1]),
                  "vehicle_north": float(columns[f"{vehicle}_north"][-1]),
                  **{f"{label}_{key}": float(columns[f"{label}_{key}"][-1])
                     for label in (case.confluence_label(system) for system in case.systems.values())
                     for key in ("altitude", "east", "north") if f"{label}_{key}" in columns}},
        "peak_tension": {k.removeprefix("tension_"): float(np.nanmax(v)) if np.isfinite(v).any() else None
                         for k, v in columns.items() if k.startswith("tension_")},
        "events": events,
        "units": units,
        "versions": versions(),
        "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
    }
    return Result(columns, units, summary)

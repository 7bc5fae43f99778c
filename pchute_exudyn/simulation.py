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


def check_sp_settings(case: Case, kappa_max: float, slack_rule: str) -> None:
    """Refuse SP settings and cases the method cannot solve (InputError)."""
    if not (isinstance(kappa_max, (int, float)) and math.isfinite(kappa_max) and kappa_max > 3.0):
        raise InputError(f"kappa_max (--kappa-max) = {kappa_max!r}: must be > 3 (the Frobenius condition number "
                         "of Eq. 3.13 is at least 3 for any 3x3 matrix; the thesis used 5)")
    if slack_rule not in SLACK_RULES:
        raise InputError(f"unknown slack rule {slack_rule!r}; slack rules are: {', '.join(SLACK_RULES)}")
    undamped = [f"{case.line_label(system, line)}" for system, line in case.lines() if line.damping <= 0.0]
    if undamped:
        every = "every line" if len(undamped) == len(case.lines()) else f"line(s) {', '.join(undamped)}"
        raise InputError(f"the sp method needs damping on every line, but {every} has zero damping: alpha of "
                         "Eq. 3.6 is built from the line damping and is singular whenever only undamped lines are "
                         "taut; use --method full (or the equilibrium method, which ignores damping)")


def run(case: Case, method: str, integrator: str, step: float, duration: float, *, kappa_max: float | None = None,
        slack_rule: str | None = None, line_law: str = "symbolic"):
    """Build and integrate the engine model of ``case`` (arguments already resolved by ``resolve_run``).

    Returns the checked engine history, the method's settings and facts for the summary.
    """
    from .engine.full import add_rk4_step_monitor, build_full_model
    from .engine.solver import integrate

    settings = {}
    if method == "sp":
        from .engine.sp import build_sp_model
        kappa_max = case.simulation.kappa_max if kappa_max is None else kappa_max
        slack_rule = case.simulation.slack_rule if slack_rule is None else slack_rule
        check_sp_settings(case, kappa_max, slack_rule)
        items = build_sp_model(case, kappa_max, slack_rule)
        settings = {"kappa_max": kappa_max, "slack_rule": slack_rule}
    elif method == "equilibrium":
        from .engine.equilibrium import build_equilibrium_model
        items = build_equilibrium_model(case)
    else:
        items = build_full_model(case, line_law=line_law)
    if integrator == "rk4" and method in ("full", "sp"):   # the equilibrium method has no confluence dynamics
        add_rk4_step_monitor(items, case, step, method)
    output_step = min(case.simulation.output_step, duration)
    raw = integrate(items, integrator, step, duration, output_step, case.simulation.spectral_radius)
    check_history(case, raw, step)
    for summarize in items.summaries:
        settings.update(summarize())
    settings["output_step"] = output_step
    return raw, settings


def simulate(case: Case, method: str | None = None, integrator: str | None = None, step: float | None = None,
             duration: float | None = None, *, kappa_max: float | None = None, slack_rule: str | None = None,
             line_law: str = "symbolic") -> Result:
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
    raw, settings = run(case, method, integrator, step, duration, kappa_max=kappa_max, slack_rule=slack_rule,
                        line_law=line_law)
    columns, units = derive_columns(case, raw)
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
        "peak_tension": {k.removeprefix("tension_"): float(np.max(v)) for k, v in columns.items()
                         if k.startswith("tension_")},
        "units": units,
        "versions": versions(),
        "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
    }
    return Result(columns, units, summary)

"""Run a case: choose the method, integrator and step, build the engine model, integrate, check, and name outputs."""

from __future__ import annotations

import math
import platform
import sys
from datetime import datetime, timezone

import numpy as np

from .case.model import INTEGRATORS, METHODS, Case
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


def simulate(case: Case, method: str | None = None, integrator: str | None = None, step: float | None = None,
             duration: float | None = None, *, line_law: str = "symbolic") -> Result:
    """Simulate ``case``.

    Parameters
    ----------
    case : Case
        From :func:`pchute_exudyn.load_case`.
    method : str, optional
        Confluence method (``full``); default from the case.
    integrator : {"rk4", "implicit"}, optional
        Default from the case.
    step : float, optional
        Integration step (s); default from the case's ``simulation.steps``.
    duration : float, optional
        Simulated time (s); default from the case.
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
    from .engine.full import add_rk4_step_monitor, build_full_model
    from .engine.solver import integrate

    items = build_full_model(case, line_law=line_law)
    if integrator == "rk4":
        add_rk4_step_monitor(items, case, step)
    output_step = min(case.simulation.output_step, duration)
    raw = integrate(items, integrator, step, duration, output_step, case.simulation.spectral_radius)
    check_history(case, raw, step)
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
        "output_step": output_step,
        "steps": raw.steps,
        "wall_time": raw.wall_time,
        "steps_per_second": raw.steps / raw.wall_time if raw.wall_time > 0 else None,
        "final": {"time": float(columns["time"][-1]),
                  "vehicle_altitude": float(columns[f"{vehicle}_altitude"][-1]),
                  "vehicle_east": float(columns[f"{vehicle}_east"][-1]),
                  "vehicle_north": float(columns[f"{vehicle}_north"][-1])},
        "peak_tension": {k.removeprefix("tension_"): float(np.max(v)) for k, v in columns.items()
                         if k.startswith("tension_")},
        "units": units,
        "versions": versions(),
        "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
    }
    return Result(columns, units, summary)

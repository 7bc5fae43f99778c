"""A fixed RK4 step checked at every phase (docs/models/step_control.md, "A fixed step at every phase").

A fixed step is chosen for the start of a run; a phase that starts later (a deployment, a cut-away, a separation)
can bring a body the step cannot fly: a light canopy deployed at speed, whose drag damps it at rho V S C_A over its
mass, hundreds of 1/s. Before a phase's first step each moving body's limit on its lines and its drag at the phase's
start state (``run.step_control.body_limits``, the adaptive steps' own cap) is compared with the step, and a step
beyond PHASE_STEP_MARGIN times it stops the run there, naming the body, the limit and the remedies. The confluences'
limits are the step monitor's (``run.step_control.add_step_monitor``); a reduced canopy's drag point is its own.
Reads the phase, writes nothing: a run that passes is unchanged.
"""

from __future__ import annotations

import math

from ..case.model import Case
from ..case.read_systems import reduced_refusal
from ..engine.phase_model import Model
from ..errors import SimulationError
from ..methods.base import Method, line_constants
from ..results.summary import DeployEvent
from .step_control import body_limits, drag_area_fraction, drag_damping, line_sums, tether_constants

PHASE_STEP_MARGIN = 1.4
"""Factor (-) by which a fixed step may exceed a body's limit at a phase's start before the run stops. The limit is
taken at the phase's first state, where a canopy just deployed flies fastest through the air and its drag damps it
most; it slows within a few steps and its limit rises, so a step somewhat beyond the limit still runs. Measured on
the rocket's main canopy flown rigid (cases/rocket/dual_deploy.toml; docs/models/step_control.md, "A fixed step at
every phase"): the main's peak load within 0.1 % of a small step's up to 1.34-1.38 times the limit, 2.6-11 % high at
1.46 times, 8-70 % high from 1.6 to 1.85 times, the run diverging from 1.9 times, for canopies of 0.17 and 1.06 kg.
The stop is where the loads go wrong, before the run fails."""


def check_phase_step(model: Model, case: Case, method: Method, step: float) -> None:
    """Stop a fixed-step RK4 run (SimulationError) before the first step of ``model``'s phase when ``step`` (s)
    exceeds PHASE_STEP_MARGIN times a moving body's stability limit on its lines and its drag at the phase's start."""
    limit, cause, body = phase_limit(model, case)
    if step > PHASE_STEP_MARGIN * limit:
        raise SimulationError(_message(case, method, model.phase, step, limit, body, cause), model.phase.start)


def phase_limit(model: Model, case: Case) -> tuple:
    """(limit in s, cause, body) of the moving body with the smallest limit on its lines and its drag at the start of
    ``model``'s phase; (inf, "", "") without one."""
    states = model.phase.body_states
    drag = drag_damping(model, case, model.phase.start, lambda name: (states[name].position, states[name].velocity),
                        _open_at_start)
    lines = [(system, *line_constants(system)) for system in model.systems]
    sums = line_sums(lines, model.massless, tether_constants(case, model.bodies))
    found = [(*limit, name) for limit, name in zip(body_limits(sums, drag), drag)]
    return min(found, default=(math.inf, "", ""), key=lambda item: item[0])


def _open_at_start(model: Model, body: str, t: float) -> float:
    """The drag-area fraction (-) of ``body`` at its phase's start ``t`` (s): none yet for an opening by its fill law
    that starts there (its line stretch), ``drag_area_fraction`` otherwise. Such a canopy slows as it fills, and the
    full drag area at the deployment's speed stops runs that fly well (the airdrop cluster of cases/airdrop at
    2.3 times that limit: its peak load within 0.1 %)."""
    member = model.aerodynamic_loads.get(body)
    opening = member is not None and member.schedule is not None and not hasattr(member.schedule, "fraction")
    return 0.0 if opening and member.deployed_at == t else drag_area_fraction(model, body, t)


def _message(case: Case, method: Method, phase, step: float, limit: float, body: str, cause: str) -> str:
    """The one line of ``check_phase_step``: what, where, the limit and the remedies."""
    system = case.canopy_system(body)
    deployed = system is not None and any(isinstance(e, DeployEvent) and e.system == system.name
                                          for e in phase.events)
    when = f"deployed at t = {phase.start:.3f} s" if deployed else f"at t = {phase.start:.3f} s"
    remedies = [r for r in ("--dt auto (adaptive steps)", _reduced_remedy(case, method, system)) if r]
    remedies.append(f"or --dt {float(f'{0.9 * limit:.2g}'):g} or smaller")
    return (f"the fixed RK4 step {step:g} s is too long for {cause}, {when}: its stability limit there is "
            f"{limit:.3g} s, and a step over {PHASE_STEP_MARGIN:g} times it diverges or gives wrong loads; use "
            f"{', '.join(remedies)}")


def _reduced_remedy(case: Case, method: Method, system) -> str:
    """The reduced canopy model as a remedy for a canopy of ``system`` that could fly it and does not; "" else."""
    if system is None or (system.canopy_model == "reduced" and method.flies_reduced_canopies):
        return ""
    if reduced_refusal(system.canopies, system.lines, case.bodies, system.bag_anchor) is not None:
        return ""
    where = "" if method.flies_reduced_canopies else " with --method sp"
    return f"the reduced canopy model (systems.{system.name}.canopy_model = \"reduced\"{where})"

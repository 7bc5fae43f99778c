"""The full-mass model (thesis Eqs. 1.1-1.7): the reference solution.

Vehicle and canopies are rigid bodies, each confluence is a 3-DoF point mass, each line an
``ObjectConnectorSpringDamper`` whose tension-only law runs as an Exudyn symbolic user function (inside the engine:
about 0.04 us per call against 0.37 us for a Python one, see ``validation/benchmark_full.py``).
"""

from __future__ import annotations

import exudyn as exu
import numpy as np
import exudyn.itemInterface as eii
from exudyn.utilities import CreateSymbolicUserFunction

from ..case.model import Case
from ..errors import SimulationError
from ..stability import confluence_rk4_limit, sp_rk4_limit, unstable_step_message
from ..phases import Phase, initial_phase
from .items import CURRENT, OV, ModelItems, add_bodies, add_point_mass, new_system

MONITOR_INTERVAL = 0.1
"""Simulated time (s) between checks of the RK4 step against the confluences' current stability limit (the limit
moves with the line loads, over seconds; a check costs about 0.25 ms). At least MONITOR_STEPS steps apart."""
MONITOR_STEPS = 100

esym = exu.symbolic
LINE_LAWS = ("symbolic", "python")


def _tension_only_symbolic(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
    # physics.lines.tension_magnitude as an expression tree: T = max(0, K dL + C dL/dt) if L > L0 else 0
    return esym.IfThenElse(deltaL > 0, esym.max(esym.Real(0.0), stiffness * deltaL + damping * deltaL_t),
                           esym.Real(0.0))


def _tension_only_python(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
    if deltaL <= 0.0:
        return 0.0
    tension = stiffness * deltaL + damping * deltaL_t
    return tension if tension > 0.0 else 0.0


def _force_reader(mbs, connector: int):
    get = mbs.GetObjectOutput
    return lambda: get(connector, OV.ForceLocal, CURRENT)


def build_full_model(case: Case, phase: Phase | None = None, line_law: str = "symbolic") -> ModelItems:
    """Build the full-mass Exudyn model of ``case`` for one phase of a run.

    Parameters
    ----------
    case : Case
    phase : Phase, optional
        Active bodies and systems and their states at the phase's start (``phases``); default: the case at t = 0.
    line_law : {"symbolic", "python"}
        How the tension-only law runs; "python" exists to measure the difference.
    """
    phase = phase or initial_phase(case)
    items = new_system(case)
    mbs = items.mbs
    add_bodies(items, case, phase)
    if line_law == "symbolic":
        law = CreateSymbolicUserFunction(mbs, _tension_only_symbolic, "springForceUserFunction",
                                         itemTypeName="ObjectConnectorSpringDamper")
        items.keep_alive.append(law)
    else:
        law = _tension_only_python
    for system in items.systems:
        confluence = add_point_mass(items, case, system.name, system.confluence.mass,
                                    phase.confluence_states[system.name])
        for line in system.lines:
            attach = items.bodies[line.body].point_markers[line.point]
            connector = mbs.AddObject(eii.ObjectConnectorSpringDamper(
                markerNumbers=[attach, confluence.marker], referenceLength=line.free_length,
                stiffness=line.stiffness, damping=line.damping, springForceUserFunction=law,
                visualization=eii.VObjectConnectorSpringDamper(show=False)))
            items.channels[("tension", system.name, line.name)] = _force_reader(mbs, connector)
    mbs.Assemble()
    return items


def add_rk4_step_monitor(items: ModelItems, case: Case, step: float, method: str = "full",
                         interval: float = MONITOR_INTERVAL) -> None:
    """Stop an RK4 run as soon as ``step`` (s) exceeds a confluence's current stability limit.

    Checked before the first step and then every ``interval`` s of simulated time (about 0.25 ms per check), on
    the current geometry: lines stretch under load and the limit falls with them. ``method`` picks the limit:
    the full-mass confluence's second-order modes or the SP confluence's first-order one.
    """
    mbs = items.mbs
    get_marker, get_node = mbs.GetMarkerOutput, mbs.GetNodeOutput
    limit_of = confluence_rk4_limit if method == "full" else sp_rk4_limit
    watched = []
    for system in items.systems:
        markers = [items.bodies[line.body].point_markers[line.point] for line in system.lines]
        if method == "full":
            marker = items.confluences[system.name].marker
            where = (lambda marker=marker: get_marker(marker, OV.Position, CURRENT))
        else:
            node = items.reduced[system.name].node
            where = (lambda node=node: get_node(node, OV.Coordinates, CURRENT)[:3])
        watched.append((system, markers, where))
    next_check = [0.0]

    def monitor(mbs_, t):
        if t < next_check[0]:
            return
        next_check[0] = t + max(interval, MONITOR_STEPS * step)
        for system, markers, where in watched:
            attach = np.array([get_marker(m, OV.Position, CURRENT) for m in markers])
            limit = limit_of(system, attach, where())
            if step > limit.step:
                raise SimulationError(unstable_step_message(step, limit, t - step, method), t - step)

    items.pre_step_hooks.append(monitor)

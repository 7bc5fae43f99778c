"""The full-mass model (thesis Eqs. 1.1-1.7): the reference solution.

Vehicle and canopies are rigid bodies, each confluence is a 3-DoF point mass, each line an
``ObjectConnectorSpringDamper`` whose tension-only law (``physics.lines``) runs as an Exudyn symbolic user function
(inside the engine: about 0.04 us per call against 0.37 us for a Python one, see ``validation/benchmark_full.py``).
A line with a load-elongation table gets its own symbolic law: the table as a sum of ramps, which the expression
language can write without a search (``LoadElongation.hinges``).
"""

from __future__ import annotations

import exudyn as exu
import exudyn.itemInterface as eii
from exudyn.utilities import CreateSymbolicUserFunction

from ..case.model import Case
from ..physics.lines import tension
from .bodies import PointConfluence, add_bodies
from .model import CURRENT, OV, Model
from .state import Phase, TensionChannel

esym = exu.symbolic
LINE_COLOUR = [0.1, 0.1, 0.6, 1.0]   # lines in Exudyn's viewer


def _tension_only_symbolic(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
    # physics.lines.tension as an expression tree: T = max(0, K dL + C dL/dt) if L > L0 else 0
    return esym.IfThenElse(deltaL > 0, esym.max(esym.Real(0.0), stiffness * deltaL + damping * deltaL_t),
                           esym.Real(0.0))


def _tension_only_python(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
    return tension(deltaL, deltaL_t, stiffness, damping)


def _table_law_symbolic(table, free_length: float):
    """A load-elongation table's line law as an expression tree: the table in its hinge form
    (``LoadElongation.hinges``: a sum of ramps, no search), T = max(0, T_table(dL / L0) + C dL/dt) if dL > 0."""
    hinges = table.hinges()

    def law(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
        strain = deltaL * (1.0 / free_length)
        elastic = esym.Real(0.0)
        for corner, change in hinges:
            elastic = elastic + change * esym.max(esym.Real(0.0), strain - corner)
        return esym.IfThenElse(deltaL > 0, esym.max(esym.Real(0.0), elastic + damping * deltaL_t), esym.Real(0.0))
    return law


def _table_law_python(table, free_length: float):
    def law(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
        return tension(deltaL, deltaL_t, stiffness, damping, table(deltaL / free_length) if deltaL > 0.0 else None)
    return law


def _line_law(model: Model, line, shared, symbolic: bool):
    """The spring-damper user function of ``line``: the shared linear law, or its own table law."""
    table = line.load_elongation
    if table is None:
        return shared
    if not symbolic:
        return _table_law_python(table, line.free_length)
    law = CreateSymbolicUserFunction(model.mbs, _table_law_symbolic(table, line.free_length),
                                     "springForceUserFunction", itemTypeName="ObjectConnectorSpringDamper")
    model.keep_alive(law)
    return law


def _force_reader(mbs, connector: int):
    get = mbs.GetObjectOutput
    return lambda: get(connector, OV.ForceLocal, CURRENT)


def build_full_model(case: Case, phase: Phase, symbolic_line_law: bool = True) -> Model:
    """Build the full-mass Exudyn model of ``case`` for one phase of a run.

    Parameters
    ----------
    case : Case
    phase : Phase
        Active bodies and systems and their states at the phase's start (``phases``).
    symbolic_line_law : bool
        Run the tension-only law as an Exudyn symbolic user function (fast) rather than a Python one (to measure).
    """
    model = Model(case, phase)
    mbs = model.mbs
    add_bodies(model, case)
    if symbolic_line_law:
        law = CreateSymbolicUserFunction(mbs, _tension_only_symbolic, "springForceUserFunction",
                                         itemTypeName="ObjectConnectorSpringDamper")
        model.keep_alive(law)
    else:
        law = _tension_only_python
    for system in model.systems:
        confluence = PointConfluence(model, case, system.name, system.confluence.mass,
                                     phase.confluence_states[system.name])
        for line in system.lines:
            attach = model.bodies[line.body].point_markers[line.point]
            connector = mbs.AddObject(eii.ObjectConnectorSpringDamper(
                markerNumbers=[attach, confluence.marker], referenceLength=line.free_length,
                stiffness=line.stiffness, damping=line.damping,
                springForceUserFunction=_line_law(model, line, law, symbolic_line_law),
                visualization=eii.VObjectConnectorSpringDamper(show=True, drawSize=0.05, color=LINE_COLOUR)))
            model.add_channel(TensionChannel(system.name, line.name), _force_reader(mbs, connector))
    return model.assemble()

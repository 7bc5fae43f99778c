"""The full-mass model (thesis Eqs. 1.1-1.7): the reference solution.

Vehicle and canopies are rigid bodies, each confluence is a 3-DoF point mass, each line an
``ObjectConnectorSpringDamper`` whose tension-only law (``physics.lines``) runs as an Exudyn symbolic user function
(inside the engine: about 0.04 us per call against 0.37 us for a Python one, see ``validation/benchmark_full.py``).
"""

from __future__ import annotations

import exudyn as exu
import exudyn.itemInterface as eii
from exudyn.utilities import CreateSymbolicUserFunction

from ..case.model import Case
from ..physics.lines import tension
from ..state import Phase, TensionChannel
from .bodies import PointConfluence, add_bodies
from .model import CURRENT, OV, Model

esym = exu.symbolic


def _tension_only_symbolic(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
    # physics.lines.tension as an expression tree: T = max(0, K dL + C dL/dt) if L > L0 else 0
    return esym.IfThenElse(deltaL > 0, esym.max(esym.Real(0.0), stiffness * deltaL + damping * deltaL_t),
                           esym.Real(0.0))


def _tension_only_python(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
    return tension(deltaL, deltaL_t, stiffness, damping)


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
                stiffness=line.stiffness, damping=line.damping, springForceUserFunction=law,
                visualization=eii.VObjectConnectorSpringDamper(show=False)))
            model.add_channel(TensionChannel(system.name, line.name), _force_reader(mbs, connector))
    return model.assemble()

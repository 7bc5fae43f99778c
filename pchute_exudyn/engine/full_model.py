"""The full-mass model (thesis Eqs. 1.1-1.7): the reference solution.

Vehicle and canopies are rigid bodies, each confluence is a 3-DoF point mass, each line an
``ObjectConnectorSpringDamper`` whose tension-only law runs as an Exudyn symbolic user function (inside the engine:
about 0.04 us per call against 0.37 us for a Python one, see ``validation/benchmark_full.py``), written from the
line's record (``physics.lines.LineLaw.expression`` in Exudyn's symbolic arithmetic). A line with a load-elongation
table gets its own symbolic law: the table as a sum of ramps, which the expression language can write without a
search (``LoadElongation.hinges``).
"""

from __future__ import annotations

import exudyn as exu
import exudyn.itemInterface as eii

from ..case.model import Case
from ..physics.lines import LineLaw
from .bodies import PointConfluence, add_bodies
from .line_laws import LINE_COLOUR, line_law
from .phase_model import CURRENT, OV, Model
from .state import Phase, TensionChannel


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
    laws: dict = {}   # the symbolic user functions made so far (``engine.line_laws.line_law``)
    for system in model.systems:
        confluence = PointConfluence(model, case, system.name, system.confluence.mass,
                                     phase.confluence_states[system.name])
        for line in system.lines:
            attach = model.bodies[line.body].point_markers[line.point]
            connector = mbs.AddObject(eii.ObjectConnectorSpringDamper(
                markerNumbers=[attach, confluence.marker], referenceLength=line.free_length,
                stiffness=line.stiffness, damping=line.damping,
                springForceUserFunction=line_law(model, line.law, laws, symbolic_line_law),
                visualization=eii.VObjectConnectorSpringDamper(show=True, drawSize=0.05, color=LINE_COLOUR)))
            model.add_channel(TensionChannel(system.name, line.name), _force_reader(mbs, connector))
    return model.assemble()


def line_connector_force(law: LineLaw, lengths, rates, symbolic: bool = True) -> list:
    """The tension (N) the engine computes with the full-mass model's user function of ``law``
    (``engine.line_laws.line_law``) in a
    spring-damper from the ground to a point mass, at each length (m) and rate of lengthening (m/s): the law as the
    engine evaluates it, for checking that form against the record (``tests/unit/test_line_law.py``)."""
    container = exu.SystemContainer()
    mbs = container.AddSystem()
    ground = mbs.AddObject(eii.ObjectGround())
    node = mbs.AddNode(eii.NodePoint(referenceCoordinates=[0.0, 0.0, 0.0]))
    mbs.AddObject(eii.MassPoint(nodeNumber=node, mass=1.0))
    markers = [mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=ground, localPosition=[0.0, 0.0, 0.0])),
               mbs.AddMarker(eii.MarkerNodePosition(nodeNumber=node))]
    kept: list = []

    class Holder:   # what ``line_law`` needs of a model: the system and somewhere to keep the function
        def keep_alive(self, item):
            kept.append(item)
    holder = Holder()
    holder.mbs = mbs
    connector = mbs.AddObject(eii.ObjectConnectorSpringDamper(
        markerNumbers=markers, referenceLength=law.free_length, stiffness=law.stiffness, damping=law.damping,
        springForceUserFunction=line_law(holder, law, {}, symbolic)))
    mbs.Assemble()
    forces = []
    for length, rate in zip(lengths, rates):
        mbs.systemData.SetODE2Coordinates([length, 0.0, 0.0], CURRENT)
        mbs.systemData.SetODE2Coordinates_t([rate, 0.0, 0.0], CURRENT)
        forces.append(float(mbs.GetObjectOutput(connector, OV.Force, CURRENT)[0]))
    container.Reset()
    return forces

"""SP's Exudyn model of a phase: the bodies and their aerodynamics as in the full model, each system's confluence an
``SPConfluence`` (a reduced canopy's system with its bridle first)."""

from __future__ import annotations

from ...case.model import Case
from ...engine.bodies import add_bodies
from ...engine.phase_model import Model
from ...engine.state import Phase
from .confluence import SPConfluence
from .reduced_canopy import bridle_first, reduced_canopy


def build_sp_model(case: Case, phase: Phase, options) -> Model:
    """Build the SP Exudyn model of ``case`` for one phase with the SP method's ``options`` (``SPOptions``); order 1
    keeps the confluence mass to first order (``balance``)."""
    model = Model(case, phase)
    canopies = {system.name: reduced_canopy(case, system) for system in model.systems}
    add_bodies(model, case, reduced=True, massless={name for name in canopies.values() if name is not None})
    for system in model.systems:
        if canopies[system.name] is not None:
            system = bridle_first(system)
        sp = SPConfluence(model, case, system, phase.confluence_states[system.name], options, phase.start)
        sp.register(case)
    return model.assemble()

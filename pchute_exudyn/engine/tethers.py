"""Tethers as Exudyn items (``case.sections.Tether``): a spring-damper between the two bodies' points whose
tension-only law (with its payout resistance) is the line law's user function (``engine.line_laws``), the same in
every method's model: a tether joins two rigid bodies with no confluence, so no method reduces it. Each reports its
tension (N) as the column ``tension_<tether>``."""

from __future__ import annotations

import math

import exudyn.itemInterface as eii

from ..case.model import Case
from .line_laws import LINE_COLOUR, line_law
from .phase_model import CURRENT, OV, Model
from .state import ColumnChannel, column_channel


def tether_channel(name: str) -> ColumnChannel:
    """The tension channel (N) of tether ``name``."""
    return column_channel("tension_{owner}", name)


class TetherState:
    """A tether's length (m) and its rate (m/s) now, from its end markers (``length_and_rate``)."""

    def __init__(self, model: Model, markers: list):
        self.get, self.markers = model.mbs.GetMarkerOutput, markers

    def length_and_rate(self) -> tuple:
        (a, b), (va, vb) = ([self.get(m, kind, CURRENT) for m in self.markers] for kind in (OV.Position, OV.Velocity))
        d = b - a
        length = float(math.sqrt(d @ d))
        return length, float(d @ (vb - va)) / length if length > 0.0 else 0.0


def add_tethers(model: Model, case: Case) -> None:
    """Every tether of ``case`` whose two bodies fly in the model's phase (neither rides in the other), with its
    tension channel and its state (``model.tethers``: name -> TetherState, for the step control)."""
    present = set(model.bodies)
    laws: dict = {}
    get = model.mbs.GetObjectOutput
    for tether in case.tethers.values():
        if not tether.acts_between(present):
            continue
        (first, first_point), (second, second_point) = tether.ends
        markers = [model.bodies[first].point_markers[first_point], model.bodies[second].point_markers[second_point]]
        connector = model.mbs.AddObject(eii.ObjectConnectorSpringDamper(
            markerNumbers=markers, referenceLength=tether.law.free_length, stiffness=tether.law.stiffness,
            damping=tether.law.damping, springForceUserFunction=line_law(model, tether.law, laws, True),
            visualization=eii.VObjectConnectorSpringDamper(show=True, drawSize=0.05, color=LINE_COLOUR)))
        model.add_channel(tether_channel(tether.name), lambda c=connector: get(c, OV.ForceLocal, CURRENT))
        model.tethers[tether.name] = TetherState(model, markers)

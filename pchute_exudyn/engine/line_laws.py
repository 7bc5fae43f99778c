"""The line law as Exudyn spring-damper user functions (``ObjectConnectorSpringDamper``): written from a line's record
(``physics.lines.LineLaw.expression``) in Exudyn's symbolic arithmetic (inside the engine: about 0.04 us a call
against 0.37 us for a Python one, ``validation/benchmark_full.py``), or as Python (``LineLaw.tension``). The full-mass
model's lines and every model's tethers use them."""

from __future__ import annotations

import exudyn as exu
from exudyn.utilities import CreateSymbolicUserFunction

from ..physics.lines import Arithmetic, LineLaw
from .phase_model import Model

esym = exu.symbolic
LINE_COLOUR = [0.1, 0.1, 0.6, 1.0]   # lines in Exudyn's viewer
SYMBOLIC = Arithmetic(lambda: esym.Real(0.0), esym.max,
                      lambda stretch, value: esym.IfThenElse(stretch > 0, value, esym.Real(0.0)),
                      lambda stretch, free_length: stretch * (1.0 / free_length),
                      lambda stretch, rate, value: esym.IfThenElse(stretch > 0, esym.Real(0.0),
                                                                   esym.IfThenElse(rate > 0, esym.Real(value),
                                                                                   esym.Real(0.0))))
"""Exudyn's symbolic expressions as the arithmetic the line law is written in (``LineLaw.expression``)."""


def _symbolic_law(law: LineLaw):
    """``law`` as an Exudyn spring-damper user function written in symbolic expressions (``LineLaw.expression``:
    the linear law with the connector's K and C, a table's in its hinge form)."""
    def symbolic(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
        return law.expression(deltaL, deltaL_t, SYMBOLIC, stiffness, damping)
    return symbolic


def _python_law(law: LineLaw):
    """``law`` as a Python spring-damper user function (``LineLaw.tension``)."""
    def python(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
        return law.tension(deltaL, deltaL_t)
    return python


def line_law(model: Model, law: LineLaw, shared: dict, symbolic: bool):
    """The spring-damper user function of a line with law ``law``: symbolic (one function for every linear line,
    whose K and C the connector passes; its own for a table) or Python (``symbolic`` False)."""
    if not symbolic:
        return _python_law(law)
    key = None if law.table is None and law.payout_resistance == 0.0 else law   # a shared linear law reads K, C
    if key not in shared:
        shared[key] = CreateSymbolicUserFunction(model.mbs, _symbolic_law(law), "springForceUserFunction",
                                                 itemTypeName="ObjectConnectorSpringDamper")
        model.keep_alive(shared[key])
    return shared[key]

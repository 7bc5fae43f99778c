"""The equilibrium-point method (Raiszadeh, the thesis's ref. 7; Eq. 2.9): no confluence states; the confluence sits
where the line stiffness forces balance and moves with the equilibrium velocity of Appendix B."""

from __future__ import annotations

from ..engine.equilibrium import EquilibriumConfluence, build_equilibrium_model
from .base import Method


class EquilibriumPoint(Method):
    """No confluence dynamics, so no step limit of its own; RK4 only (its solve runs at every RK stage, in the
    model's stage force item)."""

    name = "equilibrium"
    summary = "the confluence at the balance of the line stiffness forces (Raiszadeh, thesis Eq. 2.9)"
    integrator_note = ("its balance is solved in the bodies' force item at every RK stage, from the last solve "
                       "(``engine.equilibrium``), and an implicit solver's Newton iterations and Jacobian would "
                       "each need a converged balance; use rk4, or --method full with implicit")
    outputs = {name: unit for name, (unit, _) in EquilibriumConfluence.OUTPUTS.items()}

    def build(self, case, phase):
        return build_equilibrium_model(case, phase)

"""The equilibrium-point method (Raiszadeh, the thesis's ref. 7; thesis section 1.3 and Eq. 2.9), its model and its
confluence: no confluence states; at every right-hand-side evaluation the confluence is placed where the line
stiffness forces balance (``physics.equilibrium_point``, warm-started from the last solution), it moves with the
equilibrium velocity of Appendix B, and the line law with that velocity gives the forces on the bodies.

A solve that does not converge keeps its best point and is counted; the counts go to the summary, and
MAX_CONSECUTIVE_FAILURES failed solves in a row stop the run with an error.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..case.model import Case, ParachuteSystem
from ..engine.bodies import add_bodies
from ..engine.phase_model import Model
from ..engine.reduced import ReducedConfluence
from ..engine.state import ConfluenceState, Phase
from ..errors import SimulationError
from ..physics.equilibrium_point import equilibrium_point, equilibrium_velocity
from ..physics.lines import line_tensions, pack_lines, solve_series
from .base import Method

MAX_CONSECUTIVE_FAILURES = 20


class EquilibriumSolution(NamedTuple):
    """Equilibrium point, its velocity and the resulting line tensions at one evaluation."""

    position: tuple
    velocity: tuple
    tensions: tuple
    directions: tuple
    iterations: int
    converged: bool


class EquilibriumConfluence(ReducedConfluence):
    """State and user functions of one equilibrium-point confluence."""

    OUTPUTS = {"equilibrium_iterations": ("-", lambda c: c.current().iterations),
               "equilibrium_failures": ("-", lambda c: c.failures)}

    def __init__(self, model: Model, case: Case, system: ParachuteSystem, state: ConfluenceState):
        super().__init__(model, case, system, [0.0])
        self.guess = tuple(state.position.tolist())   # warm start: the last solution
        self.solves = self.failures = self.consecutive_failures = self.iterations = 0
        self.max_iterations_used = 0
        self.packed_lines = pack_lines(self.laws)   # (L0, K, C) rows, table points, counts: the series kernel's

    def compute(self, t, q, positions, velocities):
        if len(positions) == 2:   # a pair in series: the massless confluence on the line between them
            return self._series(positions, velocities)
        solved = equilibrium_point(positions, self.laws, guess=self.guess)
        self.solves += 1
        self.iterations += solved.iterations
        self.max_iterations_used = max(self.max_iterations_used, solved.iterations)
        if solved.converged:
            self.consecutive_failures = 0
        else:
            self.failures += 1
            self.consecutive_failures += 1
            if self.consecutive_failures >= MAX_CONSECUTIVE_FAILURES:
                raise SimulationError(
                    f"the equilibrium point of the {self.system.name} confluence did not converge in "
                    f"{MAX_CONSECUTIVE_FAILURES} solves in a row (near t = {t:.4f} s, residual {solved.residual:.3g} "
                    "N): use --method sp or full", t)
        position = tuple(solved.position.tolist())
        self.guess = position
        velocity, _ = equilibrium_velocity(positions, velocities, position, self.laws)
        tensions, directions = line_tensions(positions, velocities, position, velocity, self.laws)
        return EquilibriumSolution(position, tuple(velocity), tuple(tensions), tuple(directions), solved.iterations,
                                   solved.converged)

    def _series(self, positions, velocities) -> EquilibriumSolution:
        """Two lines in series (``physics.lines.solve_series``), the same law as SP's."""
        tensions, directions, active = np.zeros(2), np.zeros((2, 3)), np.zeros(2, np.bool_)
        attach = np.asarray(positions, float)
        vx, vy, vz, fraction = solve_series(attach, np.asarray(velocities, float), *self.packed_lines, tensions,
                                            directions, active, 0.0, 0.0, 0.0)
        position = tuple((attach[0] + fraction * (attach[1] - attach[0])).tolist())
        self.solves += 1
        return EquilibriumSolution(position, (vx, vy, vz), tuple(tensions.tolist()),
                                   tuple(tuple(d) for d in directions.tolist()), 0, True)

    def derivative(self, solution) -> list:
        return [0.0]

    def facts(self) -> dict:
        return {f"equilibrium_{self.system.name}": {
            "solves": self.solves, "failures": self.failures,
            "mean_iterations": self.iterations / max(self.solves, 1), "max_iterations": self.max_iterations_used}}


def build_equilibrium_model(case: Case, phase: Phase) -> Model:
    """Build the equilibrium-point Exudyn model of ``case`` for one phase."""
    model = Model(case, phase)
    add_bodies(model, case, reduced=True)
    for system in model.systems:
        EquilibriumConfluence(model, case, system, phase.confluence_states[system.name]).register(case)
    return model.assemble()


class EquilibriumPoint(Method):
    """No confluence dynamics, so no step limit of its own; RK4 only (its solve runs at every RK stage, in the
    model's stage force item)."""

    name = "equilibrium"
    summary = "the confluence at the balance of the line stiffness forces (Raiszadeh, thesis Eq. 2.9)"
    integrator_note = ("its balance is solved in the bodies' force item at every RK stage, from the last solve "
                       "(``EquilibriumConfluence``), and an implicit solver's Newton iterations and Jacobian would "
                       "each need a converged balance; use rk4, or --method full with implicit")
    outputs = {name: unit for name, (unit, _) in EquilibriumConfluence.OUTPUTS.items()}

    def build(self, case, phase):
        return build_equilibrium_model(case, phase)

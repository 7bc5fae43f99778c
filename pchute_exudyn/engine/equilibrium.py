"""The equilibrium-point method (Raiszadeh, the thesis's ref. 7; thesis section 1.3 and Eq. 2.9): no confluence
states; at every right-hand-side evaluation the confluence is placed where the line stiffness forces balance
(``physics.equilibrium``, warm-started from the last solution), it moves with the equilibrium velocity of Appendix B,
and the line law with that velocity gives the forces on the bodies.

A solve that does not converge keeps its best point and is counted; the counts go to the summary, and
MAX_CONSECUTIVE_FAILURES failed solves in a row stop the run with an error.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ..case.model import Case, ParachuteSystem
from ..errors import SimulationError
from ..phases import ConfluenceState, Phase, initial_phase
from ..physics.equilibrium import equilibrium_point, equilibrium_velocity
from ..physics.lines import tension
from .items import ModelItems, add_bodies, new_system
from .reduced import ReducedConfluence

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

    def __init__(self, items: ModelItems, case: Case, system: ParachuteSystem, state: ConfluenceState):
        super().__init__(items, case, system, [0.0])
        self.position = tuple(state.position.tolist())
        self.solves = self.failures = self.consecutive_failures = self.iterations = 0
        self.max_iterations_used = 0

    def compute(self, t, q, positions, velocities):
        solved = equilibrium_point(positions, self.free_length, self.stiffness, guess=self.position)
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
        self.position = position
        velocity, _ = equilibrium_velocity(positions, velocities, position, self.free_length, self.stiffness)
        wx, wy, wz = velocity
        cx, cy, cz = position
        tensions, directions = [], []
        for (px, py, pz), (vx, vy, vz), l0, k, c in zip(positions, velocities, self.free_length, self.stiffness,
                                                        self.damping):
            dx, dy, dz = px - cx, py - cy, pz - cz
            length = math.sqrt(dx * dx + dy * dy + dz * dz)
            nx, ny, nz = dx / length, dy / length, dz / length
            directions.append((nx, ny, nz))
            tensions.append(tension(length - l0, (vx - wx) * nx + (vy - wy) * ny + (vz - wz) * nz, k, c))
        return EquilibriumSolution(position, tuple(velocity), tuple(tensions), tuple(directions), solved.iterations,
                                   solved.converged)

    def derivative(self, solution) -> list:
        return [0.0]

    def add_channels(self, case: Case) -> None:
        super().add_channels(case)
        prefix = "" if len(case.systems) == 1 else f"{self.system.name}_"
        self.items.channels[("extra", f"{prefix}equilibrium_iterations", "-")] = lambda: self.current().iterations
        self.items.channels[("extra", f"{prefix}equilibrium_failures", "-")] = lambda: self.failures

    def summary(self) -> dict:
        return {"solves": self.solves, "failures": self.failures,
                "mean_iterations": self.iterations / max(self.solves, 1), "max_iterations": self.max_iterations_used}


def build_equilibrium_model(case: Case, phase: Phase | None = None) -> ModelItems:
    """Build the equilibrium-point Exudyn model of ``case`` for one phase."""
    phase = phase or initial_phase(case)
    items = new_system(case)
    add_bodies(items, case, phase, snapshot=True)
    for system in items.systems:
        confluence = EquilibriumConfluence(items, case, system, phase.confluence_states[system.name])
        items.reduced[system.name] = confluence
        confluence.register()
        confluence.add_channels(case)
        items.summaries.append(lambda confluence=confluence: {f"equilibrium_{confluence.system.name}":
                                                              confluence.summary()})
    items.mbs.Assemble()
    return items

"""The singular-perturbation model (thesis chapter 3): the confluence position as three first-order states whose
derivative is the SP velocity of ``physics.singular_perturbation`` (see ``engine.reduced`` for the Exudyn side).

v0, the confluence velocity at the end of the previous step, is held through each step's stages and updated after
the step (from the end-of-step solution Exudyn computes anyway); the first step uses the case's initial confluence
velocity.
"""

from __future__ import annotations

from ..case.model import Case, ParachuteSystem
from ..phases import ConfluenceState, Phase, initial_phase
from ..physics.singular_perturbation import confluence_velocity
from .items import CURRENT, OV, ModelItems, add_bodies, new_system
from .reduced import ReducedConfluence


class SPConfluence(ReducedConfluence):
    """State and user functions of one SP confluence."""

    def __init__(self, items: ModelItems, case: Case, system: ParachuteSystem, state: ConfluenceState,
                 kappa_max: float, slack_rule: str, start_time: float = 0.0):
        super().__init__(items, case, system, state.position.tolist())
        self.kappa_max, self.slack_rule = kappa_max, slack_rule
        self.previous_velocity = tuple(state.velocity.tolist())   # v0 of the first step: the state's velocity
        self.start_time = start_time

    def compute(self, t, q, positions, velocities):
        return confluence_velocity(positions, velocities, q, self.previous_velocity, self.free_length,
                                   self.stiffness, self.damping, self.kappa_max, self.slack_rule)

    def derivative(self, solution) -> list:
        return list(solution.velocity)

    def reusable(self, solution) -> bool:
        # v0 enters Eq. 3.10 only through C_c (and the all-slack case): without them the solve does not depend on
        # the v0 update between steps
        return solution.damping == 0.0 and any(solution.taut)

    def update_previous_velocity(self, mbs, t):
        """Post-step hook: v0 for the next step is the velocity at the end of this one."""
        if t > self.start_time:
            self.previous_velocity = self.current().velocity

    def add_channels(self, case: Case) -> None:
        super().add_channels(case)
        channels, mbs = self.items.channels, self.items.mbs
        channels[("confluence", self.system.name, "position")] = \
            lambda: mbs.GetNodeOutput(self.node, OV.Coordinates, CURRENT)
        label = case.confluence_label(self.system)
        prefix = "" if len(case.systems) == 1 else f"{self.system.name}_"
        channels[("extra", f"{label}_damping", "N s/m")] = lambda: self.current().damping
        channels[("extra", f"{prefix}condition_number", "-")] = lambda: self.current().condition_number
        channels[("extra", f"{prefix}taut_lines", "-")] = lambda: sum(self.current().taut)


def build_sp_model(case: Case, phase: Phase | None, kappa_max: float, slack_rule: str) -> ModelItems:
    """Build the SP Exudyn model of ``case`` for one phase (bodies and aerodynamics as in the full model)."""
    phase = phase or initial_phase(case)
    items = new_system(case)
    add_bodies(items, case, phase, snapshot=True)
    for system in items.systems:
        sp = SPConfluence(items, case, system, phase.confluence_states[system.name], kappa_max, slack_rule,
                          phase.start)
        items.sp[system.name] = sp
        sp.register()
        items.post_step_hooks.append(sp.update_previous_velocity)
        sp.add_channels(case)
    items.mbs.Assemble()
    return items

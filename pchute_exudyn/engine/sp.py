"""The singular-perturbation model (thesis chapter 3): the confluence position as three first-order states whose
derivative is the SP velocity of ``physics.singular_perturbation`` (see ``engine.reduced`` for the Exudyn side).

v0, the confluence velocity at the end of the previous step, is held through each step's stages and updated after
the step (from the end-of-step solution Exudyn computes anyway); the first step uses the case's initial confluence
velocity.
"""

from __future__ import annotations

from ..case.model import Case, ParachuteSystem
from ..physics.singular_perturbation import confluence_velocity
from .items import CURRENT, OV, ModelItems, add_aerodynamics, add_body, new_system
from .reduced import ReducedConfluence


class SPConfluence(ReducedConfluence):
    """State and user functions of one SP confluence."""

    def __init__(self, items: ModelItems, case: Case, system: ParachuteSystem, kappa_max: float, slack_rule: str):
        init = system.confluence.initial
        position = case.start.local_position(init.altitude, init.east, init.north)
        super().__init__(items, case, system, position.tolist())
        self.kappa_max, self.slack_rule = kappa_max, slack_rule
        self.previous_velocity = tuple(case.start.inertial_velocity(position, init.velocity_enu).tolist())

    def compute(self, t, q, positions, velocities):
        return confluence_velocity(positions, velocities, q, self.previous_velocity, self.free_length,
                                   self.stiffness, self.damping, self.kappa_max, self.slack_rule)

    def derivative(self, solution) -> list:
        return list(solution.velocity)

    def update_previous_velocity(self, mbs, t):
        """Post-step hook: v0 for the next step is the velocity at the end of this one."""
        if t > 0.0:
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


def build_sp_model(case: Case, kappa_max: float, slack_rule: str) -> ModelItems:
    """Build the SP Exudyn model of ``case`` (bodies and aerodynamics as in the full model, SP confluences)."""
    items = new_system(case)
    for body in case.bodies.values():
        add_body(items, case, body)
    for body in case.bodies.values():
        add_aerodynamics(items, case, body)
    for system in case.systems.values():
        sp = SPConfluence(items, case, system, kappa_max, slack_rule)
        items.sp[system.name] = sp
        items.post_step_hooks.append(sp.update_previous_velocity)
        sp.add_channels(case)
    items.mbs.Assemble()
    return items

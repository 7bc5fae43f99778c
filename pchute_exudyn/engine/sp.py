"""The singular-perturbation model (thesis chapter 3): the confluence position as three first-order states whose
derivative is the SP velocity of ``physics.singular_perturbation`` (see ``engine.reduced`` for the Exudyn side).

v0, the confluence velocity at the end of the previous step, is held through each step's stages and updated after
the step (from the end-of-step solution Exudyn computes anyway); the first step uses the case's initial confluence
velocity.

Order 1 (the confluence mass to first order): the reference velocity of a solve at time t is the latest end-of-step
velocity from before t, so the backward difference spans the stage's part of the step (h/2 or h) and, at a step's
first stage, the whole previous step; that stage then solves the same equation as the end-of-step call before it and
reuses its solution like order 0. At a phase's first stage there is no earlier velocity: the acceleration carried
from the previous phase (zero for a newly deployed system) enters as a force instead.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..case.model import Case, ParachuteSystem
from ..physics.lines import pack_tables
from ..physics.singular_perturbation import STAGE_COLUMNS, MassTerm, sp_stage
from ..state import ConfluenceState, Phase
from .bodies import add_bodies
from .model import CURRENT, OV, Model
from .reduced import ReducedConfluence


class StageSolution(NamedTuple):
    """An SP solve at one stage: the velocity (m/s), C_c (N s/m) and kappa it returned, and the lines as the
    kernel wrote them (``physics.singular_perturbation.sp_stage``; the confluence's work array, current until its
    next solve, which is also when this solution stops being the current one)."""

    velocity: tuple
    damping: float
    condition_number: float
    taut_count: int
    work: np.ndarray

    @property
    def tensions(self):
        return self.work[:, 0]

    @property
    def directions(self):
        return self.work[:, 1:4]

    @property
    def taut(self):
        return tuple(self.work[:, 4] > 0.0)


class SPConfluence(ReducedConfluence):
    """State and user functions of one SP confluence; ``options``: the SP method's options
    (``methods.sp.SPOptions``: kappa_max, slack_rule and order in effect)."""

    OUTPUTS = {"confluence_damping": ("N s/m", lambda c: c.current().damping),
               "condition_number": ("-", lambda c: c.current().condition_number),
               "taut_lines": ("-", lambda c: c.current().taut_count)}

    def __init__(self, model: Model, case: Case, system: ParachuteSystem, state: ConfluenceState, options,
                 start_time: float = 0.0):
        super().__init__(model, case, system, state.position.tolist())
        self.kappa_max, self.slack_rule = options.effective_kappa_max, options.slack_rule
        self.order = options.effective_order
        self.force_rule = 1.0 if options.slack_rule == "force" else 0.0
        self.table_points, counts = pack_tables(line.load_elongation for line in system.lines)
        self.layout = np.column_stack([self.points, self.free_length, self.stiffness, self.damping, counts])
        self.work = np.zeros((len(system.lines), STAGE_COLUMNS))
        self.previous_velocity = tuple(state.velocity.tolist())   # v0 of the first step: the state's velocity
        self.start_time = start_time
        self.mass = system.confluence.mass
        self.gravity = case.start.gravity_scalar
        acceleration = state.acceleration
        self.start_acceleration = (0.0, 0.0, 0.0) if acceleration is None else tuple(acceleration.tolist())
        self.end_velocities = []   # the last two (t, end-of-step confluence velocity), for order 1

    def mass_term(self, t, q) -> MassTerm | None:
        """The order-1 inertia and weight for a solve at time ``t`` (s) and confluence position ``q`` (m)."""
        if self.order == 0:
            return None
        m = self.mass
        gx, gy, gz = self.gravity(*q)
        for time, velocity in reversed(self.end_velocities):
            if time < t:
                return MassTerm(m / (t - time), velocity, (m * gx, m * gy, m * gz))
        ax, ay, az = self.start_acceleration
        return MassTerm(0.0, (0.0, 0.0, 0.0), (m * (gx - ax), m * (gy - ay), m * (gz - az)))

    def solve_stage(self, t, q):
        """The compiled stage kernel: attach points, Eq. 3.10 with C_c, the line forces into ``part``."""
        mass = self.mass_term(t, q)
        rate, bx, by, bz = 0.0, 0.0, 0.0, 0.0
        if mass is not None:
            rate, (rx, ry, rz), (gx, gy, gz) = mass
            bx, by, bz = gx + rate * rx, gy + rate * ry, gz + rate * rz
        v0x, v0y, v0z = self.previous_velocity
        vx, vy, vz, damping, kappa, taut = sp_stage(
            self.stage.states, self.layout, self.table_points, self.work, self.part, q[0], q[1], q[2], v0x, v0y,
            v0z, self.kappa_max, self.force_rule, rate, bx, by, bz)
        return StageSolution((vx, vy, vz), damping, kappa, taut, self.work)

    def tension_reader(self, i: int):
        work = self.work   # current after the post-step hook ``confirm``, which runs before the sampling
        return lambda: work[i, 0]

    def derivative(self, solution) -> list:
        return list(solution.velocity)

    def reusable(self, solution) -> bool:
        # v0 enters Eq. 3.10 only through C_c (and the all-slack case): without them the solve does not depend on
        # the v0 update between steps (order 1's reference velocity is the same for both calls: see the module doc)
        return solution.damping == 0.0 and solution.taut_count > 0

    def end_step(self, mbs, t):
        """Post-step hook: v0 for the next step is the velocity at the end of this one; order 1 records it."""
        velocity = self.current().velocity
        if t > self.start_time:
            self.previous_velocity = velocity
        if self.order == 1 and (not self.end_velocities or t > self.end_velocities[-1][0]):
            self.end_velocities = [*self.end_velocities[-1:], (t, velocity)]

    def acceleration(self):
        """Mean confluence acceleration over the last step (m/s^2), or None before the first step ends."""
        if len(self.end_velocities) < 2:
            return None
        (t0, v0), (t1, v1) = self.end_velocities
        return [(b - a) / (t1 - t0) for a, b in zip(v0, v1)]

    def position(self) -> list:
        """The ODE1 coordinates of ``current()``'s solution: the confluence position (m)."""
        return self.current_coordinates()

    def position_reader(self):
        return self.current_coordinates

    def state_position(self) -> list:
        return np.asarray(self._get_node(self.node, OV.Coordinates, CURRENT))[:3]


def build_sp_model(case: Case, phase: Phase, options) -> Model:
    """Build the SP Exudyn model of ``case`` for one phase (bodies and aerodynamics as in the full model) with the
    SP method's ``options``; order 1 keeps the confluence mass to first order (``physics.singular_perturbation``)."""
    model = Model(case, phase)
    add_bodies(model, case, reduced=True)
    for system in model.systems:
        sp = SPConfluence(model, case, system, phase.confluence_states[system.name], options, phase.start)
        sp.register(case)
        model.add_post_step(sp.end_step)
    return model.assemble()

"""The singular-perturbation model (thesis chapter 3): the confluence position as three first-order states whose
derivative is the SP velocity of ``physics.singular_perturbation``, solved by the compiled stage kernel ``sp_stage``
inside the model's stage force item and integrated in step with Exudyn's RK4 stages (``engine.reduced``).

v0, the confluence velocity at the end of the previous step, is held through each step's stages and updated after
the step (from the end-of-step solve); the first step uses the case's initial confluence velocity.

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
from ..physics.singular_perturbation import (
    MEMORY_ROWS,
    STAGE_COLUMNS,
    sp_end_of_step,
    sp_rk_stage,
    sp_rk_stage_with_bodies,
)
from ..state import ConfluenceState, Phase
from .bodies import add_bodies
from .model import Model
from .reduced import ReducedConfluence, step_size


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
        self.table_points, counts = pack_tables(line.load_elongation for line in system.lines)
        self.layout = np.column_stack([self.points, self.free_length, self.stiffness, self.damping, counts])
        self.work = np.zeros((len(system.lines), STAGE_COLUMNS))
        self.start_time = start_time
        acceleration = state.acceleration
        memory = self.memory = np.zeros((MEMORY_ROWS, 3))   # physics.singular_perturbation.MEMORY_ROWS
        memory[0] = state.position
        memory[5] = state.velocity                            # v0 of the first step: the state's velocity
        memory[6] = system.confluence.mass, self.kappa_max, 1.0 if options.slack_rule == "force" else 0.0
        mu, *vector = case.start.gravity_parameters()
        memory[7], memory[8] = (float(self.order), mu, 0.0), vector
        memory[12] = (0.0, 0.0, 0.0) if acceleration is None else acceleration
        self.stage_index = 0

    def new_step(self, mbs, t):
        """Pre-step hook (``t``: the end time of the coming step)."""
        self.stage_index = 0
        self.step_size = step_size(self.model, t - self.step_start)

    def stage_solve(self, t: float) -> None:
        """The compiled SP solve at the current RK stage (``sp_rk_stage``); stage 1 is the end-of-step state that
        ``advance`` solved, whose velocity (memory row 1) and line forces stand when the solve did not depend on the
        v0 update since."""
        index = self.stage_index
        if index < 4 and not (index == 0 and self.reusable(self.solution)):
            sp_rk_stage(self.stage.states, self.layout, self.table_points, self.work, self.part, self.memory, t,
                        index, self.step_size)
        self.stage_index = index + 1

    def warm_up(self) -> None:
        """The solve at the phase start, and the stage kernel called once the way the stages call it (numba compiles
        a call from Python apart from the same function called inside another kernel)."""
        super().warm_up()
        sp_rk_stage(self.stage.states, self.layout, self.table_points, self.work, self.part, self.memory,
                    self.model.phase.start, 0, 0.0)
        stage = self.stage
        if stage.fused is self:
            q, q_t = np.array(stage._read()), np.array(stage._read_t())
            sp_rk_stage_with_bodies(q, q_t, stage.global_layout, stage.states, self.layout, self.table_points,
                                    self.work, self.part, self.memory, self.model.phase.start, 0, 0.0, True)

    def stage_solve_with_bodies(self, t: float, q, q_t, bodies, states) -> None:
        """``stage_solve`` with the stage's body kinematics in the same kernel call (the stage force item uses it
        when this is the model's only confluence)."""
        index = self.stage_index
        solve = index < 4 and not (index == 0 and self.reusable(self.solution))
        sp_rk_stage_with_bodies(q, q_t, bodies, states, self.layout, self.table_points, self.work, self.part,
                                self.memory, t, index, self.step_size, solve)
        self.stage_index = index + 1

    def advance(self, mbs, t):
        """Post-step hook, before any other: complete the step, solve at the end-of-step state (whose velocity is
        the next step's k_1) and update v0 and order 1's record (``sp_end_of_step``)."""
        completed = self.stage_index == 4
        if completed:
            self.step_start = t
        self.stage_index = 0
        self.stage.refresh(t)
        vx, vy, vz, damping, kappa, taut = sp_end_of_step(self.stage.states, self.layout, self.table_points,
                                                          self.work, self.part, self.memory, t, self.step_size,
                                                          completed, self.start_time)
        self.solution = StageSolution((vx, vy, vz), damping, kappa, taut, self.work)

    def tension_reader(self, i: int):
        work = self.work   # current after the post-step hook ``advance``, which runs before the sampling
        return lambda: work[i, 0]

    def reusable(self, solution) -> bool:
        # v0 enters Eq. 3.10 only through C_c (and the all-slack case): without them the solve does not depend on
        # the v0 update between steps (order 1's reference velocity is the same for both calls: see the module doc)
        return solution.damping == 0.0 and solution.taut_count > 0

    def acceleration(self):
        """Mean confluence acceleration over the last step (m/s^2), or None before the first step ends."""
        memory = self.memory
        if memory[7, 2] < 2:
            return None
        return ((memory[10] - memory[11]) / (memory[9, 0] - memory[9, 1])).tolist()

    def position(self) -> list:
        """The confluence position (m) at the end of the last step: the SP state."""
        return self.memory[0].tolist()

    def position_reader(self):
        return self.position

    def state_position(self) -> list:
        return self.memory[0].tolist()


def build_sp_model(case: Case, phase: Phase, options) -> Model:
    """Build the SP Exudyn model of ``case`` for one phase (bodies and aerodynamics as in the full model) with the
    SP method's ``options``; order 1 keeps the confluence mass to first order (``physics.singular_perturbation``)."""
    model = Model(case, phase)
    add_bodies(model, case, reduced=True)
    for system in model.systems:
        sp = SPConfluence(model, case, system, phase.confluence_states[system.name], options, phase.start)
        sp.register(case)
    return model.assemble()

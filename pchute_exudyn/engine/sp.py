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

from array import array
from typing import NamedTuple

import numpy as np

from ..case.model import Case, ParachuteSystem
from ..physics.compiled import machine_code, python_form
from ..physics.lines import pack_tables
from ..physics.singular_perturbation import (
    END_TENSION,
    MEMORY_ACCELERATION,
    MEMORY_GRAVITY,
    MEMORY_NEWER,
    MEMORY_OLDER,
    MEMORY_ORDER,
    MEMORY_POSITION,
    MEMORY_ROWS,
    MEMORY_SETTINGS,
    MEMORY_TIMES,
    MEMORY_V0,
    STAGE_COLUMNS,
    WORK_DIRECTION,
    WORK_TAUT,
    holds_after_v0_update,
    record_size,
    sp_end_of_step,
    sp_end_of_step_with_bodies,
    sp_first_stage_with_bodies,
    sp_rk_stage,
    sp_rk_stage_with_bodies,
)
from .bodies import add_bodies
from .model import Model
from .reduced import ReducedConfluence, step_size
from .state import ConfluenceChannel, ConfluenceState, MethodChannel, Phase, TensionChannel

_holds_after_v0_update = python_form(holds_after_v0_update)   # checked from Python once a step


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
        return self.work[:, END_TENSION]

    @property
    def directions(self):
        return self.work[:, WORK_DIRECTION:WORK_DIRECTION + 3]

    @property
    def taut(self):
        return tuple(self.work[:, WORK_TAUT] > 0.0)


class SPConfluence(ReducedConfluence):
    """State and user functions of one SP confluence; ``options``: the SP method's options
    (``methods.sp.SPOptions``: kappa_max, slack_rule and order in effect).

    Per step the engine calls it at each RK stage (from the stage's force item) and once after the step
    (``advance``); there is no pre-step call: the step size comes from the second stage's time.

    The end-of-step work (the RK4 update of the confluence position, the solve at the end-of-step state, v0 and
    order 1's record: ``sp_end_of_step``) is due after every step. When this is the model's only confluence
    (``Stage.fused``) it is deferred to the next step's first stage, whose state is the same and whose force call
    hands over the coordinates: one kernel call does it and that stage's solve (``sp_first_stage_with_bodies``),
    with no engine read. Anything that needs it sooner (a channel reader, the touchdown check, the step monitor, the
    end of the run) settles it at once from the engine (``settle``); the outputs sampled after a step are a slot
    the deferred work fills. Otherwise ``advance`` settles at once. The kernels are called through their compiled
    code (``physics.compiled.machine_code``)."""

    OUTPUTS = {"confluence_damping": ("N s/m", lambda c: c.settled().end_of_step[3]),
               "condition_number": ("-", lambda c: c.settled().end_of_step[4]),
               "taut_lines": ("-", lambda c: c.settled().end_of_step[5])}
    """The method's channels: entries 3, 4 and 5 of the end-of-step tuple, in this order (``add_channels``)."""
    PRE_STEP = False
    DEFER = True
    """Whether the fused confluence defers its end-of-step work to the next stage (False: settle in ``advance``; the
    tests compare the two)."""

    def __init__(self, model: Model, case: Case, system: ParachuteSystem, state: ConfluenceState, options,
                 start_time: float = 0.0):
        super().__init__(model, case, system, state.position.tolist())
        self.kappa_max, self.slack_rule = options.effective_kappa_max, options.slack_rule
        self.order = options.effective_order
        self.table_points, counts = pack_tables(line.load_elongation for line in system.lines)
        self.layout = np.column_stack([self.points, self.free_length, self.stiffness, self.damping, counts])
        self.work = np.zeros((len(system.lines), STAGE_COLUMNS))
        self.start_time = float(start_time)
        acceleration = state.acceleration
        memory = self.memory = np.zeros((MEMORY_ROWS, 3))   # physics.singular_perturbation.MEMORY_ROWS
        memory[MEMORY_POSITION] = state.position
        memory[MEMORY_V0] = state.velocity                    # v0 of the first step: the state's velocity
        memory[MEMORY_SETTINGS] = (system.confluence.mass, self.kappa_max,
                                   1.0 if options.slack_rule == "force" else 0.0)
        mu, *vector = case.start.gravity_parameters()
        memory[MEMORY_ORDER], memory[MEMORY_GRAVITY] = (float(self.order), mu, 0.0), vector
        memory[MEMORY_ACCELERATION] = (0.0, 0.0, 0.0) if acceleration is None else acceleration
        self.stage_index = 0
        self.step_start = float(self.step_start)
        self.end_of_step = None   # the end-of-step solve's (vx, vy, vz, C_c, kappa, taut) (``sp_end_of_step``)
        self.pending = None       # (end time in s, whether the step completed) of end-of-step work not yet done
        self._slot = None         # the output sample waiting for that work
        self.record = np.zeros(record_size(model.stage.states, len(system.lines)))   # the outputs (``_record``)
        self._solution_of = None  # the end_of_step tuple ``solution`` was made from
        self._kernels = {kernel: kernel for kernel in (sp_rk_stage, sp_end_of_step, sp_rk_stage_with_bodies,
                                                       sp_end_of_step_with_bodies, sp_first_stage_with_bodies)}

    # -- the solver's calls -------------------------------------------------------------------------------------------

    def stage_solve(self, t: float) -> None:
        """The compiled SP solve at the current RK stage (``sp_rk_stage``), the stage's body states already set."""
        index = self.stage_index
        if self._needs_solve(t, index):
            self._kernels[sp_rk_stage](self.stage.states, self.layout, self.table_points, self.work, self.part,
                                       self.memory, t, index, self.step_size)

    def stage_solve_with_bodies(self, t: float, q, q_t, bodies, states, generalized, aerodynamics) -> None:
        """``stage_solve`` with the stage's body kinematics in the same kernel call (the stage force item uses it
        when this is the model's only confluence), the lines' generalized forces written to ``generalized`` and the
        bodies' aerodynamic loads added (``aerodynamics``: ``engine.aerodynamics.AerodynamicLoads.parts``); at a
        step's first stage, the deferred end-of-step work too."""
        index = self.stage_index
        pending = self.pending
        if index == 0 and pending is not None:
            self.stage_index = 1
            self.end_of_step = self._kernels[sp_first_stage_with_bodies](
                q, q_t, bodies, states, self.layout, self.table_points, self.work, self.part, self.memory,
                pending[0], self.step_size, pending[1], self.start_time, self.record, t, generalized, *aerodynamics)
            self._settled()
            return
        solve = self._needs_solve(t, index)
        self._kernels[sp_rk_stage_with_bodies](q, q_t, bodies, states, self.layout, self.table_points, self.work,
                                               self.part, self.memory, t, index, self.step_size, solve, generalized,
                                               *aerodynamics)

    def _needs_solve(self, t: float, index: int) -> bool:
        """Count stage ``index`` (at ``t``, s) and say whether it needs a solve; at the second stage (t_n + h/2) set
        the step size h. The first stage's state is the end-of-step state already solved: that solve stands when
        it holds after the v0 update (``holds_after_v0_update``)."""
        self.stage_index = index + 1
        if index == 1:
            self.step_size = step_size(self.model, 2.0 * (t - self.step_start))
        if index == 0:
            end = self.end_of_step
            return not _holds_after_v0_update(end[3], end[5])
        return index < 4

    def advance(self, mbs, t):
        """Post-step hook, before any other: complete the step's count and make its end-of-step work due (done
        now unless it can wait for the next stage: see the class doc)."""
        completed = self.stage_index == 4
        if completed:
            self.step_start = t
        self.stage_index = 0
        self.pending = (t, completed)
        if self.stage.fused is not self or not self.DEFER:
            self.settle()

    def settle(self) -> None:
        """Do the due end-of-step work now, from the engine's current state (the end of the last step)."""
        if self.pending is None:
            return
        t, completed = self.pending
        stage, kernels = self.stage, self._kernels
        if stage.fused is self:   # the end-of-step body states and the solve in one kernel call
            self.end_of_step = kernels[sp_end_of_step_with_bodies](
                stage.coordinates(), stage.velocities(), stage.global_layout, stage.states, self.layout,
                self.table_points, self.work, self.part, self.memory, t, self.step_size, completed, self.start_time,
                self.record)
            stage.refreshed_now(t)
        else:
            stage.refresh(t)
            self.end_of_step = kernels[sp_end_of_step](stage.states, self.layout, self.table_points, self.work,
                                                       self.part, self.memory, t, self.step_size, completed,
                                                       self.start_time, self.record)
        self._settled()

    def _settled(self) -> None:
        self.pending = None
        if self._slot is not None:   # the sample taken after the step gets its values
            self._slot.append(self.record.copy())
            self._slot = None

    def finish(self) -> None:
        """After the solve: the last step's end-of-step work."""
        self.settle()

    def warm_up(self) -> None:
        """The solve at the phase start, and each kernel's compiled code for the argument types the solver passes
        (``machine_code``; Exudyn passes the time as a float)."""
        stage, start = self.stage, float(self.model.phase.start)
        step = float(self.model.step if self.model.step is not None else 0.0)
        arguments = (stage.states, self.layout, self.table_points, self.work, self.part, self.memory)
        kernels = self._kernels
        kernels[sp_rk_stage] = machine_code(sp_rk_stage, *arguments, start, 0, step)
        kernels[sp_end_of_step] = machine_code(sp_end_of_step, *arguments, start, step, False, start, self.record)
        if stage.fused is self:
            q, q_t = array("d", stage.coordinates()), array("d", stage.velocities())   # as the force item passes them
            head = (q, q_t, stage.global_layout, stage.states, *arguments[1:])
            generalized, aerodynamics = stage.generalized, stage.loads.parts
            kernels[sp_rk_stage_with_bodies] = machine_code(sp_rk_stage_with_bodies, *head, start, 0, step, True,
                                                            generalized, *aerodynamics)
            kernels[sp_end_of_step_with_bodies] = machine_code(sp_end_of_step_with_bodies, *head, start, step,
                                                               False, start, self.record)
            kernels[sp_first_stage_with_bodies] = machine_code(sp_first_stage_with_bodies, *head, start, step,
                                                               False, start, self.record, start, generalized,
                                                               *aerodynamics)
        self.advance(None, start)
        self.settle()

    # -- what it reports ----------------------------------------------------------------------------------------------

    def settled(self) -> SPConfluence:
        """This confluence with the last step's end-of-step work done: every reader of ``end_of_step``, ``work``
        and ``memory`` goes through it (the work may be deferred: see the class doc)."""
        self.settle()
        return self

    def current(self) -> StageSolution:
        """The end-of-step solve as a ``StageSolution`` (made when first asked for after each step)."""
        end = self.settled().end_of_step
        if self._solution_of is not end:
            self.solution, self._solution_of = StageSolution(end[:3], *end[3:], self.work), end
        return self.solution

    def velocity(self):
        return self.settled().end_of_step[:3]

    def tension_reader(self, i: int):
        def tension():
            return self.settled().work[i, END_TENSION]
        return tension

    def sample(self) -> list:
        """The sampled channels' values: a list holding a copy of the end-of-step record (``_record``), or an empty
        one that the deferred end-of-step work fills."""
        if self.pending is None:
            return [self.record.copy()]
        if self._slot is None:
            self._slot = []
        return self._slot

    def add_channels(self, case: Case) -> None:
        """The channels of ``ReducedConfluence.add_channels``, sampled together (``sample``): the position, the
        end-of-step tuple (velocity and ``OUTPUTS``) and the tensions in one call."""
        super().add_channels(case)
        name = self.system.name
        keys = [ConfluenceChannel(name, "position"), ConfluenceChannel(name, "velocity")]
        keys += [MethodChannel(name, output, unit) for output, (unit, _) in self.OUTPUTS.items()]
        keys += [TensionChannel(name, line.name) for line in self.system.lines]

        first = self.stage.states.size   # the record after the body states: position, end-of-step tuple, tensions

        def split(records):
            return ([records[:, first:first + 3], records[:, first + 3:first + 6]]
                    + [records[:, first + 6 + k] for k in range(len(self.OUTPUTS))]
                    + [records[:, first + 9 + i] for i in range(len(self.system.lines))])
        self.model.add_channel_group(keys, self.sample, split)

    def acceleration(self):
        """Mean confluence acceleration over the last step (m/s^2), or None before the first step ends."""
        memory = self.settled().memory
        if memory[MEMORY_ORDER, 2] < 2:
            return None
        return ((memory[MEMORY_NEWER] - memory[MEMORY_OLDER])
                / (memory[MEMORY_TIMES, 0] - memory[MEMORY_TIMES, 1])).tolist()

    def position(self) -> list:
        """The confluence position (m) at the end of the last step: the SP state."""
        return self.settled().memory[MEMORY_POSITION].tolist()

    def position_reader(self):
        return self.position

    def state_position(self) -> list:
        return self.position()


def build_sp_model(case: Case, phase: Phase, options) -> Model:
    """Build the SP Exudyn model of ``case`` for one phase (bodies and aerodynamics as in the full model) with the
    SP method's ``options``; order 1 keeps the confluence mass to first order (``physics.singular_perturbation``)."""
    model = Model(case, phase)
    add_bodies(model, case, reduced=True)
    for system in model.systems:
        sp = SPConfluence(model, case, system, phase.confluence_states[system.name], options, phase.start)
        sp.register(case)
    return model.assemble()

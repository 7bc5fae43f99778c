"""SP's confluence at run time: the confluence position as three first-order states whose derivative is the SP
velocity (``balance``), solved by the compiled stage kernels inside the model's stage force item and integrated in step
with Exudyn's RK4 stages (``stepping``, ``engine.reduced``).

v0, the confluence velocity at the end of the previous step, is held through each step's stages and updated after
the step (from the end-of-step solve); the first step uses the case's initial confluence velocity.

Order 1 (the confluence mass to first order): the reference velocity of a solve at time t is the latest end-of-step
velocity from before t, so the backward difference spans the stage's part of the step (h/2 or h) and, at a step's
first stage, the whole previous step; that stage then solves the same equation as the end-of-step call before it and
reuses its solution like order 0. At a phase's first stage there is no earlier velocity: the acceleration carried
from the previous phase (zero for a newly deployed system) enters as a force instead.
"""

from __future__ import annotations

import math
from array import array
from functools import partial
from typing import NamedTuple

import numpy as np

from ...case.model import Case, ParachuteSystem
from ...engine.phase_model import Model
from ...engine.reduced import ReducedConfluence
from ...engine.state import ConfluenceChannel, ConfluenceState, MethodChannel, TensionChannel
from ...physics.compiled import has_machine_code, machine_code
from ...physics.lines import pack_tables
from .balance import relaxed_damping
from .memory import Memory, Record, Work, layout_damping, line_layout
from .reduced_canopy import ReducedCanopy, reduced_canopy
from .stepping import sp_settle, sp_settle_with_bodies, sp_step_stage, sp_step_stage_with_bodies, step_done

RATE_MEMORY = 2.0
"""s: the time over which a line's stretch-rate envelope fades (``SPConfluence.relaxation_allowed``): a pendulum's
period or two."""


class StageSolution(NamedTuple):
    """An SP solve at the end of a step: the velocity (m/s), C_c (N s/m) and kappa it returned, and the lines as the
    kernel wrote them (``work``: the confluence's work array, current until its next solve, which is also when this
    solution stops being the current one)."""

    velocity: tuple
    damping: float
    condition_number: float
    taut_count: int
    work: Work

    @property
    def tensions(self):
        return self.work.end_tensions

    @property
    def directions(self):
        return self.work.directions

    @property
    def taut(self):
        return tuple(self.work.taut > 0.0)


class SPConfluence(ReducedConfluence):
    """State and user functions of one SP confluence; ``options``: the SP method's options (``SPOptions``:
    kappa_max, slack_rule and order in effect).

    Per step the engine calls it at each RK stage (from the stage's force item) and once after the step
    (``advance``); there is no pre-step call: the step size comes from the second stage's time. The step's
    bookkeeping (the stage count, the step's start and size, the end-of-step work due, the last end-of-step solve)
    lives in the confluence's memory with its states (``memory.Memory``), so a stage's call passes only the time and
    the stage's node coordinates into one compiled kernel.

    The end-of-step work (the RK4 update of the confluence position, the solve at the end-of-step state, v0 and
    order 1's record: ``stepping.sp_end_of_step``) is due after every step. When this is the model's only confluence
    (``Stage.fused``) it is deferred to the next step's first stage, whose state is the same and whose force call
    hands over the coordinates: one kernel call does it and that stage's solve (``sp_step_stage_with_bodies``),
    with no engine read. Anything that needs it sooner (a channel reader, the touchdown check, the step monitor, the
    end of the run) settles it at once from the engine (``settle``); the outputs sampled after a step are a slot
    the deferred work fills. Otherwise ``advance`` settles at once. The kernels are called through their compiled
    code (``physics.compiled.machine_code``)."""

    OUTPUTS = {"confluence_damping": ("N s/m", lambda c: c.settled().memory.end_damping),
               "condition_number": ("-", lambda c: c.settled().memory.end_kappa),
               "taut_lines": ("-", lambda c: int(c.settled().memory.end_taut))}
    """The method's channels: C_c, kappa and the lines counted taut of the end-of-step solve."""
    PRE_STEP = False
    DEFER = True
    """Whether the fused confluence defers its end-of-step work to the next stage (False: settle in ``advance``; the
    tests compare the two)."""

    def __init__(self, model: Model, case: Case, system: ParachuteSystem, state: ConfluenceState, options,
                 start_time: float = 0.0):
        super().__init__(model, case, system, state.position.tolist())
        self.kappa_max, self.slack_rule = options.effective_kappa_max, options.slack_rule
        self.order = options.effective_order
        self.table_points, _ = pack_tables(law.table for law in self.laws)
        self.layout = line_layout(self.points, self.laws)
        self.work = Work(len(system.lines))
        self.memory = memory = Memory()
        memory.position = state.position
        memory.v0 = state.velocity                    # v0 of the first step: the state's velocity
        memory.settings = (system.confluence.mass, self.kappa_max, 1.0 if options.slack_rule == "force" else 0.0)
        mu, *vector = case.start.gravity_parameters()
        memory.order, memory.gravity = (float(self.order), mu, 0.0), vector
        normal = case.start.normal_gravity_parameters()
        if normal is not None:   # stepping.confluence_gravity
            memory.normal_gravity = normal
        memory.acceleration = (0.0, 0.0, 0.0) if state.acceleration is None else state.acceleration
        memory.clock = (0.0, float(self.step_start), 0.0)   # no stage yet; t_n the phase start; h unknown
        memory.run = (0.0, float(start_time), 0.0)           # the run's step is set by ``warm_up``
        self._slot = None         # the output sample waiting for the deferred end-of-step work
        self._settles = 0         # end-of-step solves so far (``current`` remakes its solution after each)
        self.layout_of_record = Record(model.stage.states.size, len(system.lines))
        self.record = np.zeros(self.layout_of_record.size)   # the outputs (``stepping._record``)
        self._solution_of = -1    # the ``_settles`` count ``solution`` was made at
        self._kernels = {kernel: kernel for kernel in (sp_step_stage, sp_settle, sp_step_stage_with_bodies,
                                                       sp_settle_with_bodies, step_done)}
        self.stage_call = (None, (), None)   # the fused stage kernel, its arguments, its coordinates' form
        self._coordinates = None        # tuple or typed array: the coordinates' form (``warm_up``)
        self.pending = False   # whether the last step's end-of-step work is due: memory's due flag as Python
        #                        sees it (set by ``advance``, cleared by ``_settled`` whoever did the work)
        self._step_done = self._kernels[step_done]   # its machine code from ``warm_up`` on
        self._settle_now = True                      # whether ``advance`` does the work at once (``warm_up``)
        self._built_damping = None                   # the lines' damping as built, once ``relax`` changes it
        self._rates, self._rates_at = [], 0.0        # the lines' stretch-rate envelope (``relaxation_allowed``)
        name = reduced_canopy(case, system)
        self.canopy = None if name is None else ReducedCanopy(model, case, system, name, memory, self.settled)

    # -- the solver's calls -------------------------------------------------------------------------------------------

    @property
    def end_of_step(self) -> tuple:
        """The last end-of-step solve's (vx, vy, vz in m/s, C_c in N s/m, kappa, lines counted taut)."""
        memory = self.memory
        vx, vy, vz = memory.end_velocity.tolist()
        return vx, vy, vz, memory.end_damping, memory.end_kappa, int(memory.end_taut)

    def stage_solve(self, t: float) -> None:
        """The compiled SP solve at the current RK stage (``sp_step_stage``), the stage's body states already set."""
        self._kernels[sp_step_stage](self.stage.states, self.layout, self.table_points, self.work.array, self.part,
                                     self.memory.array, t)

    def bind_stage_call(self) -> None:
        """Set ``stage_call`` = (the fused stage kernel, its arguments after the node coordinates and the time, the
        form the coordinates take: tuple or typed array): the stage force item calls ``kernel(form(q), form(q_t), t,
        *arguments)``; its return's flags (``physics.aerodynamics.STAGE_SETTLED``) say whether it did the deferred
        end-of-step work (``settled_by_stage``). Again whenever the aerodynamics' arguments change (a turbulence
        field grown)."""
        stage = self.stage
        arguments = (stage.layout, stage.states, self.layout, self.table_points, self.work.array, self.part,
                     self.memory.array, self.record, stage.generalized, *stage.loads.parts)
        self.stage_call = (self._kernels[sp_step_stage_with_bodies], arguments, self._coordinates)

    def settled_by_stage(self) -> None:
        """After a stage call that did the deferred end-of-step work."""
        self._settled()

    def advance(self, mbs, t):
        """Post-step hook, before any other: complete the step's count and make its end-of-step work due (done
        now unless it can wait for the next stage: see the class doc); a reduced canopy's air for the coming step."""
        if self.canopy is not None:
            self.canopy.update_air(t)
        self._step_done(self.memory.array, t)
        self.pending = True
        if self._settle_now:
            self.settle()

    def settle(self) -> None:
        """Do the due end-of-step work now, from the engine's current state (the end of the last step)."""
        if not self.pending:
            return
        stage, kernels = self.stage, self._kernels
        arguments = (self.layout, self.table_points, self.work.array, self.part, self.memory.array, self.record)
        if stage.fused is self:   # the end-of-step body states and the solve in one kernel call
            kernels[sp_settle_with_bodies](stage.coordinates(), stage.velocities(), stage.global_layout,
                                           stage.states, *arguments)
            stage.refreshed_now(self.memory.due_time)
        else:
            stage.refresh(self.memory.due_time)
            kernels[sp_settle](stage.states, *arguments)
        self._settled()

    def _settled(self) -> None:
        self.pending = False
        self._settles += 1
        if self._slot is not None:   # the sample taken after the step gets its values
            self._slot.append(self.record.copy())
            self._slot = None

    def finish(self) -> None:
        """After the solve: the last step's end-of-step work."""
        self.settle()

    def warm_up(self, step: float | None) -> None:
        """The run's step (s; None for adaptive steps) into the bookkeeping, the solve at the phase start, and each
        kernel's compiled code for the argument types the solver passes (``machine_code``; Exudyn passes the time as
        a float)."""
        stage, start = self.stage, float(self.model.phase.start)
        self.memory.run_step = step if step is not None else 0.0
        arguments = (stage.states, self.layout, self.table_points, self.work.array, self.part, self.memory.array)
        kernels = self._kernels
        kernels[sp_step_stage] = machine_code(sp_step_stage, *arguments, start)
        kernels[sp_settle] = machine_code(sp_settle, *arguments, self.record)
        kernels[step_done] = self._step_done = machine_code(step_done, self.memory.array, start)
        self._settle_now = stage.fused is not self or not self.DEFER
        if stage.fused is self:
            self._bind_fused(arguments, start)
        self.advance(None, start)
        self.settle()

    def _bind_fused(self, arguments: tuple, start: float) -> None:
        """The fused kernels' machine code for the coordinates' form the force item passes (``warm_up``)."""
        stage, kernels = self.stage, self._kernels
        q, q_t = array("d", stage.coordinates()), array("d", stage.velocities())   # as the force item passes them
        head = (q, q_t, stage.global_layout, stage.states, *arguments[1:], self.record)
        kernels[sp_settle_with_bodies] = machine_code(sp_settle_with_bodies, *head)
        # the node coordinates cross into the kernel as tuples where the compiled module has the kernel for their
        # length (a tuple of floats costs a tenth of a typed array to make and to pass), else as arrays
        rest = (stage.global_layout, *head[3:], stage.generalized, *stage.loads.parts)
        coordinates = tuple if has_machine_code(sp_step_stage_with_bodies, tuple(q), tuple(q_t), start, *rest) \
            else partial(array, "d")
        kernels[sp_step_stage_with_bodies] = machine_code(sp_step_stage_with_bodies, coordinates(q),
                                                          coordinates(q_t), start, *rest)
        self._coordinates = coordinates
        self.bind_stage_call()

    def relaxation_allowed(self, share: float, t: float) -> float:
        """The longest relaxation time (s) whose extra damping changes no taut line's tension by more than ``share``
        of it at the lines' stretch rates: (C + share T / r) / K per line, r the envelope of |de/dt| over the last
        RATE_MEMORY s (a rate that swings through zero counts at its swing's size), de/dt from the last solve's
        damping force (T - T_el) / C; inf where nothing stretches (a steady descent). ``t``: the time now (s)."""
        work = self.settled().work
        tension, elastic = work.tensions.tolist(), work.elastic.tolist()
        built = layout_damping(self.layout) if self._built_damping is None else self._built_damping
        damping = layout_damping(self.layout).tolist()
        fade = math.exp(-(t - self._rates_at) / RATE_MEMORY) if self._rates else 0.0
        self._rates_at = t
        rates, allowed = [], math.inf
        for i, (c, k) in enumerate(zip(built.tolist(), self.stiffness)):
            now = abs(tension[i] - elastic[i]) / damping[i] if tension[i] > 0.0 and damping[i] > 0.0 else 0.0
            rate = max(now, fade * self._rates[i]) if self._rates else now
            rates.append(rate)
            if rate > 0.0 and k > 0.0 and tension[i] > 0.0:
                allowed = min(allowed, (c + share * tension[i] / rate) / k)
        self._rates = rates
        return allowed

    def relax(self, relaxation_time: float) -> None:
        """Each line damped at least ``relaxation_time`` (s) times its stiffness from now on (the layout's damping
        column, which every kernel call reads): ``balance.relaxed_damping`` of the built lines' damping."""
        if len(self.system.lines) == 2:   # a pair in series: nothing to relax (``physics.lines.solve_series``)
            return
        if self._built_damping is None:
            self._built_damping = layout_damping(self.layout).copy()
        layout_damping(self.layout)[:] = relaxed_damping(self.stiffness, self._built_damping.tolist(),
                                                         relaxation_time)

    # -- what it reports ----------------------------------------------------------------------------------------------

    def settled(self) -> SPConfluence:
        """This confluence with the last step's end-of-step work done: every reader of ``end_of_step``, ``work``
        and ``memory`` goes through it (the work may be deferred: see the class doc)."""
        self.settle()
        return self

    def current(self) -> StageSolution:
        """The end-of-step solve as a ``StageSolution`` (made when first asked for after each step)."""
        self.settle()
        if self._solution_of != self._settles:
            vx, vy, vz, damping, kappa, taut = self.end_of_step
            self.solution = StageSolution((vx, vy, vz), damping, kappa, taut, self.work)
            self._solution_of = self._settles
        return self.solution

    def velocity(self):
        return self.settled().memory.end_velocity.tolist()

    def tension_reader(self, i: int):
        def tension():
            return self.settled().work.end_tensions[i]
        return tension

    def sample(self) -> list:
        """The sampled channels' values: a list holding a copy of the end-of-step record (``stepping._record``), or
        an empty one that the deferred end-of-step work fills."""
        if not self.pending:
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
        record = self.layout_of_record   # where each output is (``memory.Record``)
        outputs = [record.damping, record.kappa, record.taut]   # in the order of OUTPUTS

        def split(records):
            return ([records[:, record.position], records[:, record.velocity]] + [records[:, k] for k in outputs]
                    + [records[:, k] for k in record.tensions])
        self.model.add_channel_group(keys, self.sample, split)

    def acceleration(self):
        """Mean confluence acceleration over the last step (m/s^2), or None before the first step ends."""
        memory = self.settled().memory
        if memory.recorded < 2:
            return None
        return ((memory.newer - memory.older) / (memory.newer_time - memory.older_time)).tolist()

    def position(self) -> list:
        """The confluence position (m) at the end of the last step: the SP state; with a reduced canopy the state is
        its drag point, and the confluence is on the line to it (``canopy``)."""
        if self.canopy is not None:
            return self.canopy.position_of_confluence(self.settled().work)
        return self.settled().memory.position.tolist()

    def position_reader(self):
        return self.position

    def state_position(self) -> list:
        return self.position()

"""The singular-perturbation method (thesis chapter 3), its model and its confluence: the confluence velocity from the
line-force balance (Eq. 3.10), with the least confluence damping that keeps the solve conditioned (Eq. 3.13) while a
line is slack. The confluence position as three first-order states whose
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

import math
from array import array
from dataclasses import dataclass, replace
from functools import partial
from typing import NamedTuple

import numpy as np

from ..case.model import Case, ParachuteSystem
from ..engine.bodies import add_bodies
from ..engine.model import Model
from ..engine.reduced import ReducedConfluence
from ..engine.reduced_canopy import ReducedCanopy, bridle_first, reduced_canopy
from ..engine.state import ConfluenceChannel, ConfluenceState, MethodChannel, Phase, TensionChannel
from ..errors import InputError
from ..physics.compiled import has_machine_code, machine_code
from ..physics.linearization import (
    ILL_CONDITIONED,
    body_line_step_limit,
    crosswise_damping_ratio,
    damped_line_step_limit,
    sp_step_limit,
)
from ..physics.lines import pack_tables
from ..physics.singular_perturbation import (
    END_TENSION,
    LAYOUT_DAMPING,
    SLACK_RULES,
    SP_ORDERS,
    STAGE_COLUMNS,
    WORK_DIRECTION,
    WORK_ELASTIC,
    WORK_TAUT,
    WORK_TENSION,
    relaxed_damping,
)
from ..physics.sp_stepping import (
    DUE_TIME,
    MEMORY_ACCELERATION,
    MEMORY_CLOCK,
    MEMORY_DUE,
    MEMORY_END,
    MEMORY_END_SOLVE,
    MEMORY_GRAVITY,
    MEMORY_NEWER,
    MEMORY_NORMAL,
    MEMORY_OLDER,
    MEMORY_ORDER,
    MEMORY_POSITION,
    MEMORY_ROWS,
    MEMORY_RUN,
    MEMORY_SETTINGS,
    MEMORY_TIMES,
    MEMORY_V0,
    ORDER_RECORDED,
    RECORD_DAMPING,
    RECORD_KAPPA,
    RECORD_POSITION,
    RECORD_TAUT,
    RECORD_TENSIONS,
    RECORD_VELOCITY,
    RUN_STEP,
    SOLVED_DAMPING,
    SOLVED_KAPPA,
    SOLVED_TAUT,
    SOLVED_VELOCITY,
    TIME_NEWER,
    TIME_OLDER,
    record_size,
    sp_settle,
    sp_settle_with_bodies,
    sp_step_stage,
    sp_step_stage_with_bodies,
    step_done,
)
from ..registries.methods import OptionError
from .base import Method, StepLimit, line_arrays, line_constants, option_field

RATE_MEMORY = 2.0
"""s: the time over which a line's stretch-rate envelope fades (``SPConfluence.relaxation_allowed``): a pendulum's
period or two."""


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
    (``advance``); there is no pre-step call: the step size comes from the second stage's time. The step's
    bookkeeping (the stage count, the step's start and size, the end-of-step work due, the last end-of-step solve)
    lives in the confluence's memory array with its states (``physics.sp_stepping.MEMORY_ROWS``), so a
    stage's call passes only the time and the stage's node coordinates into one compiled kernel.

    The end-of-step work (the RK4 update of the confluence position, the solve at the end-of-step state, v0 and
    order 1's record: ``sp_end_of_step``) is due after every step. When this is the model's only confluence
    (``Stage.fused``) it is deferred to the next step's first stage, whose state is the same and whose force call
    hands over the coordinates: one kernel call does it and that stage's solve (``sp_step_stage_with_bodies``),
    with no engine read. Anything that needs it sooner (a channel reader, the touchdown check, the step monitor, the
    end of the run) settles it at once from the engine (``settle``); the outputs sampled after a step are a slot
    the deferred work fills. Otherwise ``advance`` settles at once. The kernels are called through their compiled
    code (``physics.compiled.machine_code``)."""

    OUTPUTS = {"confluence_damping": ("N s/m", lambda c: c.settled().end_of_step[SOLVED_DAMPING]),
               "condition_number": ("-", lambda c: c.settled().end_of_step[SOLVED_KAPPA]),
               "taut_lines": ("-", lambda c: c.settled().end_of_step[SOLVED_TAUT])}
    """The method's channels: C_c, kappa and the lines counted taut of the end-of-step solve."""
    OUTPUT_RECORD = {"confluence_damping": RECORD_DAMPING, "condition_number": RECORD_KAPPA, "taut_lines": RECORD_TAUT}
    """Where each of OUTPUTS is in the end-of-step record (``physics.sp_stepping._record``)."""
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
        acceleration = state.acceleration
        memory = self.memory = np.zeros((MEMORY_ROWS, 3))   # physics.sp_stepping.MEMORY_ROWS
        memory[MEMORY_POSITION] = state.position
        memory[MEMORY_V0] = state.velocity                    # v0 of the first step: the state's velocity
        memory[MEMORY_SETTINGS] = (system.confluence.mass, self.kappa_max,
                                   1.0 if options.slack_rule == "force" else 0.0)
        mu, *vector = case.start.gravity_parameters()
        memory[MEMORY_ORDER], memory[MEMORY_GRAVITY] = (float(self.order), mu, 0.0), vector
        normal = case.start.normal_gravity_parameters()
        if normal is not None:   # physics.sp_stepping.confluence_gravity
            memory[MEMORY_NORMAL:MEMORY_NORMAL + 4] = np.reshape(normal, (4, 3))
        memory[MEMORY_ACCELERATION] = (0.0, 0.0, 0.0) if acceleration is None else acceleration
        memory[MEMORY_CLOCK] = (0.0, float(self.step_start), 0.0)   # no stage yet; t_n the phase start; h unknown
        memory[MEMORY_RUN] = (0.0, float(start_time), 0.0)           # the run's step is set by ``warm_up``
        self._slot = None         # the output sample waiting for the deferred end-of-step work
        self._settles = 0         # end-of-step solves so far (``current`` remakes its solution after each)
        self.record = np.zeros(record_size(model.stage.states, len(system.lines)))   # the outputs (``_record``)
        self._solution_of = -1    # the ``_settles`` count ``solution`` was made at
        self._kernels = {kernel: kernel for kernel in (sp_step_stage, sp_settle, sp_step_stage_with_bodies,
                                                       sp_settle_with_bodies, step_done)}
        self.stage_call = (None, (), None)   # the fused stage kernel, its arguments, its coordinates' form
        self._coordinates = None        # tuple or typed array: the coordinates' form (``warm_up``)
        self.pending = False   # whether the last step's end-of-step work is due: memory's MEMORY_DUE flag as Python
        #                        sees it (set by ``advance``, cleared by ``_settled`` whoever did the work)
        self._step_done = self._kernels[step_done]   # its machine code from ``warm_up`` on
        self._settle_now = True                      # whether ``advance`` does the work at once (``warm_up``)
        self._built_damping = None                   # the lines' damping as built, once ``relax`` changes it
        self._rates, self._rates_at = [], 0.0        # the lines' stretch-rate envelope (``relaxation_allowed``)
        name = reduced_canopy(case, system)
        self.canopy = None if name is None else ReducedCanopy(model, case, system, name, memory)

    # -- the solver's calls -------------------------------------------------------------------------------------------

    @property
    def end_of_step(self) -> tuple:
        """The last end-of-step solve's (vx, vy, vz in m/s, C_c in N s/m, kappa, lines counted taut)."""
        vx, vy, vz = self.memory[MEMORY_END].tolist()
        damping, kappa, taut = self.memory[MEMORY_END_SOLVE].tolist()
        return vx, vy, vz, damping, kappa, int(taut)

    def stage_solve(self, t: float) -> None:
        """The compiled SP solve at the current RK stage (``sp_step_stage``), the stage's body states already set."""
        self._kernels[sp_step_stage](self.stage.states, self.layout, self.table_points, self.work, self.part,
                                     self.memory, t)

    def bind_stage_call(self) -> None:
        """Set ``stage_call`` = (the fused stage kernel, its arguments after the node coordinates and the time, the
        form the coordinates take: tuple or typed array): the stage force item calls ``kernel(form(q), form(q_t), t,
        *arguments)``; a return of 1 or 3 says it did the deferred end-of-step work (``settled_by_stage``). Again
        whenever the aerodynamics' arguments change (a turbulence field grown)."""
        stage = self.stage
        arguments = (stage.layout, stage.states, self.layout, self.table_points, self.work, self.part, self.memory,
                     self.record, stage.generalized, *stage.loads.parts)
        self.stage_call = (self._kernels[sp_step_stage_with_bodies], arguments, self._coordinates)

    def settled_by_stage(self) -> None:
        """After a stage call that did the deferred end-of-step work."""
        self._settled()

    def advance(self, mbs, t):
        """Post-step hook, before any other: complete the step's count and make its end-of-step work due (done
        now unless it can wait for the next stage: see the class doc); a reduced canopy's air for the coming step."""
        if self.canopy is not None:
            self.canopy.update_air(t)
        self._step_done(self.memory, t)
        self.pending = True
        if self._settle_now:
            self.settle()

    def settle(self) -> None:
        """Do the due end-of-step work now, from the engine's current state (the end of the last step)."""
        if not self.pending:
            return
        memory = self.memory
        stage, kernels = self.stage, self._kernels
        if stage.fused is self:   # the end-of-step body states and the solve in one kernel call
            kernels[sp_settle_with_bodies](stage.coordinates(), stage.velocities(), stage.global_layout,
                                           stage.states, self.layout, self.table_points, self.work, self.part,
                                           memory, self.record)
            stage.refreshed_now(float(memory[MEMORY_DUE, DUE_TIME]))
        else:
            stage.refresh(float(memory[MEMORY_DUE, DUE_TIME]))
            kernels[sp_settle](stage.states, self.layout, self.table_points, self.work, self.part, memory,
                               self.record)
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

    def warm_up(self) -> None:
        """The run's step into the bookkeeping, the solve at the phase start, and each kernel's compiled code for
        the argument types the solver passes (``machine_code``; Exudyn passes the time as a float)."""
        stage, start = self.stage, float(self.model.phase.start)
        self.memory[MEMORY_RUN, RUN_STEP] = self.model.step if self.model.step is not None else 0.0
        arguments = (stage.states, self.layout, self.table_points, self.work, self.part, self.memory)
        kernels = self._kernels
        kernels[sp_step_stage] = machine_code(sp_step_stage, *arguments, start)
        kernels[sp_settle] = machine_code(sp_settle, *arguments, self.record)
        kernels[step_done] = self._step_done = machine_code(step_done, self.memory, start)
        self._settle_now = stage.fused is not self or not self.DEFER
        if stage.fused is self:
            q, q_t = array("d", stage.coordinates()), array("d", stage.velocities())   # as the force item passes them
            head = (q, q_t, stage.global_layout, stage.states, *arguments[1:], self.record)
            kernels[sp_settle_with_bodies] = machine_code(sp_settle_with_bodies, *head)
            # the node coordinates cross into the kernel as tuples where the compiled module has the kernel for
            # their length (a tuple of floats costs a tenth of a typed array to make and to pass), else as arrays
            rest = (stage.global_layout, *head[3:], stage.generalized, *stage.loads.parts)
            coordinates = tuple if has_machine_code(sp_step_stage_with_bodies, tuple(q), tuple(q_t), start, *rest) \
                else partial(array, "d")
            kernels[sp_step_stage_with_bodies] = machine_code(sp_step_stage_with_bodies, coordinates(q),
                                                              coordinates(q_t), start, *rest)
            self._coordinates = coordinates
            self.bind_stage_call()
        self.advance(None, start)
        self.settle()

    def relaxation_allowed(self, share: float, t: float) -> float:
        """The longest relaxation time (s) whose extra damping changes no taut line's tension by more than ``share``
        of it at the lines' stretch rates: (C + share T / r) / K per line, r the envelope of |de/dt| over the last
        RATE_MEMORY s (a rate that swings through zero counts at its swing's size), de/dt from the last solve's
        damping force (T - T_el) / C; inf where nothing stretches (a steady descent). ``t``: the time now (s)."""
        work = self.settled().work
        tension, elastic = work[:, WORK_TENSION].tolist(), work[:, WORK_ELASTIC].tolist()
        built = self.layout[:, LAYOUT_DAMPING] if self._built_damping is None else self._built_damping
        damping = self.layout[:, LAYOUT_DAMPING].tolist()
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
        column, which every kernel call reads): ``physics.singular_perturbation.relaxed_damping`` of the built
        lines' damping."""
        if len(self.system.lines) == 2:   # a pair in series: nothing to relax (``solve_series``)
            return
        if self._built_damping is None:
            self._built_damping = self.layout[:, LAYOUT_DAMPING].copy()
        self.layout[:, LAYOUT_DAMPING] = relaxed_damping(self.stiffness, self._built_damping.tolist(),
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
            end, v = self.end_of_step, SOLVED_VELOCITY
            self.solution = StageSolution(end[v:v + 3], end[SOLVED_DAMPING], end[SOLVED_KAPPA], end[SOLVED_TAUT],
                                          self.work)
            self._solution_of = self._settles
        return self.solution

    def velocity(self):
        return self.settled().end_of_step[SOLVED_VELOCITY:SOLVED_VELOCITY + 3]

    def tension_reader(self, i: int):
        def tension():
            return self.settled().work[i, END_TENSION]
        return tension

    def sample(self) -> list:
        """The sampled channels' values: a list holding a copy of the end-of-step record (``_record``), or an empty
        one that the deferred end-of-step work fills."""
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

        first = self.stage.states.size   # the record after the body states (``physics.sp_stepping._record``)
        p, v, t = first + RECORD_POSITION, first + RECORD_VELOCITY, first + RECORD_TENSIONS
        outputs = [first + self.OUTPUT_RECORD[output] for output in self.OUTPUTS]

        def split(records):
            return ([records[:, p:p + 3], records[:, v:v + 3]] + [records[:, k] for k in outputs]
                    + [records[:, t + i] for i in range(len(self.system.lines))])
        self.model.add_channel_group(keys, self.sample, split)

    def acceleration(self):
        """Mean confluence acceleration over the last step (m/s^2), or None before the first step ends."""
        memory = self.settled().memory
        if memory[MEMORY_ORDER, ORDER_RECORDED] < 2:
            return None
        return ((memory[MEMORY_NEWER] - memory[MEMORY_OLDER])
                / (memory[MEMORY_TIMES, TIME_NEWER] - memory[MEMORY_TIMES, TIME_OLDER])).tolist()

    def position(self) -> list:
        """The confluence position (m) at the end of the last step: the SP state; with a reduced canopy the state is
        its drag point, and the confluence is on the line to it (``engine.reduced_canopy``)."""
        if self.canopy is not None:
            return self.canopy.position_of_confluence(self.settled().work)
        return self.settled().memory[MEMORY_POSITION].tolist()

    def step_limit(self, step: float) -> float | None:
        """A reduced canopy's drag point's RK4 limit (s) at a step ``step`` (s), for adaptive steps; None without."""
        return None if self.canopy is None else self.canopy.step_limit(self.settled().work, step)

    def position_reader(self):
        return self.position

    def state_position(self) -> list:
        return self.position()


def build_sp_model(case: Case, phase: Phase, options) -> Model:
    """Build the SP Exudyn model of ``case`` for one phase (bodies and aerodynamics as in the full model) with the
    SP method's ``options``; order 1 keeps the confluence mass to first order (``physics.singular_perturbation``)."""
    model = Model(case, phase)
    canopies = {system.name: reduced_canopy(case, system) for system in model.systems}
    add_bodies(model, case, reduced=True, massless={name for name in canopies.values() if name is not None})
    for system in model.systems:
        if canopies[system.name] is not None:
            system = bridle_first(system)
        sp = SPConfluence(model, case, system, phase.confluence_states[system.name], options, phase.start)
        sp.register(case)
    return model.assemble()


PRESETS = {"accurate": {"kappa_max": 10.0, "order": 1, "relaxation_time": 0.0},
           "thesis": {"kappa_max": 5.0, "order": 0, "relaxation_time": 0.0},
           "any_damping": {"kappa_max": 10.0, "order": 1, "relaxation_time": 5e-3}}
"""SP presets: kappa_max, the confluence-mass order and the relaxation time they stand for. ``thesis``: the thesis's
settings (Eq. 3.10, kappa_max = 5). ``accurate`` (the default): the confluence mass to first order, which removes the
error of the massless balance where the confluence swings with a body (MER cases 5-6, PA1's rocking capsule), and
kappa_max = 10, which halves the artificial confluence damping while a line is slack (MER cases 3-4): at most 1.3 N
of tension error after 2 s in every MER case at 1e-2 s, against 82 N with the thesis's settings, at the same cost
(validation/output/benchmark_sp.md). kappa_max = 20 is as accurate at 1e-2 s but not at 2e-2 s. ``any_damping``:
accurate's settings with a relaxation time of 5e-3 s, half the thesis's step: every line is damped at least tau K in
the solve (``relaxed``), so RK4 at 1e-2 s is stable for any line damping, none included (docs/models/any_damping.md)."""


RELAXED_BODY_MARGIN = 2.0
"""A fixed step may be up to this many times the RK4 limit of the bodies' motion on the relaxed lines
(``SingularPerturbation.check_step``): that estimate (the bodies pulled against each other through every line of a
system in series, damped tau K) is pessimistic; the runs diverged at about 3 times it (MER case 1 at 1e-2 s between
tau = 0.2 and 0.4 s, PA1 between 0.3 and 0.5 s)."""


RELAXED_STEPS = 1.5
"""An adaptive step over the relaxation time it asks for (``SingularPerturbation.relaxation_for_step``): RK4 is
stable on the real mode -1/tau up to 2.785 tau: 1.86 such steps, a margin for the sideways stiffness of stretched
lines (the mode of a loaded MER or pchute new confluence runs up to 1.5 times faster than -1/tau) and the grid of
tau (9 %). More relaxation (a smaller ratio) makes a light body's mode on its damped lines faster (tau K / m) and
changes the lines' tensions more: at 1.35 a canopy under a 100 kg vehicle on three bridles was left bouncing by
7.5 % of its riser's load in a steady descent (``tests/integration/test_step_control.py``)."""


@dataclass(frozen=True)
class SPOptions:
    """Options of the SP method (``[simulation.sp]`` in a case file).

    Attributes
    ----------
    preset : {"accurate", "thesis"}
        The kappa_max and order to use where they are not given (``PRESETS``).
    kappa_max : float or None
        Largest condition number of alpha (Eq. 3.13) accepted while a line is slack (-, > 3; the thesis used 5);
        None: the preset's.
    slack_rule : {"stretch", "force"}
        stretch: a line is slack when L <= L0 (the thesis); force: also when its tension would push (active set).
    order : {0, 1} or None
        Order in the confluence mass: 0 drops it (Eq. 3.10, the thesis), 1 keeps its weight and inertia to first
        order; None: the preset's.
    """

    preset: str = option_field("accurate", "--sp-preset", str, "kappa_max, order and relaxation time unless given: "
                               "thesis = 5, 0, 0 (the thesis's settings), accurate = 10, 1, 0 (the default), "
                               "any_damping = 10, 1, 5 ms (any line damping, none included)", tuple(PRESETS))
    kappa_max: float | None = option_field(None, "--kappa-max", float, "largest condition number of alpha (thesis "
                                           "Eq. 3.13) while a line is slack, > 3 (default: the preset's)")
    slack_rule: str = option_field("stretch", "--slack-rule", str, "when a line counts as slack: stretch = L <= L0 "
                                   "(the thesis), force = its tension would push (active set)", SLACK_RULES)
    order: int | None = option_field(None, "--sp-order", int, "0 = massless confluence (Eq. 3.10, the thesis), 1 = "
                                     "its weight and inertia kept to first order (default: the preset's)", SP_ORDERS)
    relaxation_time: float | None = option_field(None, "--sp-relaxation-time", float, "tau (s, 0 to 1): each line is "
                                                 "damped at least tau K, so the confluence relaxes no faster than "
                                                 "1/tau; RK4 is stable up to a step of about 2.5 tau for any line "
                                                 "damping (default: the preset's; 0 = off)")

    def __post_init__(self):
        if self.preset not in PRESETS:
            raise OptionError("preset", self.preset, f"must be one of: {', '.join(PRESETS)}")
        kappa = self.kappa_max
        if kappa is not None:
            if isinstance(kappa, bool) or not isinstance(kappa, (int, float)) or \
                    not (math.isfinite(kappa) and kappa > 3):
                raise OptionError("kappa_max", kappa, "must be > 3 (the Frobenius condition number of Eq. 3.13 "
                                                      "is at least 3 for any 3x3 matrix; the thesis used 5)")
            object.__setattr__(self, "kappa_max", float(kappa))
        if self.slack_rule not in SLACK_RULES:
            raise OptionError("slack_rule", self.slack_rule, f"must be one of: {', '.join(SLACK_RULES)}")
        tau = self.relaxation_time
        if tau is not None:
            if isinstance(tau, bool) or not isinstance(tau, (int, float)) or not (math.isfinite(tau) and 0 <= tau <= 1):
                raise OptionError("relaxation_time", tau, "must be within 0..1 (s): the confluence's slowest allowed "
                                                          "relaxation (0 = off)")
            object.__setattr__(self, "relaxation_time", float(tau))
        if self.order is not None:
            if isinstance(self.order, bool) or self.order not in SP_ORDERS:
                raise OptionError("order", self.order, "must be 0 (the massless balance of Eq. 3.10, the thesis) or "
                                                       "1 (the confluence mass kept to first order)")
            object.__setattr__(self, "order", int(self.order))

    @property
    def effective_kappa_max(self) -> float:
        """kappa_max in effect (-): the given one, else the preset's."""
        return PRESETS[self.preset]["kappa_max"] if self.kappa_max is None else self.kappa_max

    @property
    def effective_order(self) -> int:
        """The confluence-mass order in effect: the given one, else the preset's."""
        return PRESETS[self.preset]["order"] if self.order is None else self.order

    @property
    def effective_relaxation_time(self) -> float:
        """The relaxation time in effect (s): the given one, else the preset's."""
        return PRESETS[self.preset]["relaxation_time"] if self.relaxation_time is None else self.relaxation_time

    def summary(self) -> dict:
        tau = self.effective_relaxation_time   # only when on: summaries of runs without it keep their keys
        return {"sp_preset": self.preset, "kappa_max": self.effective_kappa_max, "slack_rule": self.slack_rule,
                "sp_order": self.effective_order, **({"sp_relaxation_time": tau} if tau > 0.0 else {})}


class SingularPerturbation(Method):
    """The confluence's position integrated in step with the engine's RK4 stages (``physics.sp_stepping``) inside the
    bodies' force item; RK4 only: an implicit solver evaluates the forces at Newton iterates and for its Jacobian,
    not at RK stages."""

    name = "sp"
    summary = "singular perturbation: the confluence velocity from the line-force balance (thesis ch. 3)"
    step_limited = True
    record_variants = ({"order": 0}, {"order": 1}, {"slack_rule": "force"})
    integrator_note = ("its confluence is integrated in step with RK4's four stages, which an implicit solver's "
                       "Newton iterations do not follow; use rk4 (--dt auto for adaptive steps), or --method full "
                       "with implicit")
    Options = SPOptions
    outputs = {name: unit for name, (unit, _) in SPConfluence.OUTPUTS.items()}

    def relaxed(self, system, relaxation_time: float = 0.0):
        """``system`` as the solve sees it: each line damped at least tau K (``physics.singular_perturbation.
        relaxed_damping``), tau the larger of the options' relaxation time and ``relaxation_time`` (s, an adaptive
        step's: ``relaxation_for_step``); itself without one."""
        tau = max(self.options.effective_relaxation_time, relaxation_time)
        if tau <= 0.0:
            return system
        stiffness, damping = line_constants(system)
        floors = relaxed_damping(stiffness, damping, tau)
        return replace(system, lines=tuple(replace(line, damping=c) for line, c in zip(system.lines, floors)))

    def relaxation_for_step(self, step: float, system) -> float:
        """At an adaptive step ``step`` (s) the lines are damped at least tau K with tau = step / RELAXED_STEPS
        beyond the options' own relaxation time (docs/models/step_control.md): the confluence's damped mode, rate K / C
        (Eq. 3.10 linearised), then never limits RK4 below 1.86 steps, and a line already damped more is as it is.
        Steps that long are taken only where the motion is smooth, where the lines stretch slowly. A pair in series
        has no confluence mode and is not relaxed. tau is rounded down to a grid of eighth octaves, so that the
        lines' damping changes only when the step has changed by 9 %. A cluster's lines are not relaxed either: its
        canopies' flyout and breathing keep them stretching, and damping them more changes how the canopies share
        the load (on ``pchute new``'s three-canopy Mars cluster the tensions left their steady values by 9 % within
        10 s with relaxed lines, by 2.3 % at a fixed 0.01 s and without relaxation)."""
        if len(system.lines) == 2:
            return 0.0
        if len(system.canopies) > 1:
            return self.options.effective_relaxation_time
        tau = step / RELAXED_STEPS   # on a grid of eighth octaves, rounded down: it changes only every 9 %
        tau = 2.0 ** (math.floor(8.0 * math.log2(tau)) / 8.0) if tau > 0.0 else 0.0
        return max(self.options.effective_relaxation_time, tau)

    def check(self, case, integrator):
        super().check(case, integrator)
        if not case.free_bodies():
            raise InputError("the sp method moves the confluence inside the moving bodies' force item, and every body "
                             "of this case is fixed (the chapter 2 system): use --method full or equilibrium")
        if self.options.effective_relaxation_time > 0.0:
            return
        undamped = [case.line_label(system, line) for system, line in case.lines() if line.damping <= 0.0]
        if undamped:
            every = "every line" if len(undamped) == len(case.lines()) else f"line(s) {', '.join(undamped)}"
            raise InputError(f"the sp method needs damping on every line, but {every} has zero damping: alpha of "
                             "Eq. 3.6 is built from the line damping and is singular whenever only undamped lines are "
                             "taut; use --sp-preset any_damping (a relaxation time), or --method full")

    def check_step(self, case, step: float) -> None:
        """Refuse a fixed step (s) that the relaxation time makes unstable: tau K on every line moves the bodies
        against each other at a rate (C over their reduced mass, ``body_line_step_limit``) that rises with tau."""
        tau = self.options.effective_relaxation_time
        if tau <= 0.0:
            return
        for system in case.systems.values():
            by_body = {}
            for line, k, c in zip(system.lines, *line_constants(self.relaxed(system))):
                total = by_body.setdefault(line.body, [0.0, 0.0])
                total[0], total[1] = total[0] + k, total[1] + c
            masses = [case.bodies[b].mass for b in by_body if not case.bodies[b].fixed]
            if len(by_body) < 2 or not masses or min(sum(t) for t in by_body.values()) <= 0.0:
                continue
            series = [1.0 / sum(1.0 / t[i] for t in by_body.values()) if all(t[i] > 0 for t in by_body.values())
                      else 0.0 for i in (0, 1)]
            mass = 1.0 / sum(1.0 / m for m in masses)
            limit = body_line_step_limit(mass, [series[0]], [series[1]])
            if step > RELAXED_BODY_MARGIN * limit:
                allowed = tau * RELAXED_BODY_MARGIN * limit / step
                raise InputError(f"sp relaxation time (--sp-relaxation-time) = {tau:g} s: its damping tau K moves "
                                 f"the {system.name} system's bodies against each other at up to "
                                 f"{series[1] / mass:.3g} 1/s, too fast for the RK4 step {step:g} s (limit "
                                 f"{limit:.3g} s): use at most {float(f'{allowed:.2g}'):g} s (any_damping's "
                                 f"{PRESETS['any_damping']['relaxation_time']:g} s), or --dt "
                                 f"{float(f'{0.9 * RELAXED_BODY_MARGIN * limit:.2g}'):g}")

    def build(self, case, phase):
        if self.options.effective_relaxation_time > 0.0:
            case = replace(case, systems={name: self.relaxed(system) for name, system in case.systems.items()})
        return build_sp_model(case, phase, self.options)

    def step_limit(self, system, attach_position, confluence_position) -> StepLimit:
        if len(system.lines) == 2:   # a pair in series has no confluence mode (``solve_series``)
            return StepLimit(system.name, math.inf, complex(0.0))
        mass = system.confluence.mass if self.options.effective_order == 1 else 0.0
        lines = line_arrays(self.relaxed(system), attach_position, confluence_position)
        step, eigenvalue = sp_step_limit(attach_position, confluence_position, *lines, mass=mass,
                                         kappa_max=self.options.effective_kappa_max)
        return StepLimit(system.name, step, eigenvalue, self._cause(system, step, attach_position,
                                                                    confluence_position, lines))

    def _cause(self, system, step, attach_position, confluence_position, lines) -> str:
        """What makes a short limit short, and its remedy (``StepLimit.cause``): lines nearly collinear or in one
        plane under the massless preset, or lines damped too little for the step."""
        if step >= 1e-2:
            return ""
        ratio = crosswise_damping_ratio(attach_position, confluence_position, *lines)
        if ratio < ILL_CONDITIONED and self.options.effective_order == 0:
            return (f"The {system.name} system's lines are nearly collinear or in one plane (the damping across them "
                    f"is {ratio:.2g} of that along them), and the massless balance of the {self.options.preset} "
                    "preset has almost none there: use --sp-preset accurate (the confluence's mass to first order "
                    "damps it), or --method equilibrium")
        rates = [k / c for k, c in zip(lines[1], lines[2]) if c > 0.0]
        if rates and step <= 1.2 * 2.785 / max(rates) and self.options.effective_relaxation_time <= 0.0:
            return (f"The {system.name} system's lines are damped too little for the step (K/C up to "
                    f"{max(rates):.3g} 1/s): use --sp-preset any_damping (a relaxation time), or --dt auto "
                    "(adaptive steps)")
        return self._relaxed_remedy(system, step, attach_position, confluence_position)

    def _relaxed_remedy(self, system, step, attach_position, confluence_position) -> str:
        """The any_damping preset as the remedy of a limit (s) below 1e-2 s that it lifts to 1e-2 s or more (its
        design step) without a relaxation time in effect; "" otherwise."""
        if self.options.effective_relaxation_time > 0.0:
            return ""
        preset = PRESETS["any_damping"]
        lines = line_arrays(self.relaxed(system, preset["relaxation_time"]), attach_position, confluence_position)
        relaxed, _ = sp_step_limit(attach_position, confluence_position, *lines, mass=system.confluence.mass,
                                   kappa_max=preset["kappa_max"])
        if not relaxed >= 1e-2:
            return ""
        return (f"The {system.name} system's lines are damped too little for the step: use --sp-preset any_damping "
                f"(a relaxation time; its limit here: {relaxed:.3g} s), or --dt auto (adaptive steps)")

    def lumped_step_limit(self, system) -> float:
        if len(system.lines) == 2:
            return math.inf
        return damped_line_step_limit(*line_constants(self.relaxed(system)))

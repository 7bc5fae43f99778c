"""A massless confluence in the model's stage: the common part of the SP and equilibrium-point methods.

Each solver stage, the model's stage force item (``engine.stage``) hands every reduced confluence the stage's body
states (from the item's own arguments: no engine read) and the confluence solves its method there, writing the line
forces on the bodies as a generalized-force part: one crossing from the engine into Python per stage for the whole
model. A confluence with states of its own (SP: the confluence position) integrates them itself, with the classical
RK4 tableau in step with Exudyn's RK44 stages (stage k sits at t_n + c_k h with c = 0, 1/2, 1/2, 1): its stage
coordinates are q_n + h a_k k_(k-1) and its step q_(n+1) = q_n + h (k_1 + 2 k_2 + 2 k_3 + k_4) / 6, exactly what
Exudyn does with first-order (ODE1) coordinates, without the ODE1 right-hand side's own crossing and its two engine
reads of the body state at every stage (issue 14: a third of an SP step). The post-step hook completes the step and
solves once at the end-of-step state, which the outputs and the next step's first stage reuse.

Only RK4 drives these confluences (the methods refuse the implicit integrator, whose Newton iterations are not
stages).
"""

from __future__ import annotations

from functools import partial

import numpy as np

from ..case.model import Case, ParachuteSystem
from ..physics.compiled import bound
from ..physics.kinematics import add_point_forces, point_motions
from ..physics.rk4 import RK4_STAGE_FRACTIONS, RK4_WEIGHTS
from .phase_model import Confluence, Model
from .state import ConfluenceChannel, MethodChannel, TensionChannel


def step_size(step: float | None, span: float) -> float:
    """The step (s) Exudyn takes over ``span`` (the coming step's end time minus its start): the run's own ``step``
    (s; None for adaptive steps), unless the span is another (the short last step its accumulated time can need)."""
    return step if step is not None and abs(span - step) <= 1e-6 * step else span


class ReducedConfluence(Confluence):
    """Base class: subclasses implement ``compute(t, q, positions, velocities)`` returning a solution with
    ``velocity``, ``tensions`` and ``directions``, and ``derivative(solution)`` for their own states q (none for the
    equilibrium point); ``OUTPUTS`` names the quantities they report per system (name -> (unit, function of the
    confluence)). A subclass with a compiled stage kernel overrides ``solve_stage`` instead of ``compute``."""

    OUTPUTS: dict = {}
    PRE_STEP = True
    """Whether the confluence needs the solver's pre-step call (``new_step``)."""

    def __init__(self, model: Model, case: Case, system: ParachuteSystem, initial_states: list):
        """``initial_states``: the confluence's own coordinates at the phase start (empty: none)."""
        self.model, self.system = model, system
        self.laws = [line.law for line in system.lines]   # physics.lines.LineLaw: the one line law
        self.free_length = [law.free_length for law in self.laws]
        self.stiffness = [law.stiffness for law in self.laws]
        self.damping = [law.damping for law in self.laws]
        self.stage = model.stage
        self.points = model.stage.points([(line.body, case.bodies[line.body].points[line.point])
                                          for line in system.lines])
        self.part = model.stage.add_part()                  # the lines' generalized forces on the bodies
        self.attach_motion = np.zeros((len(system.lines), 6))
        self.line_forces = np.zeros((len(system.lines), 3))
        self._point_motions, self._add_point_forces = bound(point_motions), bound(add_point_forces)   # every stage
        self.coordinates = [float(x) for x in initial_states]   # q_n, at the start of the step under way
        self.step_start = model.phase.start                     # t_n (s)
        self.step_size = 0.0                                    # h (s) of the step under way
        self.slopes: list = []                                  # the derivatives of its stages so far
        self.solution = None                                    # the solve at the last end of step
        self.run_step = None                                    # s: the run's fixed step (``warm_up``)
        model.stage.add_confluence(self)

    def compute(self, t, q, positions, velocities):  # pragma: no cover - interface
        raise NotImplementedError

    def derivative(self, solution) -> list:  # pragma: no cover - interface
        raise NotImplementedError

    def register(self, case: Case) -> None:
        """Hook this confluence into the solver's per-step work and the model's channels."""
        if self.PRE_STEP:
            self.model.add_pre_step(self.new_step)
        self.model.add_post_step(self.advance, first=True)
        self.model.confluences[self.system.name] = self
        self.add_channels(case)

    def new_step(self, mbs, t):
        """Pre-step hook (``t``: the end time of the coming step)."""
        self.slopes = []
        self.step_size = step_size(self.run_step, t - self.step_start)

    def stage_solve(self, t: float) -> None:
        """The solve at the current RK stage (called by the stage force item, the body states already current)."""
        index = len(self.slopes)
        if index == 0 and self.solution is not None and self.reusable(self.solution):
            solution = self.solution   # stage 1 is the end-of-step state solved by ``advance``; its part stands
        else:
            q = self.coordinates
            if 0 < index < 4:
                step = self.step_size * RK4_STAGE_FRACTIONS[index]
                q = [x + step * k for x, k in zip(q, self.slopes[-1])]
            solution = self.solve_stage(t, q)
        if index < 4:
            self.slopes.append(self.derivative(solution))

    def advance(self, mbs, t):
        """Post-step hook, before any other: complete the step's RK4 update of the confluence's own coordinates and
        solve at the end-of-step state (the stage's body states read from the engine: ``Stage.refresh``)."""
        if len(self.slopes) == 4:
            coordinates = self.coordinates
            for weight, slope in zip(RK4_WEIGHTS, self.slopes):   # (h b_j) k_j term by term, as Exudyn adds them
                factor = self.step_size * weight
                coordinates = [x + factor * k for x, k in zip(coordinates, slope)]
            self.coordinates = coordinates
            self.step_start = t
        self.slopes = []
        self.stage.refresh(t)
        self.solution = self.solve_stage(t, self.coordinates)

    def solve_stage(self, t, q):
        """The method's solve on the stage's body states: attach points, ``compute``, the forces -T n on the
        bodies into ``part``."""
        states, motion = self.stage.states, self.attach_motion
        self._point_motions(states, self.points, motion)
        solution = self.compute(t, q, motion[:, :3].tolist(), motion[:, 3:].tolist())
        forces = self.line_forces
        for i, (t_i, (nx, ny, nz)) in enumerate(zip(solution.tensions, solution.directions)):
            forces[i] = -t_i * nx, -t_i * ny, -t_i * nz   # on the body: -T n
        self.part.fill(0.0)
        self._add_point_forces(states, self.points, forces, self.part)
        return solution

    def acceleration(self):
        """Confluence acceleration (m/s^2) to carry into the next phase, or None (the method keeps none)."""
        return None

    def reusable(self, solution) -> bool:
        """Whether ``solution`` holds for the same state in the next step too (it does not depend on anything the
        method updates between steps); subclasses refine this."""
        return True

    def current(self):
        """The solution at the end of the last step (made by ``advance`` before any other post-step work)."""
        return self.solution

    def warm_up(self, step: float | None) -> None:
        """The run's fixed step (s; None for adaptive steps) and the solve at the phase start (the first post-step
        call, before any step, repeats it)."""
        self.run_step = step
        self.advance(None, self.model.phase.start)

    def position(self) -> list:
        return self.current().position

    def position_reader(self):
        """The position channel's reader (a subclass may serve it more directly)."""
        return self.position

    def velocity(self) -> list:
        return self.current().velocity

    def tension_reader(self, i: int):
        """The reader of line ``i``'s tension channel (N)."""
        return lambda: self.current().tensions[i]

    def add_channels(self, case: Case) -> None:
        """Output channels: confluence position and velocity, the line tensions and the method's ``OUTPUTS``."""
        name = self.system.name
        self.model.add_channel(ConfluenceChannel(name, "position"), self.position_reader())
        self.model.add_channel(ConfluenceChannel(name, "velocity"), self.velocity)
        for i, line in enumerate(self.system.lines):
            self.model.add_channel(TensionChannel(name, line.name), self.tension_reader(i))
        for output, (unit, value) in self.OUTPUTS.items():
            self.model.add_channel(MethodChannel(name, output, unit), partial(value, self))

"""A massless confluence as Exudyn items: the common part of the SP and equilibrium-point methods.

The confluence's state is a ``NodeGenericODE1`` with an ``ObjectGenericODE1`` whose right-hand side solves the method
(SP: its three coordinates are the confluence position and the right-hand side its velocity; equilibrium point: one
dummy coordinate with zero derivative, there only so that the solve runs once per stage). The line forces reach the
bodies as a generalized-force part of the model's stage (``engine.stage``). Exudyn's RK44 evaluates, in every stage,
the ODE1 right-hand side before the ODE2 forces, so the right-hand side solves once (on the stage's body states) and
the stage's force item hands out its forces; after the last stage it evaluates the right-hand side once more at the
end-of-step state, which the post-step work and the output sampling reuse (recomputing if the state differs).
"""

from __future__ import annotations

from functools import partial

import exudyn.itemInterface as eii
import numpy as np

from ..case.model import Case, ParachuteSystem
from ..physics.kinematics import add_point_forces, point_motions
from ..state import ConfluenceChannel, MethodChannel, TensionChannel
from .model import CURRENT, OV, Confluence, Model


class ReducedConfluence(Confluence):
    """Base class: subclasses implement ``compute(t, q, positions, velocities)`` returning a solution with
    ``velocity``, ``tensions`` and ``directions``, and ``derivative(solution)`` for the ODE1 states; ``OUTPUTS``
    names the quantities they report per system (name -> (unit, function of the confluence)). A subclass with a
    compiled stage kernel overrides ``solve_stage`` instead of ``compute``."""

    OUTPUTS: dict = {}

    def __init__(self, model: Model, case: Case, system: ParachuteSystem, initial_states: list):
        """``initial_states``: the ODE1 coordinates at the phase start."""
        mbs = model.mbs
        self.model, self.system = model, system
        self.free_length = [line.free_length for line in system.lines]
        self.stiffness = [line.stiffness for line in system.lines]
        self.damping = [line.damping for line in system.lines]
        tables = [line.load_elongation for line in system.lines]
        self.tables = tables if any(table is not None for table in tables) else None   # None: the linear path
        self.stage = model.stage
        self.points = model.stage.points([(line.body, case.bodies[line.body].points[line.point])
                                          for line in system.lines])
        self.part = model.stage.add_part()                  # the lines' generalized forces on the bodies
        self.attach_motion = np.zeros((len(system.lines), 6))
        self.line_forces = np.zeros((len(system.lines), 3))
        self.node = mbs.AddNode(eii.NodeGenericODE1(referenceCoordinates=[0.0] * len(initial_states),
                                                    initialCoordinates=list(initial_states),
                                                    numberOfODE1Coordinates=len(initial_states)))
        mbs.AddObject(eii.ObjectGenericODE1(nodeNumbers=[self.node], rhsUserFunction=self._rhs))
        self.solution = None
        self.solved_at = None       # (t, q) of self.solution
        self.solved_at_end = False  # self.solution is at an end-of-step state (nothing has changed since)
        self.calls_in_step = 0      # right-hand-side calls since the step began
        self._checked = -1          # post-step call in which self.solution was last confirmed current
        self._get_node = mbs.GetNodeOutput
        self._get_time = mbs.systemData.GetTime

    def compute(self, t, q, positions, velocities):  # pragma: no cover - interface
        raise NotImplementedError

    def derivative(self, solution) -> list:  # pragma: no cover - interface
        raise NotImplementedError

    STAGES = 4
    """Right-hand-side calls per RK44 step; Exudyn makes one more at the end-of-step state."""

    def new_step(self, mbs, t):
        """Pre-step hook."""
        self.calls_in_step = 0

    def confirm(self, mbs, t):
        """Post-step hook, before any other: make the solution (and the stage's body states) current for the step's
        end.

        The right-hand side's last call in a step is at the end-of-step state and time, and nothing changes the state
        between it and this hook, so a solve marked ``at_end`` at time ``t`` is current without reading the state
        back (reading the ODE1 coordinates inside the solver costs several microseconds)."""
        if self.solved_at_end and self.solved_at[0] == t:
            self._checked = self.model.post_step_count[0]
        else:
            self.current()

    def register(self, case: Case) -> None:
        """Hook this confluence into the solver's per-step work and the model's channels."""
        self.model.add_pre_step(self.new_step)
        self.model.add_post_step(self.confirm, first=True)
        self.model.confluences[self.system.name] = self
        self.add_channels(case)

    def solve(self, t, q, at_end: bool = False):
        """Solve at the current stage's body states and ODE1 coordinates ``q``; writes the line forces, caches.
        ``at_end``: the state is an end-of-step one (post-step work, or the call after the last stage)."""
        self.stage.refresh()
        solution = self.solve_stage(t, q)
        self.solution, self.solved_at, self.solved_at_end = solution, (t, q), at_end
        return solution

    def solve_stage(self, t, q):
        """The method's solve on the stage's body states: attach points, ``compute``, the forces -T n on the
        bodies into ``part``."""
        states, motion = self.stage.states, self.attach_motion
        point_motions(states, self.points, motion)
        solution = self.compute(t, q, motion[:, :3].tolist(), motion[:, 3:].tolist())
        forces = self.line_forces
        for i, (t_i, (nx, ny, nz)) in enumerate(zip(solution.tensions, solution.directions)):
            forces[i] = -t_i * nx, -t_i * ny, -t_i * nz   # on the body: -T n
        self.part.fill(0.0)
        add_point_forces(states, self.points, forces, self.part)
        return solution

    def acceleration(self):
        """Confluence acceleration (m/s^2) to carry into the next phase, or None (the method keeps none)."""
        return None

    def reusable(self, solution) -> bool:
        """Whether ``solution`` holds for the same state in the next step too (it does not depend on anything the
        method updates between steps); subclasses refine this."""
        return True

    def _rhs(self, mbs, t, item, q):
        try:
            self.calls_in_step += 1   # q: a new list at every call (Exudyn converts the coordinates)
            # the first stage of a step sees exactly the end-of-step state solved last: reuse that solve
            if self.calls_in_step == 1 and self.solved_at_end and self.solved_at == (t, q) \
                    and self.reusable(self.solution):
                return self.derivative(self.solution)
            return self.derivative(self.solve(t, q, at_end=self.calls_in_step > self.STAGES))
        except Exception as exc:  # keep our own error for the solver to report
            self.model.record_failure(exc)
            raise

    def current(self):
        """The solution at the current (end-of-step) state, reusing the last right-hand side when it matches;
        checked once per post-step call (``model.post_step_count``), then served as it is."""
        if self._checked == self.model.post_step_count[0]:
            return self.solution
        t = self._get_time()
        q = np.atleast_1d(self._get_node(self.node, OV.Coordinates, CURRENT)).tolist()
        if not (self.solved_at_end and self.solved_at == (t, q)):
            self.stage.stale = True   # the state may differ from the last stage's
            self.solve(t, q, at_end=True)
        self._checked = self.model.post_step_count[0]
        return self.solution

    def warm_up(self) -> None:
        """A solve at the phase start (the first post-step call reuses it when the state matches)."""
        q = np.atleast_1d(self._get_node(self.node, OV.Coordinates, CURRENT)).tolist()
        self.stage.stale = True
        self.solve(self.model.phase.start, q, at_end=True)

    def current_coordinates(self) -> list:
        """The ODE1 coordinates of ``current()``'s solution."""
        self.current()
        return self.solved_at[1]

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

"""A massless confluence as Exudyn items: the common part of the SP and equilibrium-point methods.

The confluence's state is a ``NodeGenericODE1`` with an ``ObjectGenericODE1`` whose right-hand side solves the method
(SP: its three coordinates are the confluence position and the right-hand side its velocity; equilibrium point: one
dummy coordinate with zero derivative, there only so that the solve runs once per stage). The line forces reach the
bodies as loads at the attach points. Exudyn's RK44 evaluates, in every stage, the ODE1 right-hand side before the
loads, so the right-hand side solves once and the loads hand out its forces; after the last stage it evaluates the
right-hand side once more at the end-of-step state, which the post-step work and the output sampling reuse
(recomputing if the state differs).
"""

from __future__ import annotations

import exudyn.itemInterface as eii
import numpy as np

from ..case.model import Case, ParachuteSystem
from .items import CURRENT, OV, ModelItems


class ReducedConfluence:
    """Base class: subclasses implement ``compute(t, q, positions, velocities)`` returning a solution with
    ``velocity``, ``tensions`` and ``directions``, and ``derivative(solution)`` for the ODE1 states."""

    def __init__(self, items: ModelItems, case: Case, system: ParachuteSystem, initial_states: list):
        mbs = items.mbs
        self.items, self.system = items, system
        self.free_length = [line.free_length for line in system.lines]
        self.stiffness = [line.stiffness for line in system.lines]
        self.damping = [line.damping for line in system.lines]
        self.markers = [items.bodies[line.body].point_markers[line.point] for line in system.lines]
        self.node = mbs.AddNode(eii.NodeGenericODE1(referenceCoordinates=[0.0] * len(initial_states),
                                                    initialCoordinates=list(initial_states),
                                                    numberOfODE1Coordinates=len(initial_states)))
        mbs.AddObject(eii.ObjectGenericODE1(nodeNumbers=[self.node], rhsUserFunction=self._rhs))
        self.forces = [[0.0, 0.0, 0.0] for _ in system.lines]
        self.solution = None
        self.solved_at = None  # (t, q) of self.solution
        self._get_marker = mbs.GetMarkerOutput
        self._get_node = mbs.GetNodeOutput
        self._get_time = mbs.systemData.GetTime
        for i, marker in enumerate(self.markers):
            mbs.AddLoad(eii.LoadForceVector(markerNumber=marker, loadVectorUserFunction=self._load(i),
                                            visualization=eii.VLoadForceVector(show=False)))

    def compute(self, t, q, positions, velocities):  # pragma: no cover - interface
        raise NotImplementedError

    def derivative(self, solution) -> list:  # pragma: no cover - interface
        raise NotImplementedError

    def solve(self, t, q):
        """Solve at the current attach-point states and ODE1 coordinates ``q``; stores forces, caches."""
        get = self._get_marker
        positions = [get(m, OV.Position, CURRENT).tolist() for m in self.markers]
        velocities = [get(m, OV.Velocity, CURRENT).tolist() for m in self.markers]
        solution = self.compute(t, q, positions, velocities)
        for force, t_i, (nx, ny, nz) in zip(self.forces, solution.tensions, solution.directions):
            force[0], force[1], force[2] = -t_i * nx, -t_i * ny, -t_i * nz   # on the body: -T n
        self.solution, self.solved_at = solution, (t, q)
        return solution

    def _rhs(self, mbs, t, item, q):
        try:
            return self.derivative(self.solve(t, list(q)))
        except Exception as exc:  # keep our own error for the solver to report
            self.items.failure = self.items.failure or exc
            raise

    def _load(self, i):
        force = self.forces[i]
        return lambda mbs, t, load: force

    def current(self):
        """The solution at the current (end-of-step) state, reusing the last right-hand side when it matches."""
        t = self._get_time()
        q = np.atleast_1d(self._get_node(self.node, OV.Coordinates, CURRENT)).tolist()
        if self.solved_at is not None and self.solved_at[0] == t and self.solved_at[1] == q:
            return self.solution
        return self.solve(t, q)

    def add_channels(self, case: Case) -> None:
        """Output channels: confluence position and velocity and the line tensions."""
        channels, name = self.items.channels, self.system.name
        channels[("confluence", name, "position")] = lambda: self.current().position
        channels[("confluence", name, "velocity")] = lambda: self.current().velocity
        for i, line in enumerate(self.system.lines):
            channels[("tension", name, line.name)] = (lambda i=i: self.current().tensions[i])

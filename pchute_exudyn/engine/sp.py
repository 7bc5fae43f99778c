"""The singular-perturbation model (thesis chapter 3) as Exudyn items.

Each confluence is three first-order states (``NodeGenericODE1`` + ``ObjectGenericODE1``): its position, whose
derivative is the SP velocity of ``physics.singular_perturbation``. The line forces reach the bodies as loads at the
attach points. Exudyn's RK44 evaluates, in every stage, the ODE1 right-hand side before the loads, so the right-hand
side solves once and the loads hand out its forces; after the last stage it evaluates the right-hand side once more
at the end-of-step state, which the post-step update of v0 and the output sampling reuse (recomputing if the state
differs). v0, the confluence velocity at the end of the previous step, is held through the step's stages; the first
step uses the case's initial confluence velocity.
"""

from __future__ import annotations

import exudyn.itemInterface as eii

from ..case.model import Case, ParachuteSystem
from ..physics.singular_perturbation import confluence_velocity
from .items import CURRENT, OV, ModelItems, add_aerodynamics, add_body, new_system


class SPConfluence:
    """State and user functions of one SP confluence."""

    def __init__(self, items: ModelItems, case: Case, system: ParachuteSystem, kappa_max: float, slack_rule: str):
        mbs = items.mbs
        self.system = system
        self.kappa_max, self.slack_rule = kappa_max, slack_rule
        self.free_length = [line.free_length for line in system.lines]
        self.stiffness = [line.stiffness for line in system.lines]
        self.damping = [line.damping for line in system.lines]
        self.markers = [items.bodies[line.body].point_markers[line.point] for line in system.lines]
        init = system.confluence.initial
        position = case.start.local_position(init.altitude, init.east, init.north)
        self.previous_velocity = tuple(case.start.inertial_velocity(position, init.velocity_enu).tolist())
        self.node = mbs.AddNode(eii.NodeGenericODE1(referenceCoordinates=[0.0, 0.0, 0.0],
                                                    initialCoordinates=position.tolist(), numberOfODE1Coordinates=3))
        mbs.AddObject(eii.ObjectGenericODE1(nodeNumbers=[self.node], rhsUserFunction=self._rhs))
        self.forces = [[0.0, 0.0, 0.0] for _ in system.lines]
        self.solution = None
        self.solved_at = None  # (t, q) of self.solution
        self.failure_target = items
        self._get_marker = mbs.GetMarkerOutput
        self._get_node = mbs.GetNodeOutput
        self._get_time = mbs.systemData.GetTime
        for i, marker in enumerate(self.markers):
            mbs.AddLoad(eii.LoadForceVector(markerNumber=marker, loadVectorUserFunction=self._load(i),
                                            visualization=eii.VLoadForceVector(show=False)))

    def solve(self, t, q):
        """SP solution at the current attach-point states and confluence position ``q``; caches it."""
        get = self._get_marker
        positions = [get(m, OV.Position, CURRENT).tolist() for m in self.markers]
        velocities = [get(m, OV.Velocity, CURRENT).tolist() for m in self.markers]
        solution = confluence_velocity(positions, velocities, q, self.previous_velocity, self.free_length,
                                       self.stiffness, self.damping, self.kappa_max, self.slack_rule)
        for force, t_i, (nx, ny, nz) in zip(self.forces, solution.tensions, solution.directions):
            force[0], force[1], force[2] = -t_i * nx, -t_i * ny, -t_i * nz   # on the body: -T n
        self.solution, self.solved_at = solution, (t, q)
        return solution

    def _rhs(self, mbs, t, item, q):
        try:
            return list(self.solve(t, list(q)).velocity)
        except Exception as exc:  # keep our own error for the solver to report
            self.failure_target.failure = self.failure_target.failure or exc
            raise

    def _load(self, i):
        force = self.forces[i]
        return lambda mbs, t, load: force

    def current(self):
        """The SP solution at the current (end-of-step) state, reusing the last right-hand side when it matches."""
        t = self._get_time()
        q = self._get_node(self.node, OV.Coordinates, CURRENT).tolist()
        if self.solved_at is not None and self.solved_at[0] == t and self.solved_at[1] == q:
            return self.solution
        return self.solve(t, q)

    def update_previous_velocity(self, mbs, t):
        """Post-step hook: v0 for the next step is the velocity at the end of this one."""
        if t > 0.0:
            self.previous_velocity = self.current().velocity


def build_sp_model(case: Case, kappa_max: float, slack_rule: str) -> ModelItems:
    """Build the SP Exudyn model of ``case`` (bodies and aerodynamics as in the full model, SP confluences)."""
    items = new_system(case)
    mbs = items.mbs
    for body in case.bodies.values():
        add_body(items, case, body)
    for body in case.bodies.values():
        add_aerodynamics(items, case, body)
    for system in case.systems.values():
        sp = SPConfluence(items, case, system, kappa_max, slack_rule)
        items.sp[system.name] = sp
        items.post_step_hooks.append(sp.update_previous_velocity)
        label = case.confluence_label(system)
        prefix = "" if len(case.systems) == 1 else f"{system.name}_"
        items.channels[("confluence", system.name, "position")] = \
            (lambda sp=sp: mbs.GetNodeOutput(sp.node, OV.Coordinates, CURRENT))
        items.channels[("confluence", system.name, "velocity")] = (lambda sp=sp: sp.current().velocity)
        for i, line in enumerate(system.lines):
            items.channels[("tension", system.name, line.name)] = (lambda sp=sp, i=i: sp.current().tensions[i])
        items.channels[("extra", f"{label}_damping", "N s/m")] = (lambda sp=sp: sp.current().damping)
        items.channels[("extra", f"{prefix}condition_number", "-")] = (lambda sp=sp: sp.current().condition_number)
        items.channels[("extra", f"{prefix}taut_lines", "-")] = (lambda sp=sp: sum(sp.current().taut))
    mbs.Assemble()
    return items

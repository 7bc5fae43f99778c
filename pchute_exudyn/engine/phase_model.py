"""The typed interface of a built Exudyn model of one phase (``Model``): what the solver, the simulation and the
methods may use of it. Exudyn's CamelCase API stays in this package.

A model holds the Exudyn system, its bodies and parachute systems, the per-step hooks the solver runs, the stop
conditions, the confluence objects of its method and its named, typed output channels (``state``: BodyChannel,
ConfluenceChannel, TensionChannel, MethodChannel). The end-of-phase state and the facts a method reports are read
through it, never by reaching into a method's parts.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import exudyn as exu
import exudyn.itemInterface as eii
import numpy as np

from ..case.model import Case
from ..physics.kinematics import ROW_POSITION, ROW_ROTATION
from .state import BodyChannel, BodyState, ConfluenceState, Phase

OV = exu.OutputVariableType
CURRENT = exu.ConfigurationType.Current

Reader = Callable[[], object]
"""An output channel: a no-argument callable returning the current value (a float or a list of floats)."""


@dataclass
class BodyItems:
    """Exudyn indices of one rigid body (``node`` -1 for a fixed body, whose markers sit on the ground)."""

    node: int
    object: int
    point_markers: dict


class Confluence:
    """What a model knows of one system's confluence, whichever the method: its state and the facts it reports.

    Subclasses (full-mass point, SP, equilibrium point) implement ``position`` and ``velocity``; ``state_position``
    is the position held by the solver's current state without any solve (the step monitor reads it before a step).
    """

    def position(self) -> list:  # pragma: no cover - interface
        raise NotImplementedError

    def velocity(self) -> list:  # pragma: no cover - interface
        raise NotImplementedError

    def state_position(self) -> list:
        return self.position()

    def acceleration(self):
        """Acceleration (m/s^2) carried into the next phase, or None when the method keeps none."""
        return None

    def facts(self) -> dict:
        """Facts for the run summary (counts add up over phases: see ``summary.merge_facts``)."""
        return {}

    def warm_up(self, step: float | None) -> None:
        """Work to do before the timed solve, with the phase's fixed step (s; None for adaptive steps): a reduced
        confluence solves at the start state."""

    def finish(self) -> None:
        """Work left after the solve (a reduced confluence's deferred end-of-step work)."""

    def relax(self, relaxation_time: float) -> None:
        """Damp the lines at least ``relaxation_time`` (s) times their stiffness from the coming step on (adaptive
        steps: ``Method.relaxation``); only a method that relaxes them does anything."""


class Model:
    """A built Exudyn model of one phase of a run (see the module docstring).

    Parameters
    ----------
    case : Case
    phase : Phase
        The phase's bodies, systems and their states at its start.
    """

    def __init__(self, case: Case, phase: Phase):
        self.case, self.phase = case, phase
        self.system_container = exu.SystemContainer()
        self.mbs = self.system_container.AddSystem()
        self.ground = self.mbs.AddObject(eii.ObjectGround(visualization=eii.VObjectGround(show=False)))
        self.planet_marker = self.mbs.AddMarker(eii.MarkerBodyPosition(
            bodyNumber=self.ground, localPosition=case.start.planet_center.tolist()))
        self.systems = [case.systems[name].with_bodies(phase.bodies) for name in phase.systems]   # present lines
        self.bodies: dict = {}
        self.massless: set = set()   # bodies of the phase that are no engine body: reduced canopies (``methods.sp``)
        self.tethers: dict = {}   # tether name -> engine.tethers.TetherState
        self.gravity_connectors: dict = {}   # body name -> (its gravity connector or normal-gravity load, its mass
        #                                      in kg): the bodies on which no other item than the stage's adds a force
        self.confluences: dict = {}
        self.channels: dict = {}
        self.channel_groups: list = []    # (keys, reader, split): channels sampled together by one call
        self.pre_step_hooks: list = []    # (mbs, t) before every step
        self.post_step_hooks: list = []   # (mbs, t) after every step and once at the start
        self.stop_conditions: list = []   # (t) -> True ends the run after this step
        self.post_step_count = [0]        # bumped by the solver at every post-step call
        self.stage = None                 # engine.stage.Stage: body states and the Python-computed loads
        self.aerodynamic_loads: dict = {}  # body -> its engine.bodies.BodyAerodynamics (to evaluate it alone)
        self.failure: Exception | None = None
        self.progress: dict = {}   # the solve's progress (``engine.solver.integrate``): "interrupted" on Ctrl-C
        self._keep_alive: list = []       # symbolic user functions must outlive the solve

    # -- building ---------------------------------------------------------------------------------------------------

    def add_channel(self, key, reader: Reader) -> None:
        """Register an output channel (a ``state`` channel key) and its reader."""
        self.channels[key] = reader

    def add_channel_group(self, keys, reader: Reader, split) -> None:
        """Sample the channels ``keys`` (each also added alone) with one call of ``reader`` per sample instead of
        one call per channel. ``reader`` returns a list holding one 1-D array (which may be filled after the step:
        ``methods.sp``); ``split`` turns the samples, rows of one 2-D array, into one array per key, in order, equal
        to what each channel's own reader would have given."""
        self.channel_groups.append((tuple(keys), reader, split))

    def add_pre_step(self, hook) -> None:
        self.pre_step_hooks.append(hook)

    def add_post_step(self, hook, first: bool = False) -> None:
        """``first``: run before the hooks already added (a method making its solution current for the others)."""
        if first:
            self.post_step_hooks.insert(0, hook)
        else:
            self.post_step_hooks.append(hook)

    def add_stop_condition(self, condition) -> None:
        self.stop_conditions.append(condition)

    def keep_alive(self, item) -> None:
        """Hold a reference for the life of the model (Exudyn keeps none to symbolic user functions)."""
        self._keep_alive.append(item)

    def record_failure(self, exc: Exception) -> None:
        """Keep the first error raised inside a user function; the solver raises it after Exudyn returns."""
        self.failure = self.failure or exc

    def assemble(self) -> Model:
        if self.stage is not None:
            self.stage.add_item()
        self.mbs.Assemble()
        if self.stage is not None:
            self.stage.assembled()
        return self

    def warm_up(self, step: float | None) -> None:
        """Before the timed solve, with the step the engine takes (s; None for adaptive steps): load the compiled
        kernels, make each confluence's first solve (at the start state, which the first post-step call then reuses)
        and hand the step to every confluence and stop condition that reads it (``warm_up(step)``)."""
        if self.stage is not None and self.stage.global_layout is not None:
            self.stage.warm_up()
        for confluence in self.confluences.values():
            confluence.warm_up(step)
        for condition in self.stop_conditions:
            if hasattr(condition, "warm_up"):
                condition.warm_up(step)

    def finish(self) -> None:
        """After the solve, before the samples are read: each confluence's work left over."""
        for confluence in self.confluences.values():
            confluence.finish()

    # -- reading ----------------------------------------------------------------------------------------------------

    def read(self, key) -> np.ndarray:
        """The current value of channel ``key`` as an array."""
        return np.asarray(self.channels[key](), float)

    def velocity_weights(self) -> np.ndarray:
        """A weight per velocity coordinate of the engine (``GetODE2Coordinates_t``): sqrt(m) (kg^0.5) for a body's
        or a full-mass confluence's velocity, sqrt(I_jj) (kg^0.5 m) for a body's body-axis angular rate about its
        axis j; then sum (w u)^2 is twice the kinetic energy (exactly for principal axes) and a weighted norm of
        velocity errors is the kinetic-energy norm (``physics.step_rule``)."""
        weights = np.zeros(len(self.mbs.systemData.GetODE2Coordinates_t()))
        for name, items in self.bodies.items():
            body = self.case.bodies[name]
            if body.fixed or int(items.node) < 0:
                continue
            first = self.mbs.GetNodeODE2Index(items.node)
            weights[first:first + 3] = np.sqrt(body.mass)
            weights[first + 3:first + 6] = np.sqrt(np.diag(np.asarray(body.inertia, float)))
        for name, confluence in self.confluences.items():
            node = getattr(confluence, "node", None)
            if node is not None:
                first = self.mbs.GetNodeODE2Index(node)
                weights[first:first + 3] = np.sqrt(self.case.systems[name].confluence.mass)
        return weights

    def attach_positions(self, system) -> np.ndarray:
        """Current positions (n_lines, 3) of a system's attach points (m); a reduced canopy's from its state row."""
        get = self.mbs.GetMarkerOutput
        rows = self.stage.settled_rows() if self.massless else None
        points = []
        for line in system.lines:
            if line.body in self.massless:
                row = rows[self.stage.row[line.body]]
                rotation = np.asarray(row[ROW_ROTATION], float).reshape(3, 3)
                points.append(np.asarray(row[ROW_POSITION], float)
                              + rotation @ np.asarray(self.case.bodies[line.body].points[line.point], float))
            else:
                points.append(get(self.bodies[line.body].point_markers[line.point], OV.Position, CURRENT))
        return np.array(points)

    def release(self) -> None:
        """After the phase: drop the engine's system and with it the user functions it holds. Exudyn keeps those from
        C++, out of the garbage collector's sight, so a model left to the collector was never freed (7 MB and 16 000
        objects a PA1 run: 7 GB in each worker of a 2000-run study)."""
        self.system_container.Reset()
        self._keep_alive.clear()

    def end_state(self) -> tuple[dict, dict]:
        """Body and confluence states at the current (end-of-phase) time, to start the next phase from."""
        bodies = {name: BodyState(self.read(BodyChannel(name, "position")),
                                  self.read(BodyChannel(name, "rotation")).reshape(3, 3),
                                  self.read(BodyChannel(name, "velocity")),
                                  self.read(BodyChannel(name, "angular_velocity")))
                  for name in self.phase.bodies}
        confluences = {}
        for name, confluence in self.confluences.items():
            acceleration = confluence.acceleration()
            confluences[name] = ConfluenceState(np.asarray(confluence.position(), float)[:3],
                                                np.asarray(confluence.velocity(), float),
                                                None if acceleration is None else np.asarray(acceleration, float))
        return bodies, confluences

    def facts(self) -> dict:
        """The facts the method's confluences report for the run summary, keyed as in ``summary.json``."""
        facts = {}
        for confluence in self.confluences.values():
            facts.update(confluence.facts())
        return facts

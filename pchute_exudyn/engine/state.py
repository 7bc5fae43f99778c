"""State types shared by the layers above the case: body and confluence states, phases, channel keys and raw
histories. Pure data and numpy (no Exudyn): the engine produces these, the simulation and outputs consume them.

Every vector is in the start frame (local east/north/up of the start point, origin on the ellipsoid; inertial):
see ``docs/models/conventions.md``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ..case.model import Body, Case, ParachuteSystem
from ..physics.kinematics import body_point
from ..physics.rotations import attitude_matrix
from ..registries.columns import column, unit


@dataclass
class BodyState:
    """A rigid body's state: position (m), attitude (body -> start frame), velocity (m/s) and angular velocity in
    body axes (rad/s)."""

    position: np.ndarray
    attitude: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray


@dataclass
class ConfluenceState:
    """A confluence's position (m), velocity (m/s) and, when a method knows it, acceleration (m/s^2; SP order 1
    carries it into the next phase)."""

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray | None = None


@dataclass
class Phase:
    """One model of a run: from ``start`` to ``end`` (s) with these systems and free bodies and their states at
    ``start``; ``events`` are the typed events that open it (``summary``)."""

    start: float
    end: float
    systems: list
    bodies: list
    body_states: dict = field(default_factory=dict)
    confluence_states: dict = field(default_factory=dict)
    events: list = field(default_factory=list)
    inflation: dict = field(default_factory=dict)   # system -> physics.inflation.InflationProgress (whole run)
    drawn: bool = True   # the bodies carry Exudyn graphics, for a script that opens Exudyn's viewer on the model


# ---------------------------------------------------------------------------------------------------------------
# initial placement: the one home of "case initial state -> start-frame state"


def initial_body_state(case: Case, body: Body) -> BodyState:
    """The case's initial state of ``body`` in the start frame (a fixed body: where it is, at rest)."""
    i = body.initial
    position = case.start.local_position(i.altitude, i.east, i.north)
    return BodyState(position, attitude_matrix(i.yaw_deg, i.pitch_deg, i.roll_deg),
                     case.start.inertial_velocity(position, i.velocity_enu), i.angular_velocity)


def initial_confluence_state(case: Case, system: ParachuteSystem) -> ConfluenceState:
    """The case's initial state of a system's confluence in the start frame."""
    i = system.confluence.initial
    position = case.start.local_position(i.altitude, i.east, i.north)
    return ConfluenceState(position, case.start.inertial_velocity(position, i.velocity_enu))


def initial_point(case: Case, body_name: str, point_name: str | None = None) -> np.ndarray:
    """Start-frame position (m) at t = 0 of a body's centre of mass or of one of its named points."""
    body = case.bodies[body_name]
    state = initial_body_state(case, body)
    local = (0.0, 0.0, 0.0) if point_name is None else body.points[point_name]
    return body_point(state.position, state.attitude, local=local)[0]


# ---------------------------------------------------------------------------------------------------------------
# output channels: what a built model can be asked for, as typed keys


class BodyChannel(NamedTuple):
    """A free or fixed body's ``quantity``: position (m), velocity (m/s), rotation (9 values, row-major, body ->
    start frame) or angular_velocity (rad/s, body axes)."""

    body: str
    quantity: str


class ConfluenceChannel(NamedTuple):
    """A confluence's ``quantity``: position (m) or velocity (m/s)."""

    system: str
    quantity: str


class TensionChannel(NamedTuple):
    """A line's tension (N, positive)."""

    system: str
    line: str


class MethodChannel(NamedTuple):
    """A quantity a method reports per system (``Method.outputs``): its column is ``name`` with one system and
    ``<system>_<name>`` with several."""

    system: str
    name: str
    unit: str


class ColumnChannel(NamedTuple):
    """A scalar output column named ``column`` as it is (e.g. ``parachute_apparent_mass_axial``), in ``unit``."""

    column: str
    unit: str


def column_channel(template: str, owner: str) -> ColumnChannel:
    """The channel of the output column ``template`` of ``owner`` (``registries.columns``), in the registry's unit."""
    name = column(template, owner)
    return ColumnChannel(name, unit(name))


BODY_QUANTITIES = ("position", "velocity", "rotation", "angular_velocity")
CONFLUENCE_QUANTITIES = ("position", "velocity")
BODY_VALUES = 18
"""Values a sample holds for one body: its BODY_QUANTITIES (position 3, velocity 3, rotation 9, angular velocity
3)."""
CONFLUENCE_VALUES = 9
"""Values a sample holds for one confluence besides one tension per line, at most: its CONFLUENCE_QUANTITIES (3 + 3)
and a method's three outputs (``methods.sp.SPConfluence.OUTPUTS``)."""


@dataclass
class RawHistory:
    """Sampled histories of an engine run, start-frame coordinates (m, m/s, rad/s); time in s."""

    time: np.ndarray
    bodies: dict = field(default_factory=dict)        # name -> {position, velocity, rotation, angular_velocity}
    confluences: dict = field(default_factory=dict)   # system -> {position, velocity}
    tensions: dict = field(default_factory=dict)      # (system, line) -> tension (N)
    method: dict = field(default_factory=dict)        # MethodChannel or ColumnChannel -> history
    steps: int = 0
    wall_time: float = 0.0
    stopped_at: float | None = None                   # time a stop condition (touchdown) ended the run
    step_control: dict | None = None                  # adaptive steps taken (smallest, largest, mean in s; count)

    @classmethod
    def from_samples(cls, times, samples: dict, steps: int, wall_time: float) -> RawHistory:
        """Sorts sampled channel values (``{channel key: list of samples}``) into the history's tables."""
        raw = cls(time=np.asarray(times, float), steps=steps, wall_time=wall_time)
        for key, values in samples.items():
            array = np.array(values, dtype=float)
            if isinstance(key, BodyChannel):
                shaped = array.reshape(-1, 3, 3) if key.quantity == "rotation" else array
                raw.bodies.setdefault(key.body, {})[key.quantity] = shaped
            elif isinstance(key, ConfluenceChannel):
                raw.confluences.setdefault(key.system, {})[key.quantity] = array
            elif isinstance(key, TensionChannel):
                raw.tensions[(key.system, key.line)] = array.reshape(-1)
            else:
                raw.method[key] = array.reshape(-1)
        return raw

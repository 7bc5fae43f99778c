"""Exudyn items every method shares: rigid bodies, spherical gravity, aerodynamic loads, output channels.

All coordinates are in the start frame (local east/north/up of the start point, origin on the ellipsoid), which is
inertial; see ``physics.planet``. Exudyn's CamelCase API stays in this package (``engine``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import exudyn as exu
import exudyn.itemInterface as eii
import numpy as np

from ..case.model import Body, Case
from ..phases import BodyState, ConfluenceState, Phase
from ..physics.aerodynamics import aerodynamic_force
from ..physics.air import AirMotion
from ..physics.planet import FlatPlanet
from ..physics.rotations import attitude_matrix, rotation_vector

OV = exu.OutputVariableType
CURRENT = exu.ConfigurationType.Current


@dataclass
class BodyItems:
    """Exudyn indices of one rigid body."""

    node: int
    object: int
    center_marker: int
    point_markers: dict


@dataclass
class PointItems:
    """Exudyn indices of one point mass (a full-mass confluence)."""

    node: int
    object: int
    marker: int


@dataclass
class ModelItems:
    """A built Exudyn system and the indices the solver and the output stage need.

    ``channels`` maps output keys to readers (no-argument callables returning floats) that the solver samples on
    the output grid: ``("body", name, quantity)`` with quantity position, velocity, rotation (9 values, row-major)
    or angular_velocity (body axes); ``("confluence", system, quantity)`` with position or velocity;
    ``("tension", system, line)``; ``("extra", column, unit)`` for method-specific columns.
    """

    system_container: object
    mbs: object
    bodies: dict = field(default_factory=dict)
    confluences: dict = field(default_factory=dict)
    channels: dict = field(default_factory=dict)
    ground: int = -1
    planet_marker: int = -1
    pre_step_hooks: list = field(default_factory=list)  # callables (mbs, t) run before every step
    post_step_hooks: list = field(default_factory=list)  # callables (mbs, t) run after every step (and at t = 0)
    keep_alive: list = field(default_factory=list)      # symbolic user functions must outlive the solve
    failure: Exception | None = None                    # first error raised inside a user function
    reduced: dict = field(default_factory=dict)         # system -> massless confluence (engine.reduced: SP, equilibrium)
    summaries: list = field(default_factory=list)       # callables returning method facts for summary.json
    systems: list = field(default_factory=list)         # the ParachuteSystems active in this model
    stop_conditions: list = field(default_factory=list)  # callables (t) -> True to end the run after this step
    post_step_count: list = field(default_factory=lambda: [0])  # bumped by the solver at every post-step call
    snapshot: "BodySnapshot | None" = None              # per-stage body states (models with a right-hand side)
    aerodynamic_loads: dict = field(default_factory=dict)  # body -> its load user function (for inspection)


def new_system(case: Case) -> ModelItems:
    """An empty Exudyn system with a ground object and a marker at the planet centre (for the gravity connectors)."""
    system_container = exu.SystemContainer()
    mbs = system_container.AddSystem()
    ground = mbs.AddObject(eii.ObjectGround(visualization=eii.VObjectGround(show=False)))
    center = mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=ground,
                                                  localPosition=case.start.planet_center.tolist()))
    return ModelItems(system_container, mbs, ground=ground, planet_marker=center)


def add_gravity(items: ModelItems, case: Case, body: int, marker: int, mass: float) -> None:
    """Gravity on the body or point mass ``body`` whose centre of mass is at ``marker``.

    Spherical gravity -mu m r/|r|^3 by Exudyn's native gravity connector to the planet centre (exact at every
    stage); on a flat planet a uniform mass-proportional load (none when g = 0).
    """
    mbs = items.mbs
    if isinstance(case.planet, FlatPlanet):
        if case.planet.gravity_acceleration != 0.0:
            mass_marker = mbs.AddMarker(eii.MarkerBodyMass(bodyNumber=body))
            mbs.AddLoad(eii.LoadMassProportional(markerNumber=mass_marker,
                                                 loadVector=[0.0, 0.0, -case.planet.gravity_acceleration],
                                                 visualization=eii.VLoadMassProportional(show=False)))
        return
    mbs.AddObject(eii.ObjectConnectorGravity(
        markerNumbers=[items.planet_marker, marker], gravitationalConstant=case.planet.gravitational_parameter,
        mass0=1.0, mass1=mass, visualization=eii.VObjectConnectorGravity(show=False)))


def _inertia6(inertia: np.ndarray) -> list:
    """Exudyn's inertia order [Jxx, Jyy, Jzz, Jyz, Jxz, Jxy]."""
    return [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[1, 2], inertia[0, 2], inertia[0, 1]]


def add_body(items: ModelItems, case: Case, body: Body, state: BodyState | None = None) -> BodyItems:
    """A 6-DoF rigid body (rotation-vector node with Lie-group integration) in ``state`` (a fixed body: at its
    case position), its point markers and gravity; a fixed body becomes markers on the ground."""
    mbs = items.mbs
    if body.fixed:
        init = body.initial
        position = case.start.local_position(init.altitude, init.east, init.north)
        attitude = attitude_matrix(init.yaw_deg, init.pitch_deg, init.roll_deg)
        points = {name: mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=items.ground,
                                                             localPosition=(position + attitude @ p).tolist()))
                  for name, p in body.points.items()}
        for name, value in (("position", position), ("velocity", np.zeros(3)), ("rotation", attitude.ravel()),
                            ("angular_velocity", np.zeros(3))):
            items.channels[("body", body.name, name)] = (lambda value=value.tolist(): value)
        result = BodyItems(-1, items.ground, -1, points)
        items.bodies[body.name] = result
        return result
    node = mbs.AddNode(eii.NodeRigidBodyRotVecLG(
        referenceCoordinates=state.position.tolist() + rotation_vector(state.attitude).tolist(),
        initialVelocities=state.velocity.tolist() + np.asarray(state.angular_velocity, float).tolist(),
        visualization=eii.VNodeRigidBodyRotVecLG(show=False)))
    obj = mbs.AddObject(eii.ObjectRigidBody(nodeNumber=node, mass=body.mass, inertia=_inertia6(body.inertia),
                                            visualization=eii.VObjectRigidBody(show=False)))
    center = mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=obj, localPosition=[0.0, 0.0, 0.0]))
    points = {name: mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=obj, localPosition=list(p)))
              for name, p in body.points.items()}
    add_gravity(items, case, obj, center, body.mass)
    result = BodyItems(node, obj, center, points)
    for name, kind in (("position", OV.Position), ("velocity", OV.Velocity), ("rotation", OV.RotationMatrix),
                       ("angular_velocity", OV.AngularVelocityLocal)):
        items.channels[("body", body.name, name)] = node_reader(mbs, node, kind)
    items.bodies[body.name] = result
    return result


def point_motion(body_state, local) -> tuple:
    """Position (m) and velocity (m/s) of the body point ``local`` (body axes, m), start-frame components, from a
    BodySnapshot entry (position, velocity, rotation matrix row-major, angular velocity). Plain floats."""
    x, v, r, w = body_state
    lx, ly, lz = local
    ax, ay, az = r[0] * lx + r[1] * ly + r[2] * lz, r[3] * lx + r[4] * ly + r[5] * lz, r[6] * lx + r[7] * ly + r[8] * lz
    return ((x[0] + ax, x[1] + ay, x[2] + az),
            (v[0] + w[1] * az - w[2] * ay, v[1] + w[2] * ax - w[0] * az, v[2] + w[0] * ay - w[1] * ax))


_SNAPSHOT_OUTPUTS = (OV.Position, OV.Velocity, OV.RotationMatrix, OV.AngularVelocity)


class BodySnapshot:
    """The free bodies' states read once per right-hand-side evaluation (4 engine calls per body), from which user
    functions of the same stage compute any body point in plain floats instead of reading markers.

    Only models whose stages start with an ODE1 right-hand side (SP, equilibrium point) use it: Exudyn evaluates that
    before the loads of the stage, and once more at the end of each step, which makes the snapshot current for the
    post-step sampling too.
    """

    def __init__(self, items: "ModelItems", names):
        self.nodes = [(name, items.bodies[name].node) for name in names]
        self.get = items.mbs.GetNodeOutput
        self.state = {}

    def refresh(self) -> None:
        get, state = self.get, self.state
        position, velocity, rotation, rate = _SNAPSHOT_OUTPUTS
        for name, node in self.nodes:   # the configuration argument left at its default, Current: a little faster
            state[name] = (get(node, position).tolist(), get(node, velocity).tolist(), get(node, rotation).tolist(),
                           get(node, rate).tolist())

    def channels(self, items: "ModelItems") -> None:
        """Serve the bodies' output channels from the snapshot (current at every post-step call)."""
        for name, _ in self.nodes:
            items.channels[("body", name, "position")] = lambda name=name: self.state[name][0]
            items.channels[("body", name, "velocity")] = lambda name=name: self.state[name][1]
            items.channels[("body", name, "rotation")] = lambda name=name: self.state[name][2]
            items.channels[("body", name, "angular_velocity")] = lambda name=name: self.local_rate(name)

    def local_rate(self, name: str) -> list:
        """Angular velocity in body axes (rad/s): R^T w."""
        _, _, r, w = self.state[name]
        return [r[0] * w[0] + r[3] * w[1] + r[6] * w[2], r[1] * w[0] + r[4] * w[1] + r[7] * w[2],
                r[2] * w[0] + r[5] * w[1] + r[8] * w[2]]


def node_reader(mbs, node: int, kind):
    """A reader of one node output in the current configuration (as a list of floats, like every channel)."""
    get = mbs.GetNodeOutput
    return lambda: get(node, kind, CURRENT).tolist()


def add_point_mass(items: ModelItems, case: Case, key: str, mass: float, state: ConfluenceState) -> PointItems:
    """A 3-DoF point mass with gravity (the full-mass confluence) in ``state``."""
    mbs = items.mbs
    node = mbs.AddNode(eii.NodePoint(referenceCoordinates=state.position.tolist(),
                                     initialVelocities=state.velocity.tolist(),
                                     visualization=eii.VNodePoint(show=False)))
    obj = mbs.AddObject(eii.ObjectMassPoint(nodeNumber=node, mass=mass,
                                            visualization=eii.VObjectMassPoint(show=False)))
    marker = mbs.AddMarker(eii.MarkerNodePosition(nodeNumber=node))
    add_gravity(items, case, obj, marker, mass)
    result = PointItems(node, obj, marker)
    for name, kind in (("position", OV.Position), ("velocity", OV.Velocity)):
        items.channels[("confluence", key, name)] = node_reader(mbs, node, kind)
    items.confluences[key] = result
    return result


def add_aerodynamics(items: ModelItems, case: Case, body: Body, schedule=None, deployed_at: float = 0.0) -> int | None:
    """The body's aerodynamic force as a load at its aerodynamic centre, evaluated at every solver stage.

    A Python load user function (no symbolic function can read the state); it reads the centre's position and
    velocity and the body axis with three engine calls and does the rest in plain floats (``physics``). The velocity
    is taken relative to the air (planet rotation and wind, ``physics.air``); ``schedule`` (a drag-area schedule)
    scales the coefficients by its fraction at the time since ``deployed_at`` (s).
    """
    aero = body.aerodynamics
    if aero is None or not aero.enabled:
        return None
    mbs = items.mbs
    body_items = items.bodies[body.name]
    marker = mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=body_items.object, localPosition=list(aero.center)))
    get_marker, get_node = mbs.GetMarkerOutput, mbs.GetNodeOutput
    snapshot, name, center = items.snapshot, body.name, tuple(aero.center)
    node = body_items.node
    altitude = case.start.altitude_scalar
    density = case.atmosphere.density
    air = AirMotion(case.start, case.wind)
    still = air.still
    area, axial, normal = aero.reference_area, aero.axial_coefficient, aero.normal_coefficient

    def aerodynamic_load(mbs_, t, load_vector):
        if snapshot is not None:   # the stage's right-hand side has read the bodies already
            state = snapshot.state[name]
            (x, y, z), (vx, vy, vz) = point_motion(state, center)
            r = state[2]
        else:
            x, y, z = get_marker(marker, OV.Position, CURRENT).tolist()
            vx, vy, vz = get_marker(marker, OV.Velocity, CURRENT).tolist()
            r = get_node(node, OV.RotationMatrix, CURRENT).tolist()
        try:
            h = altitude(x, y, z)
            rho = density(h)
        except Exception as exc:  # keep our own error (e.g. outside an atmosphere table) for the solver to raise
            items.failure = items.failure or exc
            raise
        if not still:
            wx, wy, wz = air(x, y, z, h, t)
            vx, vy, vz = vx - wx, vy - wy, vz - wz
        fraction = 1.0 if schedule is None else schedule(t - deployed_at)
        return list(aerodynamic_force((vx, vy, vz), (r[0], r[3], r[6]), rho, area, axial, normal, fraction))

    items.aerodynamic_loads[body.name] = aerodynamic_load
    return mbs.AddLoad(eii.LoadForceVector(markerNumber=marker, loadVectorUserFunction=aerodynamic_load,
                                           visualization=eii.VLoadForceVector(show=False)))


def add_bodies(items: ModelItems, case: Case, phase: Phase, snapshot: bool = False) -> None:
    """The fixed bodies and the phase's free bodies (in their phase-start states) with their aerodynamics;
    ``snapshot``: the model's right-hand side keeps a BodySnapshot that the loads and outputs read."""
    for body in case.bodies.values():
        if body.fixed or body.name in phase.bodies:
            add_body(items, case, body, phase.body_states.get(body.name))
    if snapshot and phase.systems:   # refreshed by the systems' right-hand sides, so only when there are some
        items.snapshot = BodySnapshot(items, phase.bodies)
        items.snapshot.channels(items)
    for body in case.bodies.values():
        if body.name in phase.bodies:
            system = case.canopy_system(body.name)
            schedule = system.drag_area_schedule if system is not None else None
            deployed = system.deploy_time if system is not None and system.deploy_time is not None else 0.0
            add_aerodynamics(items, case, body, schedule, deployed)
    items.systems = [case.systems[name] for name in phase.systems]


class Touchdown:
    """Stop condition: the vehicle's centre of mass reaches the ground altitude. Interpolates the crossing."""

    def __init__(self, items: ModelItems, case: Case, ground_altitude: float):
        self.position = items.channels[("body", case.vehicle, "position")]
        self.velocity = items.channels[("body", case.vehicle, "velocity")]
        self.case, self.ground = case, ground_altitude
        self.altitude = case.start.altitude_scalar
        self.previous = None
        self.event = None

    def __call__(self, t: float) -> bool:   # every step: plain floats
        x, y, z = self.position()
        height = self.altitude(x, y, z)
        if height > self.ground:
            self.previous = (t, height)
            return False
        w = 1.0
        if self.previous is not None and self.previous[1] > height:
            w = (self.previous[1] - self.ground) / (self.previous[1] - height)
        t_prev = self.previous[0] if self.previous is not None else t
        time = t_prev + w * (t - t_prev)
        # the crossing time is interpolated; the velocity changes little within a step and is taken at its end
        ground_velocity = self.case.start.velocity_to_planet_fixed(np.array([x, y, z]),
                                                                   np.asarray(self.velocity(), float), time)
        self.event = {"event": "touchdown", "time": float(time), "speed": float(np.linalg.norm(ground_velocity)),
                      "vertical_speed": float(-ground_velocity[2]),
                      "horizontal_speed": float(np.hypot(ground_velocity[0], ground_velocity[1]))}
        return True

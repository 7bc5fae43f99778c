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
from ..physics.aerodynamics import aerodynamic_force
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
    sp: dict = field(default_factory=dict)              # system -> massless confluence (engine.reduced)
    summaries: list = field(default_factory=list)       # callables returning method facts for summary.json


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


def add_body(items: ModelItems, case: Case, body: Body) -> BodyItems:
    """A 6-DoF rigid body (rotation-vector node with Lie-group integration), its point markers and gravity;
    a fixed body becomes markers on the ground."""
    mbs = items.mbs
    init = body.initial
    position = case.start.local_position(init.altitude, init.east, init.north)
    attitude = attitude_matrix(init.yaw_deg, init.pitch_deg, init.roll_deg)
    if body.fixed:
        points = {name: mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=items.ground,
                                                             localPosition=(position + attitude @ p).tolist()))
                  for name, p in body.points.items()}
        for name, value in (("position", position), ("velocity", np.zeros(3)), ("rotation", attitude.ravel()),
                            ("angular_velocity", np.zeros(3))):
            items.channels[("body", body.name, name)] = (lambda value=value.tolist(): value)
        result = BodyItems(-1, items.ground, -1, points)
        items.bodies[body.name] = result
        return result
    velocity = case.start.inertial_velocity(position, init.velocity_enu)
    node = mbs.AddNode(eii.NodeRigidBodyRotVecLG(
        referenceCoordinates=position.tolist() + rotation_vector(attitude).tolist(),
        initialVelocities=velocity.tolist() + init.angular_velocity.tolist(),
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


def node_reader(mbs, node: int, kind):
    """A reader of one node output in the current configuration."""
    get = mbs.GetNodeOutput
    return lambda: get(node, kind, CURRENT)


def add_point_mass(items: ModelItems, case: Case, key: str, mass: float, initial) -> PointItems:
    """A 3-DoF point mass with gravity (the full-mass confluence)."""
    mbs = items.mbs
    position = case.start.local_position(initial.altitude, initial.east, initial.north)
    velocity = case.start.inertial_velocity(position, initial.velocity_enu)
    node = mbs.AddNode(eii.NodePoint(referenceCoordinates=position.tolist(), initialVelocities=velocity.tolist(),
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


def add_aerodynamics(items: ModelItems, case: Case, body: Body) -> int | None:
    """The body's aerodynamic force as a load at its aerodynamic centre, evaluated at every solver stage.

    A Python load user function (no symbolic function can read the state); it reads the centre's position and
    velocity and the body axis with three engine calls and does the rest in plain floats (``physics``).
    """
    aero = body.aerodynamics
    if aero is None or not aero.enabled:
        return None
    mbs = items.mbs
    body_items = items.bodies[body.name]
    marker = mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=body_items.object, localPosition=list(aero.center)))
    get_marker, get_node = mbs.GetMarkerOutput, mbs.GetNodeOutput
    node = body_items.node
    ox, oy, oz = case.start.origin.tolist()
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = case.start.axes.tolist()
    altitude = case.planet.altitude_scalar
    density = case.atmosphere.density
    omega = case.start.rotation_vector.tolist()
    cx, cy, cz = case.start.planet_center.tolist()
    rotating = case.planet.rotation_rate != 0.0
    area, axial, normal = aero.reference_area, aero.axial_coefficient, aero.normal_coefficient

    def aerodynamic_load(mbs_, t, load_vector):
        x, y, z = get_marker(marker, OV.Position, CURRENT).tolist()
        vx, vy, vz = get_marker(marker, OV.Velocity, CURRENT).tolist()
        r = get_node(node, OV.RotationMatrix, CURRENT).tolist()
        try:
            rho = density(altitude(ox + a00 * x + a01 * y + a02 * z, oy + a10 * x + a11 * y + a12 * z,
                                   oz + a20 * x + a21 * y + a22 * z))
        except Exception as exc:  # keep our own error (e.g. outside an atmosphere table) for the solver to raise
            items.failure = items.failure or exc
            raise
        if rotating:  # the air turns with the planet: subtract omega x (r - r_centre)
            dx, dy, dz = x - cx, y - cy, z - cz
            vx -= omega[1] * dz - omega[2] * dy
            vy -= omega[2] * dx - omega[0] * dz
            vz -= omega[0] * dy - omega[1] * dx
        return list(aerodynamic_force((vx, vy, vz), (r[0], r[3], r[6]), rho, area, axial, normal))

    return mbs.AddLoad(eii.LoadForceVector(markerNumber=marker, loadVectorUserFunction=aerodynamic_load,
                                           visualization=eii.VLoadForceVector(show=False)))

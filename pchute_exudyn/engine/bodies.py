"""Exudyn items every method shares: rigid bodies, gravity, aerodynamic loads (applied through the model's
``engine.stage.Stage``), the full-mass confluence point and the touchdown stop condition.

All coordinates are in the start frame (local east/north/up of the start point, origin on the ellipsoid), which is
inertial; see ``docs/models/conventions.md``. Exudyn's CamelCase API stays in this package (``engine``).
"""

from __future__ import annotations

import math

import exudyn.itemInterface as eii
import numpy as np

from ..case.model import Body, Case
from ..physics.planet import FlatPlanet
from ..physics.rotations import rotation_vector
from .canopy import add_apparent_mass, add_fraction_channel, add_inflation_hooks
from .contact_loads import add_contact
from .display import body_graphics
from .phase_model import CURRENT, OV, BodyItems, Confluence, Model
from .stage import Stage
from .state import BodyChannel, BodyState, ConfluenceChannel, ConfluenceState, initial_body_state
from .tethers import add_tethers


def add_gravity(model: Model, case: Case, body: int, marker: int, mass: float) -> int | None:
    """Gravity on the body or point mass ``body`` whose centre of mass is at ``marker``.

    Spherical gravity -mu m r/|r|^3 by Exudyn's native gravity connector to the planet centre (exact at every
    stage), whose number it returns; with normal gravity a force load whose user function evaluates
    ``physics.gravity.normal_gravity`` at the marker's current (stage) position (``add_normal_gravity``), whose
    number it returns (``engine.stage.Stage.take_over_gravity`` tells them apart by the case); on a flat planet a
    uniform mass-proportional load (none when g = 0), and it returns None.
    """
    mbs = model.mbs
    if case.start.normal_gravity_parameters() is not None:
        return add_normal_gravity(model, case, marker, mass)
    if isinstance(case.planet, FlatPlanet):
        if case.planet.gravity_acceleration != 0.0:
            mass_marker = mbs.AddMarker(eii.MarkerBodyMass(bodyNumber=body))
            mbs.AddLoad(eii.LoadMassProportional(markerNumber=mass_marker,
                                                 loadVector=[0.0, 0.0, -case.planet.gravity_acceleration],
                                                 visualization=eii.VLoadMassProportional(show=False)))
        return None
    return mbs.AddObject(eii.ObjectConnectorGravity(
        markerNumbers=[model.planet_marker, marker], gravitationalConstant=case.planet.gravitational_parameter,
        mass0=1.0, mass1=mass, visualization=eii.VObjectConnectorGravity(show=False)))


def add_normal_gravity(model: Model, case: Case, marker: int, mass: float) -> int:
    """Normal gravity on the mass ``mass`` (kg) at ``marker``: m g(r) (N) with g from ``StartFrame.gravity_scalar``
    at the marker's position of the current solver stage (Exudyn serves the stage's state to user functions), one
    Python call per stage. Returns the load's number."""
    mbs, gravity = model.mbs, case.start.gravity_scalar
    read = mbs.GetMarkerOutput

    def weight(mbs_, t, load_vector):
        x, y, z = read(marker, OV.Position, CURRENT)
        gx, gy, gz = gravity(x, y, z)
        return [mass * gx, mass * gy, mass * gz]
    return mbs.AddLoad(eii.LoadForceVector(markerNumber=marker, loadVector=[0.0, 0.0, 0.0],
                                           loadVectorUserFunction=weight,
                                           visualization=eii.VLoadForceVector(show=False)))


def _inertia6(inertia: np.ndarray) -> list:
    """Exudyn's inertia order [Jxx, Jyy, Jzz, Jyz, Jxz, Jxy]."""
    return [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[1, 2], inertia[0, 2], inertia[0, 1]]


def add_fixed_body(model: Model, case: Case, body: Body) -> BodyItems:
    """A body fixed to the ground: its points become ground markers, its channels constants."""
    state = initial_body_state(case, body)
    points = {name: model.mbs.AddMarker(eii.MarkerBodyPosition(
        bodyNumber=model.ground, localPosition=(state.position + state.attitude @ p).tolist()))
        for name, p in body.points.items()}
    for name, value in (("position", state.position), ("velocity", np.zeros(3)),
                        ("rotation", state.attitude.ravel()), ("angular_velocity", np.zeros(3))):
        constant = value.tolist()
        model.add_channel(BodyChannel(body.name, name), lambda constant=constant: constant)
    result = BodyItems(-1, model.ground, points)
    model.bodies[body.name] = result
    return result


def add_body(model: Model, case: Case, body: Body, state: BodyState | None = None) -> BodyItems:
    """A 6-DoF rigid body (rotation-vector node with Lie-group integration) in ``state``, its point markers and
    gravity; a fixed body becomes markers on the ground."""
    if body.fixed:
        return add_fixed_body(model, case, body)
    mbs = model.mbs
    node = mbs.AddNode(eii.NodeRigidBodyRotVecLG(
        referenceCoordinates=state.position.tolist() + rotation_vector(state.attitude).tolist(),
        initialVelocities=state.velocity.tolist() + np.asarray(state.angular_velocity, float).tolist(),
        visualization=eii.VNodeRigidBodyRotVecLG(show=False)))
    mass = case.mass_of(body.name, model.phase.start)   # with the canopies that stay packed in it
    drawing = body_graphics(case.drawing(body.name)) if model.phase.drawn else []   # a run's own: 24 ms (MER)
    obj = mbs.AddObject(eii.ObjectRigidBody(nodeNumber=node, mass=mass, inertia=_inertia6(body.inertia),
                                            visualization=eii.VObjectRigidBody(graphicsData=drawing)))
    center = mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=obj, localPosition=[0.0, 0.0, 0.0]))
    points = {name: mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=obj, localPosition=list(p)))
              for name, p in body.points.items()}
    connector = add_gravity(model, case, obj, center, mass)
    if connector is not None and body.apparent_mass is None:   # its only force item besides the stage's
        model.gravity_connectors[body.name] = (connector, mass)
    add_apparent_mass(model, case, body, node)
    result = BodyItems(node, obj, points)
    for name, kind in (("position", OV.Position), ("velocity", OV.Velocity), ("rotation", OV.RotationMatrix),
                       ("angular_velocity", OV.AngularVelocityLocal)):
        model.add_channel(BodyChannel(body.name, name), node_reader(mbs, node, kind))
    model.bodies[body.name] = result
    return result


def node_reader(mbs, node: int, kind):
    """A reader of one node output in the current configuration (as a list of floats, like every channel)."""
    get = mbs.GetNodeOutput
    return lambda: get(node, kind, CURRENT).tolist()


class PointConfluence(Confluence):
    """A full-mass confluence: a 3-DoF point mass with gravity (thesis Eqs. 1.1-1.5)."""

    def __init__(self, model: Model, case: Case, system_name: str, mass: float, state: ConfluenceState):
        mbs = model.mbs
        self.node = mbs.AddNode(eii.NodePoint(referenceCoordinates=state.position.tolist(),
                                              initialVelocities=state.velocity.tolist(),
                                              visualization=eii.VNodePoint(show=True, drawSize=0.3)))
        obj = mbs.AddObject(eii.ObjectMassPoint(nodeNumber=self.node, mass=mass,
                                                visualization=eii.VObjectMassPoint(show=False)))
        self.marker = mbs.AddMarker(eii.MarkerNodePosition(nodeNumber=self.node))
        add_gravity(model, case, obj, self.marker, mass)
        self.position = node_reader(mbs, self.node, OV.Position)
        self.velocity = node_reader(mbs, self.node, OV.Velocity)
        model.add_channel(ConfluenceChannel(system_name, "position"), self.position)
        model.add_channel(ConfluenceChannel(system_name, "velocity"), self.velocity)
        model.confluences[system_name] = self


def add_aerodynamics(model: Model, case: Case, body: Body, schedule=None, deployed_at: float = 0.0,
                     efficiency: float = 1.0):
    """The body's aerodynamic load, applied through the model's stage; returns its
    ``engine.aero_loads.BodyAerodynamics`` (None for a body without aerodynamics or with them switched off)."""
    aero = body.aerodynamics
    if aero is None or not aero.enabled:
        return None
    return model.stage.add_aerodynamics(body, schedule, deployed_at, efficiency)


def add_bodies(model: Model, case: Case, reduced: bool = False, massless=()) -> None:
    """The fixed bodies and the phase's free bodies (in their phase-start states) with their aerodynamics, each
    cluster's canopy contact, and the model's stage; ``reduced``: the model's right-hand side refreshes the stage's
    body states at every stage, and the body channels read them. ``massless``: bodies of the phase that get no
    engine body (reduced canopies: their confluence's kernel moves them and applies their drag). The case's tethers
    between the phase's bodies come last (``engine.tethers``)."""
    phase = model.phase
    model.massless = set(massless)
    for body in case.bodies.values():
        if (body.fixed or body.name in phase.bodies) and body.name not in model.massless:
            add_body(model, case, body, phase.body_states.get(body.name))
    model.stage = Stage(model, case)
    if reduced and phase.systems:   # refreshed by the systems' right-hand sides, so only when there are some
        model.stage.serve_channels()
    loads = model.aerodynamic_loads
    for body in case.bodies.values():
        if body.name not in phase.bodies or body.name in model.massless:
            continue
        system = case.canopy_system(body.name)
        if system is None:
            loads[body.name] = add_aerodynamics(model, case, body)
            continue
        deployed = system.deploy_time if system.deploy_time is not None else 0.0
        opening = phase.inflation.get((system.name, body.name))
        schedule = case.opening_of(system, body.name) if opening is None else opening
        loads[body.name] = add_aerodynamics(model, case, body, schedule, deployed,
                                           case.drag_efficiency(system, body.name, phase.bodies))
        label = case.opening_label(system, body.name)
        if opening is not None and loads[body.name] is not None:
            add_inflation_hooks(model, label, body.name, opening, loads[body.name],
                                _fill_speed_reader(system, loads))
        elif system.cluster and loads[body.name] is not None:
            add_fraction_channel(model, label, schedule, deployed)
    for system in model.systems:
        if system.contact is not None and len(system.canopies) > 1:
            add_contact(model, case, system, [loads[canopy] for canopy in system.canopies])
    if case.tethers:
        add_tethers(model, case)


def _fill_speed_reader(system, loads: dict):
    """The air speed (m/s, a function of run time) a canopy whose bag anchor says so (``fills_at_load_speed``: a
    pilot chute's) fills at: the body its bag left's, the deploy point's (``loads``: the phase's ``BodyAerodynamics``
    by body, filled in by then; the canopy's own where that body has none); None (the canopy's own) otherwise. The
    pilot chute holds the canopy back near the air's speed until the line stretch, and the snatch brings it up to
    the load's within milliseconds: Knacke's fill time n D0 / V takes the load's speed at line stretch."""
    if system.bag_anchor is None or not system.bag_anchor.fills_at_load_speed:
        return None
    body = system.deploy_point[0]
    return lambda time: (loads.get(body) or loads[system.canopies[0]]).air_speed(time)


MAX_DESCENT_ACCELERATION = 30.0
"""Bound on a vehicle's downward acceleration (m/s^2: three times Earth's gravity; a parachute only slows it)."""


class Touchdown:
    """Stop condition: the vehicle's centre of mass reaches the ground altitude (m). Interpolates the crossing;
    ``crossing`` then holds (time in s, ground-relative velocity in m/s at the step's end, the unit vector down the
    local vertical there, both in the planet-fixed start-point axes (``StartFrame.velocity_to_planet_fixed``), and
    the place of the centre of mass at the crossing: the ground's altitude, east and north in m, as the output
    columns measure them).

    Every run that stops at the ground has one, so it checks cheaply: after a check at height h above the ground
    descending at v, the vehicle cannot reach the ground before t_min, the root of v t + a t^2 / 2 = h with
    a = MAX_DESCENT_ACCELERATION, and the next check waits half of that. Near the ground that is every step, so the
    crossing is interpolated between consecutive steps, as if every step were checked.
    """

    def __init__(self, model: Model, case: Case, ground_altitude: float):
        self.position = model.channels[BodyChannel(case.vehicle, "position")]
        self.velocity = model.channels[BodyChannel(case.vehicle, "velocity")]
        self.case, self.ground = case, ground_altitude
        self.altitude = case.start.altitude_scalar
        self.previous = None
        self.crossing = None
        self.next_check = -math.inf

    def __call__(self, t: float) -> bool:   # every step: a comparison, and plain floats when it checks
        if t < self.next_check:
            return False
        x, y, z = self.position()
        height = self.altitude(x, y, z)
        if height > self.ground:
            self.previous = (t, height, (x, y, z))
            down, a = -self.velocity()[2], MAX_DESCENT_ACCELERATION
            self.next_check = t + 0.5 * (math.sqrt(down * down + 2.0 * a * (height - self.ground)) - down) / a
            return False
        w = 1.0
        if self.previous is not None and self.previous[1] > height:
            w = (self.previous[1] - self.ground) / (self.previous[1] - height)
        t_prev = self.previous[0] if self.previous is not None else t
        time = t_prev + w * (t - t_prev)
        # the crossing time is interpolated; the velocity changes little within a step and is taken at its end
        start, position = self.case.start, np.array([x, y, z])
        ground_velocity = start.velocity_to_planet_fixed(position, np.asarray(self.velocity(), float), time)
        down = start.down(start.to_planet_fixed(position, time))   # the local vertical, in the same axes
        # the place at the crossing, interpolated as its time is (the step's end may lie below the ground): on the
        # ground, east and north where the interpolated position is
        before = np.array(self.previous[2] if self.previous is not None else position, float)
        fixed = start.to_planet_fixed(before + w * (position - before), time)
        place = (float(self.ground), float(fixed[0]), float(fixed[1]))
        self.crossing = (float(time), ground_velocity, down, place)
        return True

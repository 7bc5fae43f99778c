"""A run as phases between events (deployments and cut-aways), and the state carried across them.

Exudyn cannot add bodies to a running model, so a run with sequential parachute systems is a sequence of models:
each phase holds the vehicle and the systems active in it (a system deployed later does not exist yet, so it has no
effect, or rides in the vehicle as packed gear, ``case.carried``; one cut away is gone, so its lines stop acting). At
a boundary the bodies' and confluences' states carry over, the vehicle's re-referred to what it still carries, and a
newly deployed system is placed at line stretch (``physics.deployment``).
"""

from __future__ import annotations

import numpy as np

from ..case.carried import carried, case_at, stated_center, vehicle_with
from ..case.model import Case, Contact, ParachuteSystem
from ..engine.state import BodyState, ConfluenceState, Phase, initial_body_state, initial_confluence_state
from ..errors import SimulationError
from ..physics.cluster import touching_spread
from ..physics.deployment import (
    cluster_placement,
    damped_confluence_velocity,
    held_back,
    line_stretch_placement,
)
from ..physics.inflation import Inflation, InflationProgress, nominal_diameter
from ..physics.kinematics import body_point
from ..physics.separation import rigid_point_state, speed_shares
from ..results.summary import CutawayEvent, DeployEvent, SeparationEvent


def boundaries(case: Case, duration: float) -> list:
    """Phase boundary times: 0, every deployment and cut-away (of a system, or of one canopy) inside the run, and the
    duration (s)."""
    times = {0.0, duration}
    events = [t for system in case.systems.values() for t in (system.deploy_time, system.cutaway_time)]
    events += [separation.time for separation in case.separations.values()]
    for t in events + list(case.failures.cutaway.values()):
        if t is not None and 0.0 < t < duration:
            times.add(t)
    return sorted(times)


def initial_states(case: Case) -> tuple[dict, dict]:
    """States at t = 0 of the bodies and confluences that have an initial state in the case (a vehicle carrying
    bodies or packed gear: of its composite's centre of mass, ``case.carried``; the case gives the vehicle's at its
    own centre of mass, or with ``mass_includes_packed`` at that of the vehicle with its gear)."""
    bodies = {body.name: initial_body_state(case, body) for body in case.free_bodies() if body.initial is not None}
    confluences = {system.name: initial_confluence_state(case, system) for system in case.systems.values()
                   if system.confluence.initial is not None}
    riding = carried(case, 0.0, before=True)   # a part leaving at 0 s leaves the composite (``separate``)
    if riding:
        own = bodies[case.vehicle]
        _, center = vehicle_with(case, riding)
        offset = center - stated_center(case)   # the initial state is given at the stated centre of mass
        position, velocity = rigid_point_state(own.position, own.attitude, own.velocity, own.angular_velocity, offset)
        bodies[case.vehicle] = BodyState(position, own.attitude, velocity, own.angular_velocity)
    return bodies, confluences


def separate(case: Case, body_states: dict, time: float) -> tuple[dict, list]:
    """The body states after the separations at ``time`` (s), and their events: the vehicle's composite state
    re-referred to what it still carries (also when a packed system's gear leaves it then, ``case.carried``), each
    leaving body at its own centre of mass with the rigid-body velocity there and the separation speed shared by
    momentum (``physics.separation``); a deploying canopy is placed by ``deploy``."""
    leaving = [s for s in case.separations.values() if s.time == time]
    riding, rode = carried(case, time), carried(case, time, before=True)
    if len(riding) == len(rode):   # nothing leaves the vehicle at ``time``
        return body_states, []
    vehicle = body_states[case.vehicle]
    remaining, after = vehicle_with(case, riding)
    _, before = vehicle_with(case, rode)
    rigid = (vehicle.position, vehicle.attitude, vehicle.velocity, vehicle.angular_velocity)
    states, events = dict(body_states), []
    position, velocity = rigid_point_state(*rigid, after - before)
    for separation in leaving:
        body_mass = case.bodies[separation.body].mass
        vehicle_share, body_share = speed_shares(remaining.mass, body_mass, separation.speed)
        direction = vehicle.attitude @ np.asarray(separation.direction, float)
        velocity = velocity + vehicle_share * direction
        body_position, body_velocity = rigid_point_state(*rigid, np.asarray(separation.position, float) - before)
        states[separation.body] = BodyState(body_position, vehicle.attitude.copy(),
                                            body_velocity + body_share * direction, vehicle.angular_velocity.copy())
        events.append(SeparationEvent(time, separation.body, separation.speed))
    states[case.vehicle] = BodyState(position, vehicle.attitude, velocity, vehicle.angular_velocity)
    return states, events


def deploy(case: Case, system: ParachuteSystem, body_states: dict, time: float) -> tuple[dict, ConfluenceState]:
    """The states of ``system``'s canopies (those that leave the vehicle) and of its confluence, deployed at line
    stretch at ``time`` (s)."""
    vehicle_name, point = system.deploy_point
    carried = [body for body in [vehicle_name] + [line.body for line in system.lines] if body not in body_states
               and body not in system.canopies and not case.bodies[body].fixed]
    if carried:   # a nose cone that has not separated yet, say
        raise SimulationError(f"systems.{system.name} deploys at {time:g} s from body '{carried[0]}', which the "
                              f"vehicle still carries then (its separation comes later): deploy it after "
                              f"'{carried[0]}.separation'", time)
    vehicle = body_states[vehicle_name]
    canopies = [canopy for canopy in system.canopies if not case.failures.absent(canopy)]
    air = case.air_motion()
    x, y, z = vehicle.position.tolist()
    altitude = float(case.start.altitude(vehicle.position))
    air_velocity = vehicle.velocity - np.array(air(x, y, z, altitude, time))
    deploy_point = case.bodies[vehicle_name].points[point]
    trailing, held = air_velocity, None   # a static line's or pilot chute's bag holds the canopies back
    if system.bag_anchor is not None:
        trailing, held = held_back(*_bag_anchor_state(system.bag_anchor, body_states, time), body_point(
            vehicle.position, vehicle.attitude, local=deploy_point)[0])
    where = (vehicle.position, vehicle.attitude, vehicle.velocity, vehicle.angular_velocity, deploy_point, trailing)
    risers = [system.risers(canopy)[0] for canopy in canopies]   # a canopy is placed by its first riser
    if not system.cluster:
        placement = line_stretch_placement(*where, risers[0].free_length,
                                           case.bodies[canopies[0]].points[risers[0].point])
        canopy = BodyState(placement.canopy_position, placement.canopy_attitude,
                           placement.canopy_velocity if held is None else held.copy(), np.zeros(3))
        confluence = ConfluenceState(placement.confluence_position, placement.confluence_velocity)
        return {canopies[0]: canopy}, confluence if held is None else _balanced(case, system, body_states,
                                                                                {canopies[0]: canopy}, confluence)
    spread = system.deploy_spread if system.deploy_spread is not None else default_spread(case, system, canopies)
    confluence, velocity, placed = cluster_placement(*where, [(riser.free_length, case.bodies[c].points[riser.point])
                                                              for c, riser in zip(canopies, risers)], spread)
    states = {c: BodyState(position, attitude, canopy_velocity if held is None else held.copy(), np.zeros(3))
              for c, (position, attitude, canopy_velocity) in zip(canopies, placed)}
    state = ConfluenceState(confluence, velocity)
    return states, state if held is None else _balanced(case, system, body_states, states, state)


def _bag_anchor_state(anchor, body_states: dict, time: float) -> tuple:
    """(position in m, velocity in m/s) of what holds the bag at ``time`` (s): a static line's anchor flying with the
    aircraft, a pilot chute's centre of mass as it flies (``body_states``)."""
    flown = body_states.get(anchor.body) if anchor.body is not None else None
    if anchor.body is not None and flown is None:
        raise SimulationError(f"pilot chute '{anchor.body}' does not fly on its own at the line stretch", time)
    position, velocity = (None, None) if flown is None else (flown.position, flown.velocity)
    return anchor.anchor_at(time, position), anchor.anchor_velocity(velocity)


def _balanced(case: Case, system: ParachuteSystem, body_states: dict, canopies: dict,
              confluence: ConfluenceState) -> ConfluenceState:
    """``confluence`` with the velocity at which its lines' damping balances (``damped_confluence_velocity``): a
    static line's (pilot chute's) canopies move with the aircraft (pilot chute), the vehicle with the load, at line
    stretch."""
    states = {**body_states, **canopies}
    ends = []
    for line in system.lines:
        body = states[line.body]
        ends.append((*body_point(body.position, body.attitude, body.velocity, body.angular_velocity,
                                 case.bodies[line.body].points[line.point]), line.damping))
    return ConfluenceState(confluence.position, damped_confluence_velocity(confluence.position, confluence.velocity,
                                                                           ends))


def check_above_ground(case: Case, system: str, canopies: dict, time: float) -> None:
    """Refuse a deployment that places a canopy below the ground (a run that stops there): the vehicle is too low,
    or climbing, at the deploy time. Raises SimulationError naming the system, the canopy and the altitudes."""
    if not case.simulation.stop_at_ground:
        return
    ground = case.simulation.ground_altitude
    for canopy, state in canopies.items():
        altitude = float(case.start.altitude(state.position))
        if altitude < ground:
            raise SimulationError(f"systems.{system}.deploy_time = {time:g} s places canopy '{canopy}' at line "
                                  f"stretch at {altitude:.2f} m, below the ground (simulation.ground_altitude = "
                                  f"{ground:g} m): deploy it earlier or start higher", time)


def default_spread(case: Case, system: ParachuteSystem, canopies: list) -> float:
    """The cone half-angle (rad) on which ``canopies`` of a cluster deploy when the case gives none: where their
    envelopes, fully inflated, just touch (``physics.cluster.touching_spread``; the mean radius and reach of the
    canopies, each reach its first riser's free length plus the distance from that riser's attach point to the
    canopy's aerodynamic centre)."""
    contact = system.contact or Contact()
    radii, reaches = [], []
    for canopy in canopies:
        body, riser = case.bodies[canopy], system.risers(canopy)[0]
        radii.append(contact.projected_radius(body.aerodynamics.reference_area))
        arm = np.asarray(body.points[riser.point], float) - np.asarray(body.aerodynamics.center, float)
        reaches.append(riser.free_length + float(np.linalg.norm(arm)))
    return touching_spread(float(np.mean(radii)), float(np.mean(reaches)), len(canopies))


def next_phase(case: Case, start: float, end: float, body_states: dict, confluence_states: dict) -> Phase:
    """The phase from ``start`` to ``end``: systems active then, bodies separated then leaving the vehicle, newly
    deployed systems placed at line stretch."""
    body_states, separations = separate(case, body_states, start)
    case = case_at(case, start)
    systems = [s.name for s in case.systems.values() if case.acting(s, start)]
    phase = Phase(start, end, systems, case.active_bodies(start))
    phase.events.extend(separations)
    for system in case.systems.values():   # (a system whose triggered deployment has not fired has nothing to cut)
        if system.cutaway_time is not None and system.cutaway_time == start and system.deployed_by(start):
            phase.events.append(CutawayEvent(start, system.name))
    for canopy, time in case.failures.cutaway.items():
        if time == start and case.canopy_system(canopy).deployed_by(start):
            phase.events.append(CutawayEvent(start, case.canopy_system(canopy).name, canopy))
    for name in systems:
        system = case.systems[name]
        if system.deploy_time is not None and system.deploy_time == start:
            canopies, confluence = deploy(case, system, body_states, start)
            check_above_ground(case, name, canopies, start)
            body_states = {**body_states, **canopies}
            confluence_states = {**confluence_states, name: confluence}
            phase.events.append(DeployEvent(start, name))
    phase.body_states = {name: body_states[name] for name in phase.bodies}
    phase.confluence_states = {name: confluence_states[name] for name in systems}
    return phase


def inflation_progress(case: Case) -> dict:
    """A new ``InflationProgress`` for each canopy that opens by the fill-constant law, keyed by (system, canopy):
    they live through a run's phases (a later deployment or a cut-away must not restart an opening)."""
    progress = {}
    for name, system in case.systems.items():
        for canopy in system.canopies:
            opening = case.opening_of(system, canopy)
            if isinstance(opening, Inflation) and not case.failures.absent(canopy):
                progress[(name, canopy)] = InflationProgress(
                    opening, nominal_diameter(case.bodies[canopy].aerodynamics.reference_area),
                    system.deploy_time or 0.0)
    return progress


def initial_phase(case: Case) -> Phase:
    """The phase starting at t = 0 of ``case`` (what a model built without a phase holds)."""
    bodies, confluences = initial_states(case)
    end = boundaries(case, case.simulation.duration)[1]
    phase = next_phase(case, 0.0, end, bodies, confluences)
    phase.inflation = inflation_progress(case)
    return phase


def retime_openings(case: Case, openings: dict) -> None:
    """Give each opening the line stretch and disreef times ``case`` now holds (a triggered deployment or disreef
    that has fired, ``run.sequence``); the speeds measured so far stay."""
    for (name, canopy), progress in openings.items():
        system = case.systems[name]
        progress.inflation = case.opening_of(system, canopy)
        progress.line_stretch = system.deploy_time or 0.0

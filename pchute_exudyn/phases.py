"""A run as phases between events (deployments and cut-aways), and the state carried across them.

Exudyn cannot add bodies to a running model, so a run with sequential parachute systems is a sequence of models:
each phase holds the vehicle and the systems active in it (a system deployed later does not exist yet, so it has no
effect; one cut away is gone, so its lines stop acting). At a boundary the bodies' and confluences' states carry
over, and a newly deployed system is placed at line stretch (``physics.deployment``).
"""

from __future__ import annotations

import numpy as np

from .case.model import Case, ParachuteSystem
from .physics.deployment import line_stretch_placement
from .physics.inflation import InflationProgress, nominal_diameter
from .state import BodyState, ConfluenceState, Phase, initial_body_state, initial_confluence_state
from .summary import CutawayEvent, DeployEvent


def boundaries(case: Case, duration: float) -> list:
    """Phase boundary times: 0, every deployment and cut-away inside the run, and the duration (s)."""
    times = {0.0, duration}
    for system in case.systems.values():
        for t in (system.deploy_time, system.cutaway_time):
            if t is not None and 0.0 < t < duration:
                times.add(t)
    return sorted(times)


def initial_states(case: Case) -> tuple[dict, dict]:
    """States at t = 0 of the bodies and confluences that have an initial state in the case."""
    bodies = {body.name: initial_body_state(case, body) for body in case.free_bodies() if body.initial is not None}
    confluences = {system.name: initial_confluence_state(case, system) for system in case.systems.values()
                   if system.confluence.initial is not None}
    return bodies, confluences


def deploy(case: Case, system: ParachuteSystem, body_states: dict, time: float) -> tuple[BodyState, ConfluenceState]:
    """Canopy and confluence states of ``system`` deployed at line stretch at ``time`` (s)."""
    vehicle_name, point = system.deploy_point
    vehicle = body_states[vehicle_name]
    riser = next(line for line in system.lines if line.body == system.canopy)
    air = case.air_motion()
    x, y, z = vehicle.position.tolist()
    altitude = float(case.start.altitude(vehicle.position))
    air_velocity = vehicle.velocity - np.array(air(x, y, z, altitude, time))
    placement = line_stretch_placement(vehicle.position, vehicle.attitude, vehicle.velocity, vehicle.angular_velocity,
                                       case.bodies[vehicle_name].points[point], air_velocity, riser.free_length,
                                       case.bodies[system.canopy].points[riser.point])
    canopy = BodyState(placement.canopy_position, placement.canopy_attitude, placement.canopy_velocity, np.zeros(3))
    return canopy, ConfluenceState(placement.confluence_position, placement.confluence_velocity)


def next_phase(case: Case, start: float, end: float, body_states: dict, confluence_states: dict) -> Phase:
    """The phase from ``start`` to ``end``: systems active then, newly deployed ones placed at line stretch."""
    systems = [s.name for s in case.systems.values() if s.active_at(start)]
    phase = Phase(start, end, systems, case.active_bodies(start))
    for system in case.systems.values():
        if system.cutaway_time is not None and system.cutaway_time == start:
            phase.events.append(CutawayEvent(start, system.name))
    for name in systems:
        system = case.systems[name]
        if system.deploy_time is not None and system.deploy_time == start:
            canopy, confluence = deploy(case, system, body_states, start)
            body_states = {**body_states, system.canopy: canopy}
            confluence_states = {**confluence_states, name: confluence}
            phase.events.append(DeployEvent(start, name))
    phase.body_states = {name: body_states[name] for name in phase.bodies}
    phase.confluence_states = {name: confluence_states[name] for name in systems}
    return phase


def inflation_progress(case: Case) -> dict:
    """A new ``InflationProgress`` for each system that opens by the fill-constant law: they live through a run's
    phases (a later deployment or a cut-away of another system must not restart an opening)."""
    return {name: InflationProgress(system.inflation,
                                    nominal_diameter(case.bodies[system.canopy].aerodynamics.reference_area),
                                    system.deploy_time or 0.0)
            for name, system in case.systems.items() if system.inflation is not None}


def initial_phase(case: Case) -> Phase:
    """The phase starting at t = 0 of ``case`` (what a model built without a phase holds)."""
    bodies, confluences = initial_states(case)
    end = boundaries(case, case.simulation.duration)[1]
    phase = next_phase(case, 0.0, end, bodies, confluences)
    phase.inflation = inflation_progress(case)
    return phase

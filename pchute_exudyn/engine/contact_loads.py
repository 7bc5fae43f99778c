"""Canopy-canopy contact of a cluster as part of the model's stage (``physics.contact``): at every solver stage each
canopy's envelope, a sphere at its aerodynamic centre whose radius grows with the drag-area fraction its aerodynamic
load just used, pushes the others away where they overlap. The forces reach the bodies through the stage's one force
item, for every method and integrator."""

from __future__ import annotations

import numpy as np

from ..case.model import Case, ParachuteSystem
from ..physics.compiled import bound
from ..physics.contact import PAIR_COLUMNS, contact_forces, default_stiffness_damping, envelope_radius
from ..physics.kinematics import add_point_forces, point_motions
from .phase_model import Model


class CanopyContact:
    """The contact of one cluster's canopies (``loads``: their ``engine.bodies.BodyAerodynamics``, in order)."""

    def __init__(self, model: Model, case: Case, system: ParachuteSystem, loads: list):
        contact = system.contact
        self.loads = loads
        bodies = [case.bodies[load.body] for load in loads]
        self.points = model.stage.points([(body.name, body.aerodynamics.center) for body in bodies])
        self.projected = [contact.projected_radius(body.aerodynamics.reference_area) for body in bodies]
        rows = []
        for a in range(len(bodies)):
            for b in range(a + 1, len(bodies)):
                stiffness, damping = default_stiffness_damping(bodies[a].mass, bodies[b].mass)
                rows.append((a, b, stiffness if contact.stiffness is None else contact.stiffness,
                             damping if contact.damping is None else contact.damping))
        self.pairs = np.array(rows, float).reshape(-1, PAIR_COLUMNS)
        self.motion = np.zeros((len(bodies), 6))
        self.radii = np.zeros(len(bodies))
        self.forces = np.zeros((len(bodies), 3))
        self._point_motions, self._contact_forces, self._add_point_forces = (
            bound(point_motions), bound(contact_forces), bound(add_point_forces))   # the same arrays every stage

    def add_forces(self, states, generalized) -> None:
        """Add the contact forces at the stage's body ``states`` to ``generalized`` (after the aerodynamic loads,
        whose fractions size the envelopes)."""
        radii = self.radii
        for i, (load, projected) in enumerate(zip(self.loads, self.projected)):
            radii[i] = envelope_radius(projected, load.fraction)
        self._point_motions(states, self.points, self.motion)
        self._contact_forces(self.motion, radii, self.pairs, self.forces)
        self._add_point_forces(states, self.points, self.forces, generalized)


def add_contact(model: Model, case: Case, system: ParachuteSystem, loads: list) -> CanopyContact:
    """The contact between ``system``'s canopies present in the model (their aerodynamic ``loads``), applied through
    the model's stage."""
    contact = CanopyContact(model, case, system, loads)
    model.stage.add_contact(contact)
    return contact

"""Canopy physics as Exudyn items: the apparent mass of a body and the measured stage starts of an inflation.

Apparent mass (``physics.apparent_mass``): an ``ObjectGenericODE2`` on the body's own rigid-body node adds R A_t R^T
to the translational block of the system mass matrix and A_r to the rotational one (a Lie-group node's rotational
velocity coordinates are the body-axis angular velocity), and the Kirchhoff velocity terms as its generalized force.
The engine then solves (M + A) a = f at every stage with the current state: the apparent mass enters the equations
exactly, with no acceleration carried from an earlier stage. Measured against closed forms and an independent
integration of the body-axis equations in ``tests/acceptance/test_canopy_physics.py``.
"""

from __future__ import annotations

import math

import exudyn.itemInterface as eii
import numpy as np

from ..case.model import Body, Case
from ..physics.apparent_mass import kirchhoff_terms, translational_mass_matrix
from .phase_model import CURRENT, OV, Model
from .state import column_channel


class ApparentMassTerms:
    """The apparent mass of one body at the current stage: air density at its aerodynamic centre, the masses and
    the Kirchhoff terms, from the node's current position and rotation and the solver's velocities."""

    def __init__(self, model: Model, case: Case, body: Body, node: int):
        self.apparent, self.node = body.apparent_mass, node
        self.center = tuple(body.aerodynamics.center)
        self.get = model.mbs.GetNodeOutput
        self.altitude, self.density = case.start.altitude_scalar, case.atmosphere.density
        self.air = case.air_motion()
        self.model = model
        self.cached = None   # (t, masses()) of the last user-function call

    def masses(self, t=None):
        """(R row-major, CoM position, A_t diagonal, A_r diagonal) at the current state; the user functions of one
        stage (mass matrix, then forces) share one evaluation, keyed by time and position."""
        get, node = self.get, self.node
        x, y, z = position = get(node, OV.Position, CURRENT).tolist()
        if t is not None and self.cached is not None and self.cached[0] == t and self.cached[1][1] == position:
            return self.cached[1]
        r = get(node, OV.RotationMatrix, CURRENT).tolist()
        cx, cy, cz = self.center
        try:
            rho = self.density(self.altitude(x + r[0] * cx + r[1] * cy + r[2] * cz,
                                             y + r[3] * cx + r[4] * cy + r[5] * cz,
                                             z + r[6] * cx + r[7] * cy + r[8] * cz))
        except Exception as exc:  # keep our own error (outside an atmosphere table) for the solver to raise
            self.model.record_failure(exc)
            raise
        translational, rotational = self.apparent.masses(rho)
        values = (r, position, translational, rotational)
        if t is not None:
            self.cached = (t, values)
        return values

    def mass_matrix(self, mbs, t, item, q, q_t):
        r, _, translational, rotational = self.masses(t)
        matrix = np.zeros((6, 6))
        matrix[:3, :3] = translational_mass_matrix(r, translational)
        matrix[3, 3], matrix[4, 4], matrix[5, 5] = rotational
        return matrix

    def force(self, mbs, t, item, q, q_t):
        r, (x, y, z), translational, rotational = self.masses(t)
        # the node's velocity (inertial) and body-axis angular velocity; Exudyn passes a list or an array
        vx, vy, vz, wx, wy, wz = q_t.tolist() if hasattr(q_t, "tolist") else q_t
        if not self.air.still:
            ax, ay, az = self.air(x, y, z, self.altitude(x, y, z), t)
            vx, vy, vz = vx - ax, vy - ay, vz - az
        force, moment = kirchhoff_terms(r, (vx, vy, vz), (wx, wy, wz), translational, rotational)
        return [*force, *moment]


def add_apparent_mass(model: Model, case: Case, body: Body, node: int) -> None:
    """The body's apparent mass (when it has one) on its node, and its output channels (kg, kg, kg m^2)."""
    if body.apparent_mass is None:
        return
    terms = ApparentMassTerms(model, case, body, node)
    model.mbs.AddObject(eii.ObjectGenericODE2(
        nodeNumbers=[node], massMatrix=np.zeros((6, 6)), massMatrixUserFunction=terms.mass_matrix,
        forceUserFunction=terms.force, visualization=eii.VObjectGenericODE2(show=False)))
    for index, template in ((0, "{owner}_apparent_mass_axial"), (1, "{owner}_apparent_mass_lateral")):
        model.add_channel(column_channel(template, body.name), lambda i=index: terms.masses()[2][i])
    model.add_channel(column_channel("{owner}_apparent_inertia", body.name), lambda: terms.masses()[3][1])


def add_inflation_hooks(model: Model, system_name: str, canopy: str, progress, aerodynamic_load,
                        speed_reader=None) -> None:
    """The hooks of ``watch_opening`` for a rigid canopy, its air speed (unless ``speed_reader`` gives another, m/s
    at run time) and speed of sound read at its aerodynamic centre (``aerodynamic_load``:
    ``engine.aero_loads.BodyAerodynamics``) and the magnitude of its aerodynamic force (N) from it."""
    get_time = model.mbs.systemData.GetTime

    def force_magnitude():
        fx, fy, fz = aerodynamic_load(model.mbs, get_time(), None)
        return math.sqrt(fx * fx + fy * fy + fz * fz)
    watch_opening(model, system_name, canopy, progress, speed_reader or aerodynamic_load.air_speed,
                  aerodynamic_load.sound_speed, force_magnitude)


def watch_opening(model: Model, system_name: str, canopy: str, progress, speed_reader, sound_reader,
                  force_magnitude) -> None:
    """Measure the canopy's air speed (``speed_reader(time)``, m/s) around each stage start of an opening
    (``physics.inflation.InflationProgress``), with the speed of sound (``sound_reader(time)``, m/s) for a supersonic
    opening and its Mach number after every step for its breathing; report the drag-area fraction (-) and the
    magnitude of the canopy's aerodynamic force (N, ``force_magnitude()``) as channels."""
    if progress.supersonic is None:
        sound_reader = _no_sound
    get_time = model.mbs.systemData.GetTime
    last = [model.phase.start]

    def before_step(mbs, t):   # t: the coming step's end; the state is still the step's start
        if progress.pending is None and progress.due(t):   # (a retried, halved implicit step keeps its start)
            progress.begin(last[0], speed_reader(last[0]), sound_reader(last[0]))

    def after_step(mbs, t):
        if progress.pending is not None:
            progress.complete(t, speed_reader(t), sound_reader(t))
        if progress.load_factor is not None:
            progress.observe(speed_reader(t) / sound_reader(t))
        last[0] = t

    model.add_pre_step(before_step)
    model.add_post_step(after_step, first=True)
    model.add_channel(column_channel("{owner}_drag_area_fraction", system_name),
                      lambda: progress(get_time() - progress.line_stretch))
    model.add_channel(column_channel("{owner}_aerodynamic_force", canopy), force_magnitude)


def _no_sound(t):
    return None


def add_fraction_channel(model: Model, label: str, schedule, deployed_at: float) -> None:
    """The drag-area fraction (-) of a cluster's canopy that follows a time table (or none: 1) as the channel
    ``<label>_drag_area_fraction`` (an opening's own channel comes with ``add_inflation_hooks``)."""
    get_time = model.mbs.systemData.GetTime
    if schedule is None:
        model.add_channel(column_channel("{owner}_drag_area_fraction", label), lambda: 1.0)
        return
    model.add_channel(column_channel("{owner}_drag_area_fraction", label),
                      lambda: schedule(get_time() - deployed_at))



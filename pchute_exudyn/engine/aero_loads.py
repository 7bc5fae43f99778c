"""The bodies' aerodynamic loads in the model's stage: every body's force and moment at every solver stage in one
compiled kernel call (``physics.aerodynamics.aerodynamics_stage``: the altitude, the air's density, speed of sound and
motion, the coefficient tables, the loads), and single evaluations of one body from the engine's current state for
the outputs. A drag-area fraction that follows a schedule or an opening is evaluated in Python first, once per body
and stage, and handed to the kernel.
"""

from __future__ import annotations

import math

import exudyn.itemInterface as eii
import numpy as np

from ..case.model import Body, Case, DragAreaSchedule
from ..errors import SimulationError
from ..physics.aerodynamics import (
    FIELD,
    LOAD_COLUMNS,
    OUTSIDE,
    TABLE_OFFSET_COLUMNS,
    VALUE_ALPHA,
    VALUE_COLUMNS,
    WORK_FRACTIONS,
    WORK_STATUS,
    WORK_STATUS_VALUE,
    aerodynamics_stage,
    centre_load,
    pack_body,
    pack_stage,
    pack_tables,
    work_size,
)
from ..physics.compiled import bound, machine_code, python_form
from ..physics.kinematics import ROW_BODY_RATE, point_motion
from ..physics.runaway import RUNAWAY
from .phase_model import CURRENT, OV, Model

EDGE_ON_DEG = 5.0
"""How close to 90 deg (deg) a body's angle of attack counts as edge-on for a failed implicit step's message."""


def held_end(schedule) -> tuple:
    """(time since deployment in s from which ``schedule`` holds its last fraction, that fraction): a drag-area
    table's last breakpoint and its value there, the very number it returns at any later time (evaluated once: a
    stage then costs a comparison); (inf, nan) for a schedule that follows an opening as it goes."""
    if isinstance(schedule, DragAreaSchedule):
        return schedule.time[-1], schedule(schedule.time[-1])
    return math.inf, math.nan


class BodyAerodynamics:
    """One body's aerodynamics in its model's ``AerodynamicLoads``: its drag-area ``schedule`` (a schedule or an
    opening, evaluated at the time since ``deployed_at`` in s; None: fully open) and, through ``__call__``, its force
    (N) at the engine's current state (three engine reads: outputs, tests)."""

    def __init__(self, loads: AerodynamicLoads, model: Model, body: Body, index: int, schedule, deployed_at: float):
        self.loads, self.model, self.index = loads, model, index
        self.body, self.center = body.name, tuple(body.aerodynamics.center)
        self.schedule, self.deployed_at = schedule, deployed_at
        marker = model.mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=model.bodies[body.name].object,
                                                            localPosition=list(self.center)))
        get_marker, get_node, node = model.mbs.GetMarkerOutput, model.mbs.GetNodeOutput, model.bodies[body.name].node
        self.read = lambda: (get_marker(marker, OV.Position, CURRENT).tolist(),
                             get_marker(marker, OV.Velocity, CURRENT).tolist(),
                             get_node(node, OV.RotationMatrix, CURRENT),
                             get_node(node, OV.AngularVelocityLocal, CURRENT))

    @property
    def fraction(self) -> float:
        """The drag-area fraction (-) of the last stage the loads were evaluated at."""
        return float(self.loads.fractions[self.index])

    def fraction_at(self, t: float) -> float:
        """The drag-area fraction (-) at run time ``t`` (s)."""
        return 1.0 if self.schedule is None else self.schedule(t - self.deployed_at)

    def evaluate(self, t: float) -> tuple:
        """(force in N, moment in N m body axes, dynamic pressure in Pa, Mach number, angle of attack in deg) at
        the engine's current state and run time ``t`` (s)."""
        (x, y, z), (vx, vy, vz), rotation, rates = self.read()
        return self.loads.single(t, self.index, (x, y, z, vx, vy, vz), np.asarray(rotation, float).ravel(),
                                 np.asarray(rates, float), self.fraction_at(t))

    def __call__(self, mbs, t: float, load=None) -> tuple:
        return self.evaluate(t)[0]

    def air_speed(self, time: float) -> float:
        """The aerodynamic centre's air speed (m/s) from the engine at run time ``time`` (s; a step's start or
        end)."""
        (x, y, z), (vx, vy, vz), _, _ = self.read()
        air = self.loads.air
        if not air.still:
            wx, wy, wz = air(x, y, z, self.loads.altitude(x, y, z), time)
            vx, vy, vz = vx - wx, vy - wy, vz - wz
        return math.sqrt(vx * vx + vy * vy + vz * vz)

    def sound_speed(self, time: float) -> float:
        """The speed of sound (m/s) at the aerodynamic centre from the engine at run time ``time`` (s)."""
        (x, y, z), _, _, _ = self.read()
        return self.loads.atmosphere.speed_of_sound(self.loads.altitude(x, y, z))


class AerodynamicLoads:
    """The aerodynamics of a model's bodies, packed for ``physics.aerodynamics.aerodynamics_stage`` (``add`` each
    body, then ``pack`` once the stage knows the bodies' rows)."""

    def __init__(self, model: Model, case: Case):
        self.model, self.case = model, case
        self.members: list = []          # BodyAerodynamics, in the order of their rows
        self.tables_list: list = []      # CoefficientTable per member and coefficient, before packing
        self.rows: list = []             # LOAD_COLUMNS rows, offsets still indices into tables_list
        self.air = case.air_motion()
        self.altitude = case.start.altitude_scalar
        self.atmosphere = case.atmosphere
        self.scheduled: list = []        # the members whose fraction follows a schedule
        self._timed: list = []           # (index, schedule, deployed_at, held_end(schedule)...) of those members
        self._kernel = aerodynamics_stage
        self._arguments = ()             # the kernel's arguments after the stage time (``bind``)
        self.parts = ()                  # (data, field, work) of those arguments
        self.work = np.zeros(work_size(0))   # physics.aerodynamics.work_size: status, fractions, values (``pack``)
        self._centre_load = bound(centre_load)   # single evaluations (outputs, a canopy's measured speed): per step
        self.limits = case.runaway_limits      # beyond them a body has run away (physics.runaway)
        self.status, self.fractions = self.work[:WORK_FRACTIONS], self.work[WORK_FRACTIONS:WORK_FRACTIONS]

    def add(self, body: Body, schedule, deployed_at: float, efficiency: float) -> BodyAerodynamics:
        """Add ``body``'s aerodynamics; returns its ``BodyAerodynamics``."""
        aero = body.aerodynamics
        coefficients = {key: table for key, table in aero.coefficients().items() if table is not None}
        offsets = {}
        for key, table in coefficients.items():
            offsets[key] = float(len(self.tables_list))
            self.tables_list.append(table)
        uses_mach = any(table.uses_mach for table in coefficients.values())
        limits = self.limits
        self.rows.append(pack_body(aero.reference_area, aero.reference_length or 0.0, offsets, efficiency,
                                   uses_mach, limits.speed, limits.rate(body.name)))
        member = BodyAerodynamics(self, self.model, body, len(self.members), schedule, deployed_at)
        self.members.append(member)
        return member

    def pack(self, stage) -> None:
        """Pack the members for the kernel: their aerodynamic centres as a point layout of ``stage`` (the model's
        ``engine.stage.Stage``), the tables, the rows with the tables' offsets."""
        self.points = stage.points([(m.body, m.center) for m in self.members])
        self.tables, offsets = pack_tables(self.tables_list)
        self.bodies = np.array(self.rows, float).reshape(-1, LOAD_COLUMNS)
        for row in self.bodies:
            for column in TABLE_OFFSET_COLUMNS:
                if row[column] >= 0.0:
                    row[column] = offsets[int(row[column])]
        count = len(self.members)
        self.work = np.zeros(work_size(count))
        values_at = WORK_FRACTIONS + count
        self.status, self.fractions = self.work[:WORK_FRACTIONS], self.work[WORK_FRACTIONS:values_at]
        self.values = self.work[values_at:].reshape(count, VALUE_COLUMNS)
        self.fractions[:] = 1.0
        self.scheduled = [m for m in self.members if m.schedule is not None]
        self._timed = [(m.index, m.schedule, m.deployed_at) + held_end(m.schedule) for m in self.scheduled]
        self.frame = self.case.start.kernel_frame
        self.atmosphere_parameters = (self.atmosphere.kernel_parameters() if self.atmosphere is not None
                                      else np.zeros(0))   # a model without air has no aerodynamics either
        air = self.air
        self.data = pack_stage(points=self.points, bodies=self.bodies, tables=self.tables, frame=self.frame,
                               atmosphere=self.atmosphere_parameters, air=air.parameters, wind=air.wind_parameters,
                               gusts=air.gust_rows, turbulence=air.turbulence_parameters)

    def bind(self, states, generalized) -> None:
        """Fix the kernel's arguments after the stage time: the stage's body ``states`` and its ``generalized``
        forces (the same arrays at every stage), and the turbulence field as generated so far."""
        self._arguments = (states, self.data, self.air.field(), self.work, generalized)
        self.parts = self._arguments[1:4]   # for a fused stage kernel (``methods.sp``): ``apply_after`` completes it

    def warm_up(self, states, generalized) -> None:
        """Compile (or load) the kernel for the solver's argument types and call it through its machine code from
        then on (``physics.compiled.machine_code``)."""
        self._kernel = machine_code(aerodynamics_stage, 0.0, states, self.data, self.air.field(), self.work,
                                    np.zeros_like(generalized))

    def schedule(self, t: float) -> None:
        """Set the drag-area fractions that follow a schedule or an opening for stage time ``t`` (s)."""
        fractions = self.fractions
        for index, schedule, deployed_at, held_from, held in self._timed:
            since = t - deployed_at
            fractions[index] = held if since >= held_from else schedule(since)

    def apply(self, t: float) -> None:
        """Add every body's load at stage time ``t`` (s) for the body states to the generalized forces (the arrays
        ``bind`` was given)."""
        if self.scheduled:
            self.schedule(t)
        arguments = self._arguments
        self._kernel(t, *arguments)
        if self.status[WORK_STATUS] != 0.0:
            self.apply_after(t)

    def apply_after(self, t: float) -> None:
        """After a kernel call that reported a problem (status non-zero: nothing was added): mend it and call again
        until the loads are added."""
        status = self.status
        while status[WORK_STATUS] != 0.0:
            self._mend(status[WORK_STATUS], status[WORK_STATUS_VALUE], t)
            arguments = self._arguments
            self.bind(arguments[0], arguments[4])   # the field may be a new array
            self._kernel(t, *self._arguments)

    def _mend(self, code: float, value: float, t: float) -> None:
        """Grow the turbulence field (FIELD), or raise the atmosphere's error (OUTSIDE) or a body's runaway
        (RUNAWAY) at stage time ``t`` (s)."""
        if code == FIELD:
            self.air.extend(int(value))
            return
        if code == OUTSIDE:
            raise self.atmosphere.outside(value)
        if code == RUNAWAY:
            raise self.runaway(int(value), t)
        raise RuntimeError(f"aerodynamics kernel status {code}")   # pragma: no cover - no other codes

    def runaway(self, index: int, t: float) -> SimulationError:
        """The error of member ``index``, beyond its limits at stage time ``t`` (s): its speed or its rate, the
        one furthest beyond."""
        member, states = self.members[index], self._arguments[0]
        point = self.points[index]
        row = states[int(point[0])]
        velocity = python_form(point_motion)(row, point[1], point[2], point[3])[3:]
        speed, rate = math.sqrt(sum(v * v for v in velocity)), float(np.linalg.norm(row[ROW_BODY_RATE]))
        limits = self.limits
        quantity, value = (("speed", speed) if speed / limits.speed >= rate / limits.rate(member.body)
                           else ("rate", rate))
        return SimulationError(limits.message(member.body, quantity, value, t), t)

    def edge_on(self, within: float = EDGE_ON_DEG) -> list:
        """(body, angle of attack in deg) of the bodies whose last stage had them within ``within`` deg of 90 with an
        axial force that changes sign there (a folded C_A not 0 at 90 deg: docs/models/aerodatabase.md, "Edge-on"),
        which an implicit step cannot cross."""
        found = []
        for member in self.members:
            axial = self.case.bodies[member.body].aerodynamics.axial_coefficient
            alpha = float(self.values[member.index, VALUE_ALPHA])
            folded = not axial.angle_deg or axial.angle_deg[-1] == 90.0
            if folded and abs(alpha - 90.0) <= within and axial(90.0, 0.0) != 0.0:
                found.append((member.body, alpha))
        return found

    def single(self, t: float, index: int, centre, rotation, rates, fraction: float) -> tuple:
        """One body's load at ``t`` (s) from its centre's (x, y, z, vx, vy, vz) (m, m/s), rotation (9) and
        body-axis rates (rad/s): (force, moment, dynamic pressure, Mach, angle of attack)."""
        air = self.air
        while True:
            code, value, fx, fy, fz, mx, my, mz, pressure, mach, alpha = self._centre_load(
                float(t), *map(float, centre), rotation, rates, self.bodies[index], self.tables, float(fraction),
                self.frame, self.atmosphere_parameters, air.parameters, air.wind_parameters, air.gust_rows,
                air.turbulence_parameters, air.field())
            if code == 0.0:
                return (fx, fy, fz), (mx, my, mz), pressure, mach, alpha
            self._mend(code, value)

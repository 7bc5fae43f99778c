"""A reduced canopy's engine side (``physics.reduced_canopy``; docs/models/reduced_canopy.md): the SP confluence of a
system whose canopy is reduced integrates the canopy's drag point P instead of the confluence, and this object keeps
what the kernel reads of the canopy in the confluence's memory (``physics.sp_stepping``, rows MEMORY_CANOPY and
MEMORY_AIR): its stage row, its drag coefficient 1/2 rho S C_A and the air's velocity at it, set before every step
from the air at P then (the start of the step: the density over one step changes by parts in 1e5, and a gust or
turbulence cell reaches the canopy one step late at most)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..case.model import Case, ParachuteSystem
from ..physics.aerodynamics import mach_number
from ..physics.compiled import python_form
from ..physics.linearization import max_stable_step_rk4
from ..physics.lines import series_damping as series_damping_kernel
from ..physics.reduced_canopy import BRIDLE_ROW, RISER_ROW
from ..physics.singular_perturbation import WORK_ATTACH_POSITION, WORK_SCRATCH, WORK_TENSION
from ..physics.sp_stepping import (
    CANOPY_DRAG,
    MEMORY_AIR,
    MEMORY_CANOPY,
    MEMORY_NEWER,
    MEMORY_ORDER,
    MEMORY_POSITION,
    MEMORY_SETTINGS,
    MEMORY_TIMES,
    MEMORY_V0,
    ORDER_FIRST,
    ORDER_RECORDED,
    SETTING_MASS,
    TIME_NEWER,
)
from .model import Model

series_damping = python_form(series_damping_kernel)


def reduced_canopy(case: Case, system: ParachuteSystem) -> str | None:
    """The canopy of ``system`` that flies reduced (``canopy_model = "reduced"``, a single canopy on a riser in series
    with one bridle; the reader checks the layout), or None."""
    if system.canopy_model != "reduced" or len(system.lines) != 2 or len(system.canopies) != 1:
        return None
    return system.canopies[0]


def bridle_first(system: ParachuteSystem) -> ParachuteSystem:
    """A reduced canopy's system with its bridle as line 0 and its riser as line 1 (``physics.reduced_canopy``'s
    order): the lines' names and outputs are unchanged."""
    lines = sorted(system.lines, key=lambda line: line.body in system.canopies)
    return system if tuple(lines) == system.lines else replace(system, lines=tuple(lines))


class ReducedCanopy:
    """The canopy ``name`` of an SP confluence's system, reduced; sets the confluence's ``memory`` to fly it."""

    def __init__(self, model: Model, case: Case, system: ParachuteSystem, name: str, memory: np.ndarray):
        self.model, self.case, self.name, self.memory = model, case, name, memory
        body = case.bodies[name]
        riser = system.lines[1]
        point = np.asarray(body.points[riser.point], float)
        state = model.phase.body_states[name]
        memory[MEMORY_POSITION] = state.position + state.attitude @ point   # P: the riser's end
        memory[MEMORY_V0] = state.velocity
        memory[MEMORY_SETTINGS, SETTING_MASS] = body.mass + system.confluence.mass     # kg: first order in them
        memory[MEMORY_CANOPY] = (model.stage.row[name] + 1.0, 0.0, float(np.linalg.norm(point)))
        if memory[MEMORY_ORDER, ORDER_FIRST] > 0.5:   # its inertia from the phase's start: the start velocity is the
            # first reference (SP's confluence carries an acceleration instead; the canopy deploys at rest in the
            # vehicle's frame, and its drag must speed it up)
            memory[MEMORY_TIMES, TIME_NEWER], memory[MEMORY_NEWER] = model.phase.start, state.velocity
            memory[MEMORY_ORDER, ORDER_RECORDED] = 1.0
        self.area, self.coefficient = body.aerodynamics.reference_area, body.aerodynamics.axial_coefficient
        self.air, self.altitude = case.air_motion(), case.start.altitude_scalar
        self.mass = body.mass + system.confluence.mass
        self.lines = system.lines

    def update_air(self, t: float) -> None:
        """The drag coefficient and the air's velocity at P for the coming step (s: ``t`` its start)."""
        memory = self.memory
        x, y, z = memory[MEMORY_POSITION].tolist()
        h = self.altitude(x, y, z)
        density, sound = self.case.atmosphere.state(h)
        wind = (0.0, 0.0, 0.0) if self.air.still else self.air(x, y, z, h, t)
        mach = 0.0
        if self.coefficient.uses_mach:
            vx, vy, vz = memory[MEMORY_V0].tolist()
            mach = mach_number(math.dist((vx, vy, vz), wind), sound)
        memory[MEMORY_CANOPY, CANOPY_DRAG] = 0.5 * density * self.area * self.coefficient(0.0, mach)
        memory[MEMORY_AIR] = wind

    def position_of_confluence(self, work: np.ndarray) -> list:
        """The confluence on AP, where the lines' elastic stretches put it (the kernel's fraction)."""
        fraction, a = work[BRIDLE_ROW, WORK_SCRATCH], WORK_ATTACH_POSITION
        start, end = work[BRIDLE_ROW, a:a + 3], work[RISER_ROW, a:a + 3]
        return (start + fraction * (end - start)).tolist()

    def step_limit(self, work: np.ndarray, step: float) -> float:
        """RK4's limit (s) on P's first-order modes at a step ``step`` (s): along AP the pair's stiffness against the
        drag's slope 2 d V, the pair's damping and the inertia m / h; across it the tension over the length against
        d V and m / h (K_s from the lines' stiffest slopes)."""
        memory = self.memory
        drag = memory[MEMORY_CANOPY, CANOPY_DRAG]
        speed = math.dist(memory[MEMORY_V0].tolist(), memory[MEMORY_AIR].tolist())
        (k1, c1), (k2, c2) = ((law.stiffest, law.damping) for law in (line.law for line in self.lines))
        stiffness, damping = k1 * k2 / (k1 + k2), series_damping(k1, k2, c1, c2)
        inertia = self.mass / step
        a = WORK_ATTACH_POSITION
        length = float(np.linalg.norm(work[RISER_ROW, a:a + 3] - work[BRIDLE_ROW, a:a + 3]))
        along = stiffness / (2.0 * drag * speed + damping + inertia)
        across = work[RISER_ROW, WORK_TENSION] / length / (drag * speed + inertia)
        return max_stable_step_rk4([-max(along, across)])


"""A reduced canopy at run time (``canopy_kernels``; docs/models/reduced_canopy.md): the SP confluence of a system
whose canopy is reduced integrates the canopy's drag point P instead of the confluence, and this object keeps what the
kernel reads of the canopy in the confluence's memory (``memory.Memory``: its ``canopy`` and ``air`` rows): its stage
row, its drag coefficient 1/2 rho S C_A and the air's velocity at it, set before every step from the air at P then
(the start of the step: the density over one step changes by parts in 1e5, and a gust or turbulence cell reaches the
canopy one step late at most).

A canopy that opens (an ``inflation`` or a ``drag_area_schedule``) multiplies that coefficient by its drag-area
fraction f: before each step the coefficient at the step's start and its secant rate over the step go into memory
(``memory.MEMORY_FILL``), so that each RK stage takes f at its own time to second order (exact at the step's ends);
the opening's stage starts are measured as a rigid canopy's are (``engine.canopy.watch_opening``), from P's air
speed."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...case.model import Case, ParachuteSystem
from ...engine.canopy import add_fraction_channel, watch_opening
from ...engine.phase_model import Model
from ...engine.state import column_channel
from ...physics.aerodynamics import mach_number
from ...physics.linearization import max_stable_step_rk4
from .memory import BRIDLE_ROW, RISER_ROW, Memory, Work


def pair_constants(laws) -> tuple:
    """The stiffness K_s (N/m) and damping C_s (N s/m) of a bridle and a riser in series at their stiffest slopes
    (``LineLaw.stiffest``): K_1 K_2 / (K_1 + K_2) and ``physics.lines.series_damping``'s C_s, written here as this limit
    has always computed it (the square by ``** 2``, which Python takes through pow: not always the last bit of
    x * x); ``tests/unit/test_line_law.py`` holds it to the law."""
    (k1, c1), (k2, c2) = ((law.stiffest, law.damping) for law in laws)
    return k1 * k2 / (k1 + k2), (c1 * k2 * k2 + c2 * k1 * k1) / (k1 + k2) ** 2


def reduced_canopy(case: Case, system: ParachuteSystem) -> str | None:
    """The canopy of ``system`` that flies reduced (``canopy_model = "reduced"``, a single canopy on a riser in series
    with one bridle; the reader checks the layout), or None."""
    if system.canopy_model != "reduced" or len(system.lines) != 2 or len(system.canopies) != 1:
        return None
    return system.canopies[0]


def bridle_first(system: ParachuteSystem) -> ParachuteSystem:
    """A reduced canopy's system with its bridle as line 0 and its riser as line 1 (``canopy_kernels``' order): the
    lines' names and outputs are unchanged."""
    lines = sorted(system.lines, key=lambda line: line.body in system.canopies)
    return system if tuple(lines) == system.lines else replace(system, lines=tuple(lines))


class ReducedCanopy:
    """The canopy ``name`` of an SP confluence's system, reduced; sets the confluence's ``memory`` to fly it."""

    def __init__(self, model: Model, case: Case, system: ParachuteSystem, name: str, memory: Memory, settled):
        """``settled()``: the confluence with its last end-of-step solve done (``SPConfluence.settled``)."""
        self.model, self.case, self.name, self.memory, self.settled = model, case, name, memory, settled
        body = case.bodies[name]
        riser = system.lines[RISER_ROW]
        point = np.asarray(body.points[riser.point], float)
        state = model.phase.body_states[name]
        memory.position = state.position + state.attitude @ point   # P: the riser's end
        memory.v0 = state.velocity
        memory.mass = body.mass + system.confluence.mass     # kg: first order in them
        memory.canopy = (model.stage.row[name] + 1.0, 0.0, float(np.linalg.norm(point)))
        if memory.first_order > 0.5:   # its inertia from the phase's start: the start velocity is the first reference
            # (SP's confluence carries an acceleration instead; the canopy deploys at rest in the vehicle's frame,
            # and its drag must speed it up)
            memory.newer_time, memory.newer = model.phase.start, state.velocity
            memory.recorded = 1.0
        self.area, self.coefficient = body.aerodynamics.reference_area, body.aerodynamics.axial_coefficient
        # C_A at 0 deg without a Mach axis is one number: taken once, not looked up in the table every step
        self.axial = None if self.coefficient.uses_mach else self.coefficient(0.0)
        self.air, self.altitude = case.air_motion(), case.start.altitude_scalar
        self.mass = body.mass + system.confluence.mass
        self.laws = [line.law for line in system.lines]
        self.drag_coefficient = 0.0   # 1/2 rho S C_A (kg/m) at the last ``update_air``, open
        self.fraction = self._watch_opening(system)

    def _watch_opening(self, system: ParachuteSystem):
        """The opening's drag-area fraction (-) as a function of run time (s), its hooks and channels; None for a
        canopy open from its deployment (nothing added: its runs as before, to the bit)."""
        model, name = self.model, self.name
        label = self.case.opening_label(system, name)
        progress = model.phase.inflation.get((system.name, name))
        if progress is not None:
            watch_opening(model, label, name, progress, self.air_speed, self.sound_speed, self.drag_force)
            fraction = lambda t: progress(t - progress.line_stretch)   # noqa: E731
        else:
            schedule = self.case.opening_of(system, name)
            if schedule is None:
                return None
            deployed = system.deploy_time if system.deploy_time is not None else 0.0
            add_fraction_channel(model, label, schedule, deployed)
            fraction = lambda t: schedule(t - deployed)   # noqa: E731
            model.add_channel(column_channel("{owner}_aerodynamic_force", name), self.drag_force)
        model.add_pre_step(self.fill)
        model.add_post_step(self.stepped)
        self.step_start = model.phase.start
        return fraction

    def fill(self, mbs, t: float) -> None:
        """Pre-step hook (``t``: the coming step's end): the drag coefficient at the step's start and its secant rate
        over the step into memory (``MEMORY_FILL``)."""
        memory, start, fraction = self.memory, self.step_start, self.fraction
        coefficient = self.drag_coefficient
        at_start = coefficient * fraction(start)
        memory.canopy_drag = at_start
        memory.fill_rate = (coefficient * fraction(t) - at_start) / (t - start) if t > start else 0.0
        memory.fill_time = start

    def stepped(self, mbs, t: float) -> None:
        """Post-step hook: the next step starts at ``t`` (s)."""
        self.step_start = t

    def air_speed(self, t: float) -> float:
        """The speed (m/s) against the air at run time ``t`` (s) of the bridle's attach point on the vehicle, at the
        last end of step: the speed an opening's stage starts at (its fill time n D0 / V). A rigid canopy measures its
        own, which at line stretch is the vehicle's; a massless one has none of its own before its drag grows."""
        work = self.settled().work
        return self._against_air(work.attach_positions[BRIDLE_ROW], work.attach_velocities[BRIDLE_ROW], t)

    def _against_air(self, position, velocity, t: float) -> float:
        x, y, z = position.tolist()
        wind = (0.0, 0.0, 0.0) if self.air.still else self.air(x, y, z, self.altitude(x, y, z), t)
        return math.dist(velocity.tolist(), wind)

    def sound_speed(self, t: float) -> float:
        """The speed of sound (m/s) at P."""
        x, y, z = self.memory.position.tolist()
        return self.case.atmosphere.state(self.altitude(x, y, z))[1]

    def drag_force(self) -> float:
        """The magnitude of the canopy's drag (N) at the last end of step: 1/2 rho S C_A f |v - w|^2."""
        t = self.model.mbs.systemData.GetTime()
        memory = self.settled().memory
        speed = self._against_air(memory.position, memory.end_velocity, t)
        return self.drag_coefficient * self.fraction(t) * speed * speed

    def update_air(self, t: float) -> None:
        """The drag coefficient and the air's velocity at P for the coming step (s: ``t`` its start)."""
        memory = self.memory
        x, y, z = memory.position.tolist()
        h = self.altitude(x, y, z)
        density, sound = self.case.atmosphere.state(h)
        still = self.air.still   # still air: memory's air row stays zero
        wind = (0.0, 0.0, 0.0) if still else self.air(x, y, z, h, t)
        axial = self.axial
        if axial is None:
            vx, vy, vz = memory.v0.tolist()
            axial = self.coefficient(0.0, mach_number(math.dist((vx, vy, vz), wind), sound))
        self.drag_coefficient = 0.5 * density * self.area * axial
        # an opening's drag-area fraction now (the solve at a phase's start takes it; ``fill`` adds the step's rate)
        memory.canopy_drag = self.drag_coefficient if self.fraction is None else \
            self.drag_coefficient * self.fraction(t)
        if not still:
            memory.air = wind

    def position_of_confluence(self, work: Work) -> list:
        """The confluence on AP, where the lines' elastic stretches put it (the kernel's fraction)."""
        start, end = work.attach_positions[BRIDLE_ROW], work.attach_positions[RISER_ROW]
        return (start + work.fraction * (end - start)).tolist()

    def step_limit(self, work: Work, step: float) -> float:
        """RK4's limit (s) on P's first-order modes at a step ``step`` (s): along AP the pair's stiffness against the
        drag's slope 2 d V, the pair's damping and the inertia m / h; across it the tension over the length against
        d V and m / h (K_s from the lines' stiffest slopes: ``LineLaw.stiffest``)."""
        memory = self.memory
        drag = memory.canopy_drag
        speed = math.dist(memory.v0.tolist(), memory.air.tolist())
        stiffness, damping = pair_constants(self.laws)
        inertia = self.mass / step
        positions = work.attach_positions
        length = float(np.linalg.norm(positions[RISER_ROW] - positions[BRIDLE_ROW]))
        along = stiffness / (2.0 * drag * speed + damping + inertia)
        across = work.tensions[RISER_ROW] / length / (drag * speed + inertia)
        return max_stable_step_rk4([-max(along, across)])

"""The per-stage fast path: every force computed in Python reaches the bodies through one Exudyn item.

A model's ``Stage`` owns one ``ObjectGenericODE2`` over the free bodies' nodes whose force user function returns the
generalized forces of the aerodynamic loads and of every reduced confluence's lines, summed: one crossing from the
engine into Python per solver stage for all of them (a load user function per line and per body cost one crossing
each, and the engine's marker work besides). Its arguments, the nodes' coordinates and velocities, give the body
states (``physics.kinematics.body_states``) without any engine read.

The reduced confluences (SP, equilibrium point: ``engine.reduced``) solve inside the same user function, on those
body states, before the forces are summed. After each step ``refresh`` reads the end-of-step state (two engine
calls for the whole coordinate vectors) for their end-of-step solve and the outputs.

Generalized forces of a rotation-vector node: the force (N, start frame) and the body-axis moment (N m);
``physics.kinematics``.
"""

from __future__ import annotations

import exudyn.itemInterface as eii
import numpy as np

from ..case.model import Case
from ..physics.aerodynamics import STAGE_AERODYNAMICS_FAILED
from ..physics.compiled import bound, has_machine_code
from ..physics.kinematics import (
    BODY_COORDINATE_AT,
    BODY_MASS_AT,
    BODY_REFERENCE_AT,
    POINT_BODY_AT,
    POINT_COLUMNS,
    POINT_FORCE_AT,
    POINT_LOCAL_AT,
    ROW_BODY_RATE,
    ROW_POSITION,
    ROW_ROTATION,
    ROW_VELOCITY,
    STATE_COLUMNS,
    add_gravity_forces,
    add_normal_gravity_forces,
    body_states,
)
from .aero_loads import AerodynamicLoads
from .phase_model import Model
from .state import BodyChannel, initial_body_state

BODY_COLUMNS = 8
"""Columns of a body layout row: index of its first coordinate (-1: fixed), reference position, reference
rotation vector, and the mass whose gravity the stage adds (``physics.kinematics.BODY_MASS_AT``; 0: the engine's
gravity connector adds it)."""


class Stage:
    """The bodies' states at the current solver stage and the one force item of the Python-computed loads.

    Parameters
    ----------
    model : Model
        With its bodies added (``engine.bodies.add_body``); the stage covers the phase's free bodies and the case's
        fixed bodies (rows of constant state, no generalized force).
    case : Case
    """

    def __init__(self, model: Model, case: Case):
        self.model = model
        names = [name for name, body in case.bodies.items() if body.fixed or name in model.phase.bodies]
        self.row = {name: i for i, name in enumerate(names)}
        self.free = [name for name in names if not case.bodies[name].fixed and name not in model.massless]
        self.states = np.zeros((len(names), STATE_COLUMNS))
        self.layout = np.full((len(names), BODY_COLUMNS), -1.0)   # from the force function's own arguments
        self.global_layout = None                                  # from the whole coordinate vectors (refresh)
        for name in names:
            self._set_reference(case, name)
        self.loads = AerodynamicLoads(model, case)   # the bodies' aerodynamics, one compiled call per stage
        self.aerodynamic = False                     # whether any body has aerodynamics (known once packed)
        self.parts = []                   # generalized-force arrays the reduced confluences write
        self.confluences = []             # engine.reduced.ReducedConfluence: solved at every stage
        self.fused = None                 # the only confluence, when it can solve with the kinematics in one call
        self.contacts = []                # engine.contact_loads.CanopyContact of each cluster: after the aerodynamics
        self.generalized = np.zeros(6 * len(self.free))
        self.gravity_taken = False        # whether the stage adds the free bodies' gravity (``take_over_gravity``)
        self.gravity_layout = self.layout  # the layout whose rows carry the masses the stage's gravity adds
        self.refreshed = None             # (time, post-step call) of the last refresh
        self.rows = self.states.tolist()  # the states at the last refresh, as lists
        system_data = model.mbs.systemData
        self._read, self._read_t = system_data.GetODE2Coordinates, system_data.GetODE2Coordinates_t
        self._stage_states = bound(body_states)     # from the force function's arguments, at every stage
        self._form = np.array                       # the form they cross in: tuple where compiled (``warm_up``)
        self.normal = case.start.normal_gravity_parameters() is not None   # the stage's own gravity
        if self.normal:   # (``take_over_gravity``): normal gravity's parameters
            self.gravity, self._add_gravity = case.start.normal_gravity_parameters(), bound(add_normal_gravity_forces)
        else:             # (mu, planet centre) or (0, uniform g)
            self.gravity, self._add_gravity = case.start.gravity_parameters(), bound(add_gravity_forces)
        self._step_states = bound(body_states)      # from the engine's state, after a step

    def _set_reference(self, case: Case, name: str) -> None:
        row = self.row[name]
        if name in self.model.massless:   # a reduced canopy's row: its kernel writes it (``methods.sp.canopy_kernels``)
            state = self.model.phase.body_states[name]
            self.states[row, ROW_POSITION], self.states[row, ROW_ROTATION] = state.position, state.attitude.ravel()
            self.states[row, ROW_VELOCITY] = state.velocity
            return
        items = self.model.bodies[name]
        if case.bodies[name].fixed:   # its state is constant
            state = initial_body_state(case, case.bodies[name])
            self.states[row, ROW_POSITION], self.states[row, ROW_ROTATION] = state.position, state.attitude.ravel()
            return
        reference = self.model.mbs.GetNodeParameter(items.node, "referenceCoordinates")
        self.layout[row, BODY_COORDINATE_AT] = 6 * self.free.index(name)
        self.layout[row, BODY_REFERENCE_AT:BODY_REFERENCE_AT + 6] = np.asarray(reference, float)[:6]

    def points(self, bodies_and_points) -> np.ndarray:
        """A point layout (``physics.kinematics.POINT_COLUMNS``) of (body name, point in body axes) pairs."""
        layout = np.zeros((len(bodies_and_points), POINT_COLUMNS))
        for j, (name, local) in enumerate(bodies_and_points):
            row = self.row[name]
            layout[j, POINT_BODY_AT], layout[j, POINT_LOCAL_AT:POINT_LOCAL_AT + 3] = row, local
            layout[j, POINT_FORCE_AT] = self.layout[row, BODY_COORDINATE_AT]
        return layout

    def add_aerodynamics(self, body, schedule=None, deployed_at: float = 0.0, efficiency: float = 1.0):
        """Apply ``body``'s aerodynamic load through the stage (``engine.aero_loads``); returns its
        ``BodyAerodynamics``."""
        return self.loads.add(body, schedule, deployed_at, efficiency)

    def add_confluence(self, confluence) -> None:
        """Solve ``confluence`` (``engine.reduced``) at every stage, before the forces are summed."""
        self.confluences.append(confluence)

    def add_contact(self, contact) -> None:
        """Apply a cluster's canopy contact (``engine.contact_loads.CanopyContact``) through the stage, after the
        aerodynamic loads."""
        self.contacts.append(contact)

    def add_part(self) -> np.ndarray:
        """A generalized-force array for a reduced confluence to write at every stage (summed into the forces)."""
        part = np.zeros_like(self.generalized)
        self.parts.append(part)
        return part

    def add_item(self) -> None:
        """Add the force item (when anything needs it); call once every load and confluence is registered."""
        self.loads.pack(self)
        self.loads.bind(self.states, self.generalized)
        self.aerodynamic = bool(self.loads.members)
        if not self.free or not (self.aerodynamic or self.parts):
            return
        force = self.force
        if len(self.confluences) == 1 and hasattr(self.confluences[0], "stage_call"):
            self.fused = self.confluences[0]
            self.take_over_gravity()
            force = self._fused_force()
        elif self.confluences:   # several: ``force`` adds the gravity last (their methods run RK4 only, so no
            self.take_over_gravity()   # implicit step misses the engine's Jacobian of it)
        nodes = [self.model.bodies[name].node for name in self.free]
        zero = np.zeros((len(self.generalized), len(self.generalized)))
        self.model.mbs.AddObject(eii.ObjectGenericODE2(nodeNumbers=nodes, forceUserFunction=force,
                                                       jacobianUserFunction=lambda *args: zero,
                                                       visualization=eii.VObjectGenericODE2(show=False)))

    def take_over_gravity(self) -> None:
        """The stage adds the free bodies' gravity itself, after every other force (the fused stage kernel, or
        ``force``; ``physics.kinematics.add_gravity_forces``, bit for bit what the engine's gravity connectors add)
        and their connectors are switched off: they cost the engine about a microsecond per body and stage. Only on
        a spherical planet (or with normal gravity), and for the bodies on which nothing else adds a force (an
        apparent mass's item would change the order of the engine's sum, and its rounding). With normal gravity
        (``methods.sp.stepping.add_body_gravity``) the bodies' normal-gravity loads lose their user function (a
        Python call per body and stage). Canopy contact is added after the fused kernel's forces, so with it the
        masses go to a layout of their own (``gravity_layout``), which that kernel does not see, and the stage adds
        the gravity after the contact (the same sum, in the same order, as the force item and then the engine's
        loads: bit for bit)."""
        connectors = self.model.gravity_connectors
        if self.gravity[0] == 0.0 and not self.normal:
            return
        if self.contacts:
            self.gravity_layout = self.layout.copy()
        for name in self.free:
            if name not in connectors:
                continue
            connector, mass = connectors[name]
            self.gravity_taken = True
            self.gravity_layout[self.row[name], BODY_MASS_AT] = mass
            if self.normal:
                self.model.mbs.SetLoadParameter(connector, "loadVectorUserFunction", 0)
            else:
                self.model.mbs.SetObjectParameter(connector, "activeConnector", False)

    def assembled(self) -> None:
        """After Exudyn's Assemble: where each free body's coordinates sit in the system's coordinate vector."""
        self.global_layout = self.layout.copy()
        for name in self.free:
            row = self.row[name]
            self.global_layout[row, 0] = self.model.mbs.GetNodeODE2Index(self.model.bodies[name].node)

    def coordinates(self):
        """The engine's current ODE2 coordinates (one engine read)."""
        return self._read()

    def velocities(self):
        """The engine's current ODE2 velocities (one engine read)."""
        return self._read_t()

    def warm_up(self) -> None:
        """Load (or, on a machine's first run, compile) the stage's kernels before the timed solve: the body states
        at the start and the point kernels on scratch arrays."""
        body_states(np.array(self._read()), np.array(self._read_t()), self.global_layout, self.states)
        # the node coordinates as tuples where the compiled module has body_states for their count (a tuple of
        # floats is cheaper to make and to pass than an array; the same values)
        q = tuple(self._read().tolist()[:len(self.generalized)])
        self._form = tuple if has_machine_code(body_states, q, q, self.layout, self.states) else np.array
        if self.aerodynamic:
            self.loads.warm_up(self.states, self.generalized)
        for contact in self.contacts:
            contact.add_forces(self.states, np.zeros_like(self.generalized))

    def refresh(self, t: float) -> None:
        """The body states at the engine's current state (after a step, at time ``t`` in s): two engine reads,
        once per post-step call however many confluences ask."""
        key = (t, self.model.post_step_count[0])
        if key != self.refreshed:
            self._step_states(self._read(), self._read_t(), self.global_layout, self.states)
            self.refreshed = key
            self.rows = self.states.tolist()   # the body channels' values, as lists

    def refreshed_now(self, t: float) -> None:
        """Record that the states were just filled at the engine's current state (time ``t`` in s) by a kernel of
        the fused confluence (``refresh`` then reads nothing more in this post-step call)."""
        self.refreshed = (t, self.model.post_step_count[0])
        self.rows = self.states.tolist()

    def force(self, mbs, t, item, q, q_t):
        """The force user function: aerodynamic loads at this stage's state plus every confluence's part."""
        try:
            generalized = self.generalized
            form = self._form   # Exudyn passes lists
            self._stage_states(form(q), form(q_t), self.layout, self.states)
            for confluence in self.confluences:
                confluence.stage_solve(t)
            parts = self.parts
            if len(parts) > 1:
                np.add(parts[0], parts[1], out=generalized)
                for part in parts[2:]:
                    generalized += part
            elif parts:
                np.copyto(generalized, parts[0])
            else:
                generalized.fill(0.0)
            if self.aerodynamic:
                self.loads.apply(t)
            for contact in self.contacts:
                contact.add_forces(self.states, generalized)
            if self.gravity_taken:
                self._add_gravity(self.gravity_layout, self.states, *self.gravity, generalized)
            return generalized.tolist()   # the engine takes a list faster than an array
        except Exception as exc:  # keep our own error for the solver to report
            self.model.record_failure(exc)
            raise

    def _fused_force(self):
        """The force user function of a model whose only confluence solves with the kinematics and the
        aerodynamics in one kernel call (``methods.sp.SPConfluence.stage_call``): that call and nothing else in
        Python at most stages, every name it needs bound here (a stage of an MER SP run is about 5 us in all)."""
        fused, loads, states, generalized = self.fused, self.loads, self.states, self.generalized
        contacts, record_failure = self.contacts, self.model.record_failure
        add_gravity, layout, gravity = self._add_gravity, self.layout, self.gravity
        contact_gravity = self.gravity_layout if contacts and self.gravity_taken else None   # after the contact
        schedule = loads.schedule if loads.scheduled else None

        def fused_force(mbs, t, item, q, q_t):
            try:
                if schedule is not None:
                    schedule(t)
                kernel, arguments, form = fused.stage_call
                code = kernel(form(q), form(q_t), t, *arguments)
                if code:   # a sum of the stage kernel's flags
                    if code != STAGE_AERODYNAMICS_FAILED:   # STAGE_SETTLED: it did the deferred end-of-step work
                        fused.settled_by_stage()
                    if code >= STAGE_AERODYNAMICS_FAILED:   # it added nothing: mend the aerodynamics, add them,
                        loads.apply_after(t)   # then the gravity the kernel left out
                        add_gravity(layout, states, *gravity, generalized)
                        fused.bind_stage_call()   # the turbulence field may be a new array
                if contacts:
                    for contact in contacts:
                        contact.add_forces(states, generalized)
                    if contact_gravity is not None:
                        add_gravity(contact_gravity, states, *gravity, generalized)
                return generalized.tolist()   # the engine takes a list faster than an array
            except Exception as exc:  # keep our own error for the solver to report
                record_failure(exc)
                raise
        return fused_force

    def settled_rows(self) -> list:
        """The states at the end of the last step, as lists (a fused confluence may owe its end-of-step work:
        ``methods.sp.SPConfluence``)."""
        if self.fused is not None:
            self.fused.settle()
        return self.rows

    def sample(self) -> list:
        """The body channels' sample: a list holding an array that starts with the states, flattened (a fused
        confluence's sample, which may be a slot its deferred end-of-step work fills)."""
        if self.fused is not None:
            return self.fused.sample()
        return [self.states.ravel().copy()]

    def serve_channels(self) -> None:
        """Serve the free bodies' output channels from the stage states (a reduced model's confluences refresh
        them at the end of every step, before the outputs are sampled), sampled together as one array (``sample``);
        and a reduced canopy's, whose row its kernel writes."""
        model, keys, columns = self.model, [], []
        for name in self.free + sorted(model.massless, key=self.row.get):
            r = self.row[name]
            for quantity, part in (("position", ROW_POSITION), ("velocity", ROW_VELOCITY), ("rotation", ROW_ROTATION),
                                   ("angular_velocity", ROW_BODY_RATE)):
                model.add_channel(BodyChannel(name, quantity), lambda r=r, part=part: self.settled_rows()[r][part])
                keys.append(BodyChannel(name, quantity))
                columns.append((r, part))

        def split(samples):
            table = samples[:, :self.states.size].reshape(-1, *self.states.shape)
            return [table[:, r, part] for r, part in columns]
        model.add_channel_group(keys, self.sample, split)

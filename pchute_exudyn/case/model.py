"""The case: everything about a run, as frozen data (built and validated by ``pchute_exudyn.case.loader``).

Units are SI; angles are in degrees only where a name ends in ``_deg``. Body points are in body axes, relative to
the body's centre of mass. Attitude angles follow ``pchute_exudyn.physics.rotations``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ..physics.aerodynamics import CoefficientTable
from ..physics.air import AirMotion
from ..physics.apparent_mass import ApparentMass
from ..physics.atmosphere import Atmosphere
from ..physics.cluster import DEFAULT_DRAG_EFFICIENCY, drag_efficiency
from ..physics.deployment import PilotChute, StaticLine
from ..physics.inflation import Inflation, nominal_diameter, skipping, with_disreef_delays
from ..physics.interpolation import interpolate_held
from ..physics.line_materials import RatedLine
from ..physics.lines import LineLaw, LoadElongation
from ..physics.planet import FlatPlanet, Planet, StartFrame
from ..physics.runaway import RunawayLimits, fall_speed, wind_bound
from ..physics.step_rule import StepRule
from ..registries.columns import column
from ..registries.methods import INTEGRATORS
from .start import FlightConditions, Release


@dataclass(frozen=True)
class InitialState:
    """Initial state of a body or confluence.

    Attributes
    ----------
    altitude : float
        Geodetic altitude of the centre of mass (m).
    east, north : float
        Displacement from the start point along its local east and north axes (m).
    velocity_north, velocity_east, velocity_down : float
        Velocity relative to the planet surface in the start point's north/east/down axes (m/s).
    yaw_deg, pitch_deg, roll_deg : float
        Attitude angles (deg) relative to the descent frame (see ``physics.rotations``); bodies only.
    rate_x, rate_y, rate_z : float
        Angular velocity in body axes (rad/s); bodies only.
    conditions : FlightConditions or None
        The vehicle only: the Mach number, dynamic pressure, flight-path angle and heading the case gave instead of
        the altitude and velocity, which the loader found from them (``case.start.at_conditions``); None otherwise.
    """

    altitude: float
    east: float = 0.0
    north: float = 0.0
    velocity_north: float = 0.0
    velocity_east: float = 0.0
    velocity_down: float = 0.0
    yaw_deg: float = 0.0
    pitch_deg: float = 0.0
    roll_deg: float = 0.0
    rate_x: float = 0.0
    rate_y: float = 0.0
    rate_z: float = 0.0
    conditions: FlightConditions | None = None

    @property
    def velocity_enu(self) -> np.ndarray:
        """Velocity relative to the surface in east/north/up components (m/s)."""
        return np.array([self.velocity_east, self.velocity_north, -self.velocity_down])

    @property
    def angular_velocity(self) -> np.ndarray:
        """Body-axis angular velocity (rad/s)."""
        return np.array([self.rate_x, self.rate_y, self.rate_z])


@dataclass(frozen=True)
class Aerodynamics:
    """Aerodynamic model of a body (``physics.aerodynamics``): coefficients, each a constant or a table over Mach
    number and angle of attack (``physics.aerodynamics.CoefficientTable``).

    Attributes
    ----------
    reference_area : float
        S (m^2).
    axial_coefficient : CoefficientTable
        C_A (-).
    normal_coefficient : CoefficientTable
        C_N (-).
    center : tuple of 3 float
        Aerodynamic centre in body axes relative to the centre of mass (m): where the force acts, and the moment
        reference point of C_m.
    enabled : bool
        False switches the loads off (the body falls in vacuum).
    moment_coefficient : CoefficientTable or None
        C_m (-) about ``center``, with ``reference_length``; None: no static moment.
    pitch_damping : CoefficientTable or None
        C_mq + C_malphadot (-, per radian of q d / (2 V)); None: none.
    roll_damping : CoefficientTable or None
        C_lp (-, per radian of p d / (2 V)); None: none.
    reference_length : float or None
        d (m) of the moments; None when the body has none.
    """

    reference_area: float
    axial_coefficient: CoefficientTable
    normal_coefficient: CoefficientTable
    center: tuple
    enabled: bool = True
    moment_coefficient: CoefficientTable | None = None
    pitch_damping: CoefficientTable | None = None
    roll_damping: CoefficientTable | None = None
    reference_length: float | None = None

    def coefficients(self) -> dict:
        """The coefficients by the kernels' names (``axial``, ``normal``, ``moment``, ``pitch_damping``,
        ``roll_damping``; None where absent)."""
        return {"axial": self.axial_coefficient, "normal": self.normal_coefficient, "moment": self.moment_coefficient,
                "pitch_damping": self.pitch_damping, "roll_damping": self.roll_damping}

    @property
    def uses_mach(self) -> bool:
        """Whether a coefficient depends on Mach number."""
        return any(c is not None and c.uses_mach for c in self.coefficients().values())


@dataclass(frozen=True)
class Body:
    """A 6-DoF rigid body.

    Attributes
    ----------
    name : str
    mass : float or None
        Mass (kg); None for a fixed body.
    inertia : ndarray (3, 3) or None
        Inertia tensor about the centre of mass in body axes (kg m^2); None for a fixed body.
    points : dict of str to tuple
        Named points in body axes relative to the centre of mass (m): line attach points.
    initial : InitialState
    aerodynamics : Aerodynamics or None
    fixed : bool
        True for a body fixed to the ground (its points are anchors; thesis chapter 2's attach points).
    apparent_mass : ApparentMass or None
        The air the body carries (``physics.apparent_mass``); None: none.
    mass_includes_packed : bool
        The vehicle only: its stated mass (kg), inertia (kg m^2), centre of mass, points and initial state are those
        of the vehicle with the gear of its packed systems aboard, as one weighs and measures it
        (``case.carried.own_vehicle`` takes the gear out at load).
    """

    name: str
    mass: float | None
    inertia: np.ndarray | None
    points: dict
    initial: InitialState
    aerodynamics: Aerodynamics | None = None
    fixed: bool = False
    apparent_mass: ApparentMass | None = None
    mass_includes_packed: bool = False


@dataclass(frozen=True)
class Line:
    """An elastic, tension-only line from a body's attach point to its system's confluence.

    Attributes
    ----------
    name, body, point : str
        The line's name, the body holding its attach point and that point's name on it.
    free_length : float
        Unstretched length L0 (m).
    stiffness : float
        K (N/m).
    damping : float
        C (N s/m).
    load_elongation : LoadElongation or None
        A measured tension-strain table replacing K (L - L0) (``physics.lines``); None: the linear law.
    rating : RatedLine or None
        The material and breaking strength a case named (``physics.line_materials``; its table is the line's table).
    """

    name: str
    body: str
    point: str
    free_length: float
    stiffness: float
    damping: float
    load_elongation: LoadElongation | None = None
    rating: RatedLine | None = None

    @property
    def law(self) -> LineLaw:
        """The line's tension-only law (``physics.lines.LineLaw``): what every method evaluates."""
        return LineLaw(self.free_length, self.stiffness, self.damping, self.load_elongation)


@dataclass(frozen=True)
class Confluence:
    """The point where a system's lines meet.

    Attributes
    ----------
    mass : float
        Point mass m_c (kg) used by the full-mass method.
    initial : InitialState
        Position and velocity (attitude fields unused).
    """

    mass: float
    initial: InitialState


@dataclass(frozen=True)
class DragAreaSchedule:
    """Fraction of a canopy's full drag area against time since its system's deployment (inflation, reefing).

    Attributes
    ----------
    time : tuple of float
        Strictly increasing times since deployment (s), the first >= 0.
    fraction : tuple of float
        Fractions in [0, 1], linear between the points and held beyond the ends.
    """

    time: tuple
    fraction: tuple

    def __call__(self, since_deployment: float) -> float:
        """Fraction of the full drag area at ``since_deployment`` (s)."""
        if len(self.time) == 1:
            return self.fraction[0]
        return interpolate_held(self.time, self.fraction, since_deployment)


@dataclass(frozen=True)
class Contact:
    """Canopy-canopy contact within a cluster (``physics.contact``).

    Attributes
    ----------
    stiffness : float or None
        k (N/m) of every pair; None: each pair's default from its masses (``physics.contact``).
    damping : float or None
        c (N s/m) of every pair; None: the default fraction of each pair's critical damping.
    projected_diameter_ratio : float
        D_p / D_0 (-): a canopy's projected radius is this times half its nominal diameter sqrt(4 S / pi).
    """

    stiffness: float | None = None
    damping: float | None = None
    projected_diameter_ratio: float = 0.67

    def projected_radius(self, reference_area: float) -> float:
        """R_p (m) of a canopy with reference area ``reference_area`` (m^2): half its projected diameter."""
        return self.projected_diameter_ratio * 0.5 * nominal_diameter(reference_area)


@dataclass(frozen=True)
class ParachuteSystem:
    """A parachute system: a confluence and the lines meeting there (bridles from the vehicle, risers from its
    canopies). A system with several canopies is a cluster: each canopy its own body with its own riser(s).

    Attributes
    ----------
    name : str
    confluence : Confluence
    lines : tuple of Line
    canopies : tuple of str
        The bodies that are this system's parachutes (placed at deployment, removed at cut-away); empty: none.
    deploy_time : float or None
        Time (s) at which the system is placed at line stretch; None: present from the start as the case states.
    deploy_point : tuple (body, point) or None
        The vehicle point where the confluence goes at deployment (every bridle at free length).
    cutaway_time : float or None
        Time (s) at which the system is cut away: its lines stop acting and it leaves the model and the outputs.
    drag_area_schedule : DragAreaSchedule or None
        Multiplies each canopy's aerodynamic coefficients, against time since deployment (since t = 0 if present
        from the start).
    inflation : Inflation or None
        Or the fill-constant opening with reefing stages (``physics.inflation``), from deployment (line stretch), of
        each canopy on its own; a system has at most one of the two.
    drag_efficiency : tuple of float
        A cluster's eta(n) (-) for n = 1, 2, ... inflating canopies (``physics.cluster``), multiplying each
        canopy's C_A.
    deploy_spread : float or None
        Half-angle (rad) of the cone a cluster's risers lie on at line stretch; None: where the inflated canopies
        just touch (``physics.cluster.touching_spread``).
    contact : Contact or None
        Canopy-canopy contact of a cluster; None: none (a single canopy, or switched off).
    canopy_model : {"rigid", "reduced"}
        rigid: the canopy is a 6-DoF body (every method); reduced: with the SP method, a single canopy on a riser in
        series with one bridle is a massless drag point at the riser's end (its weight and inertia to first order,
        its attitude along its air-relative velocity: docs/models/reduced_canopy.md); full mass and the equilibrium
        point fly it rigid. A case that names none gets one at load (``case.canopy_choice``).
    canopy_model_chosen : bool
        True: the case did not name the canopy model (``canopy_model = "auto"``) and the loader chose it by the
        light-canopy rule (``case.canopy_choice``); False: the case named it.
    packed : bool
        True: until it deploys, the system's gear rides in the vehicle (``case.carried``): each canopy that leaves it
        and the confluence, as point masses (a packed bag), at the deploy point, so
        the suspended mass is the same before and after the deployment; False: it is absent until then. A case
        that does not say gets True for a system deployed during the run from a point of the vehicle
        (``case.carried.packed_by_default``).
    static_line : StaticLine or None
        A static line from the release aircraft (``physics.deployment.StaticLine``): the system deploys at its line
        stretch, its canopies moving with the aircraft; None: at ``deploy_time``.
    pilot_chute : PilotChute or None
        A pilot chute extracting the bag on its bridle (``physics.deployment.PilotChute``): the system deploys at its
        line stretch, its canopies moving with the pilot chute; None: at ``deploy_time`` (or by a static line).
    """

    name: str
    confluence: Confluence
    lines: tuple
    canopies: tuple = ()
    deploy_time: float | None = None
    deploy_point: tuple | None = None
    cutaway_time: float | None = None
    drag_area_schedule: DragAreaSchedule | None = None
    inflation: Inflation | None = None
    drag_efficiency: tuple = DEFAULT_DRAG_EFFICIENCY
    deploy_spread: float | None = None
    contact: Contact | None = None
    canopy_model: str = "rigid"
    canopy_model_chosen: bool = False
    packed: bool = False
    static_line: StaticLine | None = None
    pilot_chute: PilotChute | None = None

    @property
    def bag_anchor(self) -> StaticLine | PilotChute | None:
        """What holds the deployment bag back until line stretch (its static line or its pilot chute; None: the
        canopies leave with the vehicle)."""
        return self.static_line if self.static_line is not None else self.pilot_chute

    @property
    def cluster(self) -> bool:
        """Whether the system has more than one canopy."""
        return len(self.canopies) > 1

    def deployed_by(self, time: float) -> bool:
        """Whether the system has deployed by ``time`` (s) (one present from the start always has)."""
        return self.deploy_time is None or self.deploy_time <= time

    def active_at(self, time: float) -> bool:
        """Whether the system acts at ``time`` (s): deployed and not yet cut away."""
        return self.deployed_by(time) and (self.cutaway_time is None or time < self.cutaway_time)

    def end(self, canopy: str, failures, run_end: float) -> float:
        """When ``canopy`` of this system stops flying (s): the system's cut-away, the canopy's own (``failures``)
        or the end of the run ``run_end``, the first of them."""
        cuts = [t for t in (self.cutaway_time, failures.cutaway.get(canopy)) if t is not None]
        return min([run_end] + cuts)

    def risers(self, canopy: str) -> list:
        """The lines of the system attached to body ``canopy``."""
        return [line for line in self.lines if line.body == canopy]

    def with_bodies(self, bodies) -> ParachuteSystem:
        """The system as it acts while only ``bodies`` (names) move: without the lines of its canopies that are not
        among them (cut away, or never deployed); itself when none is missing."""
        absent = {canopy for canopy in self.canopies if canopy not in bodies}
        if not absent:
            return self
        return replace(self, lines=tuple(line for line in self.lines if line.body not in absent),
                       canopies=tuple(canopy for canopy in self.canopies if canopy not in absent))


@dataclass(frozen=True)
class Failures:
    """The failures a parachute system is qualified against, by canopy (``docs/models/cluster.md``).

    Attributes
    ----------
    not_inflated : tuple of str
        Canopies that never inflate.
    not_inflated_model : {"absent", "trailing"}
        absent: such a canopy never leaves the vehicle (its body and risers are not in the model; its mass rides
        with the vehicle from its system's deployment on, ``Case.mass_of``); trailing: it is deployed at line
        stretch like the others and trails on its risers, packed, with ``trailing_fraction`` of its drag area.
    trailing_fraction : float
        Drag-area fraction (-) of a trailing canopy that never inflates.
    cutaway : dict of str to float
        Canopy -> run time (s) at which it is cut away alone (its risers stop acting, it leaves the model).
    disreef_delay : dict of str to tuple of float
        Canopy -> time (s) added to each of its disreefs (stage 2..n starts): the reefing-line cutters firing late
        (> 0) or early (< 0).
    skipped_stages : dict of str to tuple of int
        Canopy -> reefed stages (numbers from 1) it skips.
    """

    not_inflated: tuple = ()
    not_inflated_model: str = "absent"
    trailing_fraction: float = 0.0
    cutaway: dict = field(default_factory=dict)
    disreef_delay: dict = field(default_factory=dict)
    skipped_stages: dict = field(default_factory=dict)

    def absent(self, canopy: str) -> bool:
        """Whether ``canopy`` never enters the model (it never inflates and stays in the vehicle)."""
        return canopy in self.not_inflated and self.not_inflated_model == "absent"

    def cut_by(self, canopy: str, time: float) -> bool:
        """Whether ``canopy`` has been cut away alone at or before ``time`` (s)."""
        cut = self.cutaway.get(canopy)
        return cut is not None and cut <= time


def canopy_opening(system: ParachuteSystem, canopy: str, failures: Failures):
    """How ``canopy`` of ``system`` opens with ``failures``: the system's ``Inflation`` with the canopy's cutter delays
    and skipped stages, or its ``DragAreaSchedule``, or the constant trailing fraction of a canopy that never
    inflates; None: fully open throughout. Raises ``physics.inflation.InflationError`` for delays or skips the
    opening cannot take."""
    if canopy in failures.not_inflated:
        return DragAreaSchedule((0.0,), (failures.trailing_fraction,))
    inflation = system.inflation
    if inflation is None:
        return system.drag_area_schedule
    if canopy in failures.disreef_delay:
        inflation = with_disreef_delays(inflation, failures.disreef_delay[canopy])
    if canopy in failures.skipped_stages:
        inflation = skipping(inflation, failures.skipped_stages[canopy])
    return inflation


@dataclass(frozen=True)
class SimulationSettings:
    """Run settings.

    Attributes
    ----------
    duration : float
        Simulated time (s).
    output_step : float
        Sampling interval of the stored time histories (s).
    method : str
        Default confluence method (a name in ``registries.methods.METHODS``).
    integrator : str
        Default integrator (one of ``registries.methods.INTEGRATORS``).
    steps : dict of str to float or str
        Default integration step (s) per method, keyed ``<method>`` for rk4 and ``<method>_implicit``; an RK4 key's
        may be ``"auto"`` (``registries.methods.ADAPTIVE_STEP``: adaptive steps).
    spectral_radius : float
        Numerical damping of the generalized-alpha integrator (spectral radius at infinity, 0..1).
    options : dict of str to options
        The options the case sets per method (``[simulation.<method>]``), as each method's validated ``Options``
        object; a method missing here runs with its defaults.
    ground_altitude : float
        Geodetic altitude of the ground (m; default 0, the planet's reference surface): every height, every trigger
        and wind above the ground and every output measure from it, whether or not the run stops there.
    descent_rate_events : tuple of float
        Descent rates (m/s) whose first downward crossing by the vehicle is logged (e.g. 9.144 = 30 ft/s).
    seed : int
        Seed of the triggers' sensor noise (``triggers.sensors``).
    step_rule : StepRule
        The adaptive steps of an RK4 run that sets no step (``physics.step_rule``).
    stop_at_ground : bool
        True: the run ends at touchdown, when the vehicle's centre of mass reaches ``ground_altitude``; False
        (``stop_at_ground = false``): it flies on below the ground, which stays where it is for everything else.
    """

    duration: float
    output_step: float
    method: str = "full"
    integrator: str = "rk4"
    steps: dict = field(default_factory=dict)
    spectral_radius: float = 0.9
    options: dict = field(default_factory=dict)
    ground_altitude: float = 0.0
    descent_rate_events: tuple = ()
    seed: int = 0
    step_rule: StepRule = field(default_factory=StepRule)
    stop_at_ground: bool = True

    def default_step(self, method: str, integrator: str) -> float | str | None:
        """The case's step (s, or "auto") for ``method`` with ``integrator``, or None when the case sets none."""
        return self.steps.get(INTEGRATORS[integrator].step_key(method))


@dataclass(frozen=True)
class Case:
    """Everything about a run.

    Attributes
    ----------
    name, description : str
    source : str
        Path of the case file (and the overrides applied), for provenance.
    planet : Planet or FlatPlanet
    start : StartFrame
        Local east/north/up frame of the start point.
    atmosphere : Atmosphere or None
        None when no body has aerodynamics.
    wind : Wind, PowerLawWind or None
        Steady horizontal wind (``physics.atmosphere.Wind``, ``physics.wind.PowerLawWind``); None for still air.
    turbulence : DrydenTurbulence or None
        ``physics.wind.DrydenTurbulence``; None for none.
    gusts : tuple of Gust
        ``physics.wind.Gust`` pulses.
    key_units : dict of str to str
        The unit of every case key the loader read ("m/s", "" for a pure number), by full dotted key.
    failures : Failures
        The canopies that fail, and how (none by default).
    velocities_relative_to : {"ground", "air"}
        What the case file's initial velocities were relative to (``case.start``); the ``InitialState`` velocities
        of a loaded case are relative to the ground either way.
    release : Release or None
        The release from an aircraft that gave the vehicle its initial velocity (``case.start``); None: none.
    warnings : tuple of str
        One line per implausible (but possible) value (``case.plausible``): printed with the run line and kept in
        ``summary.json``.
    triggers : dict of str to Trigger
        The events fired by a trigger (``triggers.definition``), by event name (``<system>.deploy``,
        ``<system>.cutaway``, ``<system>.disreef<k>``, ``<canopy>.cutaway``, ``<body>.separation``). Until it fires,
        such an event's time in the case is ``math.inf`` (pending); ``with_event_times`` sets it.
    separations : dict of str to Separation
        The bodies carried by the vehicle until they separate, by body name.
    bodies : dict of str to Body
    systems : dict of str to ParachuteSystem
    simulation : SimulationSettings
    vehicle : str
        Name of the body the summary reports (final altitude and position).
    """

    name: str
    description: str
    source: str
    planet: Planet | FlatPlanet
    start: StartFrame
    atmosphere: Atmosphere | None
    bodies: dict
    systems: dict
    simulation: SimulationSettings
    vehicle: str
    wind: object = None
    turbulence: object = None
    gusts: tuple = ()
    key_units: dict = field(default_factory=dict)
    failures: Failures = field(default_factory=Failures)
    velocities_relative_to: str = "ground"
    release: Release | None = None
    warnings: tuple = ()
    triggers: dict = field(default_factory=dict)
    separations: dict = field(default_factory=dict)
    tethers: dict = field(default_factory=dict)

    def unit_of(self, key: str) -> str | None:
        """The unit of ``key`` in override syntax (``main.lines.*.stiffness``, body and system names leading),
        None when no key read matches."""
        import fnmatch
        pattern = key.replace("[", "[[]")
        for full in self.key_units:
            if fnmatch.fnmatchcase(full, pattern) or fnmatch.fnmatchcase(full, "*." + pattern):
                return self.key_units[full]
        return None

    def air_motion(self) -> AirMotion:
        """The air's motion (``physics.air.AirMotion``): planet rotation, steady wind, turbulence and gusts."""
        return AirMotion(self.start, self.wind, self.turbulence, self.gusts)

    @cached_property
    def runaway_limits(self) -> RunawayLimits:
        """The speed and rates no body of this case reaches unless its run diverged (``physics.runaway``; computed once
        per case): from the
        bodies' start speeds and rates, the fall from the highest start altitude to the ground (to the reference
        surface, 0 m, when the case flies on below the ground), the air's largest speed up there and the planet's
        rotation."""
        starting = [body.initial for body in self.free_bodies() if body.initial is not None]
        top = max([state.altitude for state in starting], default=0.0)
        ground = self.simulation.ground_altitude if self.simulation.stop_at_ground else 0.0
        gravity = math.hypot(*self.start.gravity_scalar(0.0, 0.0, 0.0))   # at the start point, on the ground
        steady = self.wind.largest_speed(top) if self.wind is not None else 0.0
        sigma = self.turbulence.largest_sigma(top) if self.turbulence is not None else 0.0
        radius = 0.0 if isinstance(self.planet, FlatPlanet) else self.planet.equatorial_radius + top
        return RunawayLimits(
            start_speed=max([float(np.linalg.norm(state.velocity_enu)) for state in starting], default=0.0),
            fall_speed=fall_speed(gravity, top - ground),
            wind_speed=wind_bound(steady, sigma, [gust.amplitude for gust in self.gusts]),
            ground_speed=abs(self.planet.rotation_rate) * radius,
            start_rate=max([float(np.linalg.norm(state.angular_velocity)) for state in starting], default=0.0),
            radii={body.name: float(np.sqrt(np.linalg.eigvalsh(body.inertia)[0] / body.mass))
                   for body in self.free_bodies()})

    def drawing(self, body_name: str) -> dict:
        """How pictures draw body ``body_name`` (JSON-able): its role (vehicle, canopy or body), diameter (m: from
        its aerodynamic reference area, else twice its points' largest distance from the centre of mass), a canopy's
        apex direction in body axes (away from its points' mean, where its lines attach) and the body-axes points its
        lines attach to (m); a cluster's canopy also its ``envelope``: the projected diameter (m) and the column of
        the drag-area fraction that sizes it (``physics.contact``)."""
        body = self.bodies[body_name]
        points = np.array(list(body.points.values()), float).reshape(-1, 3)
        if body.aerodynamics is not None:
            diameter = float(nominal_diameter(body.aerodynamics.reference_area))
        else:
            diameter = float(2.0 * np.linalg.norm(points, axis=1).max()) if len(points) else 1.0
        apex = -points.mean(axis=0) if len(points) else np.array([-1.0, 0.0, 0.0])
        apex = apex / np.linalg.norm(apex) if np.linalg.norm(apex) > 0 else np.array([-1.0, 0.0, 0.0])
        canopy = self.canopy_system(body_name) is not None or (body_name != self.vehicle
                                                               and body.aerodynamics is not None)
        attached = sorted({line.point for system in self.systems.values() for line in system.lines
                           if line.body == body_name})
        drawing = {"role": "vehicle" if body_name == self.vehicle else "canopy" if canopy else "body",
                   "diameter": diameter, "apex": apex.tolist(), "fixed": body.fixed,
                   "line_points": [list(map(float, body.points[point])) for point in attached]}
        system = self.canopy_system(body_name)
        if system is not None and system.cluster:   # drawn as its envelope: projected diameter times sqrt(f)
            drawing["envelope"] = {"diameter": 2.0 * (system.contact or Contact()).projected_radius(
                body.aerodynamics.reference_area), "fraction": column("{owner}_drag_area_fraction", body_name)}
        return drawing

    def canopy_system(self, body_name: str):
        """The system whose canopy ``body_name`` is, or None."""
        for system in self.systems.values():
            if body_name in system.canopies:
                return system
        return None

    def active_bodies(self, time: float) -> list:
        """Free bodies present at ``time`` (s): every body but the canopies of systems not active then, the canopies
        cut away alone by then, those that never leave the vehicle (``Failures``) and the bodies it still carries
        (``separations``)."""
        active = []
        for body in self.free_bodies():
            if body.name in self.separations and self.separations[body.name].carried_at(time):
                continue   # rides with the vehicle (case.carried)
            system = self.canopy_system(body.name)
            if system is None or (self.acting(system, time) and not self.failures.absent(body.name)
                                  and not self.failures.cut_by(body.name, time)):
                active.append(body.name)
        return active

    def mass_of(self, body_name: str, time: float) -> float:
        """The mass (kg) body ``body_name`` flies with at ``time`` (s): its own, and for the vehicle also that of each
        canopy that never leaves it (``Failures.absent``) from its system's deployment on (a deployed canopy brings
        its mass into the model then; one that stays packed adds it to the vehicle instead, so the system's mass is
        the same either way). A ``packed`` system's such canopies ride at its deploy point throughout
        (``case.carried``), not here."""
        mass = self.bodies[body_name].mass
        if body_name != self.vehicle or not self.failures.not_inflated:
            return mass
        for system in self.systems.values():
            if system.deployed_by(time) and not system.packed:
                mass += sum(self.bodies[c].mass for c in system.canopies if self.failures.absent(c))
        return mass

    def acting(self, system: ParachuteSystem, time: float) -> bool:
        """Whether ``system`` acts at ``time`` (s): deployed, not cut away, and, if it has canopies, with one of them
        out of the vehicle and not cut away alone (a system whose every canopy stays packed deploys nothing)."""
        if not system.active_at(time):
            return False
        failures = self.failures
        return not system.canopies or any(not failures.absent(c) and not failures.cut_by(c, time)
                                          for c in system.canopies)

    def opening_of(self, system: ParachuteSystem, canopy: str):
        """How ``canopy`` of ``system`` opens (``canopy_opening`` with the case's failures)."""
        return canopy_opening(system, canopy, self.failures)

    def drag_efficiency(self, system: ParachuteSystem, canopy: str, bodies) -> float:
        """eta (-) of ``canopy``'s C_A while ``bodies`` (names) are present: the cluster's efficiency for the number
        of its canopies present that inflate; 1 for a single canopy and for one that never inflates."""
        if not system.cluster or canopy in self.failures.not_inflated:
            return 1.0
        inflating = [c for c in system.canopies if c in bodies and c not in self.failures.not_inflated]
        return drag_efficiency(system.drag_efficiency, len(inflating))

    def opening_label(self, system: ParachuteSystem, canopy: str) -> str:
        """Output label of a canopy's opening: the system's name for a single canopy, the canopy's in a cluster."""
        return canopy if system.cluster else system.name

    def free_bodies(self):
        """The bodies that move (not fixed), in case order."""
        return [body for body in self.bodies.values() if not body.fixed]

    def lines(self):
        """Every (system, line) pair in case order."""
        return [(system, line) for system in self.systems.values() for line in system.lines]

    def line_label(self, system: ParachuteSystem, line: Line) -> str:
        """Output label of a line: ``<line>`` with one system, ``<system>_<line>`` with several."""
        return line.name if len(self.systems) == 1 else f"{system.name}_{line.name}"

    def confluence_label(self, system: ParachuteSystem) -> str:
        """Output prefix of a confluence: ``confluence`` with one system, ``<system>_confluence`` with several."""
        return "confluence" if len(self.systems) == 1 else f"{system.name}_confluence"

"""The lines of the case ``pchute new`` writes for a vehicle under one canopy or a cluster (``DescentWriter``; a
rocket's dual deploy: ``authoring.rocket``): a complete, commented, runnable case file.

The vehicle hangs under one canopy (or a cluster) on ``bridles`` lines that meet at a confluence, and one riser per
canopy from the confluence to the canopy's suspension-line apex (the canopy body's ``riser`` point). Everything is
placed in the descent attitude, in steady descent: every line stretched by its share of the steady load (LINE_STRAIN),
the confluence where the stretched bridles put it, all moving with the air and straight down through it at
``speed``; or released from an aircraft, every system placed at line stretch at its deployment; or at line stretch at
flight conditions (``mach``, ``dynamic_pressure``; authoring.flight_start). Sizing rules (each written into the file
beside its number, and in ``docs/tutorial.md``):

* canopy: reference area S0 = drag area / C_D0 of its type (or from the nominal diameter, S0 = pi D0^2 / 4); mass
  CANOPY_AREAL_MASS x S0 unless given; the inertia of a thin hemispherical shell of the projected radius
  R_p = 0.67 D0 / 2 about its own centre, but the centre of mass (and the aerodynamic centre) at the skirt's centre,
  where the suspension lines of length L_s from the apex end (sqrt(L_s^2 - R_p^2) from it): a simplification, the
  shell's own centre lies R_p / 2 higher; C_A(alpha') C_D0 to AXIAL_FLAT_TO_DEG, then to 0 edge-on, and C_N(alpha')
  the zero-trim canopy table of MER to 60 deg, then to EDGE_ON_NORMAL;
* vehicle: a solid cylinder of the given diameter, half as tall, the bridles on a circle of 0.35 diameters on its
  top face; no aerodynamic load (at flight conditions a table of C_A = 0, so that the run records its Mach number);
* lines: stiffness from LINE_STRAIN of stretch under the vehicle's weight in steady descent, damping
  LINE_DAMPING_TIME x stiffness (MER's ratio); the confluence CONFLUENCE_MASS_FRACTION of the vehicle's mass;
* the run: SP to touchdown on the reference surface, RK4 at adaptive steps (no ``[simulation.steps]``;
  docs/models/step_control.md); with one bridle and one light canopy (LIGHT_CANOPY_TIME), a reduced canopy
  (``canopy_model = "reduced"``) unless it opens by an inflation (a release).
"""


from __future__ import annotations

import json
import math

import numpy as np

from ..case.canopy_choice import LIGHT_CANOPY_TIME
from ..physics.cluster import spread_directions
from ..physics.inflation import nominal_diameter
from ..physics.rotations import attitude_angles_deg, attitude_matrix
from ..physics.shapes import hemispherical_shell_inertia, solid_cylinder_inertia
from ..registries.canopy_types import CANOPY_TYPES
from ..registries.columns import column
from .flight_start import header_words, vehicle_rows
from .layout import Layout
from .planets import PLANETS
from .rules import (
    AXIAL_FLAT_TO_DEG,
    EDGE_ON_NORMAL,
    LINE_DAMPING_TIME,
    LINE_STRAIN,
    NORMAL_COEFFICIENT,
    OVERINFLATION_DECAY,
)
from .text import number as _n
from .text import vector as _vector


class DescentWriter:
    """The case file's lines, section by section, from the sizes of ``authoring.layout``."""

    def __init__(self, plan: Layout):
        self.plan, self.c = plan, plan.choices
        c = self.c
        self.height, self.attach_radius, self.rise = plan.height, plan.attach_radius, plan.rise()
        self.confluence_altitude = plan.altitude + 0.5 * self.height + self.rise
        self.speed = plan.steady_rate(plan.altitude) if c.speed is None else c.speed
        self.airspeed = c.release_airspeed if c.released else plan.airspeed   # at deployment (m/s); None: steady

    def lines(self) -> list:
        return self.header() + self.vehicle() + self.canopies() + self.system() + self.simulation()

    def header(self) -> list:
        c, p = self.c, self.plan
        planet_lines, atmosphere = PLANETS[c.planet][:2]
        canopy_altitude = column("{owner}_altitude", self.canopy_names()[0])
        ground = c.ground_elevation or 0.0
        return [f"# {c.name}: written by `pchute new` (pchute_exudyn.authoring.descent; docs/tutorial.md). Units SI;",
                "# angles in degrees only where named _deg. " + self.start_words()[0], *self.start_words()[1:],
                f"# Suspended mass {_n(p.total_mass)} kg; steady rate of descent sqrt(2 m g / (rho n C_V S0)) = "
                f"{p.steady_rate(p.altitude):.3f} m/s at the start,",
                f"# {p.steady_rate(ground):.3f} m/s at {ground:g} m: "
                + ("C_V = C_D0 for one canopy" if c.canopies == 1 else
                   f"C_V = eta C_D0 cos(theta) + C_N(theta) sin(theta) = {p.vertical_coefficient:.5g}, the drag "
                   f"efficiency eta = {p.drag_efficiency:g}\n# of {c.canopies} canopies flying theta = "
                   f"{math.degrees(p.spread):.2f} deg off the vertical (where their envelopes touch)") + ".",
                "# Reported altitudes are each body's centre of mass (`vehicle_altitude`: the vehicle's); the canopy's",
                f"# drag acts {_n(self.plan.canopy_height)} m higher in steady descent, at its aerodynamic centre "
                f"(`{canopy_altitude}`).", "",
                "[case]", f"name = {json.dumps(c.name)}",
                f'description = "{c.mass:g} kg vehicle under {self.canopy_words()} ({c.planet})"',
                'vehicle = "vehicle"', "", "[planet]", *planet_lines, "",
                "[start]                                    # the start point",
                f"latitude_deg = {_n(c.latitude or 0.0)}", f"longitude_deg = {_n(c.longitude or 0.0)}",
                "# initial velocities relative to the air (the wind at the vehicle's "
                "start altitude): the descent starts moving with the wind", 'velocities_relative_to = "air"',
                *self.release(), "",
                "[atmosphere]", f'model = "{atmosphere}"', *self.wind(), ""]

    def start_words(self) -> list:
        """The header's lines on how the run starts."""
        c = self.c
        if c.mach is not None:
            return header_words(c, self.plan.altitude, self.airspeed)
        if c.released:
            when = f"{c.static_line_time:g} s later" if c.static_line_length is None else \
                f"when a {c.static_line_length:g} m static line and the lines are out"
            return [f"Released from an aircraft at {_n(c.release_airspeed)} m/s through the air",
                    f"# (heading {c.release_heading_deg:g} deg, flight path {c.release_flight_path_deg:g} deg); the "
                    f"canopies deploy at line stretch {when}", f"# and open with the "
                    f"fill-constant law of a {c.canopy_type} canopy ([systems.main.inflation])."]
        rate = "the steady rate there" if c.speed is None else "as chosen"
        return [f"In steady descent: every line stretched {LINE_STRAIN:.1%} by its share of",
                "# the steady load, the confluence where the stretched bridles put it, everything moving with the air "
                "and down", f"# through it at {_n(self.speed)} m/s ({rate})."]

    def release(self) -> list:
        c = self.c
        if not c.released:
            return []
        return ["[start.release]                            # released from an aircraft: the vehicle leaves at the "
                "aircraft's velocity through the air",
                f"airspeed = {_n(c.release_airspeed)}   # m/s", f"heading_deg = {_n(c.release_heading_deg)}   # deg, "
                "clockwise from north", f"flight_path_deg = {_n(c.release_flight_path_deg)}   # deg, climbing > 0"]

    def wind(self) -> list:
        c = self.c
        if c.wind_speed == 0.0:
            return ["# [atmosphere.wind] (none): e.g. speed = 6.0 and from_deg = 270.0 for a 6 m/s west wind"]
        return ["[atmosphere.wind]                          # constant with altitude",
                f"speed = {_n(c.wind_speed)}   # m/s",
                f"from_deg = {_n(c.wind_from_deg)}   # deg: where it comes from, clockwise from north"]

    def canopy_words(self) -> str:
        c = self.c
        kind = c.canopy_type.replace("_", "-")
        return f"a {kind} canopy" if c.canopies == 1 else f"a cluster of {c.canopies} {kind} canopies"

    def vehicle(self) -> list:
        c = self.c
        rows = ["[bodies.vehicle]                           # a solid cylinder, half as tall as its diameter",
                f"mass = {_n(c.mass)}                             # kg",
                f"inertia = {_vector(solid_cylinder_inertia(c.mass, c.diameter, self.height))}   # kg m^2, "
                "principal, body axes",
                "[bodies.vehicle.points]                    # m, body axes from the centre of mass (+x down): "
                "the bridles' attach points"]
        for i, point in enumerate(self.attach_points(), start=1):
            rows.append(f"bridle{i} = {_vector(point)}")
        if c.deploys:
            rows.append(f"line_stretch = {_vector([-(0.5 * self.height + self.plan.rise(0.0)), 0.0, 0.0])}   # the "
                        "confluence at deployment: every bridle at its free length")
        if c.mach is not None:
            return rows + vehicle_rows(c, self.plan.altitude, self.airspeed) + [""]
        rows += ["[bodies.vehicle.initial]                   # attitude: body +x down (the descent attitude)",
                 f"altitude = {_n(c.altitude)}                        # m: the centre of mass"]
        if not c.released:
            rows.append(f"velocity_down = {_n(self.speed)}                  # m/s")
        return rows + [""]

    def attach_points(self) -> list:
        c = self.c
        if c.bridles == 1:
            return [[-0.5 * self.height, 0.0, 0.0]]
        angles = [2.0 * math.pi * i / c.bridles for i in range(c.bridles)]
        return [[-0.5 * self.height, self.attach_radius * math.cos(a), self.attach_radius * math.sin(a)]
                for a in angles]

    def canopy_names(self) -> list:
        return ["canopy"] if self.c.canopies == 1 else [f"canopy{i}" for i in range(1, self.c.canopies + 1)]

    def canopies(self) -> list:
        c, p = self.c, self.plan
        up = np.array([-1.0, 0.0, 0.0])    # descent frame (x down, y east, z south)
        directions = spread_directions(-up, np.array([0.0, 1.0, 0.0]), self.plan.spread, c.canopies)
        confluence = np.array([-self.confluence_altitude, 0.0, 0.0])
        rows = []
        for name, toward_confluence in zip(self.canopy_names(), directions):
            centre = confluence - self.plan.canopy_reach * toward_confluence
            yaw, pitch, roll = self.attitude(toward_confluence)
            rows += [f"[bodies.{name}]                            # {c.canopy_type}: a hemispherical shell of the "
                     "projected radius",
                     f"mass = {_n(p.canopy_mass)}                           # kg"
                     + (" (0.15 kg per m^2 of S0, assumed)" if c.canopy_mass is None else ""),
                     f"inertia = {_vector(hemispherical_shell_inertia(p.canopy_mass, p.projected_radius))}   # kg m^2",
                     f"points.riser = [{_n(p.apex_distance)}, 0.0, 0.0]   # m: the suspension lines' apex, "
                     f"{_n(c.suspension_line_length or nominal_diameter(p.reference_area))} m lines to the "
                     "skirt", *([] if c.deploys else self.canopy_initial(name, centre, yaw, pitch, roll)),
                     *self.aerodynamics(name), ""]
        return rows

    def canopy_initial(self, name: str, centre, yaw: float, pitch: float, roll: float) -> list:
        """A canopy's initial table in steady descent (a released one gets its state at line stretch)."""
        return [f"[bodies.{name}.initial]", f"altitude = {_n(-centre[0])}                  # m",
                *([] if self.c.canopies == 1 else [f"east = {_n(centre[1])}", f"north = {_n(-centre[2])}",
                                                   f"yaw_deg = {_n(yaw)}", f"pitch_deg = {_n(pitch)}",
                                                   f"roll_deg = {_n(roll)}"]),
                f"velocity_down = {_n(self.speed)}"]

    @staticmethod
    def attitude(toward_confluence) -> tuple:
        """Attitude angles (deg) that turn a canopy's +x onto ``toward_confluence`` (descent frame), no roll."""
        down = np.asarray(toward_confluence, float)
        yaw, pitch = math.atan2(down[1], down[0]), math.asin(-down[2])
        angles = attitude_angles_deg(attitude_matrix(math.degrees(yaw), math.degrees(pitch), 0.0))
        return tuple(float(a) for a in angles)

    def aerodynamics(self, name: str) -> list:
        c, p = self.c, self.plan
        alpha, value = NORMAL_COEFFICIENT
        return [f"[bodies.{name}.aerodynamics]",
                f"reference_area = {_n(p.reference_area)}               # m^2: S0, D0 = "
                f"{nominal_diameter(p.reference_area):.4f} m",
                f"axial_coefficient = {{ alpha_deg = [0.0, {AXIAL_FLAT_TO_DEG}, 90.0], value = "
                f"[{_n(c.canopy_drag_coefficient)}, {_n(c.canopy_drag_coefficient)}, 0.0] }}",
                "# C_A: C_D0 " + (f"of a {c.canopy_type} ({CANOPY_TYPES[c.canopy_type].drag_source}, mid-range)"
                                  if c.drag_coefficient is None
                                  else "as given") + f" to {AXIAL_FLAT_TO_DEG:g} deg, then to 0 edge-on (assumed)",
                "center = [0.0, 0.0, 0.0]                   # m: at the centre of mass",
                f"[bodies.{name}.aerodynamics.normal_coefficient]   # MER's zero-trim canopy table to 60 deg, "
                f"then the edge-on canopy's cross-flow drag ({EDGE_ON_NORMAL:g} at 90 deg, assumed)",
                f"alpha_deg = {alpha}", f"value = {value}"]

    def system(self) -> list:
        c, p = self.c, self.plan
        weight = c.mass * p.gravity
        bridle_tension = weight / max(c.bridles, 1) * (p.bridle_length * (1.0 + LINE_STRAIN) / self.rise)
        riser_tension = (weight + p.confluence_mass * p.gravity) / c.canopies / math.cos(self.plan.spread)
        rows = ["[systems.main]", f"canopies = {self.canopy_names()}".replace("'", '"') if c.canopies > 1
                else 'canopy = "canopy"', *self.canopy_model(), *self.deployment(), "[systems.main.confluence]",
                f"mass = {_n(p.confluence_mass)}                            # kg (0.2 % of the vehicle's, assumed)"]
        if not c.deploys:
            rows += ["[systems.main.confluence.initial]", f"altitude = {_n(self.confluence_altitude)}   # m: where "
                     "the stretched bridles put it", f"velocity_down = {_n(self.speed)}"]
        rows.append("")
        for i in range(1, c.bridles + 1):
            rows += self.line(f"bridle{i}", f"vehicle.bridle{i}", p.bridle_length, bridle_tension)
        for name in self.canopy_names():
            rows += self.line(f"riser_{name}" if c.canopies > 1 else "riser", f"{name}.riser", p.riser_length,
                              riser_tension)
        return rows

    def canopy_model(self) -> list:
        """``canopy_model = "reduced"`` for one light canopy on one bridle (LIGHT_CANOPY_TIME), unless it opens by an
        inflation (a release), which a reduced canopy refuses; nothing (rigid) otherwise."""
        c = self.c
        if c.bridles != 1 or c.canopies != 1:
            return []
        time = self.plan.canopy_drag_time(self.airspeed if c.deploys else self.speed)
        if time >= LIGHT_CANOPY_TIME:
            return []
        why = f"its drag time constant m / (rho C_D0 S0 V) = {time:.2g} s < {LIGHT_CANOPY_TIME:g} s"
        if c.deploys:
            return [f"# canopy_model: rigid (the default), though light ({why}): it opens by an inflation, which a "
                    "reduced canopy refuses"]
        return [f'canopy_model = "reduced"   # light ({why}): a drag point at the riser\'s end, without its fast '
                "modes (docs/models/reduced_canopy.md)"]

    def deployment(self) -> list:
        """A released vehicle's system: deployed at line stretch after the static line's time (at flight conditions:
        at the start), opening by its type's fill constant (CANOPY_TYPES)."""
        c = self.c
        if not c.deploys:
            return []
        canopy = CANOPY_TYPES[c.canopy_type]
        fill, exponent, overinflation = canopy.fill_constant, canopy.opening_exponent, canopy.overinflation
        fill_time = fill * nominal_diameter(self.plan.reference_area) / max(self.airspeed, 1.0)
        decay = OVERINFLATION_DECAY * fill_time if overinflation > 1.0 else 0.0
        return [*self.deploy_when(), 'deploy_point = "vehicle.line_stretch"',
                f"[systems.main.inflation]                   # one stage from line stretch; {c.canopy_type} values "
                "(pchute_exudyn/registries/canopy_types.py, docs/tutorial.md)",
                "stage_start = [0.0]                        # s after line stretch", "fraction = [1.0]",
                f"fill_constant = [{_n(fill)}]   # -: fill time n D0 / V, V the canopy's speed at line stretch",
                f"exponent = [{_n(exponent)}]   # -: the drag area grows as (t / t_fill)^exponent",
                f"overinflation = {_n(overinflation)}   # -: the drag area's overshoot at the end of the fill",
                f"overinflation_decay = {_n(decay)}   # s: a quarter of the fill time at the "
                f"{'release' if c.released else 'start'} airspeed (assumed)"]

    def deploy_when(self) -> list:
        """When the system deploys: at a static line's line stretch, after the static line's time, or at the start
        (flight conditions)."""
        c = self.c
        if not c.released:
            return ["deploy_time = 0.0   # s: line stretch at the start (flight conditions)"]
        if c.static_line_length is None:
            return [f"deploy_time = {_n(c.static_line_time)}   # s: the static line's time from the release to line "
                    "stretch"]
        return ["# the bag on a static line from the aircraft: line stretch when it and the lines are out; length (m)"
                " from the aircraft's anchor cable to the bag,", "# anchor (m) where that cable is at the release, "
                "from the vehicle's centre of mass (east, north, up)", f"static_line = {{ length = "
                f"{_n(c.static_line_length)}, anchor = [0.0, 0.0, 0.0] }}"]

    @staticmethod
    def line(name: str, attach: str, length: float, tension: float) -> list:
        """A line's table: free ``length`` (m), stiffness from LINE_STRAIN under ``tension`` (N)."""
        stiffness = tension / (LINE_STRAIN * length)
        return [f"[systems.main.lines.{name}]", f'attach = "{attach}"', f"free_length = {_n(length)}   # m",
                f"stiffness = {_n(stiffness)}   # N/m: 2.5 % stretch under its share of the vehicle's weight",
                f"damping = {_n(LINE_DAMPING_TIME * stiffness)}   # N s/m: 0.01 s x stiffness", ""]

    def simulation(self) -> list:
        c, p = self.c, self.plan
        before = (c.static_line_time if c.released else 0.0) + 30.0 if c.deploys else 0.0   # the deployment, opening
        ground = c.ground_elevation or 0.0
        duration = 10.0 * math.ceil((1.25 * (p.altitude - ground) / p.steady_rate(ground) + 10.0 + before) / 10.0)
        return ["[simulation]", f"duration = {_n(duration)}   # s: an upper bound; the run ends at touchdown "
                f"(the vehicle's centre of mass at {ground:g} m)", "output_step = 0.02                         # s",
                *([] if c.ground_elevation is None else [f"ground_altitude = {_n(ground)}   # m"]),
                'method = "sp"', 'integrator = "rk4"', "# No [simulation.steps]: RK4 takes adaptive steps "
                "(docs/models/step_control.md); to fix one, `[simulation.steps] sp = 0.01` or `--dt 0.01`."]

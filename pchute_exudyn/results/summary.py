"""The typed run summary and its events; ``RunSummary.to_dict`` is what ``summary.json`` holds.

Events, in time order in the summary (times in s from the start of the run):

* ``start``: the run begins (t = 0);
* ``deploy`` / ``cutaway``: a parachute system is placed at line stretch / leaves the model (``system``); a cutaway
  with ``canopy`` cuts that canopy of a cluster away alone (``case.model.Failures``);
* ``stage_start`` / ``disreef``: a system with an inflation (``physics.inflation``) starts its first stage at line
  stretch / a later stage at its disreef time (``system``, ``stage`` from 1, the measured air ``speed`` in m/s and
  the ``fill_time`` in s it gives); in a cluster each canopy opens on its own and its events name the ``canopy``;
* ``fill_end``: a stage's fill ends (``system``, ``stage``; ``canopy`` in a cluster);
* ``contact_start`` / ``contact_end``: two canopies of a cluster (``canopies``) begin / stop touching (their
  envelopes overlap, ``physics.contact``); the end gives the largest ``overlap`` (m) of that contact;
* ``descent_rate``: the vehicle's descent rate first falls through ``value`` (m/s) after the last deployment;
* ``touchdown``: the vehicle's centre of mass reaches the ground altitude, with its velocity relative to the ground
  (m/s): its total ``speed``, its ``descent_rate`` (down the local vertical) and ``horizontal_speed_over_ground``
  (across it), and ``vertical_speed`` and ``horizontal_speed`` along the start point's axes (``TouchdownEvent``).
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, field, fields
from typing import ClassVar

import numpy as np

from ..case.events import DISREEF
from ..physics.planet import FlatPlanet
from ..registries.columns import UNNAMED_VEHICLE, column


@dataclass(frozen=True)
class Event:
    """Something that happened at ``time`` (s); ``kind`` is its name in ``summary.json``."""

    time: float
    kind: ClassVar[str] = ""

    def to_dict(self) -> dict:
        """The event as ``summary.json`` holds it (an optional field, ``OPTIONAL``, only when set)."""
        return {"event": self.kind, "time": self.time,
                **{f.name: getattr(self, f.name) for f in fields(self)
                   if f.name != "time" and not (f.metadata.get("optional") and getattr(self, f.name) is None)}}


@dataclass(frozen=True)
class RecordedEvent(Event):
    """An event read back from a ``summary.json`` whose entries no Event class holds (a kind of a later version):
    its ``kind`` and entries as written, each entry also read as an attribute (``event.system``)."""

    kind: str = ""
    entries: dict = field(default_factory=dict)

    def __getattr__(self, name: str):
        if name.startswith("__") or name == "entries":   # not an entry: copy and pickle look these up
            raise AttributeError(name)
        try:
            return self.entries[name]
        except KeyError:
            raise AttributeError(f"{self.kind} event has no entry {name!r}") from None

    def to_dict(self) -> dict:
        return {"event": self.kind, "time": self.time, **self.entries}


def event_from_dict(data: dict) -> Event:
    """The Event of a ``summary.json`` event entry: its class by ``kind``, else a ``RecordedEvent``."""
    kinds = {c.kind: c for c in _subclasses(Event) if c.kind}
    entries = {k: v for k, v in data.items() if k not in ("event", "time")}
    kind = kinds.get(data["event"]) if isinstance(data.get("event"), str) else None
    if kind is not None and set(entries) <= {f.name for f in fields(kind)}:
        return kind(data.get("time"), **entries)
    return RecordedEvent(data.get("time"), data.get("event", ""), entries)


def _subclasses(cls) -> list:
    return [c for sub in cls.__subclasses__() for c in (sub, *_subclasses(sub))]


OPTIONAL = {"optional": True}
"""Metadata of an event field written only when it is set (a cluster's canopy)."""


@dataclass(frozen=True)
class StartEvent(Event):
    moving_with: str | None = field(default=None, metadata=OPTIONAL)   # "air": the start moved with the wind
    release: dict | None = field(default=None, metadata=OPTIONAL)      # airspeed (m/s), heading, flight path (deg)
    kind: ClassVar[str] = "start"

    @classmethod
    def of(cls, case) -> StartEvent:
        """The start of ``case`` (``case.start``: moving with the air, released from an aircraft)."""
        release = case.release
        return cls(0.0, "air" if case.velocities_relative_to == "air" else None,
                   None if release is None else {"airspeed": release.airspeed, "heading_deg": release.heading_deg,
                                                 "flight_path_deg": release.flight_path_deg})


@dataclass(frozen=True)
class DeployEvent(Event):
    system: str = ""
    trigger: dict | None = field(default=None, metadata=OPTIONAL)   # what fired it (``run.sequence``)
    kind: ClassVar[str] = "deploy"

    @property
    def name(self) -> str:
        return f"{self.system}.deploy"


@dataclass(frozen=True)
class CutawayEvent(Event):
    system: str = ""
    canopy: str | None = field(default=None, metadata=OPTIONAL)   # one canopy of a cluster cut away alone
    trigger: dict | None = field(default=None, metadata=OPTIONAL)
    kind: ClassVar[str] = "cutaway"

    @property
    def name(self) -> str:
        return f"{self.canopy or self.system}.cutaway"


@dataclass(frozen=True)
class SeparationEvent(Event):
    body: str = ""
    relative_speed: float = 0.0   # m/s, along the separation direction
    trigger: dict | None = field(default=None, metadata=OPTIONAL)
    kind: ClassVar[str] = "separation"

    @property
    def name(self) -> str:
        return f"{self.body}.separation"


@dataclass(frozen=True)
class StageStartEvent(Event):
    system: str = ""
    stage: int = 1
    speed: float = 0.0       # m/s, the canopy's air speed at the stage start
    fill_time: float = 0.0   # s
    canopy: str | None = field(default=None, metadata=OPTIONAL)   # the canopy, in a cluster
    trigger: dict | None = field(default=None, metadata=OPTIONAL)
    mach: float | None = field(default=None, metadata=OPTIONAL)          # -, a supersonic opening's line stretch
    load_factor: float | None = field(default=None, metadata=OPTIONAL)   # -, its C_k there
    kind: ClassVar[str] = "stage_start"

    @property
    def name(self) -> str:
        return f"{self.system}.{DISREEF}{self.stage}"


@dataclass(frozen=True)
class DisreefEvent(StageStartEvent):
    kind: ClassVar[str] = "disreef"


@dataclass(frozen=True)
class FillEndEvent(Event):
    system: str = ""
    stage: int = 1
    canopy: str | None = field(default=None, metadata=OPTIONAL)   # the canopy, in a cluster
    kind: ClassVar[str] = "fill_end"


@dataclass(frozen=True)
class ContactStartEvent(Event):
    canopies: tuple = ()     # the two canopies whose envelopes begin to overlap
    kind: ClassVar[str] = "contact_start"


@dataclass(frozen=True)
class ContactEndEvent(Event):
    canopies: tuple = ()
    overlap: float = 0.0     # m, the largest overlap of the contact (at the output step's resolution)
    kind: ClassVar[str] = "contact_end"


@dataclass(frozen=True)
class DescentRateEvent(Event):
    value: float = 0.0    # m/s
    kind: ClassVar[str] = "descent_rate"


@dataclass(frozen=True)
class TouchdownEvent(Event):
    """The vehicle's centre of mass at the ground, with its velocity relative to the ground split two ways: along the
    start point's axes (``vertical_speed``, ``horizontal_speed``) and along the local vertical at the touchdown point
    (``descent_rate``, ``horizontal_speed_over_ground``); the two agree on a flat planet and part by the planet's
    curvature over the drift (a 10 km drift on Earth tilts the vertical by 1.6 mrad). ``descent_rate`` squared plus
    ``horizontal_speed_over_ground`` squared is ``speed`` squared. Its ``time`` and place (``altitude``, ``east``,
    ``north``) are interpolated to the crossing of the ground, where the run's last sample may lie a step past it.
    """

    speed: float = 0.0              # m/s, total speed relative to the ground (all three components)
    vertical_speed: float = 0.0     # m/s, along the start point's up axis, downward positive
    horizontal_speed: float = 0.0   # m/s, across the start point's up axis
    descent_rate: float | None = field(default=None, metadata=OPTIONAL)   # m/s, along the local vertical, down +
    horizontal_speed_over_ground: float | None = field(default=None, metadata=OPTIONAL)   # m/s, across it
    altitude: float | None = field(default=None, metadata=OPTIONAL)   # m, the vehicle's centre of mass then
    east: float | None = field(default=None, metadata=OPTIONAL)       # m, along the start point's axes
    north: float | None = field(default=None, metadata=OPTIONAL)      # m
    kind: ClassVar[str] = "touchdown"

    @classmethod
    def from_crossing(cls, time: float, ground_velocity, down, place=(None, None, None)) -> TouchdownEvent:
        """From the crossing time (s), the ground-relative velocity (m/s, east/north/up), the unit vector down the
        local vertical there (the same axes) and the vehicle's altitude, east and north then (m)."""
        v = np.asarray(ground_velocity, float)
        descent = float(np.dot(v, down))
        level = v - descent * np.asarray(down, float)
        return cls(float(time), float(np.linalg.norm(v)), float(-v[2]), float(np.hypot(v[0], v[1])), descent,
                   float(np.linalg.norm(level)), *place)


def first_fall_through(time, values, level: float, after: float = -math.inf) -> float | None:
    """The first time (s) at or after ``after`` that ``values`` falls from above ``level`` to it or below between
    two finite samples, linear between them; None if it never does (``time`` in s, ``values`` and ``level`` in one
    unit: a rate of descent, an altitude)."""
    time, values = np.asarray(time, float), np.asarray(values, float)
    finite = np.isfinite(values) & (time >= after)
    falls = np.flatnonzero((values[:-1] > level) & finite[:-1] & finite[1:] & (values[1:] <= level))
    if not len(falls):
        return None
    i = int(falls[0]) + 1
    w = (values[i - 1] - level) / (values[i - 1] - values[i])
    return float(time[i - 1] + w * (time[i] - time[i - 1]))


def descent_rate_events(thresholds, time, descent_rate, after: float) -> list:
    """First downward crossings of each threshold (m/s) by ``descent_rate`` (m/s) after time ``after`` (s),
    linearly interpolated."""
    crossings = [(first_fall_through(time, descent_rate, threshold, after), threshold) for threshold in thresholds]
    return [DescentRateEvent(when, threshold) for when, threshold in crossings if when is not None]


def merge_facts(total: dict, facts: dict) -> None:
    """Add one phase's method facts to the run's: solve counts add up, means are weighted, maxima kept."""
    for key, value in facts.items():
        old = total.get(key)
        if isinstance(old, dict) and "solves" in old:
            solves = old["solves"] + value["solves"]
            value = {"solves": solves, "failures": old["failures"] + value["failures"],
                     "mean_iterations": (old["mean_iterations"] * old["solves"]
                                         + value["mean_iterations"] * value["solves"]) / max(solves, 1),
                     "max_iterations": max(old["max_iterations"], value["max_iterations"])}
        total[key] = value


def failures_flown(failures) -> dict:
    """The case's ``[failures]`` (``case.model.Failures``) as ``summary.json`` records them: only what is set
    (canopies that never inflate, with their model and trailing drag-area fraction; cut-away times in s; disreef
    delays in s; skipped stages); {} for a run without failures, so a tool can test ``summary.failures``."""
    flown = {}
    if failures.not_inflated:
        flown.update(not_inflated=list(failures.not_inflated), not_inflated_model=failures.not_inflated_model,
                     trailing_fraction=failures.trailing_fraction)
    for name in ("cutaway", "disreef_delay", "skipped_stages"):
        value = getattr(failures, name)
        if value:
            flown[name] = {canopy: list(v) if isinstance(v, tuple) else v for canopy, v in value.items()
                           if not (isinstance(v, float) and v == math.inf)}   # a trigger that never fired
    return flown


CLEARANCE_AFTER = 2.0
"""s after a separation at which its clearance (the distance between the two centres of mass) is reported."""


class SummaryEntry:
    """An entry of ``summary.json`` held as a frozen dataclass: ``to_dict`` gives its fields in order under their
    names in the file (``FILE_NAMES``: a field whose name is not the file's), an ``OPTIONAL`` field only when set;
    ``from_dict`` reads one back, None for a field the entry lacks (a file of an earlier version)."""

    FILE_NAMES: ClassVar[dict] = {}

    def to_dict(self) -> dict:
        return {self.FILE_NAMES.get(f.name, f.name): getattr(self, f.name) for f in fields(self)
                if not (f.metadata.get("optional") and getattr(self, f.name) is None)}

    @classmethod
    def from_dict(cls, data):
        """The entry of ``data`` (None when ``data`` is not a JSON object: a file edited by hand)."""
        if not isinstance(data, dict):
            return None
        return cls(**{f.name: data.get(cls.FILE_NAMES.get(f.name, f.name)) for f in fields(cls)})


@dataclass(frozen=True)
class Separation(SummaryEntry):
    """A body's separation (``separation_summary``): its ``time`` (s), its ``relative_speed`` (m/s, along the
    separation direction) and its ``clearance`` (m), the distance between its centre of mass and the vehicle's
    ``clearance_after`` s later (None: no finite sample)."""

    time: float
    relative_speed: float
    clearance: float | None
    clearance_after: float


@dataclass(frozen=True)
class Deployment(SummaryEntry):
    """One system's deployment loads: ``system``; ``line_stretch_time`` (s); ``snatch_load`` (N) and ``snatch_time``
    (s), the first peak; ``opening_load`` (N) and ``opening_time`` (s), the largest; ``line_stretch_speed`` (m/s);
    ``opening_stage``, the stage in which the opening load came (a reefed opening's), with ``dynamic_pressure`` (Pa)
    at its start and ``drag_area`` (m^2, its C_D S filled); ``load_factor`` (-), the opening load over that q C_D S;
    ``lines``: per line its peak ``load`` (N) and its ``time`` (s), with its ``breaking_strength`` (N) and ``margin``
    (-) when it has a rating; ``knacke_opening_load`` (N), Knacke's hand estimate beside it; ``kind``: "system", or
    "tether" (``system`` is then the tether's name, its largest load the opening load)."""

    system: str
    line_stretch_time: float
    snatch_load: float
    snatch_time: float
    opening_load: float
    opening_time: float
    line_stretch_speed: float | None = None
    dynamic_pressure: float | None = None
    drag_area: float | None = None
    load_factor: float | None = None
    lines: dict = field(default_factory=dict)
    knacke_opening_load: float | None = field(default=None, metadata=OPTIONAL)
    kind: str = "system"
    opening_stage: int | None = field(default=None, metadata=OPTIONAL)


def separation_summary(case, raw, events: list) -> dict:
    """Per body that separated, its ``Separation``: the clearance ``CLEARANCE_AFTER`` s after the separation (at the
    output sample nearest; at the run's end when that comes first: ``clearance_after`` says how long after), from
    the engine history ``raw``."""
    out = {}
    time = raw.time
    for event in events:
        if event.kind != "separation":
            continue
        i = int(np.argmin(np.abs(time - min(event.time + CLEARANCE_AFTER, float(time[-1])))))
        apart = raw.bodies[event.body]["position"][i] - raw.bodies[case.vehicle]["position"][i]
        out[event.body] = Separation(event.time, event.relative_speed, float(np.linalg.norm(apart)),
                                     float(time[i] - event.time))
    return out


@dataclass(frozen=True)
class Descent(SummaryEntry):
    """The vehicle's rate of descent (m/s, relative to the ground, down positive) averaged over the last ``window``
    s of the run (``mean_rate``) and at its end (``final_rate``); None: no finite sample (``analysis``)."""

    mean_rate: float | None
    window: float
    final_rate: float | None


@dataclass(frozen=True)
class Pendulum(SummaryEntry):
    """The vehicle's pendulum angles (deg) from ``start`` (s; ``from`` in the file: once the last configuration
    flies, ``analysis.settled_after``): the largest, the RMS and the swing amplitude (``analysis.swing_amplitude``)
    of its angle to gravity (``vertical``) and to its airspeed (``airspeed``); None: no finite sample."""

    start: float
    max_vertical_deg: float | None
    rms_vertical_deg: float | None
    amplitude_vertical_deg: float | None
    max_airspeed_deg: float | None
    rms_airspeed_deg: float | None
    amplitude_airspeed_deg: float | None
    FILE_NAMES: ClassVar[dict] = {"start": "from"}


@dataclass(frozen=True)
class ClusterLoads(SummaryEntry):
    """A cluster's loads and geometry (``analysis.cluster_summary``): its ``canopies``; the largest canopy's peak
    share of the risers' load (-, None: no sample under a real load) and when (s); the time (s) from which its
    canopies are open (``open_from``), per canopy its flyout once open (deg: ``{'max', 'mean'}``, None: never open)
    and its riser's peak (``{'tension': N, 'time': s}``, None: never loaded); with contact modelled, per pair of
    canopies (``<first>_<second>``) the largest overlap (m, >= 0; None: never both present)."""

    canopies: list
    peak_load_share: float | None
    peak_load_share_time: float | None
    open_from: float
    flyout_deg: dict
    riser_peak: dict
    max_overlap: dict | None = field(default=None, metadata=OPTIONAL)


@dataclass(frozen=True)
class FinalState:
    """The run's last sample (``summary.json``'s ``final``): its ``time`` (s) and the altitude, east and north (m) of
    the vehicle's centre of mass and of each confluence, by their columns (``values``: ``registries.columns``,
    ``<owner>_altitude``, ``<owner>_east``, ``<owner>_north``, and on an ellipsoidal planet ``<owner>_latitude`` and
    ``<owner>_longitude`` in deg; NaN, null in the file, for a confluence whose system has left). ``altitude``,
    ``east``, ``north``, ``place`` and ``lateral`` are the vehicle's."""

    time: float
    vehicle: str
    values: dict

    POSITION: ClassVar[tuple] = ("{owner}_altitude", "{owner}_east", "{owner}_north", "{owner}_latitude",
                                 "{owner}_longitude")

    def value(self, template: str, owner: str | None = None) -> float:
        """The last sample (m) of column ``template`` (``'{owner}_altitude'``) of ``owner`` (default the vehicle; a
        confluence label, ``Case.confluence_label``)."""
        return self.values[column(template, self.vehicle if owner is None else owner)]

    @property
    def altitude(self) -> float:
        """The vehicle's altitude (m) above the reference surface at the end."""
        return self.value("{owner}_altitude")

    @property
    def east(self) -> float:
        """The vehicle's east (m) of the start point at the end."""
        return self.value("{owner}_east")

    @property
    def north(self) -> float:
        """The vehicle's north (m) of the start point at the end."""
        return self.value("{owner}_north")

    @property
    def place(self) -> tuple | None:
        """The vehicle's geodetic latitude and longitude (deg) at the end; None without them (a flat planet, a
        summary written before they were kept)."""
        names = [column(t, self.vehicle) for t in ("{owner}_latitude", "{owner}_longitude")]
        values = [self.values.get(name) for name in names]
        return None if any(v is None for v in values) else (values[0], values[1])

    @property
    def lateral(self) -> float:
        """The vehicle's horizontal distance (m) from the start point at the end."""
        return math.hypot(self.east, self.north)

    def to_dict(self) -> dict:
        """As ``summary.json`` holds it: the vehicle's values under ``UNNAMED_VEHICLE``'s columns (the file's keys
        are the same whatever the vehicle is called)."""
        renamed = {column(t, self.vehicle): column(t, UNNAMED_VEHICLE) for t in self.POSITION}
        return {column("time"): self.time, **{renamed.get(name, name): value for name, value in self.values.items()}}

    @classmethod
    def from_dict(cls, data, vehicle: str | None) -> FinalState | None:
        """``to_dict``'s inverse for the run of ``vehicle`` (None: ``UNNAMED_VEHICLE``); None unless ``data`` is a
        JSON object."""
        if not isinstance(data, dict):
            return None
        vehicle = vehicle if isinstance(vehicle, str) else UNNAMED_VEHICLE
        renamed = {column(t, UNNAMED_VEHICLE): column(t, vehicle) for t in cls.POSITION}
        return cls(data.get(column("time")), vehicle,
                   {renamed.get(name, name): value for name, value in data.items() if name != column("time")})


def site_of(start) -> dict | None:
    """The start point of a run on its planet (``RunSummary.site``) from its start frame
    (``physics.planet.StartFrame``): the planet's ``planet`` name, ``equatorial_radius`` and ``polar_radius`` (m),
    the start's ``latitude_deg`` and ``longitude_deg`` (deg); None on a flat planet (no latitude there)."""
    planet = start.planet
    if isinstance(planet, FlatPlanet):
        return None
    return {"planet": planet.name, "equatorial_radius": float(planet.equatorial_radius),
            "polar_radius": float(planet.polar_radius), "latitude_deg": float(start.latitude_deg),
            "longitude_deg": float(start.longitude_deg)}


def events_planned(systems: dict, triggers: dict | None = None) -> dict:
    """Per parachute system its fixed schedule: ``deploy_time`` and ``cutaway_time`` (s; None: present from the
    start, never cut away), as the case states them, before any failure; an event fired by a trigger has None there
    and ``deploy_trigger`` / ``cutaway_trigger``: what fires it."""
    planned = {}
    for name, system in systems.items():
        entry = {}
        for kind, time in (("deploy", system.deploy_time), ("cutaway", system.cutaway_time)):
            trigger = (triggers or {}).get(f"{name}.{kind}")
            entry[f"{kind}_time"] = None if trigger is not None else time
            if trigger is not None:
                entry[f"{kind}_trigger"] = trigger.describe()
        planned[name] = entry
    return planned


@dataclass(frozen=True)
class RunSummary:
    """What a run was and how it ended: ``Result.summary``, written as ``summary.json`` (``to_dict``) and read back
    from it (``from_dict``). Units SI: s, m, N, m/s.

    Attributes
    ----------
    case, case_file, description : str
        The case's name, file and description.
    vehicle : str
        The vehicle body's name: the owner of its columns (``registries.columns``).
    method, integrator : str
        The confluence method and integrator run.
    step, duration, output_step : float
        The integration step (s; adaptive steps: the largest allowed), the simulated time (s), the output step (s).
    ground_altitude : float or None
        The ground's altitude (m), whether or not the run stops there (None: a summary of an earlier version of a run
        that flew on below the ground, which did not keep it).
    end : str
        "touchdown" or "duration".
    steps : int
        Integration steps taken.
    wall_time : float
        The engine's solve (s); ``steps_per_second`` follows from it.
    final : FinalState
        The last sample: ``final.time`` (s), ``final.altitude``, ``final.east``, ``final.north``, ``final.lateral``
        (m, the vehicle's), ``final.value(template, owner)`` (a confluence's).
    peak_tension : dict
        The largest tension (N) per line label (None for a line never present).
    events : tuple of Event
        In time order (see the module docstring); ``touchdown`` is the TouchdownEvent, ``events_of(kind)`` the
        events of one kind.
    units : dict
        The unit of each column.
    versions, created
        The versions of this package, Exudyn, numpy and Python; when the run ended (ISO 8601, UTC).
    method_settings, method_facts : dict
        The method's options as it reports them (SP: kappa_max, slack_rule, sp_order) and the counts it keeps
        (equilibrium point: solves and iterations per system); both sit at the top level of ``summary.json``.
    opening_loads : dict
        Per opening, per stage its window and the lines' peak tensions (``opening_loads``); {} without inflations.
    deployments : tuple of Deployment
        Per parachute system its line stretch, snatch and opening loads (``results.deployments``).
    cluster : dict of ClusterLoads
        Per cluster system; {} without clusters.
    pendulum : Pendulum or None
        The vehicle's pendulum angles; None for a fixed vehicle.
    descent : Descent or None
        The vehicle's rate of descent at the end.
    warnings : tuple of str
        One line per implausible case value (``Case.warnings``) and per trigger that never fired.
    failures, events_planned : dict
        The [failures] the run flew with (``failures_flown``); per system its fixed deploy and cut-away times (s).
    separations : dict of Separation
        Per separated body; {} without separations.
    step_control : dict or None
        Adaptive steps: the rule, the smallest, largest and mean step (s) and their count; None: a fixed step.
    site : dict or None
        The start point on the planet (``site_of``): the planet's name and semi-axes (m) and the start's geodetic
        latitude and longitude (deg), what a map of the run needs; None on a flat planet.
    canopy_models : dict
        Per system with canopies, the canopy model flown (``model``: "rigid" or "reduced") and who chose it
        (``chosen``: "case", or "auto" by the light-canopy rule): ``case.canopy_choice.canopy_models_flown``.
    stop_at_ground : bool
        False: the run flew on below the ground (``stop_at_ground = false``); ``summary.json`` holds the key then only.
    """

    case: str
    case_file: str
    description: str
    vehicle: str
    method: str
    integrator: str
    step: float
    duration: float
    output_step: float
    ground_altitude: float | None
    end: str
    steps: int
    wall_time: float
    final: FinalState | None
    peak_tension: dict
    events: tuple
    units: dict
    versions: dict
    created: str
    method_settings: dict = field(default_factory=dict)
    method_facts: dict = field(default_factory=dict)
    opening_loads: dict = field(default_factory=dict)
    deployments: tuple = ()
    cluster: dict = field(default_factory=dict)
    pendulum: Pendulum | None = None
    descent: Descent | None = None
    warnings: tuple = ()
    failures: dict = field(default_factory=dict)
    events_planned: dict = field(default_factory=dict)
    separations: dict = field(default_factory=dict)
    step_control: dict | None = None
    site: dict | None = None
    canopy_models: dict = field(default_factory=dict)
    stop_at_ground: bool = True

    @property
    def steps_per_second(self) -> float | None:
        """Integration steps per second of the engine's solve (None: no solve time, or a summary without them)."""
        timed = self.steps is not None and isinstance(self.wall_time, (int, float)) and self.wall_time > 0
        return self.steps / self.wall_time if timed else None

    @property
    def touchdown(self) -> TouchdownEvent | None:
        """The vehicle's touchdown (its velocity relative to the ground, m/s), None for a run that did not land."""
        return next(iter(self.events_of("touchdown")), None)

    def events_of(self, kind: str) -> list:
        """The events of ``kind`` ('deploy', 'separation', ...: ``Event.kind``), in time order."""
        return [event for event in self.events if event.kind == kind]

    @classmethod
    def from_dict(cls, data: dict) -> RunSummary:
        """The typed summary of a ``summary.json`` (``to_dict``'s inverse), of this version or an earlier one: each
        event as its Event class (``event_from_dict``), each entry as its class, the method's settings and facts
        (top-level keys of no field) in ``method_settings``; a field the file lacks is None (empty for a mapping)."""
        names = {f.name for f in fields(cls)}
        known = {k: v for k, v in data.items() if k in names}
        extra = {k: v for k, v in data.items() if k not in names and k != "steps_per_second"}
        defaults = {f.name: None for f in fields(cls) if f.default is MISSING and f.default_factory is MISSING}
        events = data.get("events")
        return cls(**{**defaults, **known, "method_settings": extra,
                      "events": tuple(event_from_dict(e) for e in events if isinstance(e, dict))
                      if isinstance(events, list) else (),
                      "warnings": tuple(data["warnings"]) if isinstance(data.get("warnings"), list) else (),
                      "final": FinalState.from_dict(data.get("final"), data.get("vehicle")),
                      # an earlier version kept no ground for a run that flew on below it
                      "stop_at_ground": data.get("stop_at_ground", data.get("ground_altitude", 0.0) is not None),
                      "pendulum": Pendulum.from_dict(data.get("pendulum")),
                      "descent": Descent.from_dict(data.get("descent")),
                      "cluster": _entries(ClusterLoads, data.get("cluster")),
                      "separations": _entries(Separation, data.get("separations")),
                      "deployments": tuple(d for d in map(Deployment.from_dict, data.get("deployments") or [])
                                           if d is not None) if isinstance(data.get("deployments"), list) else ()})

    def to_dict(self) -> dict:
        """What ``summary.json`` holds (strict JSON once ``io.json_text`` writes it)."""
        return {"case": self.case, "case_file": self.case_file, "description": self.description,
                "vehicle": self.vehicle, "method": self.method, "integrator": self.integrator, "step": self.step,
                **({"step_control": self.step_control} if self.step_control is not None else {}),
                "duration": self.duration, **self.method_settings, **self.method_facts,
                "output_step": self.output_step, "ground_altitude": self.ground_altitude,
                **({} if self.stop_at_ground else {"stop_at_ground": False}), "end": self.end,
                "steps": self.steps, "wall_time": self.wall_time, "steps_per_second": self.steps_per_second,
                "final": None if self.final is None else self.final.to_dict(), "peak_tension": self.peak_tension,
                "events": [event.to_dict() for event in self.events],
                **({"opening_loads": self.opening_loads} if self.opening_loads else {}),
                **({"deployments": [d.to_dict() for d in self.deployments]} if self.deployments else {}),
                **({"cluster": {k: v.to_dict() for k, v in self.cluster.items()}} if self.cluster else {}),
                **({"pendulum": self.pendulum.to_dict()} if self.pendulum is not None else {}),
                **({"descent": self.descent.to_dict()} if self.descent is not None else {}),
                **({"separations": {k: v.to_dict() for k, v in self.separations.items()}} if self.separations
                   else {}), "warnings": list(self.warnings),
                "failures": self.failures, "events_planned": self.events_planned,
                **({"site": self.site} if self.site is not None else {}),
                **({"canopy_models": self.canopy_models} if self.canopy_models else {}), "units": self.units,
                "versions": self.versions, "created": self.created}


def _entries(kind: type, data) -> dict:
    """Per name, the ``kind`` entry of ``data`` (a JSON object of entries; {} for anything else)."""
    if not isinstance(data, dict):
        return {}
    return {name: entry for name, entry in ((k, kind.from_dict(v)) for k, v in data.items()) if entry is not None}

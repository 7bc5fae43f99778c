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
from ..registries.columns import column


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
    its kind and entries as written."""

    name: str = ""
    entries: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {"event": self.name, "time": self.time, **self.entries}


def event_from_dict(data: dict) -> Event:
    """The Event of a ``summary.json`` event entry: its class by ``kind``, else a ``RecordedEvent``."""
    kinds = {c.kind: c for c in _subclasses(Event) if c.kind}
    entries = {k: v for k, v in data.items() if k not in ("event", "time")}
    kind = kinds.get(data.get("event"))
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


def opening_events(case, openings: dict, end: float) -> list:
    """Stage starts, disreefs and fill ends (at or before ``end``, s) of each canopy's opening (``openings``: by
    (system, canopy))."""
    events = []
    for (system, canopy), progress in openings.items():
        named = {"canopy": canopy} if case.systems[system].cluster else {}
        flies_to = case.systems[system].end(canopy, case.failures, end)   # no fill ends once the canopy has left
        for flown, (stage, fill_end, speed, fill) in enumerate(progress.fill_ends()):
            start = fill_end - fill
            kind = StageStartEvent if flown == 0 else DisreefEvent   # the first flown (stage 1 unless skipped)
            supersonic = {"mach": progress.stretch_mach, "load_factor": progress.load_factor} \
                if progress.load_factor is not None and flown == len(progress.inflation.stages) - 1 else {}
            events.append(kind(start, system, stage, speed, fill, **named, **supersonic))
            if fill_end <= flies_to:
                events.append(FillEndEvent(fill_end, system, stage, **named))
    return events


def opening_warnings(case, events) -> tuple:
    """A supersonic opening whose line stretch fell outside its ``mach_range``: its load factor was held at the
    range's end (the constants were not fitted there)."""
    warned = []
    for event in events:
        if isinstance(event, StageStartEvent) and event.mach is not None:
            low, high = case.systems[event.system].inflation.supersonic.mach_range
            if not low <= event.mach <= high:
                warned.append(f"systems.{event.system}: line stretch at Mach {event.mach:.3g}, outside the supersonic "
                              f"opening's mach_range [{low:g}, {high:g}]: its load factor was held at the range's "
                              f"end (C_k = {event.load_factor:.4g})")
    return tuple(warned)


def opening_loads(case, openings: dict, columns: dict) -> dict:
    """Per opening (by its label: the system, or the canopy in a cluster), per stage: its window (s: from the stage
    start to the next one, the cut-away or the run's end) and the peak tension (N) in it and when (s) of each line
    of the system (of the canopy's own risers, in a cluster), from the sampled histories (resolution: the output
    step)."""
    time = columns["time"]
    loads = {}
    for (name, canopy), progress in openings.items():
        system = case.systems[name]
        stages = []
        end = system.end(canopy, case.failures, float(time[-1]) + 1e-9)
        lines = system.risers(canopy) if system.cluster else system.lines
        for stage, start, stop in progress.windows(end):
            inside = (time >= start - 1e-9) & (time < stop)
            peaks = {}
            for line in lines:
                values = columns[column("tension_{owner}", case.line_label(system, line))][inside]
                if len(values) and np.isfinite(values).any():
                    k = int(np.nanargmax(values))
                    peaks[line.name] = {"tension": float(values[k]), "time": float(time[inside][k])}
            stages.append({"stage": stage, "start": start, "end": min(stop, float(time[-1])), "peaks": peaks})
        loads[case.opening_label(system, canopy)] = stages
    return loads


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
    ``horizontal_speed_over_ground`` squared is ``speed`` squared."""

    speed: float = 0.0              # m/s, total speed relative to the ground (all three components)
    vertical_speed: float = 0.0     # m/s, along the start point's up axis, downward positive
    horizontal_speed: float = 0.0   # m/s, across the start point's up axis
    descent_rate: float | None = field(default=None, metadata=OPTIONAL)   # m/s, along the local vertical, down +
    horizontal_speed_over_ground: float | None = field(default=None, metadata=OPTIONAL)   # m/s, across it
    kind: ClassVar[str] = "touchdown"

    @classmethod
    def from_crossing(cls, time: float, ground_velocity, down) -> TouchdownEvent:
        """From the crossing time (s), the ground-relative velocity (m/s, east/north/up) and the unit vector down the
        local vertical there (the same axes)."""
        v = np.asarray(ground_velocity, float)
        descent = float(np.dot(v, down))
        level = v - descent * np.asarray(down, float)
        return cls(float(time), float(np.linalg.norm(v)), float(-v[2]), float(np.hypot(v[0], v[1])), descent,
                   float(np.linalg.norm(level)))


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
    delays in s; skipped stages); {} for a run without failures, so a tool can test ``summary["failures"]``."""
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


def separation_summary(case, raw, events: list) -> dict:
    """Per body that separated: the time (s), the relative speed (m/s) and the clearance (m), the distance between
    its centre of mass and the vehicle's ``CLEARANCE_AFTER`` s later (at the output sample nearest; at the run's end
    when that comes first: ``clearance_after`` says how long after), from the engine history ``raw``."""
    out = {}
    time = raw.time
    for event in events:
        if event.kind != "separation":
            continue
        i = int(np.argmin(np.abs(time - min(event.time + CLEARANCE_AFTER, float(time[-1])))))
        apart = raw.bodies[event.body]["position"][i] - raw.bodies[case.vehicle]["position"][i]
        out[event.body] = {"time": event.time, "relative_speed": event.relative_speed,
                           "clearance": float(np.linalg.norm(apart)), "clearance_after": float(time[i] - event.time)}
    return out


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
    """What a run was and how it ended (``summary.json``; units SI: s, m, N).

    ``method_settings`` are the method's options as it reports them (SP: kappa_max, slack_rule, sp_order),
    ``method_facts`` the counts it keeps (equilibrium point: solves and iterations per system); both sit at the top
    level of ``summary.json``. ``final`` holds the last sample's time and the vehicle's and confluences' altitude,
    east and north; ``peak_tension`` the largest tension per line (None for a line never present).
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
    ground_altitude: float | None   # m; None: the run flies on below the ground (stop_at_ground = false)
    end: str                 # "touchdown" or "duration"
    steps: int
    wall_time: float         # s
    final: dict
    peak_tension: dict
    events: tuple
    units: dict
    versions: dict
    created: str
    method_settings: dict = field(default_factory=dict)
    method_facts: dict = field(default_factory=dict)
    opening_loads: dict = field(default_factory=dict)   # see ``opening_loads``; {} without inflations
    cluster: dict = field(default_factory=dict)         # per cluster (``analysis.cluster_summary``); {} without
    pendulum: dict = field(default_factory=dict)        # the vehicle's pendulum angles (``analysis``)
    descent: dict = field(default_factory=dict)         # the vehicle's rate of descent at the end (``analysis``)
    warnings: tuple = ()    # one line per implausible case value (``Case.warnings``, ``case.plausible``)
    failures: dict = field(default_factory=dict)        # the [failures] the run flew with (``failures_flown``)
    events_planned: dict = field(default_factory=dict)  # per system its fixed deploy and cut-away times (s)
    separations: dict = field(default_factory=dict)     # per separated body (``separation_summary``); {} without
    step_control: dict | None = None   # adaptive steps: smallest, largest, mean (s) and count; None: a fixed step

    @property
    def steps_per_second(self) -> float | None:
        return self.steps / self.wall_time if self.wall_time > 0 else None

    @classmethod
    def from_dict(cls, data: dict) -> RunSummary:
        """The typed summary of a ``summary.json`` (``to_dict``'s inverse): each event as its Event class
        (``event_from_dict``), the method's settings and facts (top-level keys of no field) in ``method_settings``."""
        names = {f.name for f in fields(cls)}
        known = {k: v for k, v in data.items() if k in names}
        extra = {k: v for k, v in data.items() if k not in names and k != "steps_per_second"}
        known["events"] = tuple(event_from_dict(event) for event in data.get("events", []))
        known["warnings"] = tuple(data.get("warnings", ()))
        defaults = {f.name: None for f in fields(cls) if f.default is MISSING and f.default_factory is MISSING}
        return cls(**{**defaults, **known, "method_settings": extra})

    def to_dict(self) -> dict:
        return {"case": self.case, "case_file": self.case_file, "description": self.description,
                "vehicle": self.vehicle, "method": self.method, "integrator": self.integrator, "step": self.step,
                **({"step_control": self.step_control} if self.step_control is not None else {}),
                "duration": self.duration, **self.method_settings, **self.method_facts,
                "output_step": self.output_step, "ground_altitude": self.ground_altitude, "end": self.end,
                "steps": self.steps, "wall_time": self.wall_time,
                "steps_per_second": self.steps_per_second, "final": self.final, "peak_tension": self.peak_tension,
                "events": [event.to_dict() for event in self.events],
                **({"opening_loads": self.opening_loads} if self.opening_loads else {}),
                **({"cluster": self.cluster} if self.cluster else {}),
                **({"pendulum": self.pendulum} if self.pendulum else {}),
                **({"descent": self.descent} if self.descent else {}),
                **({"separations": self.separations} if self.separations else {}), "warnings": list(self.warnings),
                "failures": self.failures, "events_planned": self.events_planned,
                "units": self.units,
                "versions": self.versions, "created": self.created}


def run_line(summary: dict, out, stability_limit: float | None = None) -> str:
    """The one-line account of a finished run (``pchute run``): its method, step (adaptive: the steps taken, smallest
    to largest, and their mean; chosen from the stability limit: that limit), end, wall time and final position."""
    s, f = summary, summary["final"]
    ending = "touchdown at" if s.get("end") == "touchdown" else "ended at"
    control = s.get("step_control")
    if control and control.get("count"):
        step = (f"adaptive steps {control['smallest']:.3g} to {control['largest']:.3g} s (mean "
                f"{control['mean']:.3g} s)")
    else:
        chosen = "" if stability_limit is None else f" (none set: from the stability limit {stability_limit:.3g} s)"
        step = f"step {s['step']:g} s{chosen}"
    return (f"{s['case']}: {s['method']}/{s['integrator']} {step}, {ending} {f['time']:.2f} s in "
            f"{s['wall_time']:.2f} s of wall time ({s['steps']} steps); final {s['vehicle']} altitude "
            f"{f['vehicle_altitude']:.2f} m, east {f['vehicle_east']:.3f} m, north {f['vehicle_north']:.3f} m"
            f"{touchdown_text(s.get('events', []))} -> {out}"
            + (f" ({len(s['warnings'])} warning(s): see summary.json)" if s.get("warnings") else ""))


def touchdown_text(events: list) -> str:
    """The run line's account of the touchdown (``summary.json`` events): the descent rate, the horizontal speed over
    the ground and the total speed (m/s); '' for a run that did not touch down (or a summary from before the split)."""
    touchdown = next((e for e in events if e.get("event") == "touchdown"), None)
    if touchdown is None or touchdown.get("descent_rate") is None:
        return ""
    return (f"; at touchdown descent rate {touchdown['descent_rate']:.2f} m/s, horizontal speed "
            f"{touchdown['horizontal_speed_over_ground']:.2f} m/s, total speed {touchdown['speed']:.2f} m/s "
            "(over the ground)")

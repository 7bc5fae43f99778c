"""A run's deployment loads (``summary.json``'s ``deployments``; docs/models/deployment_loads.md): per parachute
system its line stretch, the snatch (the first peak of its load), the opening load (the largest) and the load on
each line, from the tensions kept at every step while the loads may peak (``run.deployment_watch``) and the output
samples between.

A system's load is the tension of its risers (the lines to its canopies), summed over a cluster's canopies: what the
canopy pulls the confluence with, and, through the confluence, the vehicle's harness. Its load factor is the opening
load over the steady drag q C_D S of the stage in which it came (q = rho V^2 / 2 with V the air speed the opening
measured at that stage's start, or the vehicle's at line stretch; C_D S that stage's, filled)."""

from __future__ import annotations

import math

import numpy as np

from ..case.model import Case, DragAreaSchedule, ParachuteSystem
from ..physics.load_peaks import SNATCH_FLOOR, first_peak, largest
from ..physics.opening_force import knacke_opening_force
from ..registries.columns import column
from .summary import Deployment

SETTLE = 1.0
"""How long (s) after a fill's end (and its overshoot's decay) the watch goes on: the vehicle's deceleration after
the canopy has filled, in which a light vehicle's load may still peak."""


def watch_windows(case: Case, system: ParachuteSystem, progress) -> list:
    """(start, end) run times (s) in which ``system``'s loads may peak: see the module docstring. ``progress``: the
    ``InflationProgress`` of its opening (or of its first canopy's, in a cluster), or None."""
    line_stretch = system.deploy_time if system.deploy_time is not None else 0.0
    if progress is None:
        opening = case.opening_of(system, system.canopies[0]) if system.canopies else None
        length = opening.time[-1] if isinstance(opening, DragAreaSchedule) else 0.0
        return [(line_stretch, line_stretch + length + SETTLE)]
    inflation = progress.inflation
    windows = []
    for i, (_, fill_end, _, fill) in enumerate(progress.fill_ends()):
        decay = inflation.overinflation_decay if i == len(inflation.stages) - 1 else 0.0
        windows.append((fill_end - fill, fill_end + decay + SETTLE))
    started = len(progress.speeds)
    if started < len(inflation.stages):   # the next stage: watched from its start until it is measured
        windows.append((progress.line_stretch + inflation.stages[started].start, math.inf))
    return windows


def _merged(trace, columns: dict, lines: list, labels: list, start: float, end: float) -> tuple:
    """The times (s) and per-line tensions (N, rows; the lines ``lines`` by name, their columns ``labels``) of the step
    trace and the output samples in [start, end], in time order (a step kept and a sample at the same time once; a
    line the trace lacks, of a canopy that never left the vehicle, NaN)."""
    time = columns[column("time")]
    inside = (time >= start - 1e-9) & (time <= end + 1e-9)
    tensions = [columns[column("tension_{owner}", label)] for label in labels]   # looked up once, not per sample
    picked = [np.asarray(tension)[inside].tolist() for tension in tensions]   # Python floats, column by column
    rows = dict(zip(time[inside].tolist(), zip(*picked))) if picked else dict.fromkeys(time[inside].tolist(), ())
    if trace is not None:
        rows.update({t: tuple(row.get(name, math.nan) for name in lines)
                     for t, row in zip(trace.times, trace.tensions) if start - 1e-9 <= t <= end + 1e-9})
    times = sorted(rows)
    return times, np.array([rows[t] for t in times], float).reshape(len(times), len(labels))


def _vehicle_air(case, raw, time: float) -> tuple:
    """(air speed in m/s, density in kg/m^3) of the vehicle at the engine sample at or after ``time`` (s): its
    velocity against the air's (wind, turbulence, gusts) at its centre of mass, the density at its altitude."""
    k = min(int(np.searchsorted(raw.time, time - 1e-9)), len(raw.time) - 1)
    body = raw.bodies[case.vehicle]
    position, velocity = np.asarray(body["position"][k], float), np.asarray(body["velocity"][k], float)
    altitude = float(case.start.altitude(position))
    air = case.air_motion()
    if not air.still:
        x, y, z = position.tolist()
        velocity = velocity - np.asarray(air(x, y, z, altitude, float(raw.time[k])), float)
    density = case.atmosphere.density(altitude) if case.atmosphere is not None else 0.0
    return float(np.linalg.norm(velocity)), density


def _open_drag_area(case, system) -> float:
    """C_D S (m^2) of the system's canopies fully open (a cluster's with its drag efficiency; one that never inflates
    left out)."""
    area = 0.0
    for canopy in system.canopies:
        aerodynamics = case.bodies[canopy].aerodynamics
        if aerodynamics is not None and aerodynamics.enabled and canopy not in case.failures.not_inflated:
            efficiency = case.drag_efficiency(system, canopy, system.canopies)
            area += aerodynamics.reference_area * aerodynamics.axial_coefficient(0.0, 0.0) * efficiency
    return area


class OpeningStage:
    """The conditions of the stage in which an opening load came (the whole opening without stages): its number, the
    air speed ``speed`` (m/s) and density (kg/m^3) at its start, its filled drag area (m^2), its fill time (s), its
    exponent and C_x (None without a fill-constant opening)."""

    def __init__(self, case, system, progress, raw, line_stretch: float, opening_time: float):
        full = _open_drag_area(case, system)
        self.number, self.fill, self.exponent, self.overinflation = None, None, None, None
        if progress is None or not progress.speeds:
            self.start, self.drag_area = line_stretch, full
            self.speed, self.density = _vehicle_air(case, raw, line_stretch)
            return
        inflation = progress.inflation
        i = min(inflation.stage_at(opening_time - progress.line_stretch), len(progress.speeds) - 1)
        stage, last = inflation.stages[i], i == len(inflation.stages) - 1
        self.number, self.start = inflation.number(i), progress.line_stretch + stage.start
        self.speed, self.fill, self.exponent = progress.speeds[i], progress.fill_times[i], stage.exponent
        self.overinflation = inflation.overinflation if last else 1.0
        self.drag_area = full * stage.fraction
        self.density = _vehicle_air(case, raw, self.start)[1]

    @property
    def dynamic_pressure(self) -> float:
        return 0.5 * self.density * self.speed * self.speed


def decelerated_mass(case: Case, system: ParachuteSystem, time: float) -> float:
    """The mass (kg) a system's canopies slow at ``time`` (s): every free body of the case but its own canopies, the
    canopies of systems cut away by then and the bodies separated by then (confluences left out: grams)."""
    mass = 0.0
    for body in case.free_bodies():
        other = case.canopy_system(body.name)
        if body.name in system.canopies or (other is not None and other.cutaway_time is not None
                                            and other.cutaway_time <= time):
            continue
        if body.name in case.separations and not case.separations[body.name].carried_at(time):
            continue
        mass += body.mass
    return mass


def knacke_estimate(case: Case, system: ParachuteSystem, stage: OpeningStage, supersonic: bool):
    """Knacke's opening force (N; ``physics.opening_force``) of the stage in which the opening load came, from its
    measured speed and fill time at its start, its exponent, C_x (the overinflation for the last stage, else 1), its
    filled drag area (Pflanz's growth from nothing: a reefed stage's from its predecessor is slower, so this errs
    high) and the mass it slows; None without a fill-constant opening, or for a supersonic one (its load factor is
    its own)."""
    if stage.fill is None or supersonic or stage.density <= 0.0 or stage.speed <= 0.0:
        return None
    mass = decelerated_mass(case, system, stage.start)
    if not (mass > 0.0 and stage.drag_area > 0.0):
        return None
    return knacke_opening_force(mass, stage.drag_area, stage.density, stage.speed, stage.fill, stage.exponent,
                                stage.overinflation)


def deployment_loads(case, traces: dict, openings: dict, columns: dict, raw, histories: dict | None = None) -> tuple:
    """The ``Deployment`` of every system that flew (``case``: as flown), in the order of the case's systems, then
    of every tether, from the step traces, the output ``columns`` (tensions) and the engine history ``raw`` (the
    vehicle's state: the same whether the run keeps its history or not); ``histories`` (when given) receives each
    one's load history (name -> (times in s, loads in N): the steps kept and the samples between) for the loads
    figure."""
    histories = {} if histories is None else histories
    run_end = float(columns[column("time")][-1])
    out = []
    for system in case.systems.values():
        line_stretch = system.deploy_time if system.deploy_time is not None else 0.0
        if line_stretch > run_end or not system.lines:
            continue
        progress = next((openings[(system.name, c)] for c in system.canopies if (system.name, c) in openings), None)
        # an opening's load is its windows' largest (not the steady descent's ripple after it); without an opening
        # law, the largest over the system's whole flight (the steps kept and the samples after them)
        watched = max(end for _, end in watch_windows(case, system, progress)) if progress is not None else run_end
        end = min([run_end, watched] + [system.end(c, case.failures, run_end) for c in system.canopies])
        labels = [case.line_label(system, line) for line in system.lines]
        if any(column("tension_{owner}", label) not in columns for label in labels):
            continue
        times, tensions = _merged(traces.get(system.name), columns, [line.name for line in system.lines], labels,
                                  line_stretch, end)
        risers = [i for i, line in enumerate(system.lines) if line.body in system.canopies]
        load = np.nansum(tensions[:, risers], axis=1) if risers else np.nanmax(tensions, axis=1, initial=0.0)
        opening, opening_time = largest(times, load.tolist())
        snatch, snatch_time = first_peak(times, load.tolist(), floor=SNATCH_FLOOR * opening)
        histories[system.name] = (np.asarray(times, float), load)
        stage = OpeningStage(case, system, progress, raw, line_stretch, opening_time)
        peaks = {}
        for i, line in enumerate(system.lines):
            value, when = largest(times, tensions[:, i].tolist())
            if value != value:   # a line that never acted (its canopy stayed in the vehicle)
                continue
            peaks[line.name] = _peak(value, when, line.rating.breaking_strength if line.rating else None)
        steady = stage.dynamic_pressure * stage.drag_area
        stretch_speed = progress.speeds[0] if progress is not None and progress.speeds else stage.speed
        out.append(Deployment(system.name, line_stretch, snatch, snatch_time, opening, opening_time, stretch_speed,
                              stage.dynamic_pressure, stage.drag_area, opening / steady if steady > 0.0 else None,
                              peaks, knacke_estimate(case, system, stage, progress is not None and
                                                     progress.supersonic is not None),
                              opening_stage=stage.number))
    return tuple(out) + tuple(_tether_deployments(case, traces, histories))


def _peak(load: float, time: float, strength: float | None) -> dict:
    """A line's peak ``load`` (N) and its ``time`` (s), with its ``breaking_strength`` (N) and ``margin`` (-, the
    strength over the load less 1: negative once the load exceeds it) when it has a rating."""
    peak = {"load": load, "time": time}
    if strength is not None:
        peak.update(breaking_strength=strength, margin=strength / load - 1.0 if load > 0.0 else None)
    return peak


def _tether_deployments(case, traces: dict, histories: dict) -> list:
    """A ``Deployment`` per tether that acted: its line stretch (the first step at which it pulls, and not with its
    payout resistance), its snatch (the first peak from then on) and its largest load (``opening_load``: a tether
    opens nothing)."""
    out = []
    for tether in case.tethers.values():
        trace = traces.get(("tether", tether.name))
        if trace is None or not trace.times:
            continue
        loads = [row[tether.name] for row in trace.tensions]
        resistance = tether.law.payout_resistance   # what it pulls with paying out: anything else pulling is taut
        taut = next((i for i, load in enumerate(loads) if load > 0.0 and load != resistance), None)
        if taut is None:
            continue
        times, after = trace.times[taut:], loads[taut:]
        histories[tether.name] = (np.asarray(trace.times, float), np.asarray(loads, float))
        peak, peak_time = largest(times, after)
        snatch, snatch_time = first_peak(times, after, floor=SNATCH_FLOOR * peak)
        out.append(Deployment(tether.name, trace.times[taut], snatch, snatch_time, peak, peak_time,
                              lines={tether.name: _peak(peak, peak_time, tether.breaking_strength)}, kind="tether"))
    return out


def load_warnings(deployments) -> tuple:
    """One line per line or tether whose peak load exceeded its breaking strength."""
    warned = []
    for deployment in deployments:
        for name, peak in deployment.lines.items():
            margin = peak.get("margin")
            if margin is not None and margin < 0.0:
                where = f"tethers.{name}" if deployment.kind == "tether" else \
                    f"systems.{deployment.system}.lines.{name}"
                warned.append(f"{where}: peak load {peak['load']:.4g} N at {peak['time']:.3f} s exceeds its breaking "
                              f"strength {peak['breaking_strength']:.4g} N (margin {margin:.3g}): it would break")
    return tuple(warned)

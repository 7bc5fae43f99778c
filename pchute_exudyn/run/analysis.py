"""What analysts read of a run beyond its state histories (``docs/models/cluster.md``), from the sampled states and
columns (pure numpy, no Exudyn):

* per cluster (a system of several canopies): ``<system>_load_share`` (-), the largest canopy's riser tension over
  the mean of its canopies' (``physics.cluster.load_share``); ``<canopy>_flyout_deg``, each canopy's angle from the
  cluster axis (``physics.cluster.flyout_angles``); ``<a>_<b>_overlap`` (m) of each pair of canopies with contact,
  their envelopes' overlap (positive while they touch, ``physics.contact``), and the contact events it gives;
* for the vehicle: ``<vehicle>_pendulum_deg``, the angle between its +x axis and gravity's direction (the plumb line
  it hangs along), and ``<vehicle>_pendulum_airspeed_deg``, between its +x axis and its centre of mass's velocity
  relative to the air (its +x points away from where its lines attach: heat shield down under a canopy);
* the summary's blocks: ``cluster`` (peak load share and when, each canopy's flyout, its risers' peak, each pair's
  largest overlap), ``pendulum`` (largest and RMS pendulum angles and the swing amplitude, ``swing_amplitude``, once
  the last system is open) and ``descent``
  (the rate of descent at the end of the run).
"""

from __future__ import annotations

import numpy as np

from ..case.model import Case
from ..engine.state import RawHistory
from ..physics.cluster import flyout_angles, load_share, present_mean
from ..physics.contact import envelope_radius, overlaps
from ..physics.kinematics import body_point
from ..registries.columns import column
from ..results.summary import ClusterLoads, ContactEndEvent, ContactStartEvent, Descent, Pendulum
from .outputs import units_of

LOAD_SHARE_FLOOR = 0.1
"""The summary's peak load share counts only samples whose mean riser tension is at least this fraction of its
largest in the run: while every riser is nearly slack (line stretch, a snatch rebound) the ratio of small tensions
says nothing of how the canopies share the load."""
DESCENT_WINDOW = 5.0
"""Seconds at the end of a run over which the summary averages the vehicle's rate of descent."""


def clusters(case: Case) -> list:
    """The case's systems with more than one canopy."""
    return [system for system in case.systems.values() if system.cluster]


def riser_tensions(case: Case, system, columns: dict) -> np.ndarray:
    """(n, k) tension (N) of each of ``system``'s k canopies, summed over its risers; NaN where it is absent."""
    return np.stack([sum(columns[column("tension_{owner}", case.line_label(system, line))]
                         for line in system.risers(canopy)) for canopy in system.canopies], axis=1)


def envelope_centres(case: Case, raw: RawHistory, system) -> np.ndarray:
    """(n, k, 3) start-frame positions (m) of ``system``'s canopies' aerodynamic centres (their envelopes' centres)."""
    return np.stack([body_point(raw.bodies[canopy]["position"], raw.bodies[canopy]["rotation"],
                                local=case.bodies[canopy].aerodynamics.center)[0]
                     for canopy in system.canopies], axis=1)


def cluster_columns(case: Case, raw: RawHistory, columns: dict, units: dict) -> list:
    """Add each cluster's load share, flyout and overlap columns (see the module doc) to ``columns``/``units``;
    returns the contact events."""
    events, added = [], []
    for system in clusters(case):
        share = column("{owner}_load_share", system.name)
        columns[share] = load_share(riser_tensions(case, system, columns))
        centres = envelope_centres(case, raw, system)
        flyout = flyout_angles(raw.confluences[system.name]["position"], centres)
        added.append(share)
        for k, canopy in enumerate(system.canopies):
            added.append(column("{owner}_flyout_deg", canopy))
            columns[added[-1]] = flyout[:, k]
        if system.contact is None:
            continue
        radii = [envelope_radius(system.contact.projected_radius(case.bodies[c].aerodynamics.reference_area),
                                 columns.get(column("{owner}_drag_area_fraction", c), np.ones(len(raw.time))))
                 for c in system.canopies]
        for a, first in enumerate(system.canopies):
            for b in range(a + 1, len(system.canopies)):
                key = column("{owner}_{other}_overlap", first, system.canopies[b])
                columns[key] = overlaps(centres[:, a], centres[:, b], radii[a], radii[b])
                added.append(key)
                events += contact_events(raw.time, columns[key], (first, system.canopies[b]))
    units.update(units_of(added))
    return events


def contact_events(time, overlap, canopies: tuple) -> list:
    """Contact start and end events of one pair from its overlap history (m): the crossings of zero, interpolated
    between samples; the end gives the largest overlap in between. A contact open at the end of the run has no end."""
    touching = np.nan_to_num(overlap, nan=-np.inf) > 0.0
    events, start = [], None
    for i in np.flatnonzero(touching[1:] != touching[:-1]) + 1:
        crossing = _crossing(time, overlap, i)
        if touching[i]:
            start = i
            events.append(ContactStartEvent(crossing, canopies))
        else:
            deepest = float(np.max(overlap[start:i])) if start is not None else float(np.nanmax(overlap[:i]))
            events.append(ContactEndEvent(crossing, canopies, deepest))
            start = None
    if touching[0]:
        events.insert(0, ContactStartEvent(float(time[0]), canopies))
    return events


def _crossing(time, values, i: int) -> float:
    """The time (s) at which ``values`` crosses zero between samples i - 1 and i (sample i's time where either is
    not finite: a canopy appearing or leaving)."""
    before, after = values[i - 1], values[i]
    if not (np.isfinite(before) and np.isfinite(after)) or before == after:
        return float(time[i])
    return float(time[i - 1] + (time[i] - time[i - 1]) * before / (before - after))


def pendulum_columns(case: Case, raw: RawHistory, columns: dict, units: dict) -> None:
    """Add the vehicle's pendulum angles (deg) to ``columns``/``units`` (see the module doc)."""
    name = case.vehicle
    if case.bodies[name].fixed:
        return
    body = raw.bodies[name]
    axis = body["rotation"][:, :, 0]
    down = case.start.down(body["position"])
    vertical, airspeed = column("{owner}_pendulum_deg", name), column("{owner}_pendulum_airspeed_deg", name)
    columns[vertical] = _angle_deg(axis, down)
    air = case.air_motion()
    relative = body["velocity"] if air.still else air.relative(body["position"], body["velocity"],
                                                              case.start.altitude(body["position"]), raw.time)
    columns[airspeed] = _angle_deg(axis, relative)
    units.update(units_of((vertical, airspeed)))


def _angle_deg(a, b) -> np.ndarray:
    """Angles (deg) between rows of ``a`` and ``b`` (n, 3) (NaN where either is zero or absent)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        cosine = np.einsum("ij,ij->i", a, b) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
        return np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))


def settled_after(events: list, case: Case | None = None) -> float:
    """The time (s) from which the run's last configuration flies: its last deployment, cut-away, disreef or fill
    end (0 without any), and with ``case`` the end of any system's drag-area schedule (``open_from``)."""
    kinds = ("deploy", "cutaway", "disreef", "stage_start", "fill_end")
    opened = [open_from(system, events) for system in case.systems.values()] if case is not None else []
    return max([event.time for event in events if event.kind in kinds] + opened, default=0.0)


def cluster_summary(case: Case, columns: dict, events: list) -> dict:
    """Per cluster its ``ClusterLoads``: its peak load share and when (over samples above LOAD_SHARE_FLOOR), each
    canopy's largest and mean flyout (deg) from the system's last fill end to its cut-away or the run's end, each
    canopy's risers' peak tension (N) over the whole run and when, and each pair's largest overlap (m)."""
    time, out = columns["time"], {}
    for system in clusters(case):
        share = columns[column("{owner}_load_share", system.name)]
        tensions = riser_tensions(case, system, columns)
        mean = present_mean(tensions)
        strong = np.isfinite(share) & (mean >= LOAD_SHARE_FLOOR * mean.max())
        peak = (None, None)
        if strong.any():
            k = int(np.flatnonzero(strong)[np.argmax(share[strong])])
            peak = (float(share[k]), float(time[k]))
        start = open_from(system, events)
        end = system.cutaway_time if system.cutaway_time is not None else np.inf
        window = (time >= start) & (time < end)
        flyouts, risers = {}, {}
        for k, canopy in enumerate(system.canopies):
            flyout = columns[column("{owner}_flyout_deg", canopy)][window]
            flyout = flyout[np.isfinite(flyout)]
            flyouts[canopy] = {"max": float(flyout.max()), "mean": float(flyout.mean())} if len(flyout) else None
            finite = np.isfinite(tensions[:, k])
            if finite.any():
                j = int(np.flatnonzero(finite)[np.argmax(tensions[finite, k])])
                risers[canopy] = {"tension": float(tensions[j, k]), "time": float(time[j])}
            else:
                risers[canopy] = None
        out[system.name] = ClusterLoads(list(system.canopies), *peak, float(start), flyouts, risers,
                                        None if system.contact is None else _largest_overlaps(system, columns))
    return out


def _largest_overlaps(system, columns: dict) -> dict:
    """Per pair of the cluster's canopies (``<first>_<second>``), their largest overlap (m, >= 0; None: never both
    present)."""
    found = {}
    for a, first in enumerate(system.canopies):
        for second in system.canopies[a + 1:]:
            overlap = columns[column("{owner}_{other}_overlap", first, second)]
            largest = float(np.nanmax(overlap)) if np.isfinite(overlap).any() else None
            found[f"{first}_{second}"] = largest if largest is None else max(largest, 0.0)
    return found


def open_from(system, events: list) -> float:
    """The time (s) from which ``system``'s canopies are open: its last fill end (an inflation), the end of its
    drag-area schedule, or its deployment."""
    deployed = system.deploy_time or 0.0
    fills = [e.time for e in events if e.kind == "fill_end" and getattr(e, "system", "") == system.name]
    schedule = system.drag_area_schedule
    return max(fills + [deployed + (schedule.time[-1] if schedule is not None else 0.0)])


def swing_amplitude(angles) -> float | None:
    """The amplitude (deg) of a swinging angle history ``angles`` (deg, >= 0): the mean of its peaks (the samples
    above the one before and not below the one after), the largest value when it has none; None when empty. A
    planar swing peaks at its amplitude each half period, a coning one stays near its cone angle."""
    values = np.asarray(angles, float)
    if not len(values):
        return None
    inner = values[1:-1]
    peaks = inner[(inner > values[:-2]) & (inner >= values[2:])]
    return float(peaks.mean()) if len(peaks) else float(values.max())


def pendulum_summary(case: Case, columns: dict, events: list) -> Pendulum | None:
    """The vehicle's largest and RMS pendulum angles (deg) and their swing amplitude (``swing_amplitude``) to
    gravity and to its airspeed once the last configuration flies (``settled_after``); None for a fixed vehicle."""
    name = case.vehicle
    vertical = column("{owner}_pendulum_deg", name)
    if vertical not in columns:
        return None
    start = settled_after(events, case)
    window = columns["time"] >= start
    angles = []
    for angle in (vertical, column("{owner}_pendulum_airspeed_deg", name)):
        values = columns[angle][window]
        values = values[np.isfinite(values)]
        angles += [float(values.max()) if len(values) else None,
                   float(np.sqrt(np.mean(values ** 2))) if len(values) else None, swing_amplitude(values)]
    return Pendulum(float(start), *angles)


def descent_summary(case: Case, columns: dict) -> Descent:
    """The vehicle's rate of descent (m/s, relative to the ground, downward positive) averaged over the last
    DESCENT_WINDOW s of the run, and at its end."""
    time, rate = columns["time"], columns[column("{owner}_velocity_down", case.vehicle)]
    window = time >= time[-1] - DESCENT_WINDOW
    values = rate[window][np.isfinite(rate[window])]
    return Descent(float(values.mean()) if len(values) else None, DESCENT_WINDOW,
                   float(rate[-1]) if np.isfinite(rate[-1]) else None)

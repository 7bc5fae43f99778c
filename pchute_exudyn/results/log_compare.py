"""A run against a flight log (``pchute compare RUN LOG``): the same figures read the same way from both.

Each side's descent is a height above the ground against time from its apogee to its touchdown; the figures come
from it by one set of rules, so that a difference is the flight's and not the reading's:

* **the apogee**: its height above the ground and time (the log's: ``physics.flight_phases``; the run's highest
  sample);
* **the deployments**: each side's own record of when a canopy was released (the run's deploy events; the flight
  computer's firing or state changes where its log has them), and the **rate change** read from the heights alone:
  the descent rate (the fall of the height's running median over RATE_WINDOW across RATE_SPAN) falls from the
  drogue's rate (its median over BEFORE_CHANGE before the last sample faster than TWO_CANOPIES times the rate near
  the ground) halfway to the rate near the ground (the median over the last NEAR_GROUND of the descent). A descent
  never that fast has no rate change: one canopy;
* **the descent rates** over height bands set by the log (under the drogue DROGUE_BAND of the way from the rate
  change's height to the apogee; under the main MAIN_BAND of the rate change's height), each the Theil-Sen slope of
  the samples in the band (``physics.flight_phases``), never a derivative of single samples;
* **apogee to touchdown** (s), and the **drift** from the apogee to the landing (m) where the log has GPS positions.

A barometric log's heights are read through the run's air first (``physics.barometric``): on a warm day an
altimeter reads low.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..physics.flight_phases import band_rate, running_median

RATE_WINDOW = 1.0
"""s: the running median the heights are smoothed with before the rate change is read (ejection spikes)."""
RATE_GRID = 0.1
"""s: the spacing of the rates the rate change is found on."""
RATE_SPAN = 4.0
"""s: each rate is the smoothed heights' fall over this span, centred (a small drogue's tumbling rocket swings its
barometer by metres from second to second)."""
TWO_CANOPIES = 1.5
"""The fastest descent rate over the rate near the ground above which a descent has a rate change (a main)."""
BEFORE_CHANGE = 10.0
"""s: the drogue's rate before the change is the median over this long before the last fast sample."""
NEAR_GROUND = 0.25
"""The last fraction of the descent's time whose median rate is the rate near the ground."""
DROGUE_BAND = (0.1, 0.7)
"""The drogue's band: these fractions of the way from the rate change's height to the apogee's (-)."""
MAIN_BAND = (0.15, 0.6)
"""The main's band: these fractions of the rate change's height above the ground (-)."""
ONE_CANOPY_BAND = (0.1, 0.7)
"""Without a rate change: these fractions of the apogee's height (-)."""
EARTH_RADIUS = 6371008.8
"""m: the mean radius the drift between two GPS fixes is measured on (a few km: the flat-Earth error is 1e-7)."""


@dataclass(frozen=True)
class Descent:
    """One side's descent figures (module docstring). Times in s after the side's own apogee, heights in m above
    the ground.

    Attributes
    ----------
    apogee_time : float
        s on the side's own clock.
    apogee_height, descent_time : float
        m; s from the apogee to the touchdown.
    fired : list of (str, float, float)
        Each deployment the side records: (name, s after the apogee, m).
    rate_change : (float, float) or None
        (s after the apogee, m) of the halfway rate change.
    rates : dict
        Band label -> (rate m/s positive down, samples).
    drift : float or None
        m over the ground from the apogee to the landing.
    """

    apogee_time: float
    apogee_height: float
    descent_time: float
    fired: list
    rate_change: tuple | None
    rates: dict = field(default_factory=dict)
    drift: float | None = None


def rate_change(time, height) -> tuple | None:
    """(s, m) of the halfway rate change of a descent (``time`` s from its apogee to its touchdown, ``height`` m):
    module docstring; None for one canopy."""
    grid = np.arange(time[0], time[-1], RATE_GRID)
    if len(grid) < 20:
        return None
    smooth = running_median(time, height, RATE_WINDOW)
    rate = (np.interp(grid - 0.5 * RATE_SPAN, time, smooth) - np.interp(grid + 0.5 * RATE_SPAN, time, smooth)) \
        / RATE_SPAN
    ground = float(np.median(rate[int((1.0 - NEAR_GROUND) * len(rate)):]))
    fast = np.nonzero(rate > TWO_CANOPIES * ground)[0]
    if not len(fast) or ground <= 0.0:
        return None
    last = int(fast[-1])   # the last fast sample: the main has not yet taken over
    start = max(0, last - int(BEFORE_CHANGE / RATE_GRID))
    halfway = 0.5 * (float(np.median(rate[start:last + 1])) + ground)
    crossed = np.nonzero(rate[start:] <= halfway)[0]
    if not len(crossed) or start + crossed[0] == 0:
        return None
    k = start + int(crossed[0])
    when = float(grid[k - 1] + (rate[k - 1] - halfway) / (rate[k - 1] - rate[k]) * RATE_GRID)
    return when, float(np.interp(when, time, height))


def bands(apogee_height: float, change: tuple | None) -> dict:
    """Band label -> (low, high) in m above the ground (module docstring)."""
    if change is None:
        low, high = (f * apogee_height for f in ONE_CANOPY_BAND)
        return {"descent": (low, high)}
    span = apogee_height - change[1]
    return {"drogue": tuple(change[1] + f * span for f in DROGUE_BAND),
            "main": tuple(f * change[1] for f in MAIN_BAND)}


def descent(time, height, fired=(), drift=None, apogee_time: float = 0.0) -> Descent:
    """A side's ``Descent`` from its ``time`` (s after its apogee) and ``height`` (m above the ground) to its
    touchdown, its recorded deployments ``fired`` ((name, s after the apogee)), its ``drift`` (m or None) and its
    ``apogee_time`` on its own clock (s). The rates are filled by ``with_rates``."""
    time, height = np.asarray(time, float), np.asarray(height, float)
    fired = [(name, float(t), float(np.interp(t, time, height))) for name, t in fired]
    return Descent(apogee_time, float(height[0]), float(time[-1] - time[0]), fired, rate_change(time, height),
                   drift=drift)


def with_rates(side: Descent, time, height, chosen: dict) -> Descent:
    """``side`` with its rates over the ``chosen`` bands (label -> (low, high) m)."""
    rates = {label: band_rate(time, height, *limits) for label, limits in chosen.items()}
    return Descent(side.apogee_time, side.apogee_height, side.descent_time, side.fired, side.rate_change, rates,
                   side.drift)


def gps_drift(latitude_deg, longitude_deg) -> float:
    """m over the ground between the first and the last GPS fix (equirectangular, EARTH_RADIUS)."""
    lat = np.radians([latitude_deg[0], latitude_deg[-1]])
    lon = np.radians([longitude_deg[0], longitude_deg[-1]])
    east = (lon[1] - lon[0]) * math.cos(0.5 * (lat[0] + lat[1]))
    return float(EARTH_RADIUS * math.hypot(east, lat[1] - lat[0]))


@dataclass(frozen=True)
class LogComparison:
    """A run's ``Descent`` against a log's, with the bands both were read over and notes on how the log was read."""

    run_label: str
    log_label: str
    run: Descent
    log: Descent
    bands: dict
    notes: list

    def rows(self) -> list:
        """(quantity, unit, run value, log value) of every figure both sides have."""
        rows = [("apogee height above the ground", "m", self.run.apogee_height, self.log.apogee_height)]
        for i, (name, time, height) in enumerate(self.log.fired):
            if i < len(self.run.fired):
                rows += [(f"{self.run.fired[i][0]} deployed / log's {name}: time after apogee", "s",
                          self.run.fired[i][1], time),
                         (f"{self.run.fired[i][0]} deployed / log's {name}: height", "m", self.run.fired[i][2],
                          height)]
        if self.run.rate_change is not None and self.log.rate_change is not None:
            rows += [("rate change: time after apogee", "s", self.run.rate_change[0], self.log.rate_change[0]),
                     ("rate change: height", "m", self.run.rate_change[1], self.log.rate_change[1])]
        for label, (low, high) in self.bands.items():
            rows.append((f"descent rate under the {label}, {low:.0f} to {high:.0f} m", "m/s",
                         self.run.rates[label][0], self.log.rates[label][0]))
        rows.append(("apogee to touchdown", "s", self.run.descent_time, self.log.descent_time))
        if self.log.drift is not None and self.run.drift is not None:
            rows.append(("drift from the apogee to the landing", "m", self.run.drift, self.log.drift))
        return rows

    def table(self) -> str:
        """Markdown: the figures of both sides and run - log."""
        lines = [f"Run {self.run_label} against flight log {self.log_label}; times after each side's apogee, "
                 "heights above the ground; differences are run - log.", ""]
        lines += [f"* {note}" for note in self.notes] + [""]
        lines += ["| quantity | run | log | run - log | (run - log) / log |", "|---|---|---|---|---|"]
        for quantity, unit, run, log in self.rows():
            relative = (run - log) / log if log else math.nan
            lines.append(f"| {quantity} ({unit}) | {run:.4g} | {log:.4g} | {run - log:+.4g} | {relative:+.2%} |")
        counts = ", ".join(f"{label} {self.log.rates[label][1]}" for label in self.bands)
        lines += ["", f"Descent rates: Theil-Sen slopes over the bands (log samples: {counts})."]
        return "\n".join(lines) + "\n"

    def to_dict(self) -> dict:
        """The figures as plain data (JSON: a missing value is null)."""
        def side(d: Descent) -> dict:
            return {"apogee_time": d.apogee_time, "apogee_height": d.apogee_height, "descent_time": d.descent_time,
                    "fired": [{"name": n, "time": t, "height": h} for n, t, h in d.fired],
                    "rate_change": None if d.rate_change is None else {"time": d.rate_change[0],
                                                                       "height": d.rate_change[1]},
                    "rates": {label: {"rate": _number(r), "samples": n} for label, (r, n) in d.rates.items()},
                    "drift": d.drift}
        return {"run": self.run_label, "log": self.log_label, "notes": self.notes,
                "bands": {label: list(limits) for label, limits in self.bands.items()},
                "run_figures": side(self.run), "log_figures": side(self.log),
                "rows": [{"quantity": q, "unit": u, "run": _number(r), "log": _number(g)}
                         for q, u, r, g in self.rows()]}


def _number(value):
    return float(value) if value is not None and math.isfinite(value) else None


def run_descent(result) -> tuple:
    """(``Descent``, time s after the apogee, height m above the ground) of a run of this package: its vehicle's
    height from its highest sample to its touchdown (else its end), its deploy events, its drift."""
    from ..registries.columns import column

    vehicle = result.vehicle
    height = result[column("{owner}_height", vehicle)]
    top = int(np.nanargmax(height))
    events = result.summary.events if result.summary is not None else []
    end = next((e.time for e in events if e.kind == "touchdown"), float(result.time[-1]))
    keep = slice(top, int(np.searchsorted(result.time, end, side="right")))
    time, height = result.time[keep] - result.time[top], height[keep]
    fired = [(e.system, e.time - result.time[top]) for e in events if e.kind == "deploy"]
    east, north = (result[column(f"{{owner}}_{axis}", vehicle)][keep] for axis in ("east", "north"))
    drift = float(math.hypot(east[-1] - east[0], north[-1] - north[0]))
    return descent(time, height, fired, drift, float(result.time[top])), time, height


def log_descent(log, day_density=None, ground_altitude: float = 0.0, gravity: float | None = None) -> tuple:
    """(``Descent``, time s after the apogee, height m above the pad) of a ``results.flight_log.FlightLog`` from its
    apogee to its touchdown; a barometric log's heights read through ``day_density`` (z m above the pad -> kg/m^3;
    None: as the altimeter gave them), its pad's standard height its own reading where it has one, else
    ``ground_altitude`` (m); ``gravity`` the site's (m/s^2; None: standard)."""
    from ..physics.barometric import geometric_heights

    phases = log.phases
    time, height = log.descent()
    gps = np.searchsorted(log.time, time)   # the descent's rows of the log
    time = time - phases.apogee_time
    if day_density is not None and log.kind == "barometric":
        pad = ground_altitude if log.pad_altitude is None else log.pad_altitude
        height = geometric_heights(height, pad, day_density, *(() if gravity is None else (gravity,)))
    fired = [(name, t - phases.apogee_time) for name, t in sorted(log.events.items(), key=lambda item: item[1])
             if t >= phases.apogee_time - 2.0 * RATE_WINDOW]
    drift = None
    if log.latitude_deg is not None:
        latitude, longitude = log.latitude_deg[gps], log.longitude_deg[gps]
        fixes = np.isfinite(latitude) & np.isfinite(longitude)
        if np.count_nonzero(fixes) >= 2:
            drift = gps_drift(latitude[fixes], longitude[fixes])
    side = descent(time, height, fired, drift, phases.apogee_time)
    if log.touchdown_time is not None:   # the landing's time, not its first sample near the ground
        side = replace(side, descent_time=log.touchdown_time - phases.apogee_time)
    return side, time, height


def compare_with_log(result, log, run_label: str, log_label: str, day_density=None, air: str = "",
                     ground_altitude: float = 0.0, gravity: float | None = None) -> LogComparison:
    """A run against a flight log (module docstring); ``day_density`` and ``air`` (its name, for the notes) the
    run's air the log's barometric heights are read through (None: as the altimeter gave them)."""
    run, run_time, run_height = run_descent(result)
    log_side, log_time, log_height = log_descent(log, day_density, ground_altitude, gravity)
    chosen = bands(log_side.apogee_height, log_side.rate_change)
    if run.rate_change is None and log_side.rate_change is not None:
        chosen = bands(log_side.apogee_height, None)
    notes = [f"log: {log.format}, {log.kind} heights" + (f", read through the run's air ({air})"
                                                         if day_density is not None and log.kind == "barometric"
                                                         else ", as the altimeter gave them")
             + f"; its pad level {log.phases.pad_level:.2f} m, apogee at {log.phases.apogee_time:.2f} s on its clock"]
    if log_side.rate_change is not None and run.rate_change is None:
        notes.append("the run has one canopy's descent, the log two: one band over the whole descent")
    return LogComparison(run_label, log_label, with_rates(run, run_time, run_height, chosen),
                         with_rates(log_side, log_time, log_height, chosen), chosen, notes)

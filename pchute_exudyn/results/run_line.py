"""The one-line account of a finished run that ``pchute run`` prints (``run_line``), from its typed summary."""

from __future__ import annotations

from .summary import RunSummary, TouchdownEvent


def run_line(summary: RunSummary, out, stability_limit: float | None = None) -> str:
    """The one-line account of a finished run (``pchute run``): its method, step (adaptive: the steps taken, smallest
    to largest, and their mean; chosen from the stability limit: that limit), end, wall time, final position and
    deployment loads; a run that touched down ends at the interpolated touchdown, not at its last step past it."""
    s, f = summary, summary.final
    ending = "touchdown at" if s.end == "touchdown" else "ended at"
    landed = s.touchdown   # its place is None in a summary written before it was kept
    time, altitude, east, north = (f.time, f.altitude, f.east, f.north) if landed is None or landed.altitude is None \
        else (landed.time, landed.altitude, landed.east, landed.north)
    control = s.step_control
    if control and control.get("count"):
        step = (f"adaptive steps {control['smallest']:.3g} to {control['largest']:.3g} s (mean "
                f"{control['mean']:.3g} s)")
    else:
        chosen = "" if stability_limit is None else f" (none set: from the stability limit {stability_limit:.3g} s)"
        step = f"step {s.step:g} s{chosen}"
    return (f"{s.case}: {s.method}/{s.integrator} {step}, {ending} {time:.2f} s in "
            f"{s.wall_time:.2f} s of wall time ({s.steps} steps); final {s.vehicle} altitude "
            f"{altitude:.2f} m, east {east:.3f} m, north {north:.3f} m"
            f"{touchdown_text(s.touchdown)}{loads_text(s.deployments)}{canopy_models_text(s.canopy_models)} -> {out}"
            + (f" ({len(s.warnings)} warning(s): see summary.json)" if s.warnings else ""))


def loads_text(deployments) -> str:
    """The run line's account of the deployment loads: each system's or tether's opening (largest) load and when, with
    its snatch when that came first and was smaller (N, s); '' without deployments."""
    parts = []
    for d in deployments:
        if d.opening_load is None or not d.opening_load == d.opening_load:
            continue
        snatch = f" (snatch {d.snatch_load:.4g} N at {d.snatch_time:.2f} s)" \
            if d.snatch_time is not None and d.snatch_time < d.opening_time else ""
        parts.append(f"{d.system} {d.opening_load:.4g} N at {d.opening_time:.2f} s{snatch}")
    return "; peak loads " + ", ".join(parts) if parts else ""


def touchdown_text(touchdown: TouchdownEvent | None) -> str:
    """The run line's account of the touchdown: the descent rate, the horizontal speed over the ground and the total
    speed (m/s); '' for a run that did not touch down (or a summary from before the split)."""
    if touchdown is None or getattr(touchdown, "descent_rate", None) is None:
        return ""
    return (f"; at touchdown descent rate {touchdown.descent_rate:.2f} m/s, horizontal speed "
            f"{touchdown.horizontal_speed_over_ground:.2f} m/s, total speed {touchdown.speed:.2f} m/s "
            "(over the ground)")


def canopy_models_text(canopy_models) -> str:
    """The run line's account of the canopy models the loader chose (the case named none: ``canopy_model = "auto"``),
    e.g. "; canopy model chosen: drogue reduced, main reduced"; '' when the case named every one."""
    chosen = [f"{name} {entry['model']}" for name, entry in (canopy_models or {}).items()
              if entry.get("chosen") == "auto"]
    return "; canopy model chosen: " + ", ".join(chosen) if chosen else ""

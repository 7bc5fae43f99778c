"""Linearisation report of a confluence: equilibrium point, C_bar and K_bar, modes and the step limits they set.

For a case whose lines end on fixed bodies the attach points are used as they are; for a flight case the bodies'
state at time T comes from a full-mass run (implicit integrator) to T. The equilibrium point is solved from there
(thesis Eq. 2.9), the confluence dynamics linearised about it (Eq. 2.6, Appendix A) and the quadratic eigenproblem
m_c lambda^2 + C_bar lambda + K_bar solved (Table 2.2's quantities). The largest stable RK4 steps are those of the
full-mass confluence (the roots above) and of the SP confluence (dr/dt = v(r): roots of -C_bar^-1 K_bar).
"""

from __future__ import annotations

import numpy as np

from ..case.model import Case
from ..engine.state import initial_confluence_state, initial_point
from ..errors import InputError
from ..methods.base import line_arrays
from ..methods.full import FullMass
from ..physics.equilibrium_point import NoEquilibriumError, equilibrium_point
from ..physics.linearization import linearize, max_stable_step_rk4, modes, sp_eigenvalues
from .outputs import attach_points


def attach_state(case: Case, system, time: float):
    """Attach-point positions (n_lines, 3) and a confluence position guess at ``time`` (s), start-frame coordinates."""
    moving = {line.body for line in system.lines if not case.bodies[line.body].fixed}
    if not moving or time == 0.0:
        attach = np.array([initial_point(case, line.body, line.point) for line in system.lines])
        return attach, initial_confluence_state(case, system).position, 0.0
    from .simulation import resolve_run, run
    step = case.simulation.default_step(FullMass.name, "implicit") or 1e-3
    raw = run(case, resolve_run(case, FullMass, "implicit", min(step, time), time))[0]
    if raw.stopped_at is not None:
        raise InputError(f"--time = {time:g} s: the vehicle touches down at t = {raw.stopped_at:.2f} s, before it")
    positions, _ = attach_points(case, raw, system)
    return positions[-1], raw.confluences[system.name]["position"][-1], float(raw.time[-1])


def _presence(system) -> str:
    """When a system is present in a run, in words."""
    start = f"from {system.deploy_time:g} s" if system.deploy_time is not None else "from the start"
    return f"{system.name} {start}" + (f" to {system.cutaway_time:g} s" if system.cutaway_time is not None else "")


def system_at(case: Case, system_name: str | None, time: float):
    """The system to linearise at ``time`` (s): the named one, or the first present then; InputError when the time
    is outside the run or the system is not present then (after its deployment, before its cut-away)."""
    if not case.systems:
        raise InputError("the case has no parachute system to linearise")
    if not (0.0 <= time <= case.simulation.duration):
        raise InputError(f"--time = {time!r}: must be within the case's run, 0 to {case.simulation.duration:g} s")
    if system_name is not None and system_name not in case.systems:
        raise InputError(f"unknown system {system_name!r}; systems are: {', '.join(case.systems)}")
    candidates = [case.systems[system_name]] if system_name is not None else list(case.systems.values())
    for system in candidates:   # after its deployment (strictly: line stretch has no equilibrium to speak of)
        if case.acting(system, time) and (system.deploy_time is None or system.deploy_time < time):
            return system.with_bodies(case.active_bodies(time))
    which = f"system {system_name!r} is not" if system_name is not None else "no parachute system is"
    presence = "; ".join(_presence(system) for system in case.systems.values())
    raise InputError(f"--time = {time:g} s: {which} present then ({presence}); pass a --time after a deployment "
                     "and before its cut-away")


def linearization_report(case: Case, system_name: str | None = None, time: float = 0.0) -> dict:
    """The report as plain data (see the module docstring); lengths m, damping N s/m, stiffness N/m, times s."""
    system = system_at(case, system_name, time)
    system_name = system.name
    attach, guess, at_time = attach_state(case, system, time)
    lines = system.lines
    try:
        eq = equilibrium_point(attach, [line.law for line in lines], guess=guess, require_unique=True)
    except NoEquilibriumError as exc:
        raise InputError(f"no unique equilibrium point of the {system_name} confluence at t = {at_time:g} s: "
                         f"{exc.taut} of {exc.lines} lines are taut at the force balance and they do not pull "
                         "against each other in three dimensions (the stiffness matrix is singular); the confluence "
                         "can sit anywhere in a line or region") from None
    # L0, K and C, a table line's K its tangent stiffness at the equilibrium point
    c_bar, k_bar = linearize(attach, eq.position, *line_arrays(system, attach, eq.position))
    found = modes(system.confluence.mass, c_bar, k_bar)
    sp_roots = sp_eigenvalues(c_bar, k_bar)
    return {
        "case": case.name,
        "system": system_name,
        "time": at_time,
        "equilibrium_point": eq.position.tolist(),
        "equilibrium_iterations": eq.iterations,
        "taut_lines": [line.name for line, taut in zip(lines, eq.taut) if taut],
        "confluence_mass": system.confluence.mass,
        "C_bar": c_bar.tolist(),
        "K_bar": k_bar.tolist(),
        "eigenvalues": [[float(v.real), float(v.imag)] for v in found.eigenvalues],
        "natural_frequencies": found.natural_frequencies.tolist(),
        "damping_ratios": found.damping_ratios.tolist(),
        "natural_periods": found.natural_periods.tolist(),
        "damped_periods": [float(p) if np.isfinite(p) else None for p in found.periods],
        "mode_directions": [[float(x) for x in np.real(v / v[np.argmax(np.abs(v))])] for v in found.vectors.T],
        "max_stable_step_full": max_stable_step_rk4(found.eigenvalues),
        "max_stable_step_sp": max_stable_step_rk4(sp_roots) if len(sp_roots) else None,
    }


def format_report(report: dict) -> str:
    """The report as text for the terminal."""
    def matrix(rows):
        return "\n".join("    " + "  ".join(f"{v:12.5g}" for v in row) for row in rows)

    lines = [f"{report['case']}: {report['system']} confluence at t = {report['time']:g} s",
             "  equilibrium point (east, north, up of the start frame; m): "
             + ", ".join(f"{x:.6g}" for x in report["equilibrium_point"])
             + f"  [{report['equilibrium_iterations']} Newton iterations; taut: {', '.join(report['taut_lines'])}]",
             "  C_bar (N s/m):", matrix(report["C_bar"]), "  K_bar (N/m):", matrix(report["K_bar"]),
             f"  modes of m_c = {report['confluence_mass']:g} kg:",
             "    eigenvalue (1/s)                omega_n (rad/s)   T = 2 pi/omega_n (s)   damping ratio"]
    for (re, im), wn, tn, zeta in zip(report["eigenvalues"], report["natural_frequencies"],
                                      report["natural_periods"], report["damping_ratios"]):
        lines.append(f"    {re:12.5g} {im:+12.5g}i   {wn:14.6g}   {tn:20.4g}   {zeta:13.4g}")
    sp = report["max_stable_step_sp"]
    lines.append(f"  largest stable RK4 step: full mass {report['max_stable_step_full']:.3g} s, "
                 + (f"singular perturbation {sp:.3g} s" if sp is not None else "singular perturbation: n/a"))
    return "\n".join(lines)

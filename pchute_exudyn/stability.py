"""Step-size limits of explicit integration, from the linearised confluence (physics.linearization).

The full-mass model is stiff because of the small confluence mass: its fastest mode sets the largest stable RK4
step. Beyond it RK4 does not always blow up at once: it can return plausible-looking but wrong tensions for
seconds (measured: MER case 1 at 1e-3 s gave 4.6 times the true peak tensions in the first 3 s without any NaN).
So explicit full-mass runs are checked against this limit before they start.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .case.model import Case, ParachuteSystem
from .physics.linearization import linearize, max_stable_step_rk4, modes
from .physics.rotations import attitude_matrix


def initial_point(case: Case, body_name: str, point_name: str | None = None) -> np.ndarray:
    """Start-frame position (m) at t = 0 of a body's centre of mass or of one of its named points."""
    body = case.bodies[body_name]
    i = body.initial
    position = case.start.local_position(i.altitude, i.east, i.north)
    if point_name is None:
        return position
    return position + attitude_matrix(i.yaw_deg, i.pitch_deg, i.roll_deg) @ np.asarray(body.points[point_name])


def initial_confluence(case: Case, system: ParachuteSystem) -> np.ndarray:
    """Start-frame position (m) of a system's confluence at t = 0."""
    i = system.confluence.initial
    return case.start.local_position(i.altitude, i.east, i.north)


@dataclass(frozen=True)
class StepLimit:
    """The largest stable RK4 step of one confluence and the mode that sets it."""

    system: str
    step: float               # s
    eigenvalue: complex       # 1/s, the limiting root of m_c lambda^2 + C_bar lambda + K_bar


def confluence_rk4_limit(system: ParachuteSystem, attach_position, confluence_position) -> StepLimit:
    """RK4 stability limit of a full-mass confluence linearised at the given geometry with every line taut.

    Every line is counted as taut because a slack line adds neither stiffness nor damping: the all-taut limit holds
    through slack events. The limit falls as the lines stretch under load (MER case 1: 4.28e-4 s at free length,
    3.93e-4 s at 60 s), which is why runs re-check it as they go.
    """
    lines = system.lines
    c_bar, k_bar = linearize(attach_position, confluence_position, [l.free_length for l in lines],
                             [l.stiffness for l in lines], [l.damping for l in lines], taut=np.ones(len(lines), bool))
    found = modes(system.confluence.mass, c_bar, k_bar)
    steps = [max_stable_step_rk4([lam]) for lam in found.eigenvalues]
    worst = int(np.argmin(steps))
    return StepLimit(system.name, float(steps[worst]), complex(found.eigenvalues[worst]))


def sp_rk4_limit(system: ParachuteSystem, attach_position, confluence_position) -> StepLimit:
    """RK4 stability limit of an SP confluence at the given geometry with every line taut.

    SP makes the confluence first order: dr/dt = v(r) with Jacobian -alpha^-1 K_bar (alpha = C_bar with every line
    taut, Eq. 3.11 with C_c = 0), whose eigenvalues are real and negative (about -K/C: -100 1/s for MER, a limit
    near 2.8e-2 s). Slack lines raise alpha through C_c, which only slows this mode.
    """
    lines = system.lines
    c_bar, k_bar = linearize(attach_position, confluence_position, [l.free_length for l in lines],
                             [l.stiffness for l in lines], [l.damping for l in lines], taut=np.ones(len(lines), bool))
    eigenvalues = np.linalg.eigvals(-np.linalg.solve(c_bar, k_bar))
    fastest = eigenvalues[np.argmax(np.abs(eigenvalues))]
    return StepLimit(system.name, max_stable_step_rk4(eigenvalues), complex(fastest))


def full_mass_rk4_limit(case: Case, system: ParachuteSystem) -> StepLimit:
    """RK4 stability limit of a full-mass confluence at the case's initial state (see confluence_rk4_limit)."""
    attach = np.array([initial_point(case, line.body, line.point) for line in system.lines])
    return confluence_rk4_limit(system, attach, initial_confluence(case, system))


def unstable_step_message(step: float, limit: StepLimit, time: float, method: str = "full") -> str:
    """The error text for an RK4 step beyond a confluence's stability limit."""
    suggestion = float(f"{0.9 * limit.step:.2g}")  # below the limit even after rounding
    alternative = ", or --integrator implicit" if method == "full" else ""
    return (f"the RK4 step {step:g} s exceeds the stability limit of the {limit.system} confluence ({method} method) "
            f"at t = {time:.3f} s ({limit.step:.3g} s, set by its fastest mode {limit.eigenvalue.real:.0f} 1/s with "
            f"every line taut): the results would be wrong. Use --dt {suggestion:g} or smaller{alternative}")

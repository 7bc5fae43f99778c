"""A reduced canopy: a light canopy as a massless drag point at its riser's end (docs/models/reduced_canopy.md).

A canopy whose mass m is small against its drag (the drag's time constant m / (rho S C_A V), 10-20 ms for a rocket's
drogue and main) has modes far faster than the descent: on its riser, m lambda^2 + (C + rho S C_A V) lambda + K = 0,
and pitching about its centre of mass on the riser's tension, omega^2 = T l / I (100 rad/s and more). As m -> 0
(a second singular perturbation, beside SP's for the confluence) its equation of motion becomes a balance at the
riser's end P,

    - d |v - w| (v - w) - T u + m g - (m / tau) (v - v_r) = 0,     d = 1/2 rho S C_A,

with u the unit vector from the bridle's attach point A on the vehicle to P, w the air's velocity at P and T the
tension of the bridle and riser in series (``lines.series_pair``: one line from A to P), T = T_el(e) + C_s de/dt with
de/dt = u . (v - v_A), tension only. The weight m g and the inertia (m / tau)(v - v_r), a backward difference from the
reference velocity v_r (SP's order 1: ``stepping._mass_term``; m the canopy's and the confluence's masses), are the
first order in m; order 0 drops both. Solved for the velocity v of P by Newton's method on this strictly monotone
function (its Jacobian, -d (|v_r| I + v_r v_r^T / |v_r|) - C_s u u^T - (m / tau) I, is negative definite), from the
velocity of the last end of step; P itself is a state integrated with RK4 (as SP's confluence). The canopy's
attitude follows its air-relative velocity (zero angle of attack: its +x, towards the payload, along v - w), its
centre of mass a fixed distance behind P along that axis, its rotation rates zero: it has no rotational dynamics.
"""

from __future__ import annotations

import math

from ...physics.compiled import kernel
from ...physics.kinematics import (
    ANGULAR_VELOCITY_AT,
    BODY_RATE_AT,
    POINT_COLUMNS,
    POSITION_AT,
    ROTATION_AT,
    VELOCITY_AT,
    add_point_forces,
    point_motions,
)
from ...physics.lines import LINE_FREE_LENGTH, line_pull, series_constants
from ...physics.small_linalg import solve_symmetric_kernel
from .memory import (
    BRIDLE_ROW,
    LAYOUT_DAMPING,
    LAYOUT_FREE_LENGTH,
    LAYOUT_TABLE,
    RISER_ROW,
    WORK_ATTACH_POSITION,
    WORK_ATTACH_VELOCITY,
    WORK_DIRECTION,
    WORK_FORCE,
    WORK_FRACTION,
    WORK_TAUT,
    WORK_TENSION,
)

NEWTON_ITERATIONS = 30
"""Most Newton iterations of one solve (3 to 6 in practice from the last end-of-step velocity)."""


@kernel
def _residual(vx, vy, vz, drag, wx, wy, wz, rate, bx, by, bz, ux, uy, uz, elastic, damping, rest):
    """The balance's residual F(v) (N) and the tension (N) at the velocity (vx, vy, vz): drag with coefficient
    ``drag`` (kg/m) against the air (wx, wy, wz), the pair's tension elastic + damping u . v - rest (0 when not
    pulling: tension only), the mass term (rate in N s/m, b = m g + rate v_r in N)."""
    rx, ry, rz = vx - wx, vy - wy, vz - wz
    speed = math.sqrt(rx * rx + ry * ry + rz * rz)
    # the pair's pull T_el + C_s u . (v - v_A), its rate split as u . v - u . v_A for the Newton Jacobian
    tension = max(line_pull(elastic, damping, ux * vx + uy * vy + uz * vz) - rest, 0.0)
    fx = -drag * speed * rx - tension * ux + bx - rate * vx
    fy = -drag * speed * ry - tension * uy + by - rate * vy
    fz = -drag * speed * rz - tension * uz + bz - rate * vz
    return fx, fy, fz, tension, speed


@kernel
def canopy_velocity(drag, wx, wy, wz, rate, bx, by, bz, ux, uy, uz, elastic, damping, rest, vx, vy, vz):
    """The velocity (m/s) of the drag point that solves the balance (module docstring) by Newton's method from the
    guess (vx, vy, vz), and the tension (N). ``elastic`` (N) and ``damping`` (N s/m): the pair's elastic tension and
    series damping; ``rest`` = damping u . v_A (N) (the pair's rate is u . (v - v_A)); 0 elastic when slack. With no
    drag, no mass term and no tension the point keeps the guess."""
    for _ in range(NEWTON_ITERATIONS):
        fx, fy, fz, tension, speed = _residual(vx, vy, vz, drag, wx, wy, wz, rate, bx, by, bz, ux, uy, uz, elastic,
                                               damping, rest)
        rx, ry, rz = vx - wx, vy - wy, vz - wz
        # -J (positive definite): d (|r| I + r r^T / |r|) + rate I, plus C_s u u^T while the pair pulls
        line = damping if tension > 0.0 else 0.0
        scale = drag / speed if speed > 0.0 else 0.0
        a00 = drag * speed + scale * rx * rx + rate + line * ux * ux
        a11 = drag * speed + scale * ry * ry + rate + line * uy * uy
        a22 = drag * speed + scale * rz * rz + rate + line * uz * uz
        a01 = scale * rx * ry + line * ux * uy
        a02 = scale * rx * rz + line * ux * uz
        a12 = scale * ry * rz + line * uy * uz
        if a00 + a11 + a22 <= 0.0:   # nothing acts on the point: it keeps its velocity
            return vx, vy, vz, 0.0
        dx, dy, dz, kappa = solve_symmetric_kernel(a00, a01, a02, a11, a12, a22, fx, fy, fz)
        if not kappa >= 0.0:         # at rest in the air with nothing else: the drag's slope is zero there
            dx, dy, dz = fx / (a00 + 1e-300), fy / (a11 + 1e-300), fz / (a22 + 1e-300)
        vx, vy, vz = vx + dx, vy + dy, vz + dz
        if abs(dx) + abs(dy) + abs(dz) <= 1e-12 * (1.0 + abs(vx) + abs(vy) + abs(vz)):
            break
    fx, fy, fz, tension, speed = _residual(vx, vy, vz, drag, wx, wy, wz, rate, bx, by, bz, ux, uy, uz, elastic,
                                           damping, rest)
    return vx, vy, vz, tension


@kernel
def canopy_stage(states, layout, tables, work, generalized, px, py, pz, gx, gy, gz, drag, wx, wy, wz, rate, bx, by, bz,
                 row, offset):
    """One solver stage of a reduced canopy at P = (px, py, pz) (m): the bridle's attach point A on its body (layout
    row BRIDLE_ROW; RISER_ROW is the riser, whose end is P), the pair's tension (``lines.series_constants``), the
    balance solved for P's velocity from the guess (gx, gy, gz) (``canopy_velocity``), the tension's pull T u at A
    into ``generalized`` (zeroed first), and the canopy's state row ``row`` of ``states`` (its centre of mass
    ``offset`` m behind P along its axis, its attitude along its air-relative velocity, its rates zero). ``work`` as
    ``balance.sp_stage`` writes it (``memory``'s work columns), P in the riser's attach position and the confluence's
    fraction of AP in the bridle's. Returns (vx, vy, vz, 0, 0, lines counted taut)."""
    p, v, d, f = WORK_ATTACH_POSITION, WORK_ATTACH_VELOCITY, WORK_DIRECTION, WORK_FORCE
    a, r = BRIDLE_ROW, RISER_ROW
    point_motions(states, layout[:1, :POINT_COLUMNS], work[:1, p:v + 3])
    ax, ay, az = work[a, p], work[a, p + 1], work[a, p + 2]
    avx, avy, avz = work[a, v], work[a, v + 1], work[a, v + 2]
    dx, dy, dz = px - ax, py - ay, pz - az
    length = math.sqrt(dx * dx + dy * dy + dz * dz)
    ux, uy, uz = dx / length, dy / length, dz / length
    lines = layout[:, LAYOUT_FREE_LENGTH:LAYOUT_DAMPING + 1]
    elastic, damping, first = series_constants(lines, tables, layout[:, LAYOUT_TABLE], length, 0.0)
    rest = damping * (ux * avx + uy * avy + uz * avz)
    vx, vy, vz, tension = canopy_velocity(drag, wx, wy, wz, rate, bx, by, bz, ux, uy, uz, elastic, damping, rest,
                                          gx, gy, gz)
    work[r, p], work[r, p + 1], work[r, p + 2] = px, py, pz
    work[r, v], work[r, v + 1], work[r, v + 2] = vx, vy, vz
    work[a, WORK_FRACTION] = (lines[a, LINE_FREE_LENGTH] + first) / length
    for i in range(2):
        sign = -1.0 if i == a else 1.0
        work[i, WORK_TENSION] = tension
        work[i, WORK_TAUT] = 1.0 if tension > 0.0 else 0.0
        work[i, d], work[i, d + 1], work[i, d + 2] = sign * ux, sign * uy, sign * uz
        for k in range(3):
            work[i, f + k] = 0.0
    work[a, f], work[a, f + 1], work[a, f + 2] = tension * ux, tension * uy, tension * uz
    generalized[:] = 0.0
    add_point_forces(states, layout[:1, :POINT_COLUMNS], work[:1, f:f + 3], generalized)
    _canopy_row(states[row], px, py, pz, vx - wx, vy - wy, vz - wz, -ux, -uy, -uz, vx, vy, vz, offset)
    taut = 2 if tension > 0.0 else 0
    return vx, vy, vz, 0.0, 0.0, taut


@kernel
def _canopy_row(state, px, py, pz, rx, ry, rz, fx, fy, fz, vx, vy, vz, offset):
    """A reduced canopy's state row: its +x along the air-relative velocity (rx, ry, rz) (along (fx, fy, fz), towards
    the vehicle, when it is at rest in the air), y and z turned the least from the row's last attitude, its centre of
    mass ``offset`` m behind P = (px, py, pz), its velocity (vx, vy, vz), its rates zero."""
    norm = math.sqrt(rx * rx + ry * ry + rz * rz)
    if norm <= 0.0:
        rx, ry, rz, norm = fx, fy, fz, 1.0
    ex, ey, ez = rx / norm, ry / norm, rz / norm
    r = ROTATION_AT   # R row-major: its columns are the body axes in start-frame components
    yx, yy, yz = state[r + 1], state[r + 4], state[r + 7]   # the last y axis, made square to the new x
    dot = yx * ex + yy * ey + yz * ez
    yx, yy, yz = yx - dot * ex, yy - dot * ey, yz - dot * ez
    size = math.sqrt(yx * yx + yy * yy + yz * yz)
    if size < 1e-9:   # the last y along the new x (or no attitude yet): any axis square to it
        yx, yy, yz = (-ey, ex, 0.0) if abs(ez) < 0.9 else (0.0, -ez, ey)
        size = math.sqrt(yx * yx + yy * yy + yz * yz)
    yx, yy, yz = yx / size, yy / size, yz / size
    zx, zy, zz = ey * yz - ez * yy, ez * yx - ex * yz, ex * yy - ey * yx
    state[r], state[r + 1], state[r + 2] = ex, yx, zx
    state[r + 3], state[r + 4], state[r + 5] = ey, yy, zy
    state[r + 6], state[r + 7], state[r + 8] = ez, yz, zz
    state[POSITION_AT], state[POSITION_AT + 1], state[POSITION_AT + 2] = (px - offset * ex, py - offset * ey,
                                                                          pz - offset * ez)
    state[VELOCITY_AT], state[VELOCITY_AT + 1], state[VELOCITY_AT + 2] = vx, vy, vz
    for k in range(3):
        state[ANGULAR_VELOCITY_AT + k] = 0.0
        state[BODY_RATE_AT + k] = 0.0

"""Singular-perturbation (SP) confluence velocity (thesis chapter 3, Eqs. 3.1-3.13; ``docs/models/mer.md``,
"Singular-perturbation details").

As the confluence mass goes to zero its equation of motion becomes a balance of the line forces (Eq. 3.1). Solving the
balance for the confluence velocity v (Eqs. 3.4-3.11), with a confluence damping force -C_c (v - v0) (Eq. 3.7) that
keeps the solve well-posed while a line is slack::

    alpha v = sum_taut [K (L - L0) + C v_i . n] n + C_c v0,     alpha = sum_taut C n n^T + C_c I      (3.10, 3.11)

n is the unit vector from the confluence to the attach point i, v0 the confluence velocity at the end of the
previous step. C_c = 0 while every line is taut; while any line is slack (or alpha is singular, e.g. with two taut
lines along one direction), C_c is the smallest value >= 0 for which the condition number of alpha (Eq. 3.13) is at
most kappa_max (``physics.conditioning``). The line law is ``physics.lines``'s (``LineLaw``): T_el, the pull and the
clip come from its kernels.

Slack rules: ``stretch`` (the thesis): taut means L > L0. ``force`` (active set): a line counts as taut when it is
stretched and its linear-law tension K (L - L0) + C (v_i - v) . n at the solved v is >= 0. Starting from the stretched
lines, each pass drops every taut line that pushes or, when none does, takes back every stretched line left out that
would pull, and solves again, until the set is consistent both ways (a set seen before ends the search). All
lines slack: the confluence keeps its previous velocity (reported C_c = 0, kappa = 0).

First-order confluence mass (``order = 1``, our addition beyond the thesis). Eq. 3.1 is the zeroth-order term of the
confluence's equation of motion m_c a_c = sum T n + m_c g as m_c -> 0, so SP drops the confluence's weight and
inertia: the bodies then carry a system lighter by m_c, and a mode in which the confluence moves (a capsule rocking on
its bridles) runs at the massless frequency. Order 1 keeps both in the same solve, with the acceleration as a
backward difference from a reference velocity v_r at an earlier time (m_c / tau = rate)::

    sum T n + m_c g - rate (v - v_r) = 0   ->   alpha' = alpha + rate I,   b' = b + m_c g + rate v_r

The inertia adds rate to every eigenvalue of alpha, so the solve is never less regular than the massless one (it is
unconditionally stable, where an explicit, lagged m_c a_c is not once m_c / tau exceeds alpha's smallest eigenvalue),
C_c is still the smallest value meeting kappa_max for the sum, and with every line slack the confluence falls freely
(v = v_r + tau g). As m_c -> 0 it is the massless solve again.

Compiled (``compiled.kernel``; under 1 us a call for four taut lines): it runs at every solver stage. The force
rule tries at most MAX_ACTIVE_SETS active sets per solve (two or three in practice).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...physics.compiled import kernel
from ...physics.conditioning import SINGULAR, minimum_damping_of
from ...physics.kinematics import POINT_COLUMNS, add_point_forces, point_motions
from ...physics.lines import (
    LINE_DAMPING,
    LINE_FREE_LENGTH,
    LINE_STIFFNESS,
    line_elastic,
    line_pull,
    line_tension,
    pack_lines,
    solve_series,
)
from ...physics.small_linalg import solve_symmetric_kernel, symmetric_eigenvalues
from .memory import (
    LAYOUT_DAMPING,
    LAYOUT_FREE_LENGTH,
    LAYOUT_TABLE,
    WORK_ATTACH_POSITION,
    WORK_ATTACH_VELOCITY,
    WORK_DIRECTION,
    WORK_FORCE,
    WORK_FRACTION,
    WORK_SCRATCH,
    WORK_TAUT,
    WORK_TENSION,
)

SLACK_RULES = ("stretch", "force")
SP_ORDERS = (0, 1)
"""Order in the confluence mass: 0, the massless balance of Eq. 3.10 (the thesis); 1, the mass kept to first order."""

def relaxed_damping(stiffness, damping, relaxation_time: float) -> list:
    """Each line's damping (N s/m) raised to at least tau K (K in N/m, tau = ``relaxation_time`` in s): the
    relaxed SP law (docs/models/any_damping.md). The balance's fast mode decays at rate K / C (Eq. 3.10 linearised),
    so with C >= tau K it is never faster than 1 / tau and RK4 is stable at steps up to about 2.5 tau for any C >= 0,
    none included; a line already damped that much is left as it is."""
    return [max(c, relaxation_time * k) for k, c in zip(stiffness, damping)]


MAX_ACTIVE_SETS = 64
"""Active sets the force rule tries in one solve before it keeps the last (a set seen before ends it sooner)."""


class MassTerm(NamedTuple):
    """The confluence mass kept to first order (``order = 1``): the inertia rate (v - v_r) and the weight m_c g.

    Attributes
    ----------
    rate : float
        m_c / tau (N s/m): the confluence mass over the time since the reference velocity; 0 when there is none yet
        (then ``weight`` may carry the inertial force of a known acceleration instead).
    reference_velocity : tuple of 3 float
        v_r (m/s), the confluence velocity at that earlier time.
    weight : tuple of 3 float
        m_c g (N), the confluence's weight (minus m_c a_c when ``rate`` is 0 and a_c is known).
    """

    rate: float
    reference_velocity: tuple
    weight: tuple


class SPSolution(NamedTuple):
    """Result of one SP solve.

    Attributes
    ----------
    velocity : tuple of 3 float
        Confluence velocity v (m/s).
    damping : float
        Confluence damping C_c used (N s/m).
    condition_number : float
        kappa of the alpha that was solved (Eq. 3.13); 0 when every line is slack (no alpha).
    taut : tuple of bool
        Lines counted taut in the final solve.
    tensions : list of float
        Line tensions T >= 0 (N) from the line law with velocity v: the forces on the bodies are -T n.
    directions : list of tuple
        Unit vectors n from the confluence to each attach point.
    """

    velocity: tuple
    damping: float
    condition_number: float
    taut: tuple
    tensions: list
    directions: list


@kernel
def _assemble(attach, attach_velocity, cx, cy, cz, lines, tables, table_counts, active, forced, rate, b0x, b0y, b0z,
              geometry):
    """One pass over the lines: their geometry into ``geometry`` (rows nx, ny, nz, stretch, attach velocity along n,
    elastic tension), and alpha (Eq. 3.11, six entries a00 a01 a02 a11 a12 a22) and b (Eq. 3.10) summed over the
    active lines, on top of the mass term's ``rate`` and ``b0``. ``forced``: ``active`` holds the force rule's set;
    else the stretched lines are marked active. The elastic tension is K (L - L0), or the line's table T_table."""
    a00 = a11 = a22 = rate
    a01 = a02 = a12 = 0.0
    bx, by, bz = b0x, b0y, b0z
    for i in range(attach.shape[0]):
        dx, dy, dz = attach[i, 0] - cx, attach[i, 1] - cy, attach[i, 2] - cz
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        nx, ny, nz = dx / length, dy / length, dz / length
        l0, k, c = lines[i, LINE_FREE_LENGTH], lines[i, LINE_STIFFNESS], lines[i, LINE_DAMPING]
        stretch = length - l0
        vn = attach_velocity[i, 0] * nx + attach_velocity[i, 1] * ny + attach_velocity[i, 2] * nz
        elastic = line_elastic(tables[i], int(table_counts[i]), stretch, l0, k)   # 0 when slack: never read then
        geometry[i, 0], geometry[i, 1], geometry[i, 2] = nx, ny, nz
        geometry[i, 3], geometry[i, 4], geometry[i, 5] = stretch, vn, elastic
        if not forced:
            active[i] = stretch > 0.0
        if active[i]:
            cnx, cny = c * nx, c * ny
            a00 += cnx * nx
            a01 += cnx * ny
            a02 += cnx * nz
            a11 += cny * ny
            a12 += cny * nz
            a22 += c * nz * nz
            f = line_pull(elastic, c, vn)   # Eq. 3.10's right-hand side: the pull at the attach point's velocity
            bx += f * nx
            by += f * ny
            bz += f * nz
    return a00, a01, a02, a11, a12, a22, bx, by, bz


@kernel
def _solve_balance(alpha_b, all_active, any_active, rate, v0x, v0y, v0z, kappa_max):
    """Velocity (m/s), C_c (N s/m) and kappa of Eq. 3.10 for an assembled alpha and b: C_c = 0 with every line
    taut and alpha regular, else the smallest C_c meeting kappa_max (Eq. 3.13); every line slack and no mass term:
    the previous velocity (C_c = 0, kappa = 0)."""
    if not any_active and rate == 0.0:
        return v0x, v0y, v0z, 0.0, 0.0
    a00, a01, a02, a11, a12, a22, bx, by, bz = alpha_b
    if all_active:
        x0, x1, x2, kappa = solve_symmetric_kernel(a00, a01, a02, a11, a12, a22, bx, by, bz)
        if kappa >= 0.0 and kappa < 1.0 / SINGULAR:  # every line taut and alpha regular: C_c = 0
            return x0, x1, x2, 0.0, kappa
    m0, m1, m2 = symmetric_eigenvalues(a00, a01, a02, a11, a12, a22)
    c_c = minimum_damping_of(m0, m1, m2, kappa_max)
    x0, x1, x2, kappa = solve_symmetric_kernel(a00 + c_c, a01, a02, a11 + c_c, a12, a22 + c_c,
                                               bx + c_c * v0x, by + c_c * v0y, bz + c_c * v0z)
    return x0, x1, x2, c_c, kappa


@kernel
def _next_active_set(geometry, lines, active, velocity, visited, seen):
    """Force rule: update ``active`` toward consistency; False when it is consistent (or would repeat a set).

    Every taut line that pushes is dropped at once (docs/models/mer.md: a taut line whose tension comes out negative);
    when none does, every stretched line left out that would pull is taken back. Changing lines together keeps
    symmetric configurations symmetric (one-at-a-time picks one of equal bridles by index and starts a swing).
    ``visited`` holds the ``seen`` sets tried so far as bit masks.
    """
    wx, wy, wz = velocity
    drop = 0
    take = 0
    for i in range(geometry.shape[0]):
        nx, ny, nz, stretch, vn, elastic = geometry[i, 0], geometry[i, 1], geometry[i, 2], geometry[i, 3], \
            geometry[i, 4], geometry[i, 5]
        if stretch <= 0.0:
            continue
        linear = line_pull(elastic, lines[i, LINE_DAMPING], vn - wx * nx - wy * ny - wz * nz)
        if active[i] and linear < 0.0:
            drop |= 1 << i
        elif not active[i] and linear > 0.0:
            take |= 1 << i
    change = drop if drop else take
    if not change:
        return False
    candidate = 0
    for i in range(geometry.shape[0]):
        if active[i] != bool(change >> i & 1):
            candidate |= 1 << i
    for j in range(seen):
        if visited[j] == candidate:
            return False
    if seen >= visited.shape[0]:
        return False
    visited[seen] = candidate
    for i in range(geometry.shape[0]):
        active[i] = bool(candidate >> i & 1)
    return True


@kernel
def _mask(active):
    mask = 0
    for i in range(active.shape[0]):
        if active[i]:
            mask |= 1 << i
    return mask


@kernel
def solve_confluence(attach, attach_velocity, cx, cy, cz, v0x, v0y, v0z, lines, tables, table_counts, kappa_max,
                     force_rule, rate, b0x, b0y, b0z, tensions, directions, active, geometry):
    """The SP solve (Eqs. 3.10-3.13) on arrays; the one home of the method, ``confluence_velocity`` wraps it.

    Inputs: attach points (n, 3) in m and their velocities (n, 3) in m/s, the confluence position in m and v0 in
    m/s, per line (L0 in m, K in N/m, C in N s/m) as ``lines`` (n, 3), the tables (``lines.pack_tables``),
    kappa_max, ``force_rule`` (the force slack rule, else stretch), the mass term's rate (N s/m) and b0 = m_c g +
    rate v_r (N). Writes the tensions (n) in N, the unit vectors n (n, 3) and the lines counted taut (n), using
    ``geometry`` (n, 6) as scratch; returns (vx, vy, vz, C_c, kappa). Allocates only the force rule's record. Two
    lines are a pair in series (``solve_series``: C_c = 0, kappa = 0, no alpha).
    """
    n = attach.shape[0]
    if n == 2:
        vx, vy, vz, _ = solve_series(attach, attach_velocity, lines, tables, table_counts, tensions, directions,
                                     active, 0.0, 0.0, 0.0)
        return vx, vy, vz, 0.0, 0.0
    visited = np.empty(MAX_ACTIVE_SETS if force_rule else 1, np.int64)
    seen = 0
    forced = False
    while True:
        alpha_b = _assemble(attach, attach_velocity, cx, cy, cz, lines, tables, table_counts, active, forced, rate,
                            b0x, b0y, b0z, geometry)
        all_active, any_active = True, False
        for i in range(n):
            all_active = all_active and active[i]
            any_active = any_active or active[i]
        vx, vy, vz, c_c, kappa = _solve_balance(alpha_b, all_active, any_active, rate, v0x, v0y, v0z, kappa_max)
        if not force_rule:
            break
        if seen == 0:
            visited[0] = _mask(active)
            seen = 1
        if not _next_active_set(geometry, lines, active, (vx, vy, vz), visited, seen):
            break
        seen += 1
        forced = True
    for i in range(n):
        nx, ny, nz, stretch, vn, elastic = geometry[i, 0], geometry[i, 1], geometry[i, 2], geometry[i, 3], \
            geometry[i, 4], geometry[i, 5]
        directions[i, 0], directions[i, 1], directions[i, 2] = nx, ny, nz
        tensions[i] = line_tension(stretch, elastic, lines[i, LINE_DAMPING], vn - vx * nx - vy * ny - vz * nz)
    return vx, vy, vz, c_c, kappa


def confluence_velocity(attach_position, attach_velocity, confluence_position, previous_velocity, laws,
                        kappa_max: float = 5.0, slack_rule: str = "stretch",
                        mass_term: MassTerm | None = None) -> SPSolution:
    """SP confluence velocity (Eq. 3.10) with the minimal confluence damping of Eq. 3.13 (``solve_confluence``
    for sequences of floats).

    Parameters
    ----------
    attach_position, attach_velocity : sequence of (x, y, z)
        Position (m) and velocity (m/s) of each line's attach point.
    confluence_position : (x, y, z)
        Confluence position (m).
    previous_velocity : (x, y, z)
        Confluence velocity at the end of the previous step, v0 (m/s).
    laws : sequence of LineLaw
        The lines (``case.model.Line.law``); every C must be > 0.
    kappa_max : float
        Largest condition number accepted while a line is slack (> 3).
    slack_rule : {"stretch", "force"}
    mass_term : MassTerm, optional
        The confluence mass to first order (see the module docstring); None for the massless balance of Eq. 3.10.

    Returns
    -------
    SPSolution
    """
    n = len(laws)
    if mass_term is None:
        rate, b0 = 0.0, (0.0, 0.0, 0.0)
    else:
        rate, (rx, ry, rz), (gx, gy, gz) = mass_term
        b0 = (gx + rate * rx, gy + rate * ry, gz + rate * rz)
    constants, table_points, table_counts = pack_lines(laws)
    tensions, directions, active = np.empty(n), np.empty((n, 3)), np.zeros(n, np.bool_)
    cx, cy, cz = (float(x) for x in list(confluence_position)[:3])
    v0x, v0y, v0z = (float(x) for x in previous_velocity)
    vx, vy, vz, c_c, kappa = solve_confluence(
        np.asarray(attach_position, float).reshape(n, 3), np.asarray(attach_velocity, float).reshape(n, 3),
        cx, cy, cz, v0x, v0y, v0z, constants, table_points,
        table_counts, float(kappa_max), slack_rule == "force", float(rate), *(float(b) for b in b0), tensions,
        directions, active, np.empty((n, 6)))
    return SPSolution((vx, vy, vz), c_c, kappa, tuple(bool(a) for a in active), tensions.tolist(),
                      [tuple(d) for d in directions.tolist()])


@kernel
def sp_stage(states, layout, tables, work, generalized, cx, cy, cz, v0x, v0y, v0z, kappa_max, force_rule, rate,
             b0x, b0y, b0z):
    """One solver stage of an SP confluence: attach-point motion from the body states (``kinematics``), the SP
    solve, and the lines' generalized forces -T n on the bodies into ``generalized`` (zeroed first).

    ``states`` as in ``kinematics``; ``layout`` rows: the attach point (``kinematics.POINT_COLUMNS``), then L0
    (m), K (N/m), C (N s/m) and the line's table points (0: linear); ``tables`` (n, m, 2) as
    ``lines.pack_tables``; ``work`` (n, STAGE_COLUMNS) receives the lines. Scalars: the confluence position (m),
    v0 (m/s), kappa_max, 1.0 for the force slack rule (else 0.0), the mass term's rate (N s/m) and b0 = m_c g +
    rate v_r (N). Returns (vx, vy, vz, C_c, kappa, lines counted taut). Scalars travel as separate floats: a
    tuple argument costs numba's dispatcher a microsecond more.
    """
    n = layout.shape[0]
    points = layout[:, :POINT_COLUMNS]
    p, v, d, f = WORK_ATTACH_POSITION, WORK_ATTACH_VELOCITY, WORK_DIRECTION, WORK_FORCE
    point_motions(states, points, work[:, p:v + 3])   # (x, y, z, vx, vy, vz): position and velocity side by side
    active = np.empty(n, np.bool_)
    if n == 2:   # a pair in series: b0 is then the confluence's weight, shared by the two ends by its place on AB
        return _series_stage(states, layout, tables, work, generalized, active, b0x, b0y, b0z)
    vx, vy, vz, c_c, kappa = solve_confluence(
        work[:, p:p + 3], work[:, v:v + 3], cx, cy, cz, v0x, v0y, v0z, layout[:, LAYOUT_FREE_LENGTH:LAYOUT_DAMPING + 1],
        tables, layout[:, LAYOUT_TABLE], kappa_max, force_rule > 0.0, rate, b0x, b0y, b0z, work[:, WORK_TENSION],
        work[:, d:d + 3], active, work[:, WORK_SCRATCH:WORK_SCRATCH + 6])
    taut = 0
    for i in range(n):
        taut += 1 if active[i] else 0
        work[i, WORK_TAUT] = 1.0 if active[i] else 0.0
        for k in range(3):
            work[i, f + k] = -work[i, WORK_TENSION] * work[i, d + k]   # on the body: -T n
    generalized[:] = 0.0
    add_point_forces(states, points, work[:, f:f + 3], generalized)
    return vx, vy, vz, c_c, kappa, taut


@kernel
def _series_stage(states, layout, tables, work, generalized, active, wx, wy, wz):
    """``sp_stage`` for two lines in series (``solve_series``): the forces -T n on the bodies; the confluence's
    weight (wx, wy, wz) in N (0 for the massless order) pulls line 0 harder along AB, and its part across AB is
    shared by the two attach points as a beam's two supports share a load (1 - f and f, f the confluence's
    fraction of the way from line 0's attach point)."""
    points = layout[:, :POINT_COLUMNS]
    p, v, d, f = WORK_ATTACH_POSITION, WORK_ATTACH_VELOCITY, WORK_DIRECTION, WORK_FORCE
    vx, vy, vz, fraction = solve_series(work[:, p:p + 3], work[:, v:v + 3],
                                        layout[:, LAYOUT_FREE_LENGTH:LAYOUT_DAMPING + 1], tables,
                                        layout[:, LAYOUT_TABLE], work[:, WORK_TENSION], work[:, d:d + 3], active,
                                        wx, wy, wz)
    work[0, WORK_FRACTION] = fraction   # for the end-of-step position (``stepping.sp_end_of_step``)
    ux, uy, uz = work[1, d], work[1, d + 1], work[1, d + 2]
    along = wx * ux + wy * uy + wz * uz
    cx, cy, cz = wx - along * ux, wy - along * uy, wz - along * uz   # the weight across AB
    taut = 0
    for i in range(2):
        taut += 1 if active[i] else 0
        work[i, WORK_TAUT] = 1.0 if active[i] else 0.0
        share = 1.0 - fraction if i == 0 else fraction
        work[i, f] = -work[i, WORK_TENSION] * work[i, d] + share * cx
        work[i, f + 1] = -work[i, WORK_TENSION] * work[i, d + 1] + share * cy
        work[i, f + 2] = -work[i, WORK_TENSION] * work[i, d + 2] + share * cz
    generalized[:] = 0.0
    add_point_forces(states, points, work[:, f:f + 3], generalized)
    return vx, vy, vz, 0.0, 0.0, taut

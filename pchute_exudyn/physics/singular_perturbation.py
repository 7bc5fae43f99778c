"""Singular-perturbation (SP) confluence velocity (thesis chapter 3, Eqs. 3.1-3.13; ``docs/models/mer.md``,
"Singular-perturbation details").

As the confluence mass goes to zero its equation of motion becomes a balance of the line forces (Eq. 3.1). Solving the
balance for the confluence velocity v (Eqs. 3.4-3.11), with a confluence damping force -C_c (v - v0) (Eq. 3.7) that
keeps the solve well-posed while a line is slack::

    alpha v = sum_taut [K (L - L0) + C v_i . n] n + C_c v0,     alpha = sum_taut C n n^T + C_c I      (3.10, 3.11)

n is the unit vector from the confluence to the attach point i, v0 the confluence velocity at the end of the
previous step. C_c = 0 while every line is taut; while any line is slack (or alpha is singular, e.g. with two taut
lines along one direction), C_c is the smallest value >= 0 for which the condition number
kappa = sqrt(trace(alpha^2) trace(alpha^-2)) (Eq. 3.13) is at most kappa_max. kappa falls monotonically with C_c:
with x_k = mu_k + C_c (mu_k the eigenvalues of sum C n n^T),
d/dC_c [sum x^2 sum x^-2] = 2 (sum x sum x^-2 - sum x^2 sum x^-3) <= 0, so the smallest C_c is found by a bracketed
Newton iteration on kappa^2 = kappa_max^2 (bracket [0, 3 mu_max / (kappa_max - 3)], from kappa <= 3 (1 + mu_max/C_c)).
The Frobenius condition number of a 3x3 matrix is at least 3, so kappa_max must exceed 3.

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

from .aerodynamics import aerodynamics_stage
from .compiled import kernel
from .kinematics import POINT_COLUMNS, add_gravity_forces, add_point_forces, body_states, point_motions
from .lines import pack_tables, table_tension
from .planet import gravity_acceleration
from .small_linalg import solve_symmetric_kernel, symmetric_eigenvalues

SLACK_RULES = ("stretch", "force")
SP_ORDERS = (0, 1)
"""Order in the confluence mass: 0, the massless balance of Eq. 3.10 (the thesis); 1, the mass kept to first order."""

SINGULAR = 1e-12
"""Relative singularity test: alpha counts as singular when its condition number exceeds 1/SINGULAR (its smallest
eigenvalue is below about SINGULAR times its largest) or its determinant is not positive."""

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
def _condition_number(m0, m1, m2, damping):
    x0, x1, x2 = m0 + damping, m1 + damping, m2 + damping
    if min(x0, x1, x2) <= 0.0:
        return math.inf
    return math.sqrt((x0 * x0 + x1 * x1 + x2 * x2) * (1.0 / (x0 * x0) + 1.0 / (x1 * x1) + 1.0 / (x2 * x2)))


def condition_number(eigenvalues, damping: float = 0.0) -> float:
    """kappa = sqrt(sum x^2 sum x^-2) (Eq. 3.13) for alpha with eigenvalues ``eigenvalues`` + ``damping``."""
    return _condition_number(*(float(mu) for mu in eigenvalues), float(damping))


@kernel
def _minimum_damping(m0, m1, m2, kappa_max):
    """``minimum_damping`` for three eigenvalues; -1 when alpha is zero."""
    m0, m1, m2 = max(m0, 0.0), max(m1, 0.0), max(m2, 0.0)
    mu_max = max(m0, m1, m2)
    if mu_max <= 0.0:
        return -1.0
    if min(m0, m1, m2) > SINGULAR * mu_max and _condition_number(m0, m1, m2, 0.0) <= kappa_max:
        return 0.0
    target = kappa_max * kappa_max
    lo, hi = 0.0, 3.0 * mu_max / (kappa_max - 3.0)
    c = hi
    for _ in range(100):
        x0, x1, x2 = m0 + c, m1 + c, m2 + c
        s1 = x0 + x1 + x2
        s2 = x0 * x0 + x1 * x1 + x2 * x2
        sm2 = 1.0 / (x0 * x0) + 1.0 / (x1 * x1) + 1.0 / (x2 * x2)
        sm3 = 1.0 / (x0 * x0 * x0) + 1.0 / (x1 * x1 * x1) + 1.0 / (x2 * x2 * x2)
        f = s2 * sm2 - target
        if f > 0.0:
            lo = c
        else:
            hi = c
        slope = 2.0 * (s1 * sm2 - s2 * sm3)
        newton = c - f / slope if slope < 0.0 else 0.5 * (lo + hi)
        # kappa^2 is convex and falling in C_c: Newton from the upper bound walks down to the root from the
        # feasible side (f <= 0), so a negligible step there is convergence
        if f <= 0.0 and abs(newton - c) <= 1e-13 * c or hi - lo <= 1e-13 * hi:
            break
        c = newton if lo < newton < hi else 0.5 * (lo + hi)
    return hi  # the bracket's upper end: kappa(hi) <= kappa_max holds exactly


def minimum_damping(eigenvalues, kappa_max: float) -> float:
    """Smallest C_c >= 0 with condition_number(eigenvalues, C_c) <= kappa_max (N s/m); three eigenvalues >= 0.

    Exact for the given eigenvalues; with eigenvalues from ``symmetric_eigenvalues`` of a (near-)singular alpha,
    kappa recomputed from alpha itself can exceed kappa_max by a few parts in 1e9 (eigenvalue round-off).
    """
    damping = _minimum_damping(*(float(mu) for mu in eigenvalues), float(kappa_max))
    if damping < 0.0:
        raise ValueError("alpha is zero: no taut line has damping")
    return damping


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
        l0, k, c = lines[i, 0], lines[i, 1], lines[i, 2]
        stretch = length - l0
        vn = attach_velocity[i, 0] * nx + attach_velocity[i, 1] * ny + attach_velocity[i, 2] * nz
        count = int(table_counts[i])
        elastic = k * stretch if count == 0 else table_tension(tables[i], count, stretch / l0)
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
            f = elastic + c * vn
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
    c_c = _minimum_damping(m0, m1, m2, kappa_max)
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
        linear = elastic + lines[i, 2] * (vn - wx * nx - wy * ny - wz * nz)
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
    ``geometry`` (n, 6) as scratch; returns (vx, vy, vz, C_c, kappa). Allocates only the force rule's record.
    """
    n = attach.shape[0]
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
        value = elastic + lines[i, 2] * (vn - vx * nx - vy * ny - vz * nz)   # lines.tension's law
        tensions[i] = value if stretch > 0.0 and value > 0.0 else 0.0
    return vx, vy, vz, c_c, kappa


def confluence_velocity(attach_position, attach_velocity, confluence_position, previous_velocity,
                        free_length, stiffness, damping, kappa_max: float = 5.0,
                        slack_rule: str = "stretch", mass_term: MassTerm | None = None,
                        tables=None) -> SPSolution:
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
    free_length, stiffness, damping : sequence of float
        L0 (m), K (N/m), C (N s/m) per line; every C must be > 0.
    kappa_max : float
        Largest condition number accepted while a line is slack (> 3).
    slack_rule : {"stretch", "force"}
    mass_term : MassTerm, optional
        The confluence mass to first order (see the module docstring); None for the massless balance of Eq. 3.10.
    tables : sequence of LoadElongation or None, optional
        Per line, a load-elongation table whose tension replaces K (L - L0); None: every line linear.

    Returns
    -------
    SPSolution
    """
    n = len(free_length)
    if mass_term is None:
        rate, b0 = 0.0, (0.0, 0.0, 0.0)
    else:
        rate, (rx, ry, rz), (gx, gy, gz) = mass_term
        b0 = (gx + rate * rx, gy + rate * ry, gz + rate * rz)
    table_points, table_counts = pack_tables(tables if tables is not None else [None] * n)
    tensions, directions, active = np.empty(n), np.empty((n, 3)), np.zeros(n, np.bool_)
    cx, cy, cz = (float(x) for x in list(confluence_position)[:3])
    v0x, v0y, v0z = (float(x) for x in previous_velocity)
    vx, vy, vz, c_c, kappa = solve_confluence(
        np.asarray(attach_position, float).reshape(n, 3), np.asarray(attach_velocity, float).reshape(n, 3),
        cx, cy, cz, v0x, v0y, v0z, np.column_stack([free_length, stiffness, damping]).astype(float), table_points,
        table_counts, float(kappa_max), slack_rule == "force", float(rate), *(float(b) for b in b0), tensions,
        directions, active, np.empty((n, 6)))
    return SPSolution((vx, vy, vz), c_c, kappa, tuple(bool(a) for a in active), tensions.tolist(),
                      [tuple(d) for d in directions.tolist()])


STAGE_COLUMNS = 21
"""Columns of ``sp_stage``'s per-line work array: tension (N), n (3), taut (1 or 0), attach position (3, m) and
velocity (3, m/s), the force on the body -T n (3, N), the solve's scratch (6), and the tension of the last
end-of-step solve (N, column END_TENSION: ``sp_end_of_step``; a later stage's solve leaves it)."""
(WORK_TENSION, WORK_DIRECTION, WORK_TAUT, WORK_ATTACH_POSITION, WORK_ATTACH_VELOCITY, WORK_FORCE,
 WORK_SCRATCH) = 0, 1, 4, 5, 8, 11, 14
"""Where each part of a work row starts (three columns each for n, the attach motion and the force; six of scratch)."""
END_TENSION = 20


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
    vx, vy, vz, c_c, kappa = solve_confluence(
        work[:, p:p + 3], work[:, v:v + 3], cx, cy, cz, v0x, v0y, v0z, layout[:, POINT_COLUMNS:POINT_COLUMNS + 3],
        tables, layout[:, POINT_COLUMNS + 3], kappa_max, force_rule > 0.0, rate, b0x, b0y, b0z, work[:, WORK_TENSION],
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


(MEMORY_POSITION, MEMORY_STAGE_VELOCITIES, MEMORY_V0, MEMORY_SETTINGS, MEMORY_ORDER, MEMORY_GRAVITY, MEMORY_TIMES,
 MEMORY_NEWER, MEMORY_OLDER, MEMORY_ACCELERATION, MEMORY_CLOCK, MEMORY_DUE, MEMORY_RUN, MEMORY_END,
 MEMORY_END_SOLVE) = 0, 1, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17
"""The rows of an SP confluence's memory by name (see MEMORY_ROWS; MEMORY_STAGE_VELOCITIES is k_1, the first of
four)."""
MEMORY_ROWS = 18
"""Rows (of 3 floats) of an SP confluence's memory for ``sp_rk_stage``:

0 the confluence position q_n at the start of the step under way (m); 1-4 the stage velocities k_1 .. k_4 of the
step (m/s; row 1 is also the end-of-step solve's velocity); 5 v0 (m/s); 6 (m_c in kg, kappa_max, 1 for the force
slack rule else 0); 7 (order, gravity mu in m^3/s^2, number of recorded end-of-step velocities, at most 2); 8 the
planet centre (m; mu > 0) or the uniform gravity (m/s^2; mu = 0); 9 (times of the newer and the older recorded
end-of-step velocities in s, -); 10 and 11 those velocities (m/s); 12 the acceleration carried from the previous
phase (m/s^2).

The step's bookkeeping, kept here so that a stage's call from Python passes nothing but the time (``sp_step_stage``):
13 (the index of the coming RK stage, 0-4; t_n, the start of the step under way in s; its step h in s); 14 (1 when
the end-of-step work of the last step is due, else 0; that step's end time in s; 1 when it completed its four
stages); 15 (the run's step as the engine holds it in s, 0 until the solver sets it; the phase start in s; -);
16 and 17 the last end-of-step solve's (vx, vy, vz) in m/s and (C_c in N s/m, kappa, lines counted taut)."""

RK4_STAGE_FRACTIONS = (0.0, 0.5, 0.5, 1.0)
"""a_k of the classical RK4 tableau (Exudyn's RK44): stage k's state is q_n + h a_k k_(k-1) (stage 1: q_n)."""
RK4_WEIGHTS = (1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0)


@kernel
def _mass_term(memory, t, qx, qy, qz):
    """The order-1 mass term (``MassTerm``) as (rate, b0 x, y, z): the reference velocity is the latest recorded
    end-of-step velocity from before ``t``; with none, the carried acceleration enters as a force."""
    if memory[MEMORY_ORDER, 0] < 0.5:
        return 0.0, 0.0, 0.0, 0.0
    m = memory[MEMORY_SETTINGS, 0]
    g = MEMORY_GRAVITY
    gx, gy, gz = gravity_acceleration(memory[MEMORY_ORDER, 1], memory[g, 0], memory[g, 1], memory[g, 2], qx, qy, qz)
    for j in range(int(memory[MEMORY_ORDER, 2])):   # the newer first
        time = memory[MEMORY_TIMES, j]
        if time < t:
            rate, row = m / (t - time), MEMORY_NEWER + j
            return rate, m * gx + rate * memory[row, 0], m * gy + rate * memory[row, 1], m * gz + rate * memory[row, 2]
    a = MEMORY_ACCELERATION
    return 0.0, m * (gx - memory[a, 0]), m * (gy - memory[a, 1]), m * (gz - memory[a, 2])


@kernel
def sp_rk_stage(states, layout, tables, work, part, memory, t, index, h):
    """SP at RK4 stage ``index`` (0-3) of a step of ``h`` (s) at time ``t`` (s): the stage's confluence position
    from ``memory`` (``MEMORY_ROWS``), the order-1 mass term when the memory asks for it, ``sp_stage``, and the
    stage velocity into memory row index + 1. Returns (vx, vy, vz, C_c, kappa, lines counted taut)."""
    qx, qy, qz = memory[MEMORY_POSITION, 0], memory[MEMORY_POSITION, 1], memory[MEMORY_POSITION, 2]
    if index > 0:
        step = h * RK4_STAGE_FRACTIONS[index]
        k = MEMORY_STAGE_VELOCITIES + index - 1   # k_(index), the previous stage's velocity
        qx, qy, qz = qx + step * memory[k, 0], qy + step * memory[k, 1], qz + step * memory[k, 2]
    rate, bx, by, bz = _mass_term(memory, t, qx, qy, qz)
    v0, settings = MEMORY_V0, MEMORY_SETTINGS
    vx, vy, vz, c_c, kappa, taut = sp_stage(states, layout, tables, work, part, qx, qy, qz, memory[v0, 0],
                                            memory[v0, 1], memory[v0, 2], memory[settings, 1], memory[settings, 2],
                                            rate, bx, by, bz)
    k = MEMORY_STAGE_VELOCITIES + index
    memory[k, 0], memory[k, 1], memory[k, 2] = vx, vy, vz
    return vx, vy, vz, c_c, kappa, taut


@kernel
def rk4_update(memory, h):
    """Complete an RK4 step of ``h`` (s): q_(n+1) = q_n + h (k_1 + 2 k_2 + 2 k_3 + k_4) / 6 into memory row 0, added
    term by term as (h b_j) k_j in Exudyn's own order, so that the result is the engine's to the last bit."""
    for j in range(4):
        factor = h * RK4_WEIGHTS[j]
        for i in range(3):
            memory[MEMORY_POSITION, i] += factor * memory[MEMORY_STAGE_VELOCITIES + j, i]


@kernel
def sp_end_of_step(states, layout, tables, work, part, memory, t, h, completed, start_time, record):
    """The SP work after a step of ``h`` (s) ending at ``t`` (s): the RK4 update when the step ``completed`` its
    four stages, the solve at the end-of-step state (its velocity is the next step's k_1), then v0 for the next step
    (after ``start_time``, the phase start: before it the case's initial velocity stands) and, for order 1, the
    velocity recorded for the backward difference; the outputs into ``record`` (``_record``). Returns
    ``sp_rk_stage``'s (vx, vy, vz, C_c, kappa, taut)."""
    if completed:
        rk4_update(memory, h)
    vx, vy, vz, c_c, kappa, taut = sp_rk_stage(states, layout, tables, work, part, memory, t, 0, 0.0)
    work[:, END_TENSION] = work[:, WORK_TENSION]
    if t > start_time:
        memory[MEMORY_V0, 0], memory[MEMORY_V0, 1], memory[MEMORY_V0, 2] = vx, vy, vz
    count = int(memory[MEMORY_ORDER, 2])
    if memory[MEMORY_ORDER, 0] > 0.5 and (count == 0 or t > memory[MEMORY_TIMES, 0]):
        memory[MEMORY_TIMES, 1] = memory[MEMORY_TIMES, 0]   # the newer becomes the older
        for i in range(3):
            memory[MEMORY_OLDER, i] = memory[MEMORY_NEWER, i]
        memory[MEMORY_TIMES, 0] = t
        memory[MEMORY_NEWER, 0], memory[MEMORY_NEWER, 1], memory[MEMORY_NEWER, 2] = vx, vy, vz
        memory[MEMORY_ORDER, 2] = min(count + 1, 2)
    _record(states, memory, work, vx, vy, vz, c_c, kappa, taut, record)
    return vx, vy, vz, c_c, kappa, taut


def record_size(states, lines: int) -> int:
    """Length of an SP confluence's end-of-step record (``_record``) for ``states`` and ``lines`` lines."""
    return states.size + 9 + lines


@kernel
def _record(states, memory, work, vx, vy, vz, c_c, kappa, taut, record):
    """An SP confluence's outputs at the end of a step, as one array: the stage's body states (rows of
    ``kinematics.STATE_COLUMNS``, flattened), the confluence position (3, m), the end-of-step solve's (vx, vy, vz,
    C_c, kappa, taut), and the end-of-step tensions (one per line, N)."""
    k = 0
    for row in range(states.shape[0]):
        for column in range(states.shape[1]):
            record[k] = states[row, column]
            k += 1
    for i in range(3):
        record[k + i] = memory[MEMORY_POSITION, i]
    record[k + 3], record[k + 4], record[k + 5] = vx, vy, vz
    record[k + 6], record[k + 7], record[k + 8] = c_c, kappa, taut
    for i in range(work.shape[0]):
        record[k + 9 + i] = work[i, END_TENSION]


@kernel
def sp_rk_stage_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, t, index, h, solve,
                            generalized, aerodynamics, field, aerodynamic_work):
    """``kinematics.body_states`` from the stage's node coordinates, then (when ``solve``) ``sp_rk_stage``, the
    lines' generalized forces (``part``, from this solve or the last) copied into ``generalized``, and the bodies'
    aerodynamic loads added (``aerodynamics.aerodynamics_stage`` on ``aerodynamics``, ``field`` and
    ``aerodynamic_work``, when there are any): a model with one SP confluence does a stage's kernel work in one
    call. Returns nothing (the stage velocity goes to memory row index + 1)."""
    body_states(q, q_t, bodies, states)
    if solve:
        sp_rk_stage(states, layout, tables, work, part, memory, t, index, h)
    generalized[:] = part
    if aerodynamics[0] > 0.0:
        aerodynamics_stage(t, states, aerodynamics, field, aerodynamic_work, generalized)


@kernel
def holds_after_v0_update(damping, taut_count):
    """Whether an end-of-step solve that returned C_c = ``damping`` (N s/m) with ``taut_count`` lines taut is also
    the next step's first-stage solve: v0 enters Eq. 3.10 only through C_c (and the all-slack case), so without
    them the v0 update between the two does not change it (order 1's reference velocity is the same for both calls:
    see ``sp_rk_stage``)."""
    return damping == 0.0 and taut_count > 0


@kernel
def sp_end_of_step_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, t, h, completed,
                               start_time, record):
    """``kinematics.body_states`` from the end-of-step node coordinates, then ``sp_end_of_step``: a model with one
    SP confluence does its post-step kernel work in one call. Returns ``sp_end_of_step``'s tuple."""
    body_states(q, q_t, bodies, states)
    return sp_end_of_step(states, layout, tables, work, part, memory, t, h, completed, start_time, record)


@kernel
def sp_first_stage_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, t_end, h, completed,
                               start_time, record, t, generalized, aerodynamics, field, aerodynamic_work):
    """The end-of-step work of the step that ended at ``t_end`` (s), done at the next step's first RK stage (time
    ``t``, s; the same state): ``sp_end_of_step_with_bodies``, then that stage's solve with the updated v0 unless
    the end-of-step solve holds for it (``holds_after_v0_update``). The same arithmetic, in the same order, as the
    two calls it replaces; the lines' generalized forces and the aerodynamic loads into ``generalized`` as
    ``sp_rk_stage_with_bodies``. Returns ``sp_end_of_step``'s tuple."""
    end = sp_end_of_step_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, t_end, h,
                                     completed, start_time, record)
    if not holds_after_v0_update(end[3], end[5]):
        sp_rk_stage(states, layout, tables, work, part, memory, t, 0, h)
    generalized[:] = part
    if aerodynamics[0] > 0.0:
        aerodynamics_stage(t, states, aerodynamics, field, aerodynamic_work, generalized)
    return end


@kernel
def count_stage(memory, t):
    """Count the RK stage at time ``t`` (s) in ``memory``'s step bookkeeping (rows MEMORY_CLOCK, MEMORY_RUN) and
    return (its index 0-4, whether it needs a solve). The second stage (t_n + h/2) sets the step h: the run's step
    when the span 2 (t - t_n) is within 1e-6 of it, else the span (a short last step). The first stage's state is
    the end-of-step state already solved: that solve stands when it holds after the v0 update
    (``holds_after_v0_update``); a fifth call or more solves nothing."""
    index = int(memory[MEMORY_CLOCK, 0])
    memory[MEMORY_CLOCK, 0] = index + 1
    if index == 1:
        span = 2.0 * (t - memory[MEMORY_CLOCK, 1])
        step = memory[MEMORY_RUN, 0]
        memory[MEMORY_CLOCK, 2] = step if step > 0.0 and abs(span - step) <= 1e-6 * step else span
    if index == 0:
        return index, not holds_after_v0_update(memory[MEMORY_END_SOLVE, 0], memory[MEMORY_END_SOLVE, 2])
    return index, index < 4


@kernel
def step_done(memory, t):
    """After a step ending at ``t`` (s): the step's end-of-step work becomes due (MEMORY_DUE) and, when the step
    completed its four stages, t is the next step's start; the stage count starts again."""
    completed = memory[MEMORY_CLOCK, 0] == 4.0
    if completed:
        memory[MEMORY_CLOCK, 1] = t
    memory[MEMORY_CLOCK, 0] = 0.0
    memory[MEMORY_DUE, 0], memory[MEMORY_DUE, 1] = 1.0, t
    memory[MEMORY_DUE, 2] = 1.0 if completed else 0.0


@kernel
def _keep_end(memory, vx, vy, vz, c_c, kappa, taut):
    """Keep the end-of-step solve (MEMORY_END, MEMORY_END_SOLVE); the due work is done."""
    memory[MEMORY_END, 0], memory[MEMORY_END, 1], memory[MEMORY_END, 2] = vx, vy, vz
    memory[MEMORY_END_SOLVE, 0], memory[MEMORY_END_SOLVE, 1], memory[MEMORY_END_SOLVE, 2] = c_c, kappa, taut
    memory[MEMORY_DUE, 0] = 0.0


@kernel
def sp_step_stage(states, layout, tables, work, part, memory, t):
    """An RK stage at ``t`` (s) with the step's bookkeeping in ``memory`` (``count_stage``), then ``sp_rk_stage``
    when it needs a solve (the body states already set)."""
    index, solve = count_stage(memory, t)
    if solve:
        sp_rk_stage(states, layout, tables, work, part, memory, t, index, memory[MEMORY_CLOCK, 2])


@kernel
def sp_settle(states, layout, tables, work, part, memory, record):
    """The due end-of-step work (``sp_end_of_step`` with the bookkeeping's time, step and completion), the body
    states already set at the end of the step; the solve kept in memory."""
    due = MEMORY_DUE
    vx, vy, vz, c_c, kappa, taut = sp_end_of_step(states, layout, tables, work, part, memory, memory[due, 1],
                                                  memory[MEMORY_CLOCK, 2], memory[due, 2] > 0.5,
                                                  memory[MEMORY_RUN, 1], record)
    _keep_end(memory, vx, vy, vz, c_c, kappa, taut)


@kernel
def sp_settle_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, record):
    """``kinematics.body_states`` from the end-of-step node coordinates, then ``sp_settle``."""
    body_states(q, q_t, bodies, states)
    sp_settle(states, layout, tables, work, part, memory, record)


@kernel
def sp_step_stage_with_bodies(q, q_t, t, bodies, states, layout, tables, work, part, memory, record, generalized,
                              aerodynamics, field, aerodynamic_work):
    """A stage of a model whose only confluence is this one, in one call: the body states from the stage's node
    coordinates, the SP solve, the lines' generalized forces into ``generalized`` and the bodies' aerodynamic loads
    added (as ``sp_rk_stage_with_bodies``). At a step's first stage with the last step's end-of-step work due, that
    work first (``sp_first_stage_with_bodies``). Last, the gravity of the bodies whose layout rows carry their mass
    (``kinematics.add_gravity_forces``), added after everything else as the engine's gravity connectors would add
    it. Returns 1 when it did the end-of-step work, plus 2 when the aerodynamics reported a problem and added nothing
    (their status in ``aerodynamic_work``; the gravity is then left to the caller too)."""
    done = 0.0
    if memory[MEMORY_CLOCK, 0] == 0.0 and memory[MEMORY_DUE, 0] > 0.5:
        memory[MEMORY_CLOCK, 0] = 1.0
        due = MEMORY_DUE
        vx, vy, vz, c_c, kappa, taut = sp_first_stage_with_bodies(
            q, q_t, bodies, states, layout, tables, work, part, memory, memory[due, 1], memory[MEMORY_CLOCK, 2],
            memory[due, 2] > 0.5, memory[MEMORY_RUN, 1], record, t, generalized, aerodynamics, field,
            aerodynamic_work)
        _keep_end(memory, vx, vy, vz, c_c, kappa, taut)
        done = 1.0
    else:
        index, solve = count_stage(memory, t)
        sp_rk_stage_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, t, index,
                                memory[MEMORY_CLOCK, 2], solve, generalized, aerodynamics, field, aerodynamic_work)
    if aerodynamic_work[0] != 0.0:   # the aerodynamics added nothing: the caller adds them, then the gravity
        return done + 2.0
    g = MEMORY_GRAVITY
    add_gravity_forces(bodies, states, memory[MEMORY_ORDER, 1], memory[g, 0], memory[g, 1], memory[g, 2], generalized)
    return done

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

Plain floats throughout (about 7 us a call for four taut lines): it runs at every solver stage.
"""

from __future__ import annotations

import math
from itertools import repeat
from typing import NamedTuple

from .lines import line_geometry, tension
from .small_linalg import solve_symmetric, symmetric_eigenvalues  # noqa: F401  (re-exported)

SLACK_RULES = ("stretch", "force")
SP_ORDERS = (0, 1)
"""Order in the confluence mass: 0, the massless balance of Eq. 3.10 (the thesis); 1, the mass kept to first order."""

SINGULAR = 1e-12
"""Relative singularity test: alpha counts as singular when its condition number exceeds 1/SINGULAR (its smallest
eigenvalue is below about SINGULAR times its largest) or its determinant is not positive."""


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
    """Result of one SP solve (a named tuple: it is made at every solver stage).

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


def condition_number(eigenvalues, damping: float = 0.0) -> float:
    """kappa = sqrt(sum x^2 sum x^-2) (Eq. 3.13) for alpha with eigenvalues ``eigenvalues`` + ``damping``."""
    xs = [mu + damping for mu in eigenvalues]
    if min(xs) <= 0.0:
        return math.inf
    return math.sqrt(sum(x * x for x in xs) * sum(1.0 / (x * x) for x in xs))


def minimum_damping(eigenvalues, kappa_max: float) -> float:
    """Smallest C_c >= 0 with condition_number(eigenvalues, C_c) <= kappa_max (N s/m); eigenvalues >= 0.

    Exact for the given eigenvalues; with eigenvalues from ``symmetric_eigenvalues`` of a (near-)singular alpha,
    kappa recomputed from alpha itself can exceed kappa_max by a few parts in 1e9 (eigenvalue round-off).
    """
    mus = [max(mu, 0.0) for mu in eigenvalues]
    mu_max = max(mus)
    if mu_max <= 0.0:
        raise ValueError("alpha is zero: no taut line has damping")
    if min(mus) > SINGULAR * mu_max and condition_number(mus) <= kappa_max:
        return 0.0
    target = kappa_max * kappa_max
    lo, hi = 0.0, 3.0 * mu_max / (kappa_max - 3.0)
    c = hi
    for _ in range(100):
        xs = [mu + c for mu in mus]
        s1 = sum(xs)
        s2 = sum(x * x for x in xs)
        sm2 = sum(1.0 / (x * x) for x in xs)
        sm3 = sum(1.0 / (x * x * x) for x in xs)
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


def _next_active_set(lines, active, velocity, visited) -> bool:
    """Force rule: update ``active`` in place toward consistency; False when it is consistent (or would cycle).

    Every taut line that pushes is dropped at once (docs/models/mer.md: a taut line whose tension comes out negative);
    when none does, every stretched line left out that would pull is taken back. Changing lines together keeps
    symmetric configurations symmetric (one-at-a-time picks one of equal bridles by index and starts a swing).
    """
    wx, wy, wz = velocity
    drop, take = [], []
    for i, ((nx, ny, nz, stretch, vn, elastic, c), on) in enumerate(zip(lines, active)):
        if stretch <= 0.0:
            continue
        linear = elastic + c * (vn - wx * nx - wy * ny - wz * nz)
        if on and linear < 0.0:
            drop.append(i)
        elif not on and linear > 0.0:
            take.append(i)
    change = drop or take
    if not change:
        return False
    candidate = list(active)
    for i in change:
        candidate[i] = not candidate[i]
    if tuple(candidate) in visited:
        return False
    visited.add(tuple(candidate))
    active[:] = candidate
    return True


def _assemble(attach_position, attach_velocity, confluence_position, free_length, stiffness, damping, tables,
              forced, rate: float, b0: tuple):
    """One pass over the lines: their geometry (``lines.line_geometry``), and alpha (Eq. 3.11, six entries a00 a01
    a02 a11 a12 a22) and b (Eq. 3.10) summed over the active ones (``forced``, else the stretched ones), on top of the
    mass term's ``rate`` and ``b0``; the force rule's extra passes repeat it. Returns alpha, b, the lines as (nx, ny,
    nz, stretch, attach velocity along n, elastic tension, C), the directions and the active flags. The elastic
    tension is K (L - L0), or a load-elongation table's T_table (``tables``; its slope enters nowhere here)."""
    a00 = a11 = a22 = rate
    a01 = a02 = a12 = 0.0
    bx, by, bz = b0
    lines, directions, active = [], [], []
    geometry = line_geometry(attach_position, confluence_position)
    for (length, nx, ny, nz), (vx, vy, vz), l0, k, c, table, on in zip(
            geometry, attach_velocity, free_length, stiffness, damping, tables or repeat(None),
            forced or repeat(None)):
        stretch, vn = length - l0, vx * nx + vy * ny + vz * nz
        elastic = k * stretch if table is None else table(stretch / l0)
        directions.append((nx, ny, nz))
        lines.append((nx, ny, nz, stretch, vn, elastic, c))
        taut = stretch > 0.0 if on is None else on
        active.append(taut)
        if taut:
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
    return (a00, a01, a02, a11, a12, a22), (bx, by, bz), lines, directions, active


def _solve_balance(alpha: tuple, b: tuple, active: list, rate: float, previous_velocity, kappa_max: float):
    """Velocity (m/s), C_c (N s/m) and kappa of Eq. 3.10 for an assembled alpha and b: C_c = 0 with every line
    taut and alpha regular, else the smallest C_c meeting kappa_max (Eq. 3.13); every line slack and no mass term:
    the previous velocity (C_c = 0, kappa = 0)."""
    v0x, v0y, v0z = previous_velocity
    if True not in active and rate == 0.0:
        return (v0x, v0y, v0z), 0.0, 0.0
    a00, a01, a02, a11, a12, a22 = alpha
    bx, by, bz = b
    solved = solve_symmetric(a00, a01, a02, a11, a12, a22, bx, by, bz) if False not in active else None
    if solved is not None and solved[1] < 1.0 / SINGULAR:  # every line taut and alpha regular: C_c = 0
        return solved[0], 0.0, solved[1]
    c_c = minimum_damping(symmetric_eigenvalues(a00, a01, a02, a11, a12, a22), kappa_max)
    velocity, kappa = solve_symmetric(a00 + c_c, a01, a02, a11 + c_c, a12, a22 + c_c,
                                      bx + c_c * v0x, by + c_c * v0y, bz + c_c * v0z)
    return velocity, c_c, kappa


def confluence_velocity(attach_position, attach_velocity, confluence_position, previous_velocity,
                        free_length, stiffness, damping, kappa_max: float = 5.0,
                        slack_rule: str = "stretch", mass_term: MassTerm | None = None,
                        tables=None) -> SPSolution:
    """SP confluence velocity (Eq. 3.10) with the minimal confluence damping of Eq. 3.13.

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
    if mass_term is None:
        rate, b0 = 0.0, (0.0, 0.0, 0.0)
    else:
        rate, (rx, ry, rz), (gx, gy, gz) = mass_term
        b0 = (gx + rate * rx, gy + rate * ry, gz + rate * rz)
    forced = None    # the force rule's active set, once a pass has found the last one inconsistent
    visited = None   # the force rule's active sets seen so far
    while True:
        alpha, b, lines, directions, active = _assemble(attach_position, attach_velocity, confluence_position,
                                                        free_length, stiffness, damping, tables, forced, rate, b0)
        velocity, c_c, kappa = _solve_balance(alpha, b, active, rate, previous_velocity, kappa_max)
        if slack_rule != "force":
            break
        if visited is None:
            visited = {tuple(active)}
        if not _next_active_set(lines, active, velocity, visited):
            break
        forced = active
    wx, wy, wz = velocity
    tensions = [tension(stretch, vn - wx * nx - wy * ny - wz * nz, 0.0, c, elastic)
                for nx, ny, nz, stretch, vn, elastic, c in lines]
    return SPSolution(velocity, c_c, kappa, tuple(active), tensions, directions)

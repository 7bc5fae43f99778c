"""The confluence damping that keeps singular perturbation's balance solvable (thesis Eq. 3.13): the condition number
kappa = sqrt(trace(alpha^2) trace(alpha^-2)) of the 3x3 matrix alpha (Eq. 3.11) from its eigenvalues, and the least
damping C_c added to every eigenvalue that brings kappa down to kappa_max.

kappa falls monotonically with C_c: with x_k = mu_k + C_c (mu_k the eigenvalues of sum C n n^T),
d/dC_c [sum x^2 sum x^-2] = 2 (sum x sum x^-2 - sum x^2 sum x^-3) <= 0, so the smallest C_c is found by a bracketed
Newton iteration on kappa^2 = kappa_max^2 (bracket [0, 3 mu_max / (kappa_max - 3)], from kappa <= 3 (1 + mu_max/C_c)).
The Frobenius condition number of a 3x3 matrix is at least 3, so kappa_max must exceed 3. SP's solve runs it at every
stage (``methods.sp.balance``); the linearisation's SP modes use it too (``linearization.sp_step_limit``).
"""

from __future__ import annotations

import math

from .compiled import kernel

SINGULAR = 1e-12
"""Relative singularity test: alpha counts as singular when its condition number exceeds 1/SINGULAR (its smallest
eigenvalue is below about SINGULAR times its largest) or its determinant is not positive."""


@kernel
def condition_number_of(m0, m1, m2, damping):
    """kappa (Eq. 3.13) of alpha with eigenvalues m0, m1, m2 (N s/m) plus ``damping`` (N s/m); inf when singular."""
    x0, x1, x2 = m0 + damping, m1 + damping, m2 + damping
    if min(x0, x1, x2) <= 0.0:
        return math.inf
    return math.sqrt((x0 * x0 + x1 * x1 + x2 * x2) * (1.0 / (x0 * x0) + 1.0 / (x1 * x1) + 1.0 / (x2 * x2)))


def condition_number(eigenvalues, damping: float = 0.0) -> float:
    """kappa = sqrt(sum x^2 sum x^-2) (Eq. 3.13) for alpha with eigenvalues ``eigenvalues`` + ``damping``."""
    return condition_number_of(*(float(mu) for mu in eigenvalues), float(damping))


@kernel
def minimum_damping_of(m0, m1, m2, kappa_max):
    """``minimum_damping`` for three eigenvalues; -1 when alpha is zero."""
    m0, m1, m2 = max(m0, 0.0), max(m1, 0.0), max(m2, 0.0)
    mu_max = max(m0, m1, m2)
    if mu_max <= 0.0:
        return -1.0
    if min(m0, m1, m2) > SINGULAR * mu_max and condition_number_of(m0, m1, m2, 0.0) <= kappa_max:
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
    damping = minimum_damping_of(*(float(mu) for mu in eigenvalues), float(kappa_max))
    if damping < 0.0:
        raise ValueError("alpha is zero: no taut line has damping")
    return damping

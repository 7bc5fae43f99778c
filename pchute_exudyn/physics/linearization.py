"""Linearised confluence dynamics (thesis Eq. 2.6, Appendix A) and what they say about integration steps.

About a confluence position r_c with the attach points held, the line forces linearise to
m_c dr'' + C_bar dr' + K_bar dr = 0 with, summed over taut lines (n = unit vector confluence -> attach point)::

    C_bar = sum C n n^T
    K_bar = sum K [ (1 - L0/L) I + (L0/L) n n^T ]

(the general 3x3 form of Appendix A; its printed off-diagonal stiffness K L0/L (dx dy) lacks a 1/L^2: with
dx = L n_x the term is K (L0/L) n_x n_y, as a finite difference of the line forces confirms in the tests).
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import numpy as np

from .compiled import kernel
from .conditioning import SINGULAR, minimum_damping


def line_stiffness(stiffness, free_length, length, direction):
    """Tangent stiffness of each line, K [(1 - L0/L) I + (L0/L) n n^T] (N/m), shape (n_lines, 3, 3).

    Pass zero stiffness for slack lines. dF/dr_i of the line force on the confluence is this matrix, and
    dF/dr_c is minus it (Appendix A/B). A line of zero length (its attach point at the confluence) has no direction
    and adds nothing.
    """
    k = np.asarray(stiffness, float)
    length = np.asarray(length, float)
    k = np.where(length > 0.0, k, 0.0)
    ratio = np.divide(np.asarray(free_length, float), length, out=np.zeros_like(length), where=length > 0.0)
    n = np.asarray(direction, float)
    return (k * (1.0 - ratio))[:, None, None] * np.eye(3) + (k * ratio)[:, None, None] * np.einsum("li,lj->lij", n, n)


def linearize(attach_position, confluence_position, free_length, stiffness, damping, taut=None):
    """Equivalent damping and stiffness matrices C_bar (N s/m) and K_bar (N/m) of the confluence (Eq. 2.6).

    Parameters
    ----------
    attach_position : array_like, shape (n_lines, 3)
        Attach point positions (m).
    confluence_position : array_like, shape (3,)
        Confluence position (m) to linearise about.
    free_length, stiffness, damping : array_like, shape (n_lines,)
        L0 (m), K (N/m), C (N s/m).
    taut : array_like of bool, optional
        Lines to include; default: those with L > L0. Pass all True for the stiffest (all-taut) bound.
    """
    rel = np.asarray(attach_position, float) - np.asarray(confluence_position, float)
    length = np.linalg.norm(rel, axis=-1)
    n = np.divide(rel, length[:, None], out=np.zeros_like(rel), where=length[:, None] > 0.0)
    if taut is None:
        taut = length > np.asarray(free_length, float)
    w = np.asarray(taut, bool) & (length > 0.0)   # a zero-length line has no direction: it adds nothing
    c_bar = np.einsum("l,li,lj->ij", np.asarray(damping, float) * w, n, n)
    k_bar = line_stiffness(np.asarray(stiffness, float) * w, free_length, length, n).sum(axis=0)
    return c_bar, k_bar


@dataclass(frozen=True)
class Modes:
    """Modes of m dr'' + C dr' + K dr = 0 (thesis Table 2.2's quantities).

    Attributes
    ----------
    eigenvalues : ndarray (6,) complex
        Roots lambda of det(m lambda^2 I + lambda C + K) = 0 (1/s), sorted by |lambda|.
    vectors : ndarray (3, 6) complex
        Mode directions (position part of each eigenvector, unit norm).
    natural_frequencies : ndarray (6,)
        |lambda| (rad/s); for a complex pair, omega_n of that mode.
    damping_ratios : ndarray (6,)
        -Re(lambda) / |lambda| (-).
    periods : ndarray (6,)
        Damped period 2 pi / |Im(lambda)| (s); inf for real (overdamped) roots.
    natural_periods : ndarray (6,)
        2 pi / omega_n (s): the "T" of thesis Table 2.2.
    """

    eigenvalues: np.ndarray
    vectors: np.ndarray
    natural_frequencies: np.ndarray
    damping_ratios: np.ndarray
    periods: np.ndarray
    natural_periods: np.ndarray


def companion_matrix(mass, damping_matrix, stiffness_matrix) -> np.ndarray:
    """First-order system matrix A = [[0, I], [-M^-1 K, -M^-1 C]] (1/s) of M x'' + C x' + K x = 0, whose eigenvalues
    are the roots of det(M lambda^2 + C lambda + K) = 0 (thesis Eq. 2.6). ``mass``: a scalar m (kg; M = m I) or a
    mass matrix."""
    c = np.asarray(damping_matrix, float)
    k = np.asarray(stiffness_matrix, float)
    n = k.shape[0]
    if np.ndim(mass) == 0:
        lower = [-k / mass, -c / mass]
    else:
        lower = [-np.linalg.solve(mass, k), -np.linalg.solve(mass, c)]
    return np.block([[np.zeros((n, n)), np.eye(n)], lower])


def sp_eigenvalues(damping_matrix, stiffness_matrix) -> np.ndarray:
    """Eigenvalues (1/s) of the SP confluence's first-order dynamics dr/dt = v(r), Jacobian -C_bar^-1 K_bar (thesis
    Eq. 3.10 linearised with C_c = 0). Where C_bar is singular (collinear lines) only its range is solved with
    C_c = 0: the other directions move at the pace of the confluence damping C_c, which only slows them; empty when
    C_bar is zero."""
    c = np.asarray(damping_matrix, float)
    k = np.asarray(stiffness_matrix, float)
    values, vectors = np.linalg.eigh(c)
    kept = vectors[:, values > 1e-12 * max(values.max(), 0.0)] if values.max() > 0.0 else vectors[:, :0]
    if kept.shape[1] == 0:
        return np.array([], dtype=complex)
    return np.linalg.eigvals(-np.linalg.solve(kept.T @ c @ kept, kept.T @ k @ kept))


def modes(mass: float, damping_matrix, stiffness_matrix) -> Modes:
    """Solve the quadratic eigenvalue problem m lambda^2 I + lambda C + K = 0 via its first-order companion form."""
    values, vectors = np.linalg.eig(companion_matrix(mass, damping_matrix, stiffness_matrix))
    order = np.lexsort((values.imag, np.abs(values)))
    values, vectors = values[order], vectors[:3, order]
    vectors = vectors / np.linalg.norm(vectors, axis=0)
    magnitude = np.abs(values)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(magnitude > 0, -values.real / magnitude, 1.0)
        period = np.where(np.abs(values.imag) > 1e-12 * np.maximum(magnitude, 1.0),
                          2.0 * np.pi / np.abs(values.imag), np.inf)
    with np.errstate(divide="ignore"):
        natural_period = np.where(magnitude > 0, 2.0 * np.pi / magnitude, np.inf)
    return Modes(values, vectors, magnitude, ratio, period, natural_period)


def max_stable_step_rk4(eigenvalues) -> float:
    """Largest step h (s) for which classical RK4 is stable for every eigenvalue: |R(h lambda)| <= 1.

    R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24; the step is found along each eigenvalue's ray by bisection (the RK4
    region is star-shaped about 0; on the negative real axis it ends at z = -2.785, on the imaginary axis at
    2.828). Eigenvalues with a non-negative real part impose no limit (unstable physics, not numerics); returns inf
    when none limits.
    """
    return _smallest_limit(np.atleast_1d(np.asarray(eigenvalues, dtype=complex)).tolist())


def _smallest_limit(eigenvalues: list) -> float:
    """``max_stable_step_rk4`` of a list of Python complex numbers (no array round trip: the step control's checks
    call it hundreds of times a run)."""
    limit = float("inf")
    for lam in eigenvalues:
        if lam.real >= 0.0 or lam.imag < 0.0:  # conjugates share the limit of their partner
            continue
        limit = min(limit, _stable_step_along(lam.real, lam.imag))
    return limit


@kernel
def _stable_step_along(real, imag):
    """The largest h with |R(h lambda)| <= 1 for lambda = real + i imag (real < 0), by bisection (compiled: the
    step monitor calls it for every mode)."""
    lam = complex(real, imag)
    lo, hi = 0.0, 3.0 / abs(lam)
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        z = mid * lam
        if abs(1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0)))) <= 1.0:
            lo = mid
        else:
            hi = mid
    return lo


RK4_LEFT_RADIUS = 2.6155
"""Radius (-) of the largest half-disc of the left half-plane inside RK4's stability region (its boundary is
closest to 0 at about 2.6156, between the real axis's 2.785 and the imaginary axis's 2.828): RK4 is stable for
every h lambda with Re(lambda) < 0 and |h lambda| below it."""


def spectral_step_bound(mass, stiffness, damping) -> float:
    """A stable RK4 step (s) for ``mass`` (kg) on lines of ``stiffness`` (N/m) and ``damping`` (N s/m) in any layout
    with every line at or beyond its free length: with A = C_bar / m and B = K_bar / m, an eigenvalue of
    lambda^2 + A lambda + B obeys |lambda|^2 <= |lambda| |A| + |B|, and |C_bar| <= sum C, |K_bar| <= sum K (each
    line's K_bar term has norm K), so |lambda| <= rho = (a + sqrt(a^2 + 4 b)) / 2 with a = sum C / m,
    b = sum K / m; the step is RK4_LEFT_RADIUS / rho (MER's confluence: 1.99e-4 s against 4.28e-4 s from its
    geometry). inf without stiffness or damping."""
    a, b = float(np.sum(damping)) / mass, float(np.sum(stiffness)) / mass
    rho = 0.5 * (a + math.sqrt(a * a + 4.0 * b))
    return RK4_LEFT_RADIUS / rho if rho > 0.0 else math.inf


def body_line_step_limit(mass, stiffness, damping) -> float:
    """A stable RK4 step (s) for a body of ``mass`` (kg) on lines of ``stiffness`` (N/m) and ``damping`` (N s/m)
    pulling along one direction, the stiffest layout: the roots of m lambda^2 + (sum C) lambda + sum K = 0 and RK4's
    limit along their rays (``max_stable_step_rk4``). Where every line has the same C/K (``pchute new``'s lines),
    C_bar and K_bar share their eigenvectors and every other layout's modes are those of a smaller K on the same
    rays, slower; with other ratios it is an estimate (``spectral_step_bound`` bounds any layout, up to twice
    smaller). Sideways stiffness T/L of stretched lines is left out. inf without stiffness or damping."""
    c, k = _total(damping), _total(stiffness)
    if c <= 0.0 and k <= 0.0:
        return math.inf
    root = cmath.sqrt(c * c - 4.0 * mass * k)
    return _smallest_limit([(-c + root) / (2.0 * mass), (-c - root) / (2.0 * mass)])


def _total(values) -> float:
    """``float(np.sum(values))``, a single number's sum without numpy (numpy's sum starts from +0.0: -0.0 sums to
    0.0, as here)."""
    if isinstance(values, list) and len(values) == 1 and isinstance(values[0], float):
        return 0.0 + values[0]
    return float(np.sum(values))


def damped_line_step_limit(stiffness, damping) -> float | None:
    """Largest stable RK4 step (s) of a massless confluence's first-order mode at free length, without geometry:
    there the eigenvalues of C_bar^-1 K_bar are Rayleigh quotients sum K (n.v)^2 / sum C (n.v)^2 <= max K/C, so
    -max(K/C) (1/s) is the fastest mode (MER: -100 1/s, 2.79e-2 s). Stretched lines add sideways stiffness without
    damping and can make the mode faster (the run's step monitor checks the real geometry). None (no bound) when a
    line has stiffness without damping; inf when no line has stiffness."""
    if any(k > 0.0 and c <= 0.0 for k, c in zip(stiffness, damping)):
        return None
    rates = [k / c for k, c in zip(stiffness, damping) if c > 0.0]
    return max_stable_step_rk4([-max(rates)]) if rates else math.inf


def _all_taut(attach_position, confluence_position, free_length, stiffness, damping):
    """C_bar and K_bar with every line counted taut: a slack line adds neither stiffness nor damping, so this
    stiffest state bounds the step limit through slack events."""
    return linearize(attach_position, confluence_position, free_length, stiffness, damping,
                     taut=np.ones(len(free_length), bool))


def full_mass_step_limit(mass, attach_position, confluence_position, free_length, stiffness, damping):
    """Largest stable RK4 step (s) of a full-mass confluence of ``mass`` (kg) linearised at the given geometry
    with every line taut, and the eigenvalue (1/s) that sets it. The limit falls as the lines stretch under load
    (MER case 1: 4.28e-4 s at free length, 3.93e-4 s at 60 s)."""
    c_bar, k_bar = _all_taut(attach_position, confluence_position, free_length, stiffness, damping)
    found = modes(mass, c_bar, k_bar)
    steps = [max_stable_step_rk4([lam]) for lam in found.eigenvalues]
    worst = int(np.argmin(steps))
    return float(steps[worst]), complex(found.eigenvalues[worst])


def sp_step_limit(attach_position, confluence_position, free_length, stiffness, damping, mass: float = 0.0,
                  kappa_max: float | None = None):
    """Largest stable RK4 step (s) of an SP confluence at the given geometry with every line taut, and its fastest
    eigenvalue (1/s): real and negative, about -K/C (-100 1/s for MER, a limit near 2.8e-2 s). Slack lines raise
    alpha through C_c, which only slows this mode.

    The solve's own regularisation of alpha counts (docs/models/step_control.md, "Every line layout"): with the
    confluence ``mass`` (kg) kept to first order its inertia adds m_c / tau to alpha, tau at most the step h, so the
    mode is that of (C_bar + (m_c / h) I)^-1 K_bar and the limit the largest h that RK4 keeps stable at that h;
    massless with ``kappa_max`` given, a singular C_bar (collinear lines, or lines in one plane) is solved with the
    C_c of Eq. 3.13. A C_bar that is regular but nearly singular (lines close to collinear) has no such help in the
    massless solve: its sideways mode is fast, and the limit says so."""
    c_bar, k_bar = _all_taut(attach_position, confluence_position, free_length, stiffness, damping)
    regularisation = 0.0
    values = np.linalg.eigvalsh(c_bar)
    if mass <= 0.0 and kappa_max is not None and values.max() > 0.0 and values.min() <= SINGULAR * values.max():
        regularisation = minimum_damping(values, kappa_max)
    if values.min() > ILL_CONDITIONED * values.max():
        mass = 0.0   # the mass term only raises the limit (the Rayleigh quotients of K_bar over alpha fall): needless
    if mass <= 0.0 and regularisation == 0.0:
        eigenvalues = sp_eigenvalues(c_bar, k_bar)
        if len(eigenvalues) == 0:   # no damping at all: nothing to limit (the SP solve refuses such lines)
            return math.inf, complex(0.0)
        fastest = eigenvalues[np.argmax(np.abs(eigenvalues))]
        return max_stable_step_rk4(eigenvalues), complex(fastest)
    return _regularised_step_limit(c_bar, k_bar, regularisation, mass)


def crosswise_damping_ratio(attach_position, confluence_position, free_length, stiffness, damping) -> float:
    """C_bar's smallest eigenvalue over its largest, every line taut (-): near 0 when the lines are nearly collinear
    or lie in one plane (the damping across them vanishes); 0 without damping."""
    values = np.linalg.eigvalsh(_all_taut(attach_position, confluence_position, free_length, stiffness, damping)[0])
    return float(values.min() / values.max()) if values.max() > 0.0 else 0.0


ILL_CONDITIONED = 1e-3
"""C_bar's smallest eigenvalue over its largest below which ``sp_step_limit`` counts the mass term (the limit without
it is a safe lower bound, close enough where C_bar is well conditioned, and one eigen-solve instead of a dozen)."""


def _regularised_step_limit(c_bar, k_bar, regularisation: float, mass: float):
    """``sp_step_limit`` with alpha = C_bar + (C_c + m_c / h) I. With the mass term the limit L(h) falls as h grows
    (m_c / h, and the damping with it, falls), so the largest stable step is the root of L(h) = h, bracketed and
    bisected (in log h) to 3 %; the step returned is the bracket's stable end."""
    identity = np.eye(3)

    def limit_at(extra):
        values = np.linalg.eigvals(-np.linalg.solve(c_bar + (regularisation + extra) * identity, k_bar))
        return max_stable_step_rk4(values), values

    if mass <= 0.0:
        step, values = limit_at(0.0)
    else:
        low, high = 1e-9, 10.0
        while high > 1.03 * low:
            middle = math.sqrt(low * high)
            if limit_at(mass / middle)[0] >= middle:
                low = middle
            else:
                high = middle
        step, values = low, limit_at(mass / low)[1]
    if len(values) == 0:
        return math.inf, complex(0.0)
    return step, complex(values[np.argmax(np.abs(values))])

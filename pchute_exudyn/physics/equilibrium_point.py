"""The confluence equilibrium point (thesis Eq. 2.9; Raiszadeh's method, the thesis's ref. 7) and its velocity
(thesis Appendix B).

The equilibrium point is where the line stiffness forces balance: F(r) = sum K (L - L0)+ n = 0 (n from the confluence
to each attach point, tension-only). F is minus the gradient of U(r) = sum 1/2 K (L - L0)+^2, a convex potential
(each term is a convex non-decreasing function of the convex |r_i - r|) that grows without bound, so a balance always
exists; it is unique and isolated where the taut lines make K_bar = dF/dr... positive definite (linearization.py).
The thesis's complaint, Newton diverging when a step slackens a line, comes from taking full Newton steps on F. Here
each step minimises U: a Newton step on the regularised Hessian K_bar + mu I (Levenberg-Marquardt; mu grows when a
step does not decrease U, so slack lines with their zero stiffness cannot derail it), accepted by an Armijo line
search. It converges from any starting point; a warm start from the previous solution makes it a few iterations.
Plain floats (about 20 us a solve): the equilibrium-point method solves at every solver stage.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .lines import LineLaw, line_geometry
from .small_linalg import solve_symmetric, symmetric_eigenvalues


class NoEquilibriumError(ValueError):
    """The lines have no unique (isolated) equilibrium point: ``taut`` of ``lines`` lines are taut at the force
    balance (0 of n when no line has stiffness)."""

    def __init__(self, message: str, taut: int = 0, lines: int = 0):
        self.taut, self.lines = taut, lines
        super().__init__(message)


@dataclass(frozen=True)
class Equilibrium:
    """Result of an equilibrium-point solve.

    Attributes
    ----------
    position : ndarray (3,)
        The equilibrium point (m).
    converged : bool
        |F| fell below the tolerance.
    iterations : int
        Newton iterations taken.
    residual : float
        |F| at the returned point (N).
    taut : ndarray of bool
        Lines with L > L0 at the point.
    unique : bool
        K_bar is positive definite there: an isolated equilibrium (False when all lines are slack, or the taut lines
        cannot pull against each other in three dimensions).
    """

    position: np.ndarray
    converged: bool
    iterations: int
    residual: float
    taut: np.ndarray
    unique: bool


def line_terms(law: LineLaw, length: float) -> tuple:
    """A taut line's (``law``, at length ``length`` in m) elastic tension f (N), energy (J) and the two parts of its
    tangent stiffness (N/m), (f / L) I + (df/dL - f / L) n n^T: for the linear law K (1 - L0/L) and K L0/L; for a
    load-elongation table T_table / L and slope / L0 - T_table / L (``LineLaw.elastic``, ``slope``, ``energy``)."""
    stretch = length - law.free_length
    f = law.elastic(stretch)
    if law.table is None:
        ratio = law.free_length / length
        return f, law.energy(stretch), law.stiffness * (1.0 - ratio), law.stiffness * ratio
    return f, law.energy(stretch), f / length, law.slope(stretch) - f / length


def stiffness_laws(free_length, stiffness, tables=None) -> list:
    """The lines' laws for the balance of their stiffness forces (no damping: it does not enter Eq. 2.9)."""
    tables = tables or [None] * len(free_length)
    return [LineLaw(l0, k, 0.0, table) for l0, k, table in zip(free_length, stiffness, tables)]


def stiffness_forces(attach_position, position, laws):
    """Force sum F (N), potential U (J), tangent stiffness K_bar = -dF/dr (N/m, six entries a00, a01, a02, a11,
    a12, a22; ``linearization.line_stiffness`` summed) and taut flags at ``position`` of the lines ``laws``
    (``stiffness_laws``). Plain floats."""
    fx = fy = fz = potential = 0.0
    a00 = a01 = a02 = a11 = a12 = a22 = iso = 0.0
    taut = []
    for (length, nx, ny, nz), law in zip(line_geometry(attach_position, position), laws):
        stretch = length - law.free_length
        if stretch <= 0.0 or law.stiffness == 0.0:
            taut.append(stretch > 0.0)
            continue
        taut.append(True)
        f, energy, line_iso, kr = line_terms(law, length)
        fx += f * nx
        fy += f * ny
        fz += f * nz
        potential += energy
        iso += line_iso
        a00 += kr * nx * nx
        a01 += kr * nx * ny
        a02 += kr * nx * nz
        a11 += kr * ny * ny
        a12 += kr * ny * nz
        a22 += kr * nz * nz
    return (fx, fy, fz), potential, (a00 + iso, a01, a02, a11 + iso, a12, a22 + iso), taut


def _is_regular(k_bar) -> bool:
    eigenvalues = symmetric_eigenvalues(*k_bar)
    return eigenvalues[0] > 1e-9 * max(eigenvalues[2], 1e-300)


def _descent_step(attach, laws, r, state, mu: float, scale: float):
    """One damped Newton step on U from ``r`` (``state``: stiffness_forces there): Newton on the regularised Hessian
    K_bar + mu I with an Armijo line search, mu raised tenfold until a step is accepted. Returns the new point, its
    state and mu, or None when no step is found."""
    force, potential, k_bar, _ = state
    for _ in range(60):
        solved = solve_symmetric(k_bar[0] + mu, k_bar[1], k_bar[2], k_bar[3] + mu, k_bar[4], k_bar[5] + mu,
                                 *force)   # Newton on U: -grad U = F, Hessian K_bar (+ mu I)
        if solved is None:
            mu *= 10.0
            continue
        step = solved[0]
        slope = force[0] * step[0] + force[1] * step[1] + force[2] * step[2]   # -(dU/dt) at t = 0
        # U carries round-off of ~1e-10 of itself (lengths from coordinates kilometres from the origin): once
        # the decrease a step promises is below that, judge the step by the force residual instead
        resolved = slope > 1e-9 * potential
        residual = force[0] ** 2 + force[1] ** 2 + force[2] ** 2
        t = 1.0
        while t > 1e-10:
            trial = (r[0] + t * step[0], r[1] + t * step[1], r[2] + t * step[2])
            trial_state = stiffness_forces(attach, trial, laws)
            if resolved:
                accepted = trial_state[1] <= potential - 1e-4 * t * slope
            else:
                f = trial_state[0]
                accepted = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] < residual
            if accepted:
                return trial, trial_state, max(mu * (0.3 if t == 1.0 else 1.0), 1e-12 * scale)
            t *= 0.5
        mu *= 10.0
    return None


def equilibrium_point(attach_position, laws, guess=None, tolerance: float = 1e-9, max_iterations: int = 100,
                      require_unique: bool = False) -> Equilibrium:
    """Solve Eq. 2.9 for the confluence position by damped Newton on the convex potential U.

    Parameters
    ----------
    attach_position : sequence of (x, y, z)
        Attach points (m).
    laws : sequence of LineLaw
        The lines (``stiffness_laws`` makes them from L0 in m, K in N/m and tables); a table's tension and slope
        replace K (L - L0) and K; the damping does not enter.
    guess : (x, y, z), optional
        Starting point (m), e.g. the previous solution; default: the stiffness-weighted mean of the attach points.
    tolerance : float
        Convergence when |F| <= tolerance * sum(K * L0) (relative to the lines' force scale).
    max_iterations : int
    require_unique : bool
        Raise NoEquilibriumError when the balance is not isolated (K_bar singular there).

    Returns
    -------
    Equilibrium
    """
    # plain floats for the loops below (accepts lists or arrays; cheap: this runs at every solver stage)
    attach = [(float(p[0]), float(p[1]), float(p[2])) for p in attach_position]
    free_length = [float(law.free_length) for law in laws]
    stiffness = [float(law.stiffness) for law in laws]
    total = sum(stiffness)
    if not total > 0.0:
        raise NoEquilibriumError("no line has stiffness", 0, len(stiffness))
    if guess is None:
        r = tuple(sum(k * p[i] for k, p in zip(stiffness, attach)) / total for i in range(3))
    else:
        r = tuple(float(c) for c in guess)
    scale = sum(k * l0 for k, l0 in zip(stiffness, free_length))
    force, potential, k_bar, taut = stiffness_forces(attach, r, laws)
    mu = 1e-9 * scale / max(sum(free_length) / len(free_length), 1e-12)
    iterations = 0
    while math.sqrt(force[0] ** 2 + force[1] ** 2 + force[2] ** 2) > tolerance * scale \
            and iterations < max_iterations:
        iterations += 1
        stepped = _descent_step(attach, laws, r, (force, potential, k_bar, taut), mu, scale)
        if stepped is None:
            break
        r, (force, potential, k_bar, taut), mu = stepped
    residual = math.sqrt(force[0] ** 2 + force[1] ** 2 + force[2] ** 2)
    unique = _is_regular(k_bar)
    if require_unique and not unique:
        raise NoEquilibriumError("the stiffness matrix K_bar is singular at the force balance", sum(taut), len(taut))
    return Equilibrium(np.array(r), residual <= tolerance * scale, iterations, residual, np.array(taut), unique)


def equilibrium_velocity(attach_position, attach_velocity, position, laws):
    """Velocity of the equilibrium point (thesis Appendix B): K_bar v_eq = sum K_i_bar v_i.

    Differentiating F(r_eq, r_i) = 0 in time gives K_bar v_eq = sum_i K_i_bar v_i, with K_i_bar = K_i [(1 - L0/L) I +
    (L0/L) n n^T] the stiffness of taut line i. Where K_bar is singular (a slack system) the minimum-norm solution is
    returned, so slack directions take no velocity.

    Returns
    -------
    velocity : tuple of 3 float (m/s)
    regular : bool
        False where K_bar was singular.
    """
    bx = by = bz = 0.0
    a00 = a01 = a02 = a11 = a12 = a22 = iso = 0.0
    for (length, nx, ny, nz), (vx, vy, vz), law in zip(line_geometry(attach_position, position), attach_velocity,
                                                       laws):
        if length <= law.free_length or law.stiffness == 0.0:
            continue
        _, _, ki, kr = line_terms(law, length)
        along = kr * (vx * nx + vy * ny + vz * nz)
        bx += ki * vx + along * nx
        by += ki * vy + along * ny
        bz += ki * vz + along * nz
        iso += ki
        a00 += kr * nx * nx
        a01 += kr * nx * ny
        a02 += kr * nx * nz
        a11 += kr * ny * ny
        a12 += kr * ny * nz
        a22 += kr * nz * nz
    k_bar = (a00 + iso, a01, a02, a11 + iso, a12, a22 + iso)
    if _is_regular(k_bar):
        return solve_symmetric(*k_bar, bx, by, bz)[0], True
    matrix = np.array([[k_bar[0], k_bar[1], k_bar[2]], [k_bar[1], k_bar[3], k_bar[4]],
                       [k_bar[2], k_bar[4], k_bar[5]]])
    return tuple(np.linalg.lstsq(matrix, [bx, by, bz], rcond=1e-9)[0].tolist()), False

"""The analytic (linearised) confluence motion about its equilibrium point (thesis Eqs. 2.6-2.8, chapter 2).

m dr'' + C_bar dr' + K_bar dr = 0 is written as y' = A y with y = (dr, dr'), A = [[0, I], [-K_bar/m, -C_bar/m]], and
solved by superposing its eigenmodes: y(t) = V exp(Lambda t) V^-1 y0. For diagonal C_bar and K_bar this is the thesis's
per-axis solution (Eq. 2.7 for real root pairs, Eq. 2.8 for complex ones); the modal form also covers coupled,
non-diagonal matrices (an off-axis equilibrium). Where the eigenvectors are nearly dependent (a repeated, defective
root such as critical damping) it falls back to the matrix exponential.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm

from .linearization import companion_matrix


def analytic_response(mass: float, damping_matrix, stiffness_matrix, initial_offset, initial_velocity, times):
    """Confluence offset from equilibrium dr(t) (m) and its rate dr'(t) (m/s) at ``times`` (s).

    Parameters
    ----------
    mass : float
        Confluence mass m_c (kg).
    damping_matrix, stiffness_matrix : array_like (3, 3)
        C_bar (N s/m) and K_bar (N/m) at the equilibrium point.
    initial_offset, initial_velocity : array_like (3,)
        dr(0) = r_c(0) - r_eq (m) and dr'(0) = r_c'(0) - r_eq' (m/s).
    times : array_like (n,)

    Returns
    -------
    offset, rate : ndarray (n, 3)
    """
    a = companion_matrix(mass, damping_matrix, stiffness_matrix)
    y0 = np.concatenate([np.asarray(initial_offset, float), np.asarray(initial_velocity, float)])
    times = np.asarray(times, float)
    values, vectors = np.linalg.eig(a)
    if np.linalg.cond(vectors) < 1e8:
        amplitudes = np.linalg.solve(vectors, y0.astype(complex))   # modal coordinates of y0
        y = (vectors[None, :, :] * (amplitudes * np.exp(np.outer(times, values)))[:, None, :]).sum(axis=2).real
    else:
        y = np.array([expm(a * t) @ y0 for t in times])
    return y[:, :3], y[:, 3:]

"""Exudyn's own linearisation of a full-mass model, to cross-check ``physics.linearization``."""

from __future__ import annotations

import exudyn as exu
import numpy as np

from ..case.model import Case
from .full import build_full_model


def exudyn_linear_system(case: Case):
    """Mass, stiffness and damping matrices (M, K, D) of the full-mass model at the case's initial state, from
    Exudyn's ``ComputeLinearizedSystem`` (numerical differentiation of the engine's forces)."""
    items = build_full_model(case)
    m, k, d = items.mbs.ComputeLinearizedSystem(exu.SimulationSettings(), projectIntoConstraintNullspace=False)
    return np.asarray(m), np.asarray(k), np.asarray(d)


def exudyn_eigenvalues(case: Case) -> np.ndarray:
    """Roots of det(M lambda^2 + D lambda + K) = 0 from Exudyn's linearisation (1/s)."""
    m, k, d = exudyn_linear_system(case)
    n = m.shape[0]
    companion = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(m, k), -np.linalg.solve(m, d)]])
    return np.linalg.eigvals(companion)

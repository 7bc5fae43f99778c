"""Exudyn's own linearisation of a full-mass model, to cross-check ``physics.linearization``."""

from __future__ import annotations

import exudyn as exu
import numpy as np

from ..case.model import Case
from ..physics.linearization import companion_matrix
from .full_model import build_full_model
from .state import Phase


def exudyn_linear_system(case: Case, phase: Phase):
    """Mass, stiffness and damping matrices (M, K, D) of the full-mass model at the phase's start state, from
    Exudyn's ``ComputeLinearizedSystem`` (numerical differentiation of the engine's forces)."""
    model = build_full_model(case, phase)
    m, k, d = model.mbs.ComputeLinearizedSystem(exu.SimulationSettings(), projectIntoConstraintNullspace=False)
    return np.asarray(m), np.asarray(k), np.asarray(d)


def exudyn_eigenvalues(case: Case, phase: Phase) -> np.ndarray:
    """Roots of det(M lambda^2 + D lambda + K) = 0 from Exudyn's linearisation (1/s)."""
    m, k, d = exudyn_linear_system(case, phase)
    return np.linalg.eigvals(companion_matrix(m, d, k))

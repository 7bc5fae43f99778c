"""Symmetric 3x3 linear algebra in scalar floats, compiled (``compiled.kernel``): per-stage kernels.

A symmetric matrix is passed as its six entries a00, a01, a02, a11, a12, a22.
"""

from __future__ import annotations

import math

from .compiled import kernel


@kernel
def solve_symmetric_kernel(a00, a01, a02, a11, a12, a22, bx, by, bz):
    """Solve A x = b by cofactors; returns (x0, x1, x2, kappa), kappa = -1 when det(A) <= 0 (no solution).

    kappa = ||A||_F ||A^-1||_F (thesis Eq. 3.12 with Frobenius norms, equal to Eq. 3.13) comes from the cofactors
    at no extra cost.
    """
    m00 = a11 * a22 - a12 * a12
    m01 = a02 * a12 - a01 * a22
    m02 = a01 * a12 - a02 * a11
    det = a00 * m00 + a01 * m01 + a02 * m02
    if not det > 0.0:
        return 0.0, 0.0, 0.0, -1.0
    m11 = a00 * a22 - a02 * a02
    m12 = a01 * a02 - a00 * a12
    m22 = a00 * a11 - a01 * a01
    norm_a = a00 * a00 + a11 * a11 + a22 * a22 + 2.0 * (a01 * a01 + a02 * a02 + a12 * a12)
    norm_m = m00 * m00 + m11 * m11 + m22 * m22 + 2.0 * (m01 * m01 + m02 * m02 + m12 * m12)
    return ((m00 * bx + m01 * by + m02 * bz) / det, (m01 * bx + m11 * by + m12 * bz) / det,
            (m02 * bx + m12 * by + m22 * bz) / det, math.sqrt(norm_a * norm_m) / det)


def solve_symmetric(a00, a01, a02, a11, a12, a22, bx, by, bz):
    """Solve A x = b (``solve_symmetric_kernel``); returns (x, kappa) or None when det(A) <= 0."""
    x0, x1, x2, kappa = solve_symmetric_kernel(a00, a01, a02, a11, a12, a22, bx, by, bz)
    return None if kappa < 0.0 else ((x0, x1, x2), kappa)


@kernel
def symmetric_eigenvalues(a00, a01, a02, a11, a12, a22):
    """Eigenvalues (ascending) of a symmetric 3x3 matrix in closed form (trigonometric method)."""
    p1 = a01 * a01 + a02 * a02 + a12 * a12
    if p1 == 0.0:
        low, mid, high = a00, a11, a22
        if low > mid:
            low, mid = mid, low
        if mid > high:
            mid, high = high, mid
        if low > mid:
            low, mid = mid, low
        return low, mid, high
    q = (a00 + a11 + a22) / 3.0
    b00, b11, b22 = a00 - q, a11 - q, a22 - q
    p = math.sqrt((b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * p1) / 6.0)
    det = (b00 * (b11 * b22 - a12 * a12) - a01 * (a01 * b22 - a12 * a02) + a02 * (a01 * a12 - b11 * a02))
    r = max(-1.0, min(1.0, det / (2.0 * p * p * p)))
    phi = math.acos(r) / 3.0
    largest = q + 2.0 * p * math.cos(phi)
    smallest = q + 2.0 * p * math.cos(phi + 2.0 * math.pi / 3.0)
    return smallest, 3.0 * q - largest - smallest, largest

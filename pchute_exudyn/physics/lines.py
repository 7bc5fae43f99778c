"""Tension-only elastic lines (thesis Eqs. 1.6-1.7; ``docs/models/conventions.md``, "Line law and sign convention").

Sign convention (the only place it is defined)::

    attach point r_i (on a body)                               confluence r_c
          o <-------------------------------------------------------- o
          |  body is pulled by  -T n            confluence is pulled by +T n
          |                                                           |
          n = (r_i - r_c) / L    points from the confluence to the attach point
          L = |r_i - r_c|,   L_dot = (v_i - v_c) . n   (positive while the line lengthens)

    taut  when L > L0:  T = max(0, K (L - L0) + C L_dot)      (tension positive, a line never pushes)
    slack when L <= L0: T = 0

Everything here is pure numpy and broadcasts over any leading axes, so one call handles all lines of a
system (shape ``(n_lines, 3)``) or all output samples at once (shape ``(n_samples, n_lines, 3)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class LineState:
    """Geometry and tension of a set of lines.

    Attributes
    ----------
    length : ndarray
        Current length L (m).
    direction : ndarray
        Unit vector n from the confluence to the attach point (shape ``(..., 3)``).
    length_rate : ndarray
        dL/dt (m/s), positive while the line lengthens.
    tension : ndarray
        Tension magnitude T (N), >= 0.
    taut : ndarray of bool
        True where L > L0.
    """

    length: np.ndarray
    direction: np.ndarray
    length_rate: np.ndarray
    tension: np.ndarray
    taut: np.ndarray

    def force_on_confluence(self) -> np.ndarray:
        """Force of each line on the confluence, +T n (N)."""
        return self.tension[..., None] * self.direction

    def force_on_body(self) -> np.ndarray:
        """Force of each line on the body at its attach point, -T n (N)."""
        return -self.force_on_confluence()


def tension(stretch: float, length_rate: float, stiffness: float, damping: float) -> float:
    """The line law for one line in plain floats (per-stage user functions); same law as ``tension_magnitude``.

    Parameters are the stretch L - L0 (m), dL/dt (m/s), K (N/m) and C (N s/m); returns T (N) >= 0.
    """
    if stretch <= 0.0:
        return 0.0
    value = stiffness * stretch + damping * length_rate
    return value if value > 0.0 else 0.0


def line_geometry(attach_position, confluence_position) -> list:
    """Length L (m) and unit vector n = (r_i - r_c) / L of each line, as (L, nx, ny, nz) in plain floats: the one
    home of the line geometry for the per-stage kernels (SP, equilibrium point, the line law)."""
    cx, cy, cz = confluence_position
    geometry = []
    for px, py, pz in attach_position:
        dx, dy, dz = px - cx, py - cy, pz - cz
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        geometry.append((length, dx / length, dy / length, dz / length))
    return geometry


def line_tensions(attach_position, attach_velocity, confluence_position, confluence_velocity, free_length,
                  stiffness, damping) -> tuple[tuple, tuple]:
    """Tensions T (N) and unit vectors n (confluence -> attach point) of a system's lines in plain floats (the
    per-stage form of ``line_states``): sequences of (x, y, z) in m and m/s, and per-line L0 (m), K (N/m), C (N s/m).
    """
    wx, wy, wz = confluence_velocity
    tensions, directions = [], []
    for (length, nx, ny, nz), (vx, vy, vz), l0, k, c in zip(line_geometry(attach_position, confluence_position),
                                                            attach_velocity, free_length, stiffness, damping):
        directions.append((nx, ny, nz))
        tensions.append(tension(length - l0, (vx - wx) * nx + (vy - wy) * ny + (vz - wz) * nz, k, c))
    return tuple(tensions), tuple(directions)


def tension_magnitude(length, length_rate, free_length, stiffness, damping):
    """Tension-only line law (Eq. 1.6 with the clip of ``docs/models/conventions.md``).

    Parameters
    ----------
    length : array_like
        Line length L (m).
    length_rate : array_like
        dL/dt (m/s).
    free_length : array_like
        Unstretched length L0 (m).
    stiffness : array_like
        Spring constant K (N/m).
    damping : array_like
        Damping constant C (N s/m).

    Returns
    -------
    ndarray
        T = max(0, K (L - L0) + C dL/dt) where L > L0, and 0 where the line is slack (N).
    """
    length = np.asarray(length, dtype=float)
    linear = stiffness * (length - free_length) + damping * np.asarray(length_rate, dtype=float)
    return np.where(length > free_length, np.maximum(linear, 0.0), 0.0)


def line_states(attach_position, attach_velocity, confluence_position, confluence_velocity,
                free_length, stiffness, damping) -> LineState:
    """Evaluate lines from their attach points to a confluence (Eqs. 1.6-1.7).

    Parameters
    ----------
    attach_position, attach_velocity : array_like, shape (..., n_lines, 3)
        Inertial position (m) and velocity (m/s) of each line's attach point.
    confluence_position, confluence_velocity : array_like, shape (..., 3)
        Inertial position (m) and velocity (m/s) of the confluence; broadcast against the lines.
    free_length, stiffness, damping : array_like, shape (n_lines,)
        L0 (m), K (N/m) and C (N s/m) of each line.

    Returns
    -------
    LineState
    """
    rel = np.asarray(attach_position, float) - np.asarray(confluence_position, float)[..., None, :]
    rel_v = np.asarray(attach_velocity, float) - np.asarray(confluence_velocity, float)[..., None, :]
    length = np.linalg.norm(rel, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        direction = np.where(length[..., None] > 0.0, rel / length[..., None], 0.0)
    length_rate = np.einsum("...i,...i->...", rel_v, direction)
    tension = tension_magnitude(length, length_rate, free_length, stiffness, damping)
    return LineState(length=length, direction=direction, length_rate=length_rate, tension=tension,
                     taut=length > np.asarray(free_length))

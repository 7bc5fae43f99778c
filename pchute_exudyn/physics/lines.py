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

A line may instead give its elastic tension as a measured load-elongation table (``LoadElongation``)::

    taut  when L > L0:  T = max(0, T_table(eps) + C L_dot),   eps = (L - L0) / L0

The array functions here are pure numpy and broadcast over any leading axes, so one call handles all lines of a
system (shape ``(n_lines, 3)``) or all output samples at once (shape ``(n_samples, n_lines, 3)``).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from itertools import repeat

import numpy as np

from .compiled import kernel
from .invalid import InvalidField


class LoadElongationError(InvalidField):
    """A load-elongation table that is not a valid line law; ``field`` names the offending column."""


@dataclass(frozen=True)
class LoadElongation:
    """A line's measured load-elongation curve: elastic tension against strain.

    Attributes
    ----------
    strain : tuple of float
        Strain eps = (L - L0) / L0 (-), starting at 0 and strictly increasing.
    tension : tuple of float
        Elastic tension T_table (N) at each strain, starting at 0 and strictly increasing.

    Linear between the points; beyond the last point the last segment's slope continues (a measured curve ends
    before the line breaks, not where it stops stretching).
    """

    strain: tuple
    tension: tuple

    def __post_init__(self):
        strain, tension = self.strain, self.tension
        if len(strain) < 2 or len(tension) != len(strain):
            raise LoadElongationError("strain", list(strain), "needs at least two points and as many tensions "
                                                             "as strains")
        if strain[0] != 0.0 or tension[0] != 0.0:
            name, values = ("strain", strain) if strain[0] != 0.0 else ("tension", tension)
            raise LoadElongationError(name, list(values), "the table must start at (0, 0)")
        for name, values in (("strain", strain), ("tension", tension)):
            if any(b <= a for a, b in zip(values, values[1:])):
                raise LoadElongationError(name, list(values), "must increase strictly")

    def slopes(self) -> list:
        """dT/d eps of each segment (N)."""
        e, f = self.strain, self.tension
        return [(f[i + 1] - f[i]) / (e[i + 1] - e[i]) for i in range(len(e) - 1)]

    def _segment(self, strain: float) -> int:
        return min(max(bisect.bisect_right(self.strain, strain) - 1, 0), len(self.strain) - 2)

    def __call__(self, strain: float) -> float:
        """T_table(eps) (N) for eps >= 0 (0 at eps <= 0)."""
        return table_tension(self.points(), len(self.strain), strain)

    def points(self) -> np.ndarray:
        """The table as an array (n_points, 2) of (strain, tension): the compiled kernels' form."""
        return np.array([self.strain, self.tension], float).T.copy()

    def slope(self, strain: float) -> float:
        """dT_table/d eps (N) at ``strain``: the segment's slope (the first segment's at or below 0)."""
        return self.slopes()[self._segment(strain)]

    def strain_at(self, tension: float) -> float:
        """The strain (-) at which T_table reaches ``tension`` (N, >= 0): the table's inverse."""
        e, f = self.strain, self.tension
        i = min(max(bisect.bisect_right(f, tension) - 1, 0), len(f) - 2)
        return e[i] + (tension - f[i]) * (e[i + 1] - e[i]) / (f[i + 1] - f[i])

    def hinges(self) -> tuple:
        """The curve as T(eps) = s_0 eps + sum_j (s_j - s_(j-1)) max(0, eps - eps_j) for eps >= 0: ((eps_j,
        slope change), ...) with eps_0 = 0 first. Exactly the piecewise-linear table with its last slope continued,
        in a form that needs no search (the full-mass model's symbolic line law)."""
        slopes = self.slopes()
        return ((0.0, slopes[0]),) + tuple((self.strain[j], slopes[j] - slopes[j - 1])
                                           for j in range(1, len(slopes)))

    def energy(self, strain: float) -> float:
        """Integral of T_table from 0 to ``strain`` (N, per unit L0): the line's elastic energy over L0."""
        if strain <= 0.0:
            return 0.0
        return sum(change * 0.5 * (strain - corner) ** 2 for corner, change in self.hinges() if strain > corner)


@kernel
def table_tension(points, count, strain):
    """T_table(eps) (N) of a load-elongation table given as ``points`` (rows of strain, tension; the first
    ``count`` rows used): linear between points, the last slope continued, 0 at eps <= 0."""
    if strain <= 0.0:
        return 0.0
    i = 0   # the segment: the last point at or below the strain, at most the second to last
    while i < count - 2 and points[i + 1, 0] <= strain:
        i += 1
    e0, e1, f0, f1 = points[i, 0], points[i + 1, 0], points[i, 1], points[i + 1, 1]
    return f0 + (f1 - f0) / (e1 - e0) * (strain - e0)


@kernel
def _elastic(points, count, stretch, free_length, stiffness):
    """Elastic tension (N) of a line stretched by ``stretch`` (m): K (L - L0), or its table's (0 when slack)."""
    if stretch <= 0.0:
        return 0.0
    return stiffness * stretch if count == 0 else table_tension(points, count, stretch / free_length)


@kernel
def _slope(points, count, stretch, free_length, stiffness):
    """Tangent stiffness (N/m) of a line at ``stretch`` (m): K, or its table's slope / L0 (the segment's, from the
    right at a breakpoint; the first segment's when slack)."""
    if count == 0:
        return stiffness
    strain = max(stretch / free_length, 0.0)
    i = 0
    while i < count - 2 and points[i + 1, 0] <= strain:
        i += 1
    return (points[i + 1, 1] - points[i, 1]) / (points[i + 1, 0] - points[i, 0]) / free_length


@kernel
def series_constants(lines, tables, table_counts, length, load):
    """The elastic side of two lines in series (``series_pair``) at the distance ``length`` (m) between their far
    attach points, with ``load`` (N) along it on the confluence (the first line carries it on top of the second's
    tension): (the second line's elastic tension T_2,el in N, the pair's series damping C_s in N s/m, the first line's
    stretch e_1 in m). Slack (length <= L0_1 + L0_2): (0, 0, e L0_1 / (L0_1 + L0_2))."""
    l1, k1, c1 = lines[0, 0], lines[0, 1], lines[0, 2]
    l2, k2, c2 = lines[1, 0], lines[1, 1], lines[1, 2]
    n1, n2 = int(table_counts[0]), int(table_counts[1])
    stretch = length - l1 - l2
    if stretch <= 0.0:
        return 0.0, 0.0, stretch * l1 / (l1 + l2)
    if n1 == 0 and n2 == 0:
        first = min(max((stretch * k2 + load) / (k1 + k2), 0.0), stretch)
    else:   # T_1(e_1) - T_2(e - e_1) - load rises with e_1
        low, high = 0.0, stretch
        first = 0.5 * stretch
        for _ in range(200):
            first = 0.5 * (low + high)
            if high - low <= 1e-15 * stretch:
                break
            if _elastic(tables[0], n1, first, l1, k1) - _elastic(tables[1], n2, stretch - first, l2, k2) < load:
                low = first
            else:
                high = first
    t1, t2 = _slope(tables[0], n1, first, l1, k1), _slope(tables[1], n2, stretch - first, l2, k2)
    total = t1 + t2
    damping = (c1 * t2 * t2 + c2 * t1 * t1) / (total * total) if total > 0.0 else 0.0
    return _elastic(tables[1], n2, stretch - first, l2, k2), damping, first


@kernel
def series_pair(lines, tables, table_counts, length, length_rate, load):
    """Two lines in series through a massless confluence, as one tension-only line (docs/models/step_control.md,
    "Lines in series"): ``lines`` rows (L0 in m, K in N/m, C in N s/m) of the first line (from A) and the second
    (to B), ``length`` the distance AB (m), ``length_rate`` its rate (m/s) and ``load`` a force on the confluence
    along AB (N, towards B; its weight's component, 0 when massless), which the first line carries on top of the
    second's tension: T_1 = T_2 + load.

    The elastic split e_1 + e_2 = e = length - L0_1 - L0_2 with T_1(e_1) = T_2(e_2) + load (for linear lines
    K_1 e_1 = K_2 e_2 + load; a table's by bisection); the pair's damping the series value that matches its
    compliance to first order in frequency, C_s = (C_1 K_2^2 + C_2 K_1^2) / (K_1 + K_2)^2 with the tangent
    stiffnesses at the split (exact at every frequency when C_1 / K_1 = C_2 / K_2); T_2 = T_2,el + C_s de/dt,
    tension only (``series_constants``). Returns (T_1, T_2 in N, the first line's stretch e_1 in m, its rate in
    m/s); slack (e <= 0, or no tension): e_1 = e L0_1 / (L0_1 + L0_2)."""
    l1, l2 = lines[0, 0], lines[1, 0]
    share = l1 / (l1 + l2)
    elastic, damping, first = series_constants(lines, tables, table_counts, length, load)
    second = elastic + damping * length_rate
    stretch = length - l1 - l2
    if stretch <= 0.0 or (second <= 0.0 and second + load <= 0.0):
        return 0.0, 0.0, stretch * share, length_rate * share
    t1 = _slope(tables[0], int(table_counts[0]), first, l1, lines[0, 1])
    t2 = _slope(tables[1], int(table_counts[1]), stretch - first, l2, lines[1, 1])
    rate_share = t2 / (t1 + t2) if t1 + t2 > 0.0 else share
    return max(second + load, 0.0), max(second, 0.0), first, length_rate * rate_share


def pack_tables(tables) -> tuple[np.ndarray, np.ndarray]:
    """Per-line tables (LoadElongation or None) as the compiled kernels take them: points (n_lines, m, 2), zero
    padded, and the number of points of each line (0: a linear line, K (L - L0))."""
    tables = list(tables)
    size = max([len(t.strain) for t in tables if t is not None], default=2)
    points = np.zeros((len(tables), size, 2))
    counts = np.zeros(len(tables), np.int64)
    for j, table in enumerate(tables):
        if table is not None:
            counts[j] = len(table.strain)
            points[j, :counts[j]] = table.points()
    return points, counts


def elastic_tension(stretch: float, free_length: float, stiffness: float, table: LoadElongation | None) -> float:
    """The elastic part of a taut line's tension (N) at ``stretch`` = L - L0 > 0 (m): K (L - L0), or the table's
    T_table((L - L0) / L0)."""
    return stiffness * stretch if table is None else table(stretch / free_length)


def tangent_stiffness(stretch: float, free_length: float, stiffness: float, table: LoadElongation | None) -> float:
    """d(elastic tension)/dL (N/m) at ``stretch`` (m): K, or the table's slope over L0 (its first segment's while
    the line is slack)."""
    return stiffness if table is None else table.slope(stretch / free_length) / free_length


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


def tension(stretch: float, length_rate: float, stiffness: float, damping: float, elastic: float | None = None
            ) -> float:
    """The line law for one line in plain floats (per-stage user functions); same law as ``tension_magnitude``.

    Parameters are the stretch L - L0 (m), dL/dt (m/s), K (N/m) and C (N s/m); ``elastic``: the elastic tension
    (N) when a load-elongation table gives it (``elastic_tension``), else K (L - L0). Returns T (N) >= 0.
    """
    if stretch <= 0.0:
        return 0.0
    value = (stiffness * stretch if elastic is None else elastic) + damping * length_rate
    return value if value > 0.0 else 0.0


def line_geometry(attach_position, confluence_position) -> list:
    """Length L (m) and unit vector n = (r_i - r_c) / L of each line, as (L, nx, ny, nz) in plain floats: the one
    home of the line geometry for the per-stage kernels (SP, equilibrium point, the line law). A line of zero length
    (its attach point at the confluence: slack) gets n = 0."""
    cx, cy, cz = confluence_position
    geometry = []
    for px, py, pz in attach_position:
        dx, dy, dz = px - cx, py - cy, pz - cz
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        if length > 0.0:
            geometry.append((length, dx / length, dy / length, dz / length))
        else:
            geometry.append((0.0, 0.0, 0.0, 0.0))
    return geometry


def line_tensions(attach_position, attach_velocity, confluence_position, confluence_velocity, free_length,
                  stiffness, damping, tables=None) -> tuple[tuple, tuple]:
    """Tensions T (N) and unit vectors n (confluence -> attach point) of a system's lines in plain floats (the
    per-stage form of ``line_states``): sequences of (x, y, z) in m and m/s, and per-line L0 (m), K (N/m), C (N s/m)
    and load-elongation tables (None: every line linear).
    """
    wx, wy, wz = confluence_velocity
    tensions, directions = [], []
    for (length, nx, ny, nz), (vx, vy, vz), l0, k, c, table in zip(
            line_geometry(attach_position, confluence_position), attach_velocity, free_length, stiffness, damping,
            tables or repeat(None)):
        directions.append((nx, ny, nz))
        stretch = length - l0
        elastic = None if table is None or stretch <= 0.0 else table(stretch / l0)
        tensions.append(tension(stretch, (vx - wx) * nx + (vy - wy) * ny + (vz - wz) * nz, k, c, elastic))
    return tuple(tensions), tuple(directions)


def elastic_tensions(stretch, free_length, stiffness, tables=None) -> np.ndarray:
    """Elastic tensions (N) of lines at ``stretch`` = L - L0 (m, shape (..., n_lines)) for L > L0: K (L - L0), or
    T_table((L - L0) / L0) for a line with a table (``tables``: per line, None for a linear line)."""
    stretch = np.asarray(stretch, dtype=float)
    elastic = np.asarray(stiffness, float) * stretch
    if tables is None or all(table is None for table in tables):
        return elastic
    elastic = np.array(np.broadcast_to(elastic, stretch.shape))
    for j, (table, l0) in enumerate(zip(tables, np.broadcast_to(free_length, stretch.shape[-1:]))):
        if table is not None:
            strain = np.maximum(stretch[..., j] / l0, 0.0)
            elastic[..., j] = sum(change * np.maximum(strain - corner, 0.0) for corner, change in table.hinges())
    return elastic


def tension_magnitude(length, length_rate, free_length, stiffness, damping, tables=None):
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
    tables : sequence of LoadElongation or None, optional
        Per line (last axis), a load-elongation table replacing K (L - L0); None: every line linear.

    Returns
    -------
    ndarray
        T = max(0, K (L - L0) + C dL/dt) where L > L0, and 0 where the line is slack (N).
    """
    length = np.asarray(length, dtype=float)
    linear = elastic_tensions(length - free_length, free_length, stiffness, tables) \
        + damping * np.asarray(length_rate, dtype=float)
    return np.where(length > free_length, np.maximum(linear, 0.0), 0.0)


def line_states(attach_position, attach_velocity, confluence_position, confluence_velocity,
                free_length, stiffness, damping, tables=None) -> LineState:
    """Evaluate lines from their attach points to a confluence (Eqs. 1.6-1.7).

    Parameters
    ----------
    attach_position, attach_velocity : array_like, shape (..., n_lines, 3)
        Inertial position (m) and velocity (m/s) of each line's attach point.
    confluence_position, confluence_velocity : array_like, shape (..., 3)
        Inertial position (m) and velocity (m/s) of the confluence; broadcast against the lines.
    free_length, stiffness, damping : array_like, shape (n_lines,)
        L0 (m), K (N/m) and C (N s/m) of each line.
    tables : sequence of LoadElongation or None, optional
        Per line, a load-elongation table replacing K (L - L0).

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
    tension = tension_magnitude(length, length_rate, free_length, stiffness, damping, tables)
    return LineState(length=length, direction=direction, length_rate=length_rate, tension=tension,
                     taut=length > np.asarray(free_length))

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

One law, one home. The law is written once, as the kernels ``line_elastic`` (T_el), ``line_slope`` (dT_el/dL),
``line_pull`` and ``line_tension`` (the clip and the slack rule), with the series pair of two lines through a
massless confluence (``series_constants``, ``series_pair``, ``series_damping``) built on them; a line is one
``LineLaw`` record (``case.model.Line.law``), whose methods call the same kernels as Python. Every method uses them:
SP's solve and its reduced canopy (compiled, per stage), the equilibrium point, the linearisation's tangent
stiffness, the full-mass model's Python law. The forms that cannot call a kernel are written from the record:
``LineLaw.expression`` over an ``Arithmetic`` gives the full-mass model's Exudyn symbolic user function
(``engine.full_model``) and the law over numpy arrays (``tension_magnitude``, ``line_states``: whole histories,
broadcast over leading axes). ``tests/unit/test_line_law.py`` evaluates every form on random states against the
record.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from .compiled import kernel, python_form
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


LINE_FREE_LENGTH, LINE_STIFFNESS, LINE_DAMPING = 0, 1, 2
"""The columns of a packed line's row of constants (``pack_lines``): L0 (m), K (N/m), C (N s/m)."""


# -- the line law: the one definition (compiled for the per-stage solves, called as Python elsewhere) ------------

@kernel
def line_elastic(points, count, stretch, free_length, stiffness):
    """Elastic tension T_el (N) of a line stretched by ``stretch`` = L - L0 (m): K (L - L0), or its table's
    T_table((L - L0) / L0) (``points``: its first ``count`` rows of strain and tension; count 0: linear); 0 when
    slack (stretch <= 0)."""
    if stretch <= 0.0:
        return 0.0
    return stiffness * stretch if count == 0 else table_tension(points, count, stretch / free_length)


@kernel
def line_slope(points, count, stretch, free_length, stiffness):
    """Tangent stiffness dT_el/dL (N/m) at ``stretch`` (m): K, or the table's slope / L0 (the segment's, from the
    right at a breakpoint; the first segment's when slack)."""
    if count == 0:
        return stiffness
    strain = max(stretch / free_length, 0.0)
    i = 0
    while i < count - 2 and points[i + 1, 0] <= strain:
        i += 1
    return (points[i + 1, 1] - points[i, 1]) / (points[i + 1, 0] - points[i, 0]) / free_length


@kernel
def line_pull(elastic, damping, rate):
    """The line's pull along n before the tension-only clip (N): T_el + C dL/dt, ``elastic`` T_el in N,
    ``damping`` C in N s/m, ``rate`` dL/dt in m/s (Eq. 1.6). Negative: the law would push."""
    return elastic + damping * rate


@kernel
def line_tension(stretch, elastic, damping, rate):
    """The tension-only line law (Eq. 1.6 with the clip; module docstring): T = max(0, T_el + C dL/dt) (N) while
    the line is taut (``stretch`` = L - L0 > 0, m), 0 while it is slack; ``elastic`` T_el = ``line_elastic``."""
    pull = line_pull(elastic, damping, rate)
    return pull if stretch > 0.0 and pull > 0.0 else 0.0


@kernel
def series_damping(first_stiffness, second_stiffness, first_damping, second_damping):
    """The damping (N s/m) of two lines in series with (tangent) stiffnesses K_1, K_2 (N/m) and damping C_1, C_2
    (N s/m), matched to their compliance to first order in frequency: C_s = (C_1 K_2^2 + C_2 K_1^2) / (K_1 + K_2)^2
    (exact at every frequency when C_1 / K_1 = C_2 / K_2); 0 when neither has stiffness."""
    total = first_stiffness + second_stiffness
    if not total > 0.0:
        return 0.0
    return (first_damping * second_stiffness * second_stiffness
            + second_damping * first_stiffness * first_stiffness) / (total * total)


@kernel
def series_constants(lines, tables, table_counts, length, load):
    """The elastic side of two lines in series (``series_pair``) at the distance ``length`` (m) between their far
    attach points, with ``load`` (N) along it on the confluence (the first line carries it on top of the second's
    tension): (the second line's elastic tension T_2,el in N, the pair's series damping C_s in N s/m, the first line's
    stretch e_1 in m). Slack (length <= L0_1 + L0_2): (0, 0, e L0_1 / (L0_1 + L0_2))."""
    l1, k1, c1 = lines[0, LINE_FREE_LENGTH], lines[0, LINE_STIFFNESS], lines[0, LINE_DAMPING]
    l2, k2, c2 = lines[1, LINE_FREE_LENGTH], lines[1, LINE_STIFFNESS], lines[1, LINE_DAMPING]
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
            if line_elastic(tables[0], n1, first, l1, k1) - line_elastic(tables[1], n2, stretch - first, l2, k2) \
                    < load:
                low = first
            else:
                high = first
    t1, t2 = line_slope(tables[0], n1, first, l1, k1), line_slope(tables[1], n2, stretch - first, l2, k2)
    damping = series_damping(t1, t2, c1, c2)
    return line_elastic(tables[1], n2, stretch - first, l2, k2), damping, first


@kernel
def series_pair(lines, tables, table_counts, length, length_rate, load):
    """Two lines in series through a massless confluence, as one tension-only line (docs/models/step_control.md,
    "Lines in series"): ``lines`` rows (L0 in m, K in N/m, C in N s/m) of the first line (from A) and the second
    (to B), ``length`` the distance AB (m), ``length_rate`` its rate (m/s) and ``load`` a force on the confluence
    along AB (N, towards B; its weight's component, 0 when massless), which the first line carries on top of the
    second's tension: T_1 = T_2 + load.

    The elastic split e_1 + e_2 = e = length - L0_1 - L0_2 with T_1(e_1) = T_2(e_2) + load (for linear lines
    K_1 e_1 = K_2 e_2 + load; a table's by bisection); the pair's damping ``series_damping`` with the tangent
    stiffnesses at the split; T_2 = T_2,el + C_s de/dt (``line_pull``), tension only (``series_constants``).
    Returns (T_1, T_2 in N, the first line's stretch e_1 in m, its rate in m/s); slack (e <= 0, or no tension):
    e_1 = e L0_1 / (L0_1 + L0_2)."""
    l1, l2 = lines[0, LINE_FREE_LENGTH], lines[1, LINE_FREE_LENGTH]
    share = l1 / (l1 + l2)
    elastic, damping, first = series_constants(lines, tables, table_counts, length, load)
    second = line_pull(elastic, damping, length_rate)
    stretch = length - l1 - l2
    if stretch <= 0.0 or (second <= 0.0 and second + load <= 0.0):
        return 0.0, 0.0, stretch * share, length_rate * share
    t1 = line_slope(tables[0], int(table_counts[0]), first, l1, lines[0, LINE_STIFFNESS])
    t2 = line_slope(tables[1], int(table_counts[1]), stretch - first, l2, lines[1, LINE_STIFFNESS])
    rate_share = t2 / (t1 + t2) if t1 + t2 > 0.0 else share
    return max(second + load, 0.0), max(second, 0.0), first, length_rate * rate_share


@kernel
def solve_series(attach, attach_velocity, lines, tables, table_counts, tensions, directions, active, wx, wy, wz):
    """Two lines in series through the massless confluence (docs/models/step_control.md, "Lines in series"): the
    pair acts as one tension-only line between their attach points A (line 0) and B (line 1), ``lines.series_pair``,
    and the confluence sits on AB where the lines' elastic stretches put it, moving with that point. (wx, wy, wz) is
    the confluence's weight (N; 0 massless): its component along AB makes line 0's tension exceed line 1's; the
    caller shares the rest between A and B. Writes both tensions (N), the unit vectors n from the confluence to each
    attach point (-u and u, u from A to B) and the lines counted taut; returns (vx, vy, vz) of the confluence (m/s)
    and its fraction (-) of the way from A to B.

    The massless balance T_1 n_1 + T_2 n_2 = 0 has no solution off AB with a tension: the confluence has no
    stiffness across the pair, so Eq. 3.10's alpha is singular there and a state of its own would only follow the
    line with a fast, artificial mode. In the massless limit this is exact."""
    ax, ay, az = attach[0, 0], attach[0, 1], attach[0, 2]
    dx, dy, dz = attach[1, 0] - ax, attach[1, 1] - ay, attach[1, 2] - az
    length = math.sqrt(dx * dx + dy * dy + dz * dz)
    ux, uy, uz = dx / length, dy / length, dz / length
    rx = attach_velocity[1, 0] - attach_velocity[0, 0]
    ry = attach_velocity[1, 1] - attach_velocity[0, 1]
    rz = attach_velocity[1, 2] - attach_velocity[0, 2]
    length_rate = rx * ux + ry * uy + rz * uz
    first, second, stretch, stretch_rate = series_pair(lines, tables, table_counts, length, length_rate,
                                                       wx * ux + wy * uy + wz * uz)
    along = lines[0, LINE_FREE_LENGTH] + stretch   # from A to the confluence (m)
    tensions[0], tensions[1] = first, second
    for i in range(2):
        active[i] = tensions[i] > 0.0
        sign = -1.0 if i == 0 else 1.0
        directions[i, 0], directions[i, 1], directions[i, 2] = sign * ux, sign * uy, sign * uz
    turn = along / length                # the confluence turns with u: (r - (r.u) u) along / length
    vx = attach_velocity[0, 0] + stretch_rate * ux + turn * (rx - length_rate * ux)
    vy = attach_velocity[0, 1] + stretch_rate * uy + turn * (ry - length_rate * uy)
    vz = attach_velocity[0, 2] + stretch_rate * uz + turn * (rz - length_rate * uz)
    return vx, vy, vz, along / length


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


class Arithmetic(NamedTuple):
    """The operations a form of the line law that is not written in floats is built from (``LineLaw.expression``):
    ``zero()`` a zero, ``maximum(a, b)``, ``where_taut(stretch, value)``: ``value`` where the stretch is > 0, else
    zero; ``strain(stretch, free_length)``: (L - L0) / L0 as that form has always computed it; ``where_paying_out
    (stretch, rate, value)``: ``value`` where the line is slack (stretch <= 0) and lengthens (rate > 0), else zero."""

    zero: Callable
    maximum: Callable
    where_taut: Callable
    strain: Callable
    where_paying_out: Callable


NO_TABLE = np.zeros((2, 2))
NO_TABLE.flags.writeable = False
"""The table rows a linear line passes to the kernels (which never read them: its count is 0)."""
ARRAYS = Arithmetic(lambda: 0.0, np.maximum, lambda stretch, value: np.where(stretch > 0.0, value, 0.0),
                    lambda stretch, free_length: np.maximum(stretch / free_length, 0.0),
                    lambda stretch, rate, value: np.where((stretch <= 0.0) & (rate > 0.0), value, 0.0))
"""The line law over numpy arrays (``tension_magnitude``: whole histories)."""


@dataclass(frozen=True)
class LineLaw:
    """One tension-only spring-damper line: the record every form of the line law is evaluated on (module docstring;
    ``case.model.Line.law``).

    Attributes
    ----------
    free_length : float
        L0 (m).
    stiffness : float
        K (N/m); with a table, its first slope / L0 (for reports: the table gives the tension).
    damping : float
        C (N s/m).
    table : LoadElongation or None
        A load-elongation table whose tension replaces K (L - L0).
    payout_resistance : float
        R (N): the tension while the line is slack and paying out (L <= L0, dL/dt > 0): bag friction, folds, ties;
        0 (the default): a slack line carries nothing. Only a tether's law has one (``case.sections.Tether``): the
        per-stage kernels of a system's lines never see it.

    The law itself is the kernels above (``line_elastic``, ``line_slope``, ``line_tension``, the series pair), which
    the per-stage solves run compiled and these methods run as Python; ``expression`` writes the same law in another
    arithmetic (numpy arrays, Exudyn's symbolic expressions). ``tests/unit/test_line_law.py`` holds every form to
    this record on random states.
    """

    free_length: float
    stiffness: float
    damping: float
    table: LoadElongation | None = None
    payout_resistance: float = 0.0

    @cached_property
    def count(self) -> int:
        """Points of the table as the kernels read them (0: linear)."""
        return 0 if self.table is None else len(self.table.strain)

    @cached_property
    def points(self) -> np.ndarray:
        """The table's (strain, tension) rows (``NO_TABLE`` for a linear line)."""
        return NO_TABLE if self.table is None else self.table.points()

    def elastic(self, stretch: float) -> float:
        """T_el (N) at ``stretch`` = L - L0 (m): ``line_elastic``."""
        return _elastic(self.points, self.count, stretch, self.free_length, self.stiffness)

    def slope(self, stretch: float) -> float:
        """Tangent stiffness dT_el/dL (N/m) at ``stretch`` (m): ``line_slope``."""
        return _slope(self.points, self.count, stretch, self.free_length, self.stiffness)

    def tension(self, stretch: float, rate: float) -> float:
        """T (N) at ``stretch`` = L - L0 (m) and ``rate`` = dL/dt (m/s): ``line_tension``; R while it pays out."""
        if self.payout_resistance > 0.0 and stretch <= 0.0 and rate > 0.0:
            return self.payout_resistance
        return _tension(stretch, self.elastic(stretch), self.damping, rate)

    @property
    def stiffest(self) -> float:
        """The largest tangent stiffness (N/m): K, or the table's steepest slope / L0 (its last slope continues)."""
        return self.stiffness if self.table is None else max(self.table.slopes()) / self.free_length

    def energy(self, stretch: float) -> float:
        """Elastic energy (J) stored at ``stretch`` > 0 (m): the integral of T_el over the stretch."""
        if self.table is None:
            return 0.5 * (self.stiffness * stretch) * stretch
        return self.free_length * self.table.energy(stretch / self.free_length)

    def expression(self, stretch, rate, ops: Arithmetic = ARRAYS, stiffness=None, damping=None):
        """The law in the arithmetic ``ops`` (the Exudyn symbolic form: ``engine.full_model``; numpy arrays): T = max(0,
        T_el + C rate) where taut, R where paying out, 0 elsewhere, T_el = K stretch or the table in its hinge form
        (``LoadElongation.hinges``: a sum of ramps, no search) of the strain ``ops.strain``. ``stiffness`` and
        ``damping`` (N/m, N s/m) may be given as values of that arithmetic (the engine's connector parameters);
        default this line's."""
        stiffness = self.stiffness if stiffness is None else stiffness
        damping = self.damping if damping is None else damping
        if self.table is None:
            elastic = stiffness * stretch
        else:
            strain = ops.strain(stretch, self.free_length)
            elastic = ops.zero()
            for corner, change in self.table.hinges():
                elastic = elastic + change * ops.maximum(ops.zero(), strain - corner)
        taut = ops.where_taut(stretch, ops.maximum(ops.zero(), elastic + damping * rate))
        if self.payout_resistance > 0.0:   # (only then: every other law's expression stays as it was)
            return taut + ops.where_paying_out(stretch, rate, self.payout_resistance)
        return taut


_elastic, _slope, _tension = python_form(line_elastic), python_form(line_slope), python_form(line_tension)
"""The law's kernels as Python, for ``LineLaw``'s calls from Python (a compiled call costs more than the sum)."""


def pack_lines(laws) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lines (LineLaw) as the compiled kernels take them: rows (n, 3) of L0 (m), K (N/m), C (N s/m), and the tables
    as ``pack_tables`` packs them (points, counts)."""
    laws = list(laws)
    constants = np.array([(law.free_length, law.stiffness, law.damping) for law in laws], float).reshape(-1, 3)
    return (constants, *pack_tables(law.table for law in laws))


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


def line_tensions(attach_position, attach_velocity, confluence_position, confluence_velocity, laws
                  ) -> tuple[tuple, tuple]:
    """Tensions T (N) and unit vectors n (confluence -> attach point) of a system's lines (``laws``: LineLaw each)
    in plain floats (the per-stage form of ``line_states``): sequences of (x, y, z) in m and m/s."""
    wx, wy, wz = confluence_velocity
    tensions, directions = [], []
    for (length, nx, ny, nz), (vx, vy, vz), law in zip(line_geometry(attach_position, confluence_position),
                                                       attach_velocity, laws):
        directions.append((nx, ny, nz))
        tensions.append(law.tension(length - law.free_length, (vx - wx) * nx + (vy - wy) * ny + (vz - wz) * nz))
    return tuple(tensions), tuple(directions)


def tension_magnitude(length, length_rate, laws):
    """The line law over arrays (``LineLaw.expression`` with numpy): T (N) of the lines ``laws`` (the last axis)
    at lengths ``length`` (m) and rates ``length_rate`` (m/s), shape (..., n_lines); T = max(0, T_el + C dL/dt)
    where L > L0, 0 where the line is slack."""
    length = np.asarray(length, dtype=float)
    rate = np.broadcast_to(np.asarray(length_rate, dtype=float), length.shape)
    tension = np.zeros(length.shape)
    for j, law in enumerate(laws):
        tension[..., j] = law.expression(length[..., j] - law.free_length, rate[..., j])
    return tension


def line_states(attach_position, attach_velocity, confluence_position, confluence_velocity, laws) -> LineState:
    """Evaluate lines from their attach points to a confluence (Eqs. 1.6-1.7).

    Parameters
    ----------
    attach_position, attach_velocity : array_like, shape (..., n_lines, 3)
        Inertial position (m) and velocity (m/s) of each line's attach point.
    confluence_position, confluence_velocity : array_like, shape (..., 3)
        Inertial position (m) and velocity (m/s) of the confluence; broadcast against the lines.
    laws : sequence of LineLaw
        The lines (``case.model.Line.law``).

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
    tension = tension_magnitude(length, length_rate, laws)
    free = np.array([law.free_length for law in laws], float)
    return LineState(length=length, direction=direction, length_rate=length_rate, tension=tension,
                     taut=length > free)

"""SP's named memory: the arrays an SP confluence's compiled kernels read and write, each position named once here.

The kernels (``balance``, ``stepping``, ``canopy_kernels``) take plain float arrays (numba compiles them, and a
structured record would cost the per-stage call its speed); they index them with the integer constants below, which
numba folds in. Python reads and writes them only by name: ``Memory`` gives an SP confluence's memory array as named
views (``memory.position``, ``memory.v0``, ``memory.settings.mass`` ...) and ``Record`` its end-of-step record. No
module outside this package names a position (``tests/acceptance/test_architecture.py``).

Four layouts:

* **the line layout** (one row per line, ``LAYOUT_COLUMNS``): the attach point (``kinematics.POINT_COLUMNS``), then
  L0 (m), K (N/m), C (N s/m) and the number of points of its load-elongation table (0: linear);
* **the work array** (one row per line, ``STAGE_COLUMNS``): what a stage's solve writes of each line (``WORK_``);
* **the memory** (``MEMORY_ROWS`` rows of three floats): the confluence's state, the step's bookkeeping and its
  settings (``MEMORY_``, with the columns of the rows that hold three different things);
* **the end-of-step record** (after the stage's body states): what the outputs sample (``RECORD_``).
"""

from __future__ import annotations

import numpy as np

from ...physics.kinematics import POINT_COLUMNS

# -- the line layout ------------------------------------------------------------------------------------------------

LAYOUT_FREE_LENGTH, LAYOUT_STIFFNESS, LAYOUT_DAMPING, LAYOUT_TABLE = (POINT_COLUMNS, POINT_COLUMNS + 1,
                                                                      POINT_COLUMNS + 2, POINT_COLUMNS + 3)
"""The columns of a line's layout row after its attach point's: L0 (m), K (N/m), C (N s/m) and the number of points
of its load-elongation table (0: linear)."""


def line_layout(points: np.ndarray, laws) -> np.ndarray:
    """The line layout (one row per line) of attach points ``points`` (rows of ``kinematics.POINT_COLUMNS``) and
    lines ``laws`` (``physics.lines.LineLaw``)."""
    return np.column_stack([points, [law.free_length for law in laws], [law.stiffness for law in laws],
                            [law.damping for law in laws], [law.count for law in laws]])


def layout_damping(layout: np.ndarray) -> np.ndarray:
    """The damping column (N s/m) of a line layout, as a view (relaxing the lines writes it)."""
    return layout[:, LAYOUT_DAMPING]

# -- the work array (per line) --------------------------------------------------------------------------------------

STAGE_COLUMNS = 21
"""Columns of the per-line work array: tension (N), n (3), taut (1 or 0), attach position (3, m) and velocity (3,
m/s), the force on the body -T n (3, N), the solve's scratch (6), and the tension of the last end-of-step solve (N,
column END_TENSION: ``stepping.sp_end_of_step``; a later stage's solve leaves it)."""
(WORK_TENSION, WORK_DIRECTION, WORK_TAUT, WORK_ATTACH_POSITION, WORK_ATTACH_VELOCITY, WORK_FORCE,
 WORK_SCRATCH) = 0, 1, 4, 5, 8, 11, 14
"""Where each part of a work row starts (three columns each for n, the attach motion and the force; six of scratch:
the solve's geometry, ``balance._assemble``)."""
WORK_ELASTIC = WORK_SCRATCH + 5
"""The solve's elastic tension T_el of each line (N; the last of its scratch columns)."""
WORK_FRACTION = WORK_SCRATCH
"""A pair in series (and a reduced canopy): the confluence's fraction of the way along AB, in line 0's row (-)."""
END_TENSION = 20
BRIDLE_ROW, RISER_ROW = 0, 1
"""A reduced canopy's rows in the work array: the bridle (from the vehicle; its scratch holds the confluence's
fraction of AP) and the riser (whose end is P)."""

# -- the memory (rows of three floats) ------------------------------------------------------------------------------

(MEMORY_POSITION, MEMORY_STAGE_VELOCITIES, MEMORY_V0, MEMORY_SETTINGS, MEMORY_ORDER, MEMORY_GRAVITY, MEMORY_TIMES,
 MEMORY_NEWER, MEMORY_OLDER, MEMORY_ACCELERATION, MEMORY_CLOCK, MEMORY_DUE, MEMORY_RUN, MEMORY_END,
 MEMORY_END_SOLVE, MEMORY_CANOPY, MEMORY_AIR, MEMORY_NORMAL, MEMORY_FILL) = (0, 1, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14,
                                                                             15, 16, 17, 18, 19, 20, 24)
MEMORY_ROWS = 25
"""Rows (of 3 floats) of an SP confluence's memory:

0 the confluence position q_n at the start of the step under way (m); 1-4 the stage velocities k_1 .. k_4 of the
step (m/s; row 1 is also the end-of-step solve's velocity); 5 v0 (m/s); 6 (m_c in kg, kappa_max, 1 for the force
slack rule else 0); 7 (order, gravity mu in m^3/s^2, number of recorded end-of-step velocities, at most 2); 8 the
planet centre (m; mu > 0) or the uniform gravity (m/s^2; mu = 0); 9 (times of the newer and the older recorded
end-of-step velocities in s, -); 10 and 11 those velocities (m/s); 12 the acceleration carried from the previous
phase (m/s^2).

The step's bookkeeping, kept here so that a stage's call from Python passes nothing but the time
(``stepping.sp_step_stage``): 13 (the index of the coming RK stage, 0-4; t_n, the start of the step under way in s;
its step h in s); 14 (1 when the end-of-step work of the last step is due, else 0; that step's end time in s; 1 when
it completed its four stages); 15 (the run's step as the engine takes it in s, 0 for adaptive steps; the phase start
in s; -); 16 and 17 the last end-of-step solve's (vx, vy, vz) in m/s and (C_c in N s/m, kappa, lines counted taut).

A reduced canopy (``canopy_kernels``; the confluence's state is then its drag point P at the riser's end): 18 (its
state row in the stage's states + 1, 0 without a reduced canopy; its drag coefficient 1/2 rho S C_A in kg/m; the
distance from P back to its centre of mass in m); 19 the air's velocity at it (m/s). The air is the one at the start
of the step, set before each step (``reduced_canopy.ReducedCanopy.update_air``).

20-23 normal gravity (``gravity.NORMAL_COLUMNS``: planet centre, spin axis, a and b, gamma_e, k, m, the frame's
rotation rate), all 0 with spherical or uniform gravity (rows 7 and 8 then): ``stepping.confluence_gravity``.

24 a reduced canopy's opening over the step under way (``reduced_canopy.ReducedCanopy.fill``): (the rate of its drag
coefficient in kg/m/s, the time in s at which the coefficient of row 18 holds, -): a stage at time t takes
1/2 rho S C_A f = row 18's + rate (t - time), the secant of the opening's drag-area fraction f over the step; all 0
for a canopy that is open (its drag then row 18's to the bit)."""

# The columns of the memory rows that hold three different things (the other rows hold x, y, z):
SETTING_MASS, SETTING_KAPPA, SETTING_FORCE_SLACK = 0, 1, 2      # MEMORY_SETTINGS: m_c (kg), kappa_max, force rule
ORDER_FIRST, ORDER_MU, ORDER_RECORDED = 0, 1, 2                 # MEMORY_ORDER: order 1?, mu, end velocities kept
TIME_NEWER, TIME_OLDER = 0, 1                                   # MEMORY_TIMES: their times (s)
CLOCK_STAGE, CLOCK_START, CLOCK_STEP = 0, 1, 2                  # MEMORY_CLOCK: coming stage, t_n (s), h (s)
DUE_PENDING, DUE_TIME, DUE_COMPLETED = 0, 1, 2                  # MEMORY_DUE: work due?, its step's end (s), 4 stages?
RUN_STEP, RUN_START = 0, 1                                      # MEMORY_RUN: the engine's step (s), the phase start
SOLVE_DAMPING, SOLVE_KAPPA, SOLVE_TAUT = 0, 1, 2                # MEMORY_END_SOLVE: C_c (N s/m), kappa, taut lines
CANOPY_STATE_ROW, CANOPY_DRAG, CANOPY_OFFSET = 0, 1, 2          # MEMORY_CANOPY: row + 1, 1/2 rho S C_A, P to CG (m)
FILL_RATE, FILL_TIME = 0, 1                                     # MEMORY_FILL: drag's rate (kg/m/s), its time (s)

# A solve's tuple (``stepping.sp_rk_stage``): (vx, vy, vz, C_c, kappa, lines counted taut)
SOLVED_VELOCITY, SOLVED_DAMPING, SOLVED_KAPPA, SOLVED_TAUT = 0, 3, 4, 5

# -- the end-of-step record -----------------------------------------------------------------------------------------

# after the body states: the confluence position (3), the solve's velocity (3), C_c, kappa and taut lines, then one
# tension per line
RECORD_POSITION, RECORD_VELOCITY, RECORD_DAMPING, RECORD_KAPPA, RECORD_TAUT, RECORD_TENSIONS = 0, 3, 6, 7, 8, 9


# -- the same by name, for Python ----------------------------------------------------------------------------------

class _Row:
    """A memory row (3 floats) as a named view: reading gives the row itself (a view), writing sets its values."""

    def __init__(self, row: int, rows: int = 1):
        self.rows = slice(row, row + rows) if rows > 1 else row
        self.single = rows == 1

    def __get__(self, memory, owner=None):
        return self if memory is None else memory.array[self.rows]

    def __set__(self, memory, value):
        if self.single:   # three floats into one row, as numpy takes them (it broadcasts no further): per step
            memory.array[self.rows] = value
        else:
            memory.array[self.rows] = np.reshape(value, memory.array[self.rows].shape)


class _Cell:
    """One float of a memory row, by name."""

    def __init__(self, row: int, column: int):
        self.row, self.column = row, column

    def __get__(self, memory, owner=None):
        return self if memory is None else float(memory.array[self.row, self.column])

    def __set__(self, memory, value):
        memory.array[self.row, self.column] = value


class Memory:
    """An SP confluence's memory (``MEMORY_ROWS`` rows of three floats, ``array``: what the kernels take) by name.

    Rows: ``position`` (m), ``v0`` (m/s), ``acceleration`` carried from the previous phase (m/s^2), ``gravity``
    (the planet centre in m, or the uniform gravity in m/s^2), ``normal_gravity`` (four rows), ``newer`` and
    ``older`` recorded end-of-step velocities (m/s), ``end_velocity`` (m/s), ``air`` (m/s); ``settings``, ``order``,
    ``clock``, ``run``, ``times`` and ``canopy`` whole; and their cells: ``mass`` (kg), ``first_order``
    (1 or 0), ``recorded``, ``newer_time`` and ``older_time`` (s), ``due_time`` (s), ``run_step`` (s),
    ``canopy_drag`` (kg/m), ``fill_rate`` (kg/m/s), ``fill_time`` (s), ``end_damping`` (N s/m), ``end_kappa``,
    ``end_taut``."""

    position = _Row(MEMORY_POSITION)
    v0 = _Row(MEMORY_V0)
    settings = _Row(MEMORY_SETTINGS)
    order = _Row(MEMORY_ORDER)
    gravity = _Row(MEMORY_GRAVITY)
    times = _Row(MEMORY_TIMES)
    newer = _Row(MEMORY_NEWER)
    older = _Row(MEMORY_OLDER)
    acceleration = _Row(MEMORY_ACCELERATION)
    clock = _Row(MEMORY_CLOCK)
    run = _Row(MEMORY_RUN)
    end_velocity = _Row(MEMORY_END)
    canopy = _Row(MEMORY_CANOPY)
    air = _Row(MEMORY_AIR)
    normal_gravity = _Row(MEMORY_NORMAL, 4)
    fill = _Row(MEMORY_FILL)
    mass = _Cell(MEMORY_SETTINGS, SETTING_MASS)
    first_order = _Cell(MEMORY_ORDER, ORDER_FIRST)
    recorded = _Cell(MEMORY_ORDER, ORDER_RECORDED)
    newer_time = _Cell(MEMORY_TIMES, TIME_NEWER)
    older_time = _Cell(MEMORY_TIMES, TIME_OLDER)
    due_time = _Cell(MEMORY_DUE, DUE_TIME)
    run_step = _Cell(MEMORY_RUN, RUN_STEP)
    canopy_drag = _Cell(MEMORY_CANOPY, CANOPY_DRAG)
    fill_rate = _Cell(MEMORY_FILL, FILL_RATE)
    fill_time = _Cell(MEMORY_FILL, FILL_TIME)
    end_damping = _Cell(MEMORY_END_SOLVE, SOLVE_DAMPING)
    end_kappa = _Cell(MEMORY_END_SOLVE, SOLVE_KAPPA)
    end_taut = _Cell(MEMORY_END_SOLVE, SOLVE_TAUT)

    def __init__(self):
        self.array = np.zeros((MEMORY_ROWS, 3))


class Work:
    """The per-line work array (``STAGE_COLUMNS`` columns, ``array``) by name: ``tensions`` (N, the stage's),
    ``end_tensions`` (N, the last end-of-step solve's), ``elastic`` (T_el, N), ``taut`` (1 or 0), ``directions`` (n),
    ``attach_positions`` (m), ``attach_velocities`` (m/s), ``fraction`` (-: a pair in series, the confluence's share
    of AB from line 0)."""

    def __init__(self, lines: int):
        self.array = np.zeros((lines, STAGE_COLUMNS))

    @property
    def tensions(self) -> np.ndarray:
        return self.array[:, WORK_TENSION]

    @property
    def end_tensions(self) -> np.ndarray:
        return self.array[:, END_TENSION]

    @property
    def elastic(self) -> np.ndarray:
        return self.array[:, WORK_ELASTIC]

    @property
    def taut(self) -> np.ndarray:
        return self.array[:, WORK_TAUT]

    @property
    def directions(self) -> np.ndarray:
        return self.array[:, WORK_DIRECTION:WORK_DIRECTION + 3]

    @property
    def attach_positions(self) -> np.ndarray:
        return self.array[:, WORK_ATTACH_POSITION:WORK_ATTACH_POSITION + 3]

    @property
    def attach_velocities(self) -> np.ndarray:
        return self.array[:, WORK_ATTACH_VELOCITY:WORK_ATTACH_VELOCITY + 3]

    @property
    def fraction(self) -> float:
        return float(self.array[0, WORK_FRACTION])


class Record:
    """Where each output is in the end-of-step record of a stage with ``state_size`` floats of body states: slices
    and indices for splitting sampled records (rows) into channels."""

    def __init__(self, state_size: int, lines: int):
        first = state_size
        self.position = slice(first + RECORD_POSITION, first + RECORD_POSITION + 3)
        self.velocity = slice(first + RECORD_VELOCITY, first + RECORD_VELOCITY + 3)
        self.damping, self.kappa, self.taut = first + RECORD_DAMPING, first + RECORD_KAPPA, first + RECORD_TAUT
        self.tensions = [first + RECORD_TENSIONS + i for i in range(lines)]
        self.size = first + RECORD_TENSIONS + lines

"""SP's confluence integrated in step with the engine's RK4 stages (``docs/architecture.md``, "One crossing per solver
stage"): the stage count, the RK4 update and the end-of-step work on the confluence's memory (``memory``), and the
one-call stage kernels of a model whose only confluence is SP's. The SP solve itself, one stage's lines and forces,
is ``balance.sp_stage``; a reduced canopy's, ``canopy_kernels.canopy_stage``."""

from __future__ import annotations

from ...physics.aerodynamics import (
    HEADER_BODY_COUNT,
    STAGE_AERODYNAMICS_FAILED,
    STAGE_SETTLED,
    WORK_STATUS,
    aerodynamics_stage,
)
from ...physics.compiled import kernel
from ...physics.gravity import normal_gravity
from ...physics.kinematics import add_gravity_forces, add_normal_gravity_forces, body_states
from ...physics.planet import gravity_acceleration
from ...physics.rk4 import RK4_STAGE_FRACTIONS, RK4_WEIGHTS
from .balance import sp_stage
from .canopy_kernels import canopy_stage
from .memory import (
    CANOPY_DRAG,
    CANOPY_OFFSET,
    CANOPY_STATE_ROW,
    CLOCK_STAGE,
    CLOCK_START,
    CLOCK_STEP,
    DUE_COMPLETED,
    DUE_PENDING,
    DUE_TIME,
    END_TENSION,
    FILL_RATE,
    FILL_TIME,
    MEMORY_ACCELERATION,
    MEMORY_AIR,
    MEMORY_CANOPY,
    MEMORY_CLOCK,
    MEMORY_DUE,
    MEMORY_END,
    MEMORY_END_SOLVE,
    MEMORY_FILL,
    MEMORY_GRAVITY,
    MEMORY_NEWER,
    MEMORY_NORMAL,
    MEMORY_OLDER,
    MEMORY_ORDER,
    MEMORY_POSITION,
    MEMORY_RUN,
    MEMORY_SETTINGS,
    MEMORY_STAGE_VELOCITIES,
    MEMORY_TIMES,
    MEMORY_V0,
    ORDER_FIRST,
    ORDER_MU,
    ORDER_RECORDED,
    RECORD_DAMPING,
    RECORD_KAPPA,
    RECORD_POSITION,
    RECORD_TAUT,
    RECORD_TENSIONS,
    RECORD_VELOCITY,
    RUN_START,
    RUN_STEP,
    SETTING_FORCE_SLACK,
    SETTING_KAPPA,
    SETTING_MASS,
    SOLVE_DAMPING,
    SOLVE_KAPPA,
    SOLVE_TAUT,
    SOLVED_DAMPING,
    SOLVED_TAUT,
    TIME_NEWER,
    TIME_OLDER,
    WORK_ATTACH_POSITION,
    WORK_FRACTION,
    WORK_TENSION,
)


@kernel
def confluence_gravity(memory, x, y, z):
    """The gravity (m/s^2) at the start-frame point (x, y, z) (m) of the planet the memory holds: normal gravity
    (``gravity.normal_gravity``) when its rows hold a semi-axis a > 0, else ``planet.gravity_acceleration`` with
    rows 7 and 8 (the same call as before normal gravity existed: the same bits)."""
    n = MEMORY_NORMAL
    if memory[n + 2, 0] > 0.0:
        return normal_gravity(memory[n, 0], memory[n, 1], memory[n, 2], memory[n + 1, 0], memory[n + 1, 1],
                              memory[n + 1, 2], memory[n + 2, 0], memory[n + 2, 1], memory[n + 2, 2],
                              memory[n + 3, 0], memory[n + 3, 1], memory[n + 3, 2], x, y, z)
    g = MEMORY_GRAVITY
    return gravity_acceleration(memory[MEMORY_ORDER, ORDER_MU], memory[g, 0], memory[g, 1], memory[g, 2], x, y, z)


@kernel
def add_body_gravity(bodies, states, memory, generalized):
    """The gravity of the bodies whose layout rows carry their mass, from the planet the memory holds (as
    ``confluence_gravity``): ``kinematics.add_normal_gravity_forces`` or ``kinematics.add_gravity_forces`` (the
    same call as before normal gravity existed: the same bits)."""
    n = MEMORY_NORMAL
    if memory[n + 2, 0] > 0.0:
        add_normal_gravity_forces(bodies, states, memory[n, 0], memory[n, 1], memory[n, 2], memory[n + 1, 0],
                                  memory[n + 1, 1], memory[n + 1, 2], memory[n + 2, 0], memory[n + 2, 1],
                                  memory[n + 2, 2], memory[n + 3, 0], memory[n + 3, 1], memory[n + 3, 2], generalized)
        return
    g = MEMORY_GRAVITY
    add_gravity_forces(bodies, states, memory[MEMORY_ORDER, ORDER_MU], memory[g, 0], memory[g, 1], memory[g, 2],
                       generalized)


@kernel
def _mass_term(memory, t, qx, qy, qz):
    """The order-1 mass term (``MassTerm``) as (rate, b0 x, y, z): the reference velocity is the latest recorded
    end-of-step velocity from before ``t``; with none, the carried acceleration enters as a force."""
    if memory[MEMORY_ORDER, ORDER_FIRST] < 0.5:
        return 0.0, 0.0, 0.0, 0.0
    m = memory[MEMORY_SETTINGS, SETTING_MASS]
    gx, gy, gz = confluence_gravity(memory, qx, qy, qz)
    for j in range(int(memory[MEMORY_ORDER, ORDER_RECORDED])):   # the newer first
        time = memory[MEMORY_TIMES, TIME_NEWER + j]
        if time < t:
            rate, row = m / (t - time), MEMORY_NEWER + j
            return rate, m * gx + rate * memory[row, 0], m * gy + rate * memory[row, 1], m * gz + rate * memory[row, 2]
    a = MEMORY_ACCELERATION
    return 0.0, m * (gx - memory[a, 0]), m * (gy - memory[a, 1]), m * (gz - memory[a, 2])


@kernel
def sp_rk_stage(states, layout, tables, work, part, memory, t, index, h):
    """SP at RK4 stage ``index`` (0-3) of a step of ``h`` (s) at time ``t`` (s): the stage's confluence position
    from ``memory`` (``MEMORY_ROWS``), the order-1 mass term when the memory asks for it, ``sp_stage``, and the
    stage velocity into memory row index + 1. Returns (vx, vy, vz, C_c, kappa, lines counted taut)."""
    qx, qy, qz = memory[MEMORY_POSITION, 0], memory[MEMORY_POSITION, 1], memory[MEMORY_POSITION, 2]
    if index > 0:
        step = h * RK4_STAGE_FRACTIONS[index]
        k = MEMORY_STAGE_VELOCITIES + index - 1   # k_(index), the previous stage's velocity
        qx, qy, qz = qx + step * memory[k, 0], qy + step * memory[k, 1], qz + step * memory[k, 2]
    canopy = MEMORY_CANOPY
    if memory[canopy, CANOPY_STATE_ROW] > 0.5:   # a reduced canopy: the state is its drag point, solved with its drag
        rate, bx, by, bz = _mass_term(memory, t, qx, qy, qz)
        air, v0 = MEMORY_AIR, MEMORY_V0
        fill = MEMORY_FILL   # an opening: the drag's secant over the step (0 once open: row 18's to the bit)
        drag = max(memory[canopy, CANOPY_DRAG] + memory[fill, FILL_RATE] * (t - memory[fill, FILL_TIME]), 0.0)
        vx, vy, vz, c_c, kappa, taut = canopy_stage(
            states, layout, tables, work, part, qx, qy, qz, memory[v0, 0], memory[v0, 1], memory[v0, 2],
            drag, memory[air, 0], memory[air, 1], memory[air, 2], rate, bx, by, bz,
            int(memory[canopy, CANOPY_STATE_ROW]) - 1, memory[canopy, CANOPY_OFFSET])
        k = MEMORY_STAGE_VELOCITIES + index
        memory[k, 0], memory[k, 1], memory[k, 2] = vx, vy, vz
        return vx, vy, vz, c_c, kappa, taut
    if layout.shape[0] == 2:   # a pair in series: no mass term in a solve; order 1 keeps the confluence's weight
        rate, bx, by, bz = 0.0, 0.0, 0.0, 0.0
        if memory[MEMORY_ORDER, ORDER_FIRST] > 0.5:
            m = memory[MEMORY_SETTINGS, SETTING_MASS]
            gx, gy, gz = confluence_gravity(memory, qx, qy, qz)
            bx, by, bz = m * gx, m * gy, m * gz
    else:
        rate, bx, by, bz = _mass_term(memory, t, qx, qy, qz)
    v0, settings = MEMORY_V0, MEMORY_SETTINGS
    vx, vy, vz, c_c, kappa, taut = sp_stage(states, layout, tables, work, part, qx, qy, qz, memory[v0, 0],
                                            memory[v0, 1], memory[v0, 2], memory[settings, SETTING_KAPPA],
                                            memory[settings, SETTING_FORCE_SLACK],
                                            rate, bx, by, bz)
    k = MEMORY_STAGE_VELOCITIES + index
    memory[k, 0], memory[k, 1], memory[k, 2] = vx, vy, vz
    return vx, vy, vz, c_c, kappa, taut


@kernel
def rk4_update(memory, h):
    """Complete an RK4 step of ``h`` (s): q_(n+1) = q_n + h (k_1 + 2 k_2 + 2 k_3 + k_4) / 6 into memory row 0, added
    term by term as (h b_j) k_j in Exudyn's own order, so that the result is the engine's to the last bit."""
    for j in range(4):
        factor = h * RK4_WEIGHTS[j]
        for i in range(3):
            memory[MEMORY_POSITION, i] += factor * memory[MEMORY_STAGE_VELOCITIES + j, i]


@kernel
def sp_end_of_step(states, layout, tables, work, part, memory, t, h, completed, start_time, record):
    """The SP work after a step of ``h`` (s) ending at ``t`` (s): the RK4 update when the step ``completed`` its
    four stages, the solve at the end-of-step state (its velocity is the next step's k_1), then v0 for the next step
    (after ``start_time``, the phase start: before it the case's initial velocity stands) and, for order 1, the
    velocity recorded for the backward difference; the outputs into ``record`` (``_record``). Returns
    ``sp_rk_stage``'s (vx, vy, vz, C_c, kappa, taut)."""
    if completed:
        rk4_update(memory, h)
    vx, vy, vz, c_c, kappa, taut = sp_rk_stage(states, layout, tables, work, part, memory, t, 0, 0.0)
    work[:, END_TENSION] = work[:, WORK_TENSION]
    if layout.shape[0] == 2 and memory[MEMORY_CANOPY, CANOPY_STATE_ROW] < 0.5:   # a pair in series: the confluence
        # is where the solve put it on AB, not a state
        fraction, a = work[0, WORK_FRACTION], WORK_ATTACH_POSITION
        for i in range(3):
            memory[MEMORY_POSITION, i] = work[0, a + i] + fraction * (work[1, a + i] - work[0, a + i])
    if t > start_time:
        memory[MEMORY_V0, 0], memory[MEMORY_V0, 1], memory[MEMORY_V0, 2] = vx, vy, vz
    count = int(memory[MEMORY_ORDER, ORDER_RECORDED])
    if memory[MEMORY_ORDER, ORDER_FIRST] > 0.5 and (count == 0 or t > memory[MEMORY_TIMES, TIME_NEWER]):
        memory[MEMORY_TIMES, TIME_OLDER] = memory[MEMORY_TIMES, TIME_NEWER]   # the newer becomes the older
        for i in range(3):
            memory[MEMORY_OLDER, i] = memory[MEMORY_NEWER, i]
        memory[MEMORY_TIMES, TIME_NEWER] = t
        memory[MEMORY_NEWER, 0], memory[MEMORY_NEWER, 1], memory[MEMORY_NEWER, 2] = vx, vy, vz
        memory[MEMORY_ORDER, ORDER_RECORDED] = min(count + 1, 2)
    _record(states, memory, work, vx, vy, vz, c_c, kappa, taut, record)
    return vx, vy, vz, c_c, kappa, taut


@kernel
def _record(states, memory, work, vx, vy, vz, c_c, kappa, taut, record):
    """An SP confluence's outputs at the end of a step, as one array: the stage's body states (rows of
    ``kinematics.STATE_COLUMNS``, flattened), the confluence position (3, m), the end-of-step solve's (vx, vy, vz,
    C_c, kappa, taut), and the end-of-step tensions (one per line, N)."""
    k = 0
    for row in range(states.shape[0]):
        for column in range(states.shape[1]):
            record[k] = states[row, column]
            k += 1
    p, v = k + RECORD_POSITION, k + RECORD_VELOCITY
    if work.shape[0] == 2:   # two lines in series (a reduced canopy's too): on AB where the solve put it
        fraction, a = work[0, WORK_FRACTION], WORK_ATTACH_POSITION
        for i in range(3):
            record[p + i] = work[0, a + i] + fraction * (work[1, a + i] - work[0, a + i])
    else:
        for i in range(3):
            record[p + i] = memory[MEMORY_POSITION, i]
    record[v], record[v + 1], record[v + 2] = vx, vy, vz
    record[k + RECORD_DAMPING], record[k + RECORD_KAPPA], record[k + RECORD_TAUT] = c_c, kappa, taut
    for i in range(work.shape[0]):
        record[k + RECORD_TENSIONS + i] = work[i, END_TENSION]


@kernel
def sp_rk_stage_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, t, index, h, solve,
                            generalized, aerodynamics, field, aerodynamic_work):
    """``kinematics.body_states`` from the stage's node coordinates, then (when ``solve``) ``sp_rk_stage``, the
    lines' generalized forces (``part``, from this solve or the last) copied into ``generalized``, and the bodies'
    aerodynamic loads added (``aerodynamics.aerodynamics_stage`` on ``aerodynamics``, ``field`` and
    ``aerodynamic_work``, when there are any): a model with one SP confluence does a stage's kernel work in one
    call. Returns nothing (the stage velocity goes to memory row index + 1)."""
    body_states(q, q_t, bodies, states)
    if solve:
        sp_rk_stage(states, layout, tables, work, part, memory, t, index, h)
    generalized[:] = part
    if aerodynamics[HEADER_BODY_COUNT] > 0.0:
        aerodynamics_stage(t, states, aerodynamics, field, aerodynamic_work, generalized)


@kernel
def holds_after_v0_update(damping, taut_count):
    """Whether an end-of-step solve that returned C_c = ``damping`` (N s/m) with ``taut_count`` lines taut is also
    the next step's first-stage solve: v0 enters Eq. 3.10 only through C_c (and the all-slack case), so without
    them the v0 update between the two does not change it (order 1's reference velocity is the same for both calls:
    see ``sp_rk_stage``)."""
    return damping == 0.0 and taut_count > 0


@kernel
def sp_end_of_step_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, t, h, completed,
                               start_time, record):
    """``kinematics.body_states`` from the end-of-step node coordinates, then ``sp_end_of_step``: a model with one
    SP confluence does its post-step kernel work in one call. Returns ``sp_end_of_step``'s tuple."""
    body_states(q, q_t, bodies, states)
    return sp_end_of_step(states, layout, tables, work, part, memory, t, h, completed, start_time, record)


@kernel
def sp_first_stage_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, t_end, h, completed,
                               start_time, record, t, generalized, aerodynamics, field, aerodynamic_work):
    """The end-of-step work of the step that ended at ``t_end`` (s), done at the next step's first RK stage (time
    ``t``, s; the same state): ``sp_end_of_step_with_bodies``, then that stage's solve with the updated v0 unless
    the end-of-step solve holds for it (``holds_after_v0_update``). The same arithmetic, in the same order, as the
    two calls it replaces; the lines' generalized forces and the aerodynamic loads into ``generalized`` as
    ``sp_rk_stage_with_bodies``. Returns ``sp_end_of_step``'s tuple."""
    end = sp_end_of_step_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, t_end, h,
                                     completed, start_time, record)
    if not holds_after_v0_update(end[SOLVED_DAMPING], end[SOLVED_TAUT]):
        sp_rk_stage(states, layout, tables, work, part, memory, t, 0, h)
    generalized[:] = part
    if aerodynamics[HEADER_BODY_COUNT] > 0.0:
        aerodynamics_stage(t, states, aerodynamics, field, aerodynamic_work, generalized)
    return end


@kernel
def count_stage(memory, t):
    """Count the RK stage at time ``t`` (s) in ``memory``'s step bookkeeping (rows MEMORY_CLOCK, MEMORY_RUN) and
    return (its index 0-4, whether it needs a solve). The second stage (t_n + h/2) sets the step h: the run's step
    when the span 2 (t - t_n) is within 1e-6 of it, else the span (a short last step). The first stage's state is
    the end-of-step state already solved: that solve stands when it holds after the v0 update
    (``holds_after_v0_update``); a fifth call or more solves nothing."""
    index = int(memory[MEMORY_CLOCK, CLOCK_STAGE])
    memory[MEMORY_CLOCK, CLOCK_STAGE] = index + 1
    if index == 1:
        span = 2.0 * (t - memory[MEMORY_CLOCK, CLOCK_START])
        step = memory[MEMORY_RUN, RUN_STEP]
        memory[MEMORY_CLOCK, CLOCK_STEP] = step if step > 0.0 and abs(span - step) <= 1e-6 * step else span
    if index == 0:
        solve = MEMORY_END_SOLVE
        return index, not holds_after_v0_update(memory[solve, SOLVE_DAMPING], memory[solve, SOLVE_TAUT])
    return index, index < 4


@kernel
def step_done(memory, t):
    """After a step ending at ``t`` (s): the step's end-of-step work becomes due (MEMORY_DUE) and, when the step
    completed its four stages, t is the next step's start; the stage count starts again."""
    completed = memory[MEMORY_CLOCK, CLOCK_STAGE] == 4.0
    if completed:
        memory[MEMORY_CLOCK, CLOCK_START] = t
    memory[MEMORY_CLOCK, CLOCK_STAGE] = 0.0
    memory[MEMORY_DUE, DUE_PENDING], memory[MEMORY_DUE, DUE_TIME] = 1.0, t
    memory[MEMORY_DUE, DUE_COMPLETED] = 1.0 if completed else 0.0


@kernel
def _keep_end(memory, vx, vy, vz, c_c, kappa, taut):
    """Keep the end-of-step solve (MEMORY_END, MEMORY_END_SOLVE); the due work is done."""
    memory[MEMORY_END, 0], memory[MEMORY_END, 1], memory[MEMORY_END, 2] = vx, vy, vz
    solve = MEMORY_END_SOLVE
    memory[solve, SOLVE_DAMPING], memory[solve, SOLVE_KAPPA], memory[solve, SOLVE_TAUT] = c_c, kappa, taut
    memory[MEMORY_DUE, DUE_PENDING] = 0.0


@kernel
def sp_step_stage(states, layout, tables, work, part, memory, t):
    """An RK stage at ``t`` (s) with the step's bookkeeping in ``memory`` (``count_stage``), then ``sp_rk_stage``
    when it needs a solve (the body states already set)."""
    index, solve = count_stage(memory, t)
    if solve:
        sp_rk_stage(states, layout, tables, work, part, memory, t, index, memory[MEMORY_CLOCK, CLOCK_STEP])


@kernel
def sp_settle(states, layout, tables, work, part, memory, record):
    """The due end-of-step work (``sp_end_of_step`` with the bookkeeping's time, step and completion), the body
    states already set at the end of the step; the solve kept in memory."""
    due = MEMORY_DUE
    vx, vy, vz, c_c, kappa, taut = sp_end_of_step(states, layout, tables, work, part, memory, memory[due, DUE_TIME],
                                                  memory[MEMORY_CLOCK, CLOCK_STEP], memory[due, DUE_COMPLETED] > 0.5,
                                                  memory[MEMORY_RUN, RUN_START], record)
    _keep_end(memory, vx, vy, vz, c_c, kappa, taut)


@kernel
def sp_settle_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, record):
    """``kinematics.body_states`` from the end-of-step node coordinates, then ``sp_settle``."""
    body_states(q, q_t, bodies, states)
    sp_settle(states, layout, tables, work, part, memory, record)


@kernel
def sp_step_stage_with_bodies(q, q_t, t, bodies, states, layout, tables, work, part, memory, record, generalized,
                              aerodynamics, field, aerodynamic_work):
    """A stage of a model whose only confluence is this one, in one call: the body states from the stage's node
    coordinates, the SP solve, the lines' generalized forces into ``generalized`` and the bodies' aerodynamic loads
    added (as ``sp_rk_stage_with_bodies``). At a step's first stage with the last step's end-of-step work due, that
    work first (``sp_first_stage_with_bodies``). Last, the gravity of the bodies whose layout rows carry their mass
    (``add_body_gravity``), added after everything else as the engine's gravity connectors would add
    it. Returns the sum of its flags: STAGE_SETTLED when it did the end-of-step work, STAGE_AERODYNAMICS_FAILED when
    the aerodynamics reported a problem and added nothing (their status in ``aerodynamic_work``; the gravity is then
    left to the caller too)."""
    done = 0.0
    if memory[MEMORY_CLOCK, CLOCK_STAGE] == 0.0 and memory[MEMORY_DUE, DUE_PENDING] > 0.5:
        memory[MEMORY_CLOCK, CLOCK_STAGE] = 1.0
        due = MEMORY_DUE
        vx, vy, vz, c_c, kappa, taut = sp_first_stage_with_bodies(
            q, q_t, bodies, states, layout, tables, work, part, memory, memory[due, DUE_TIME],
            memory[MEMORY_CLOCK, CLOCK_STEP], memory[due, DUE_COMPLETED] > 0.5, memory[MEMORY_RUN, RUN_START], record,
            t, generalized, aerodynamics, field,
            aerodynamic_work)
        _keep_end(memory, vx, vy, vz, c_c, kappa, taut)
        done = STAGE_SETTLED
    else:
        index, solve = count_stage(memory, t)
        sp_rk_stage_with_bodies(q, q_t, bodies, states, layout, tables, work, part, memory, t, index,
                                memory[MEMORY_CLOCK, CLOCK_STEP], solve, generalized, aerodynamics, field,
                                aerodynamic_work)
    if aerodynamic_work[WORK_STATUS] != 0.0:   # the aerodynamics added nothing: the caller adds them, then the gravity
        return done + STAGE_AERODYNAMICS_FAILED
    add_body_gravity(bodies, states, memory, generalized)
    return done

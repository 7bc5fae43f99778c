"""Run Exudyn's integrators on a built model and collect the sampled histories.

* ``rk4``: Exudyn's explicit RK44 with Lie-group rotation updates (what the thesis used), at a fixed step or at
  adaptive steps (``control``: ``run.step_control``, which sets the engine's step after every step).
* ``implicit``: Exudyn's generalized-alpha (Lie group, Newton per step), fixed nominal step; Exudyn halves a step
  whose Newton iteration fails and the summary counts the steps actually taken.

A post-step hook runs the model's post-step work (SP's end-of-step solve, the RK4 step monitor, sensed triggers),
its stop conditions and the sampling of the outputs, and for an explicit run without pre-step work also counts the
steps and checks the state for NaN/inf, so that a diverging run stops early with the time (Exudyn itself reports
success in some diverged runs, so results are checked too); otherwise a pre-step hook does that counting and
checking, with the model's pre-step work. Exudyn calls the post-step hook once before the first step too.
"""

from __future__ import annotations

import functools
import gc
import math
import platform
import signal
import sys
import threading
import time as _time

import exudyn as exu
import numpy as np

from .. import _interrupt
from ..errors import Interrupted, PchuteError, SimulationError
from ..kernels.form import BUILDER as KERNEL_BUILDER
from ..physics.atmosphere import OutsideAtmosphereError
from ..physics.compiled import MODE as KERNEL_FORM
from ..registries.methods import INTEGRATORS
from .phase_model import Model
from .state import RawHistory

CHECK_EVERY = 200
"""Steps between NaN/inf checks of the state (a check costs about 2 us; a full-mass MER RK4 step about 70 us)."""


def solver_steps(start: float, end: float, step: float) -> int:
    """Steps Exudyn takes from ``start`` to ``end`` (s) for a requested ``step`` (s): it divides the span evenly, so
    its step is (end - start) / this number, within half a step of the requested one."""
    return max(1, int(round((end - start) / step)))


def _settings(integrator: str, step: float, start: float, end: float, spectral_radius: float,
              solution_file=None, output_step: float = 0.0):
    settings = exu.SimulationSettings()
    settings.solution.file.write = solution_file is not None   # Exudyn's own solution file, for its viewer
    if solution_file is not None:
        settings.solution.file.name = str(solution_file)
        settings.solution.file.writePeriod = output_step
    settings.solution.sensors.active = False  # outputs are sampled by the post-step hook, on an exact grid
    settings.show.statistics = False
    ti = settings.timeIntegration
    ti.startTime = start
    ti.endTime = end
    ti.numberOfSteps = solver_steps(start, end, step)
    ti.verboseMode = 0
    ti.automaticStepSize = False
    if INTEGRATORS[integrator].explicit:
        ti.explicit.useLieGroupIntegration = True
        ti.explicit.computeEndOfStepAccelerations = False  # saves a fifth right-hand side per step
        return settings, exu.DynamicSolverType.RK44
    ga = ti.generalizedAlpha
    ga.spectralRadius = spectral_radius
    ga.lieGroupAddTangentOperator = True
    ti.adaptiveStep = True  # only reduces a step whose Newton iteration fails
    ti.newton.useModifiedNewton = True
    return settings, exu.DynamicSolverType.GeneralizedAlpha


def _pre_step_function(model: Model, progress: dict, step: float):
    """Exudyn's pre-step hook: counts steps, runs the model's pre-step hooks, checks the state every CHECK_EVERY
    steps; returning False stops the solver (the failure is raised after it returns)."""
    hooks = list(model.pre_step_hooks)
    finite = _finite_state(model)

    def pre_step(mbs_, t):
        # t is the end time of the coming step; Exudyn's accumulated time can fall short of the end time by round-off
        # (1e-10 s after 30 000 steps of 1e-2 s) and it then adds a step of that length: not counted
        if t - progress["time"] > ROUND_OFF * step:
            progress["steps"] += 1
        progress["time"] = t
        if progress["interrupted"]:   # Ctrl-C: stop before this step (see _interrupt_flag)
            return False
        try:
            for hook in hooks:
                hook(mbs_, t)
        except Exception as exc:  # stop cleanly and raise it after the solver has returned
            model.record_failure(exc)
            return False
        if progress["steps"] % CHECK_EVERY == 0 and not finite():
            progress["bad"] = t
            return False
        return True
    return pre_step


def _finite_state(model: Model):
    """A check that the engine's state holds no NaN or infinity (about 2 us)."""
    get_coordinates = model.mbs.systemData.GetODE2Coordinates
    get_first_order = model.mbs.systemData.GetODE1Coordinates
    return lambda: math.isfinite(float(get_coordinates().sum())) and math.isfinite(float(get_first_order().sum()))


ROUND_OFF = 1e-6
"""Fraction of a step below which two times count as the same (Exudyn's accumulated time drifts by ~1e-10 s)."""


def grid_times(times, start: float, step: float, output_step: float) -> list:
    """The times (s) to record for samples taken at solver times ``times``: each step's own time start + n step, and
    the output grid's k output_step when it falls there, free of the solver's accumulated round-off and printed to 15
    significant digits (55.41, not 55.409999999997545); a time off both (an implicit run's shortened step) is kept.
    One pass over arrays (numpy's rint rounds half to even, as Python's round)."""
    t = np.asarray(times, float)
    exact = start + np.rint((t - start) / step) * step
    k_output = np.rint(exact / output_step) * output_step
    on_output = np.where(np.abs(exact - k_output) <= ROUND_OFF * step, k_output, exact)
    off_step = np.abs(t - exact) > ROUND_OFF * step
    printed = list(map(_printed, on_output.tolist()))   # map: no Python frame per sample (a fixed step's 6000)
    if not off_step.any():
        return printed
    return [time if off else grid for time, off, grid in zip(t.tolist(), off_step.tolist(), printed)]


@functools.lru_cache(maxsize=1 << 16)
def _printed(time: float) -> float:
    """``time`` to 15 significant digits (a study's runs share their sample times: formatted once per worker)."""
    return float(f"{time:.15g}")


REPORT_EVERY = 100
"""Steps between calls of a run's progress reporter (``integrate(report=...)``)."""


def _hook_parts(model: Model) -> tuple:
    """What a post-step hook works with: the channels' readers, the sample rows and times it fills, the model's
    post-step hooks and stop conditions, its post-step count and its state check."""
    reads = [reader for _, reader in _sampled_channels(model)[0]] + [group[1] for group in model.channel_groups]
    return (reads, [], [], list(model.post_step_hooks), list(model.stop_conditions), model.post_step_count,
            _finite_state(model))


class _FixedSteps:
    """A post-step hook's clock at a fixed step ``step`` (s): a sample at the first step on or past each output time
    (within half a step)."""

    def __init__(self, step: float):
        self.step = step

    def seen(self, t: float, last: float) -> bool:
        """Whether the call at ``t`` (s) repeats the one of the last sample (Exudyn calls once more at the end)."""
        return t <= last + 0.5 * self.step

    def count(self, progress: dict, t: float, taken: float, finite) -> bool:
        """The pre-step hook's bookkeeping (``_count_step``), with the coming step's end time (for messages)."""
        progress["time"] = t + self.step
        return _count_step(progress, t, taken > ROUND_OFF * self.step, finite)

    def margin(self, taken: float) -> float:
        return 0.5 * self.step

    def next_sample(self, t: float, output_step: float) -> float:
        return (round(t / output_step) + 1) * output_step

    def advance(self, mbs, t: float, progress: dict, counts: bool, end: float) -> None:
        """Nothing to choose: every step is the same."""


class _AdaptiveSteps:
    """A post-step hook's clock at steps ``control`` chooses (``run.step_control``): after the model's hooks it asks
    ``control.after_step(t)`` for the coming step and sets it as the engine's step (the engine's explicit solver takes
    the step size it holds at each step's start); a sample at the first step end on or past each output time, and at
    every step end where steps are longer than the output step."""

    def __init__(self, control):
        self.control, self.solver = control, None

    def seen(self, t: float, last: float) -> bool:
        return t <= last

    def count(self, progress: dict, t: float, taken: float, finite) -> bool:
        return _count_step(progress, t, taken > ROUND_OFF * self.control.rule.smallest, finite)

    def margin(self, taken: float) -> float:
        return 0.5 * taken

    def next_sample(self, t: float, output_step: float) -> float:
        return (math.floor(t / output_step + ROUND_OFF) + 1) * output_step

    def advance(self, mbs, t: float, progress: dict, counts: bool, end: float) -> None:
        coming = self.control.after_step(t)
        if self.solver is None:
            self.solver = mbs.sys["dynamicSolver"].it
        self.solver.currentStepSize = coming
        if counts:
            progress["time"] = min(t + coming, end)


def _post_step_function(model: Model, clock, end: float, output_step: float, progress: dict, report=None,
                        counts: bool = False):
    """Exudyn's post-step hook: runs the model's post-step hooks and stop conditions and samples every channel at
    the step ``clock`` says (``_FixedSteps``, ``_AdaptiveSteps``; Exudyn's own sensor clock anchors each write to the
    last one and drifts off the grid: seen 55.4102 s for 55.41 s at 2e-4 s), then lets the clock choose the coming
    step. Returns the hook and the sample times and rows it fills. ``counts``: it also does the pre-step hook's
    bookkeeping, for an explicit run without pre-step hooks, which then needs no pre-step call (the state after step
    n is the state before step n + 1): count the step, record the coming step's end time (for messages), stop on
    Ctrl-C, check the state every CHECK_EVERY steps."""
    reads, rows, times, post_hooks, stop_conditions, count, finite = _hook_parts(model)
    start = progress["time"]
    next_sample = [start]
    last = [None]   # solver time of the last sample (a fixed step's recorded time is its grid value)
    last_end = [start]   # the end of the last step (counts)

    def post_step(mbs_, t):
        if last[0] is not None and clock.seen(t, last[0]):  # Exudyn calls this once more after the last step
            return True
        count[0] += 1
        taken = t - last_end[0]
        last_end[0] = t
        if counts and not clock.count(progress, t, taken, finite):
            return False
        try:
            for hook in post_hooks:
                hook(mbs_, t)
            stop = False
            for condition in stop_conditions:
                stop = condition(t) or stop
            margin = clock.margin(taken)
            if stop or t >= next_sample[0] - margin or t >= end - margin:
                rows.append([read() for read in reads])
                times.append(t)   # solver time; a fixed step's grid_times after the run
                last[0] = t
                next_sample[0] = clock.next_sample(t, output_step)
            if stop:
                progress["stopped"] = t
                return False
            clock.advance(mbs_, t, progress, counts, end)
            if report is not None and count[0] % REPORT_EVERY == 0:
                report(t)
        except Exception as exc:  # stop cleanly and raise it after the solver has returned
            model.record_failure(exc)
            return False
        return True
    return post_step, times, rows


def _count_step(progress: dict, t: float, taken: bool, finite) -> bool:
    """The pre-step hook's bookkeeping done after a step ending at ``t`` (s) (``_post_step_function``'s ``counts``):
    count it when ``taken`` (not the start), and False to stop on Ctrl-C or a state gone NaN or infinite."""
    if taken:
        progress["steps"] += 1
    if progress["interrupted"]:
        return False
    if progress["steps"] % CHECK_EVERY == 0 and not finite():
        progress["bad"] = t
        return False
    return True


class _interrupt_flag:
    """While a solve runs, SIGINT (Ctrl-C) sets ``progress["interrupted"]`` instead of raising inside an Exudyn user
    function, where the engine would turn the KeyboardInterrupt into a failed user function and the run into a
    reported divergence; the pre-step hook then stops the solver cleanly. SIGTERM does the same when the command
    takes it as a clean stop (its handler ``_interrupt.terminate``), noting ``progress["terminated"]``. Only in the
    main thread (where Python delivers signals; a Dask worker's threads keep the default behaviour)."""

    def __init__(self, progress: dict):
        self.progress, self.previous = progress, {}

    def __enter__(self):
        if threading.current_thread() is not threading.main_thread():
            return self
        if signal.getsignal(signal.SIGINT) in (signal.default_int_handler, _interrupt.interrupt):
            self.previous[signal.SIGINT] = signal.signal(signal.SIGINT, self._handle)
        if signal.getsignal(signal.SIGTERM) is _interrupt.terminate:
            self.previous[signal.SIGTERM] = signal.signal(signal.SIGTERM, self._handle)
        if hasattr(signal, "SIGALRM") and signal.getsignal(signal.SIGALRM) is _interrupt.interrupt:
            # a signal an import deferred (``_interrupt``) comes back on this timer, maybe now, inside the solve
            self.previous[signal.SIGALRM] = signal.signal(signal.SIGALRM, self._handle)
        return self

    def _handle(self, signum, frame):
        deferred = hasattr(signal, "SIGALRM") and signum == signal.SIGALRM
        self.progress["interrupted"] = True
        self.progress["terminated"] = (self.progress.get("terminated", False) or signum == signal.SIGTERM
                                       or (deferred and _interrupt.pending_is_termination()))

    def __exit__(self, *exc):
        for signum, previous in self.previous.items():
            signal.signal(signum, previous)
        return False


def _solve(model: Model, settings, solver_type, progress: dict, integrator: str, step: float) -> float:
    """Run Exudyn's solver; returns the wall time (s). Errors raised in user functions come out as ours."""
    console = exu.config.printToConsole
    exu.config.printToConsole = False  # the exception below carries the engine's message
    # Pause Python's cyclic garbage collector during the solve (as timeit does): the per-stage user functions make
    # no reference cycles (a whole PA1 SP run leaves 18 cyclic objects), and a full collection of the process's
    # heap, triggered mid-run by what earlier runs allocated, otherwise lands in this run (measured: 0.25 s in a
    # 1.7 s SP run of validation/cev_pa1.py). Collections resume, with the previous setting, when the solve ends.
    collector_was_enabled = gc.isenabled()
    gc.disable()
    started = _time.perf_counter()
    try:
        with _interrupt_flag(progress):
            model.mbs.SolveDynamic(settings, solverType=solver_type, showHints=False)
    except Exception as exc:  # the engine wraps user-function errors; report ours, else a divergence
        if progress["interrupted"]:   # a stop a signal asked for (the engine may raise on it): ``integrate`` says so
            return _time.perf_counter() - started
        if model.failure is not None:
            raise _user_error(model.failure, progress["time"]) from None
        implicit = not INTEGRATORS[integrator].explicit
        edge_on = model.stage.loads.edge_on() if model.stage is not None and implicit else []
        raise SimulationError(engine_stop_message(str(exc), integrator, step, progress["time"], edge_on),
                              progress["time"]) from None
    finally:
        wall = _time.perf_counter() - started
        if collector_was_enabled:
            gc.enable()
        exu.config.printToConsole = console
    return wall


def _sampled_channels(model: Model) -> tuple[list, list]:
    """The (key, reader) pairs of the channels sampled one by one, and the model's channel groups."""
    grouped = {key for keys, _, _ in model.channel_groups for key in keys}
    return [(key, reader) for key, reader in model.channels.items() if key not in grouped], model.channel_groups


def _samples(model: Model, rows: list) -> dict:
    """``{channel key: its samples}`` from the sampled rows: the single channels' values, then each group's."""
    single, groups = _sampled_channels(model)
    samples = {key: [row[i] for row in rows] for i, (key, _) in enumerate(single)}
    tables: dict = {}   # a group's samples as one array, shared by groups whose reader handed out the same lists
    for j, (keys, _, split) in enumerate(groups, start=len(single)):
        first = id(rows[0][j]) if rows else None
        if first not in tables:
            tables[first] = np.array([row[j][0] for row in rows], float).reshape(len(rows), -1)
        samples.update(zip(keys, split(tables[first])))
    return samples


def integrate(model: Model, integrator: str, step: float, duration: float, output_step: float,
              spectral_radius: float = 0.9, start: float = 0.0, report=None, solution_file=None,
              control=None) -> RawHistory:
    """Integrate a built model from ``start`` to ``duration`` (s, absolute times) with ``step`` (s), sampling on the
    grid of ``output_step`` (s). A stop condition (``model.stop_conditions``) may end it early, after a step it
    samples; ``RawHistory.stopped_at`` then holds that time. ``report``, if given, receives the simulation time (s)
    every REPORT_EVERY steps. Ctrl-C stops the solver after the step it is in and raises ``errors.Interrupted``.
    ``solution_file``: a path for Exudyn's own solution file (coordinates every ``output_step``), for its viewer.
    ``control``: for an explicit integrator, a step control that chooses every step as the run goes
    (``control.after_step(t)`` returns the coming step in s; ``step`` is then the largest, the model's ``step`` None
    and the sample times the step ends'); None: every step is ``step``.

    Raises
    ------
    SimulationError
        When the state becomes NaN or infinite, a user function fails or the engine stops; the message gives the
        simulation time and what to try.
    """
    settings, solver_type = _settings(integrator, step, start, duration, spectral_radius, solution_file, output_step)
    step = (duration - start) / solver_steps(start, duration, step)   # the step Exudyn takes
    progress = {"steps": 0, "time": start, "bad": None, "stopped": None, "interrupted": False}
    before_steps = model.pre_step_hooks or not INTEGRATORS[integrator].explicit   # an implicit step may be retried
    if before_steps:
        model.mbs.SetPreStepUserFunction(_pre_step_function(model, progress, step))
    clock = _FixedSteps(step) if control is None else _AdaptiveSteps(control)
    post_step, times, rows = _post_step_function(model, clock, duration, output_step, progress, report,
                                                 counts=not before_steps)
    model.mbs.SetPostStepUserFunction(post_step)
    model.progress = progress
    model.warm_up(step if control is None else None)
    wall = _solve(model, settings, solver_type, progress, integrator, step)
    if progress["interrupted"]:
        raise Interrupted(progress["time"], duration, progress.get("cause", ""), progress.get("terminated", False))
    if model.failure is not None:
        raise _user_error(model.failure, progress["time"])
    if progress["bad"] is not None:
        raise SimulationError(
            f"the state became NaN or infinite near t = {progress['bad']:.4f} s with the {integrator} integrator "
            f"at step {step:g} s: try a smaller step", progress["bad"])
    model.finish()
    samples = _samples(model, rows)
    times = grid_times(times, start, step, output_step) if control is None else times
    raw = RawHistory.from_samples(times, samples, progress["steps"], wall)
    raw.stopped_at = progress["stopped"]
    return raw


def engine_stop_message(engine_text: str, integrator: str, step: float, time: float, edge_on=()) -> str:
    """The user's words for an engine that stopped at ``time`` (s) without a failure of ours: its own text names
    C++ classes and options the user never sees, so it is read here and not repeated. ``edge_on``: (body, angle of
    attack in deg) of bodies flying edge-on with an axial force that changes sign there (``AerodynamicLoads``)."""
    where = f"the {integrator} integration stopped at t = {time:.4f} s"
    if edge_on:
        body, alpha = edge_on[0]
        return (f"{where}: body {body} flies edge-on to the air (angle of attack {alpha:.1f} deg), where its constant "
                "or 0-90 deg axial coefficient changes sign (docs/models/aerodatabase.md, 'Edge-on'): an implicit "
                "step has no solution across that jump at any step size; use RK4 (--integrator rk4, SP or full "
                "mass), or give the canopy a C_A table that falls to 0 at 90 deg")
    if "ConnectorGravity" in engine_text and "length = 0" in engine_text:
        cause = ("a body or confluence reached the planet's centre: the state blew up (a mass or inertia far too "
                 "small for its lines, or a step far too large)")
    elif not INTEGRATORS[integrator].explicit:
        cause = ("its Newton iteration failed even on halved steps: the model is too stiff for the step or its "
                 "state blew up (check masses, inertias and line stiffnesses)")
    else:
        cause = "the state most likely diverged"
    return f"{where}: {cause}; try a smaller step than {step:g} s, and check the case's masses and inertias"


def _user_error(failure: Exception, time: float) -> Exception:
    """The error to raise for the first exception a user function raised at ``time`` (s): ours as it is, a
    physics model's range error as a SimulationError with its own message, anything else named as a failure."""
    if isinstance(failure, PchuteError):
        return failure
    if isinstance(failure, OutsideAtmosphereError):
        return SimulationError(str(failure), time)
    return SimulationError(f"a user function failed at t = {time:.4f} s: {failure!r}", time)


@functools.cache
def versions() -> dict:
    """Versions of this package and the libraries the numbers depend on (for result files); numba's is the one that
    compiled the kernels (the compiled module records it; a run with the Python kernels never imports numba)."""
    from .._version import __version__

    numba_version = KERNEL_BUILDER.get("numba")
    if numba_version is None:
        from importlib.metadata import version
        numba_version = version("numba")
    return {"pchute_exudyn": __version__, "exudyn": exu.__version__, "numpy": np.__version__,
            "numba": numba_version, "kernels": KERNEL_FORM,
            "python": sys.version.split()[0], "platform": platform.platform()}

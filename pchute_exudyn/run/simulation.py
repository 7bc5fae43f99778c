"""Run a case: resolve the method (through the method table), integrator and step, build the method's Exudyn model
phase by phase, integrate, check, and name the outputs."""

from __future__ import annotations

import copy
import math
import tempfile
from dataclasses import dataclass, field, fields
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from ..boundary import check_callable, check_case, check_flag
from ..case.canopy_choice import canopy_models_flown
from ..case.carried import case_at
from ..case.model import Case
from ..case.plausible import check_time_scales, implausible_settings
from ..engine.bodies import Touchdown
from ..engine.solver import integrate, versions
from ..engine.state import BODY_VALUES, CONFLUENCE_VALUES
from ..engine.trigger_monitor import TriggerMonitor
from ..errors import InputError, Interrupted, SimulationError, short_repr
from ..kernels import selection
from ..methods.base import Method
from ..physics.step_rule import StepRule
from ..registries.columns import column, owner
from ..registries.methods import ADAPTIVE_STEP, INTEGRATORS, METHODS, OptionError
from ..results.deployments import deployment_loads, load_warnings
from ..results.openings import opening_events, opening_loads, opening_warnings
from ..results.result import Result
from ..results.summary import (
    FinalState,
    RunSummary,
    StartEvent,
    TouchdownEvent,
    descent_rate_events,
    events_planned,
    failures_flown,
    merge_facts,
    separation_summary,
    site_of,
)
from .analysis import cluster_columns, cluster_summary, descent_summary, pendulum_columns, pendulum_summary
from .deployment_watch import watch_deployments
from .outputs import check_history, concatenate, derive_columns, places_last, scene
from .phase_step import check_phase_step
from .phases import boundaries, inflation_progress, initial_states, next_phase, retime_openings
from .sequence import Sequence
from .step_control import AdaptiveSteps, add_step_monitor, stability_step

MAX_STEPS = 2**31 - 1
"""Steps the engine can count in one run (its step counter is a 32-bit integer)."""
MAX_OUTPUT_BYTES = 4e9
"""Largest memory (bytes) the sampled histories of one run may need; beyond it a run is refused before it starts."""
BYTES_PER_SAMPLE_VALUE = 40
"""Memory per sampled value while a run collects it (a Python float in a row list, then its array entry)."""
MAX_TRIGGER_SAMPLES = 1e7
"""Samples one trigger's sensor may take in a run (rate in Hz times the duration in s): each is drawn in Python (its
noise, about 1 us, even for a sample a fixed step skips) and, at adaptive steps, is an engine step of its own; a
10 kHz sensor over 1000 s is within it."""


@dataclass(frozen=True)
class RunPlan:
    """A resolved, validated run: the method (with its options), integrator, step (s) and duration (s)."""

    method: Method
    integrator: str
    step: float
    duration: float
    stability_limit: float | None = None   # s: set when the step was chosen from it (``stability_step``)
    control: StepRule | None = None        # adaptive steps (``run.step_control``): ``step`` is then the largest
    warnings: tuple = ()                   # one line each: a case setting this plan leaves without effect


def option_error(exc: OptionError, method_class=None) -> InputError:
    """An OptionError as a user-facing InputError, naming the command-line flag where the option has one."""
    flag = None
    if method_class is not None and exc.field in {f.name for f in fields(method_class.Options)}:
        flag = next(f.metadata.get("flag") for f in fields(method_class.Options) if f.name == exc.field)
    name = f"{exc.field} ({flag})" if flag else exc.field
    return InputError(f"{name} = {exc.value!r}: {exc.allowed}")


def method_class_of(case: Case, method=None) -> type:
    """The method class of a name or a class (default: the case's), unconfigured."""
    try:
        return METHODS.resolve(case.simulation.method if method is None else method)
    except OptionError as exc:
        raise InputError(str(exc)) from None


def resolve_method(case: Case, method=None, options=None) -> Method:
    """The method (a name or a Method class; default: the case's) with the case's options for it, overridden by
    ``options`` (a mapping of option names to values, or an Options object)."""
    method_class = method_class_of(case, method)
    if options is not None and not isinstance(options, dict):
        if not isinstance(options, method_class.Options):
            raise InputError(f"options of type {type(options).__name__} do not belong to the {method_class.name} "
                             f"method (it takes {method_class.Options.__name__})")
        return method_class(options)
    try:
        return method_class.configure(case, options)
    except OptionError as exc:
        raise option_error(exc, method_class) from None


def _check_number(name: str, value, flag: str) -> float:
    number = math.nan
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        try:
            number = float(value)
        except OverflowError:   # an integer of hundreds of digits
            number = math.inf
    if not (math.isfinite(number) and number > 0.0):
        allowed = f" or {ADAPTIVE_STEP!r} (adaptive steps)" if name == "step" else ""
        raise InputError(f"{name} ({flag}) = {short_repr(value)}: must be a number > 0 (s){allowed}")
    return number


def resolve_run(case: Case, method=None, integrator: str | None = None, step: float | None = None,
                duration: float | None = None, options=None) -> RunPlan:
    """Fill in the case's defaults and validate method, options, integrator, step (s) and duration (s)."""
    check_case(case)
    if selection.rejected_choice():   # the environment's kernel form, checked with the run's other inputs
        raise InputError(selection.rejected_choice())
    resolved = resolve_method(case, method, options)
    integrator = case.simulation.integrator if integrator is None else integrator
    try:
        resolved.check(case, integrator)
    except OptionError as exc:
        raise InputError(str(exc)) from None
    duration = _check_number("duration", case.simulation.duration if duration is None else duration, "--t-end")
    limit = control = None
    if step is None:
        step = case.simulation.default_step(resolved.name, integrator)
        if step is None:
            step = ADAPTIVE_STEP if INTEGRATORS[integrator].explicit else None
    if step == ADAPTIVE_STEP:
        if not INTEGRATORS[integrator].explicit:
            raise InputError(f"step (--dt) = {ADAPTIVE_STEP!r}: adaptive steps are RK4's; the {integrator} "
                             "integrator needs a step in s")
        control = case.simulation.step_rule
        step = min(control.largest, duration)
    elif step is None:
        step, limit = stability_step(case, resolved, integrator)
        step = min(step, duration)
    step = _check_number("step", step, "--dt")
    if step > duration:
        raise InputError(f"step (--dt) = {step:g} s: must not exceed the duration ({duration:g} s)")
    _check_size(case, step, duration)
    _check_samples(case, duration)
    if control is None and INTEGRATORS[integrator].explicit:
        resolved.check_step(case, step)
    check_time_scales(case, step)
    return RunPlan(resolved, integrator, step, duration, limit, control,
                   _idle_step_control(case, control, step) + _rigid_instead(case, resolved)
                   + _output_below_step(case, control, step))


def _idle_step_control(case: Case, control: StepRule | None, step: float) -> tuple:
    """A warning when the case sets ``[simulation.step_control]`` but the run takes a fixed ``step`` (s)."""
    if control is not None or case.simulation.step_rule == StepRule():
        return ()
    return (f"simulation.step_control: has no effect in this run: its step is fixed ({step:g} s, from --dt, "
            "[simulation.steps] or the stability limit); the adaptive steps it tunes are RK4's with --dt auto or no "
            "step set",)


def _output_below_step(case: Case, control: StepRule | None, step: float) -> tuple:
    """A warning when ``simulation.output_step`` (s) is shorter than any step the run takes (a fixed ``step``, s, or
    adaptive steps' smallest): the output then holds a row per step, not per output step."""
    shortest = step if control is None else control.smallest
    if not case.simulation.output_step < shortest:
        return ()
    return (f"simulation.output_step = {case.simulation.output_step:g} s: has no effect below the run's "
            f"{'step' if control is None else 'smallest adaptive step'} ({shortest:g} s): the output holds one row "
            "per step",)


def _rigid_instead(case: Case, method) -> tuple:
    """A warning per system the case names reduced when ``method`` flies every canopy rigid (only SP has a reduced
    canopy, ``Method.flies_reduced_canopies``); a reduced canopy "auto" chose is the method's to fly as it can."""
    if method.flies_reduced_canopies:
        return ()
    return tuple(f"systems.{name}.canopy_model = 'reduced': has no effect in this run: the {method.name} method "
                 "flies every canopy rigid (a reduced canopy is SP's, --method sp)"
                 for name, system in case.systems.items() if system.canopy_model == "reduced"
                 and not system.canopy_model_chosen)


def _check_size(case: Case, step: float, duration: float) -> None:
    """Refuse, before any work, a run the engine cannot count or whose histories would not fit in memory."""
    steps = duration / step
    if steps > MAX_STEPS:
        raise InputError(f"{duration:g} s at a step of {step:g} s is {steps:.3g} steps; the engine counts at most "
                         f"{MAX_STEPS} in a run: shorten the run (--t-end) or lengthen the step (--dt)")
    samples = min(duration / case.simulation.output_step, steps) + 1
    values = ((BODY_VALUES + 1) * len(case.bodies)   # +1: the estimate as first written (19), so the limit is unchanged
              + sum(CONFLUENCE_VALUES + len(system.lines) for system in case.systems.values()))
    need = samples * values * BYTES_PER_SAMPLE_VALUE
    if need > MAX_OUTPUT_BYTES:
        raise InputError(f"{duration:g} s sampled every {case.simulation.output_step:g} s is {samples:.3g} samples "
                         f"of {values} values, about {need / 1e9:.0f} GB: more than the {MAX_OUTPUT_BYTES / 1e9:g} GB "
                         "a run may hold; raise simulation.output_step (--set simulation.output_step=...) or "
                         "shorten the run")


def _check_samples(case: Case, duration: float) -> None:
    """Refuse, before any work, a trigger whose sampling rate (Hz) gives more than MAX_TRIGGER_SAMPLES in the run."""
    for trigger in case.triggers.values():
        rate = trigger.sensor.rate
        if rate is not None and rate * duration > MAX_TRIGGER_SAMPLES:
            raise InputError(f"{trigger.key}.rate = {rate:g} Hz: {duration:g} s at that rate is "
                             f"{rate * duration:.3g} samples; a trigger takes at most {MAX_TRIGGER_SAMPLES:.0e} in a "
                             f"run: lower the rate (at most {MAX_TRIGGER_SAMPLES / duration:.3g} Hz here) or shorten "
                             "the run")


def _run_phase(case: Case, plan: RunPlan, phase, output_step: float, report=None, solution_file=None,
               sequence: Sequence | None = None, traces: dict | None = None):
    """Build and integrate one phase; returns the model, its checked history, its touchdown and its trigger monitor
    (each None when the phase has none). ``traces``: the run's deployment load traces (``run.deployment_watch``)."""
    phase.drawn = solution_file is not None   # Exudyn's graphics only where its solution file is kept
    model = plan.method.build(case, phase)
    if traces is not None:
        watch_deployments(model, case, traces, phase.inflation)
    fixed_rk4 = plan.control is None and INTEGRATORS[plan.integrator].explicit
    if fixed_rk4:
        try:
            check_phase_step(model, case, plan.method, plan.step)
        except SimulationError:
            model.release()
            raise
    if fixed_rk4 and model.systems and plan.method.step_limited:
        add_step_monitor(model, plan.method, plan.step)
    touchdown = monitor = None
    if case.simulation.stop_at_ground and not case.bodies[case.vehicle].fixed:
        touchdown = Touchdown(model, case, case.simulation.ground_altitude)
        model.add_stop_condition(touchdown)
    if sequence is not None and sequence.pending_watches():
        monitor = TriggerMonitor(model, case, sequence.pending_watches(), sequence.times)
        monitor.horizon = plan.step   # adaptive steps: at most the plan's step
        model.add_stop_condition(monitor)
    control = None if plan.control is None else AdaptiveSteps(model, case, plan.method, plan.control,
                                                              None if monitor is None else monitor.landing)
    try:
        raw = integrate(model, plan.integrator, plan.step, phase.end, output_step, case.simulation.spectral_radius,
                        start=phase.start, report=report, solution_file=solution_file, control=control)
        check_history(case, raw, plan.step)
        raw.step_control = None if control is None else control.summary()
    except Interrupted as exc:   # say how far the whole run got, not the phase
        model.release()
        raise Interrupted(exc.time, plan.duration, exc.cause, exc.terminated) from None
    except BaseException:
        model.release()
        raise
    return model, raw, touchdown, monitor


@dataclass
class _Run:
    """What a run has gathered so far (``run``); ``saved`` restores it to a phase's start."""

    body_states: dict
    confluence_states: dict
    openings: dict
    events: list
    histories: list = field(default_factory=list)
    facts: dict = field(default_factory=dict)
    traces: dict = field(default_factory=dict)   # system -> run.deployment_watch.LoadTrace

    def saved(self) -> _Run:
        return _Run(self.body_states, self.confluence_states, copy.deepcopy(self.openings), list(self.events),
                    list(self.histories), dict(self.facts), copy.deepcopy(self.traces))


def run(case: Case, plan: RunPlan, report=None, solution_folder=None):
    """Integrate ``case`` phase by phase as ``plan`` says; ``report`` receives the simulation time (s) as it goes;
    with ``solution_folder`` Exudyn writes each phase's solution file there (``ENGINE_SOLUTION``).

    Returns the checked engine history of the whole run, the method's facts, the event log, the openings
    (``physics.inflation.InflationProgress`` per system with an inflation), the sequence (``run.sequence``) and the
    deployment load traces (``run.deployment_watch.LoadTrace`` per system).
    """
    output_step = min(case.simulation.output_step, plan.duration)
    sequence = Sequence(case)
    state = _Run(*initial_states(case), inflation_progress(sequence.case), [StartEvent.of(case)])
    start, number = 0.0, 0
    try:
        while start < plan.duration:
            current = sequence.case
            end = next(t for t in sorted(set(boundaries(current, plan.duration)) | sequence.boundaries(plan.duration))
                       if t > start)
            # what a phase integrated again to a firing time needs (only a run with sensed triggers has one)
            saved, watches = (state.saved(), sequence.snapshot()) if sequence.triggered else (None, None)
            if sequence.triggered:
                retime_openings(current, state.openings)
            phase = next_phase(current, start, end, state.body_states, state.confluence_states)
            sequence.note_conditions(start, phase.body_states)
            phase.inflation = state.openings
            state.events.extend(phase.events)
            solution_file = None if solution_folder is None else Path(solution_folder) / ENGINE_SOLUTION.format(number)
            model, raw, touchdown, monitor = _run_phase(case_at(current, start), plan, phase, output_step, report,
                                                        solution_file, sequence, state.traces)
            try:
                stopped = raw.stopped_at
                landed = touchdown.crossing[0] if touchdown is not None and touchdown.crossing is not None else math.inf
                firings = [f for f in monitor.firings if f.time < landed] if monitor is not None else []
                if firings and sequence.fire(firings, start) < stopped:   # inside the step just taken: again to t_f
                    state, _ = saved, sequence.restore(watches)
                    continue
                state.histories.append(raw)
                number += 1
                merge_facts(state.facts, model.facts())
                if touchdown is not None and touchdown.crossing is not None:
                    state.events.append(TouchdownEvent.from_crossing(*touchdown.crossing))
                    break
                state.body_states, state.confluence_states = model.end_state()
                start = stopped if stopped is not None else end
            finally:
                model.release()   # every phase model's engine system freed as soon as it is read
    except SimulationError as error:   # a run that dies with a trigger still waiting says which
        raise sequence.with_unfired(error) from None
    raw = concatenate(case, state.histories)
    events = state.events + opening_events(sequence.case, state.openings, float(raw.time[-1]))
    return raw, state.facts, sequence.attach(events), state.openings, sequence, state.traces


def _final_values(case: Case, columns: dict) -> FinalState:
    """The last sample's time (s) and the altitude, east and north (m) of the vehicle and of each confluence."""
    owners = [case.vehicle] + [case.confluence_label(system) for system in case.systems.values()]
    where = [column(template, name) for name in owners for template in FinalState.POSITION]
    return FinalState(float(columns[column("time")][-1]), case.vehicle,
                      {name: float(columns[name][-1]) for name in where if name in columns})


def summarize(case: Case, plan: RunPlan, raw, facts: dict, events: list, columns: dict, units: dict,
              openings: dict | None = None, sequence: Sequence | None = None, deployments: tuple = (),
              progress: dict | None = None) -> RunSummary:
    """The typed summary of a finished run (``progress``: each opening's ``InflationProgress``, by (system,
    canopy))."""
    last_deployment = max([e.time for e in events if e.kind == "deploy"], default=0.0)
    events = sorted(events + descent_rate_events(case.simulation.descent_rate_events, columns["time"],
                                                 columns[column("{owner}_velocity_down", case.vehicle)],
                                                 last_deployment),
                    key=lambda e: e.time)
    lines = {k: owner(k, "tension_{owner}") for k in columns}
    peaks = {line: float(np.nanmax(columns[k])) if np.isfinite(columns[k]).any() else None
             for k, line in lines.items() if line is not None}
    return RunSummary(
        case=case.name, case_file=case.source, description=case.description, vehicle=case.vehicle,
        method=plan.method.name, integrator=plan.integrator, step=plan.step, duration=plan.duration,
        output_step=min(case.simulation.output_step, plan.duration),
        ground_altitude=case.simulation.ground_altitude, stop_at_ground=case.simulation.stop_at_ground,
        end="touchdown" if any(e.kind == "touchdown" for e in events) else "duration", steps=raw.steps,
        wall_time=raw.wall_time, final=_final_values(case, columns), peak_tension=peaks, events=tuple(events),
        units=units, versions=versions(), created=datetime.now(timezone.utc).isoformat(timespec="seconds"),
        method_settings=plan.method.settings(), method_facts=facts, opening_loads=openings or {},
        deployments=deployments,
        cluster=cluster_summary(case, columns, events), pendulum=pendulum_summary(case, columns, events),
        descent=descent_summary(case, columns), failures=failures_flown(case.failures),
        # the plan's (settings without effect in this run) last: every earlier warning keeps its place in the list
        warnings=case.warnings + opening_warnings(case, events, progress) + load_warnings(deployments)
        + tuple(sequence.warnings(float(raw.time[-1])) if sequence is not None else ()) + plan.warnings,
        events_planned=events_planned(case.systems, None if sequence is None else sequence.base.triggers),
        separations=separation_summary(case, raw, events),
        step_control=None if plan.control is None else {"rule": "adaptive", **(raw.step_control or {})},
        site=site_of(case.start), canopy_models=canopy_models_flown(case.systems, plan.method.flies_reduced_canopies))


ENGINE_SOLUTION = "exudyn_solution_phase{}.txt"
"""Exudyn's own solution file of phase k (``simulate(engine_solution=True)``): the coordinates of that phase's
model every output step, for scripts that rebuild the model and open Exudyn's viewer on it."""


def _check_arguments(case, progress, engine_solution, history) -> None:
    """The public API's boundary: an argument of the wrong type gets one line naming it."""
    check_case(case)
    check_callable(progress, "progress")
    check_flag(engine_solution, "engine_solution")
    check_flag(history, "history")


def _options(options, option_values: dict):
    """The method's options: an Options object, or single options by name (None: the case's), not both."""
    option_values = {name: value for name, value in option_values.items() if value is not None}
    if options is not None and option_values:
        raise InputError("give the method's options either as an Options object or by name, not both")
    return options if options is not None else option_values


def _plan(case, plan, method, integrator, step, duration, options, option_values) -> RunPlan:
    """The run's plan: resolved here from the arguments, or the one given, alone."""
    if plan is None:
        return resolve_run(case, method, integrator, step, duration, _options(options, option_values))
    if not isinstance(plan, RunPlan) or any(v is not None for v in (method, integrator, step, duration, options)) \
            or any(v is not None for v in option_values.values()):
        raise InputError("plan: a RunPlan (resolve_run) alone, without method, integrator, step, duration or options")
    return plan


def simulate(case: Case, method=None, integrator: str | None = None, step: float | None = None,
             duration: float | None = None, *, plan: RunPlan | None = None, options=None, progress=None,
             engine_solution: bool = False, history: bool = True, **option_values) -> Result:
    """Simulate ``case``.

    Parameters
    ----------
    case : Case
        From ``pchute_exudyn.load_case``.
    method : str or Method class, optional
        Confluence method: a name in ``pchute_exudyn.METHODS`` ("full", "sp", "equilibrium") or a method class;
        default from the case.
    integrator : str, optional
        "rk4" or "implicit"; default from the case; each method lists the integrators it supports.
    step : float, optional
        Integration step (s); default from the case's ``simulation.steps``, else from the stability limit
        (``stability_step``).
    duration : float, optional
        Simulated time (s); default from the case.
    plan : RunPlan, optional
        A run already resolved (``resolve_run``), given alone: no method, integrator, step, duration or options.
    options : Options object of the method, optional
        The method's options as a whole (e.g. ``SPOptions(kappa_max=10)``).
    progress : callable, optional
        Receives the simulation time (s) every few steps (as ``progress.TerminalProgress`` draws it).
    engine_solution : bool
        Also keep Exudyn's solution file of each phase (``ENGINE_SOLUTION``) with the result (written in the solve).
    history : bool
        False: a run whose history nobody keeps (a study's): without the columns the summary never reads
        (``outputs.derive_columns``) and without the scene (its files hold no scene to animate).
    **option_values
        Or single options by name, on top of the case's (None: the case's): SP ``preset`` ("accurate",
        "thesis"), ``kappa_max`` (-, > 3), ``slack_rule`` ("stretch", "force"), ``order`` (0, 1); full mass
        ``line_law`` ("symbolic", "python").

    Returns
    -------
    Result

    Raises
    ------
    InputError
    SimulationError
    Interrupted
        On Ctrl-C (a KeyboardInterrupt saying the time reached); nothing of the run is returned.
    """
    _check_arguments(case, progress, engine_solution, history)
    plan = _plan(case, plan, method, integrator, step, duration, options, option_values)
    if not engine_solution:   # no folder: a process killed mid-run (a study's worker on Ctrl-C) leaves none behind
        return _result(plan, *_flown(case, plan, progress, None), history, {})
    with tempfile.TemporaryDirectory() as folder:
        flown = _flown(case, plan, progress, folder)
        attachments = {path.name: path.read_text() for path in sorted(Path(folder).glob("*.txt"))}
    return _result(plan, *flown, history, attachments)


def _flown(case: Case, plan: RunPlan, progress, folder):
    """``run``, with a stop that follows a plausibility warning naming the warned settings."""
    try:
        return run(case, plan, progress, folder)
    except SimulationError as error:
        raise _naming_implausible(error, case) from None


def _naming_implausible(error: SimulationError, case: Case) -> SimulationError:
    """``error`` with the case's implausible settings named (``case.plausible``): a run stopped by what such a value
    caused (out of the atmosphere, a line stretch below the ground) says which warned setting to look at first."""
    settings = implausible_settings(case.warnings)
    if not settings:
        return error
    return SimulationError(f"{error} (the case has implausible settings, warned before the run: "
                           f"{', '.join(settings)})", error.time)


def _result(plan: RunPlan, raw, facts, events, openings, sequence, traces, history, attachments) -> Result:
    """The ``Result`` of a run (``run``'s returns): columns named, summary made."""
    flown = sequence.case   # the case with every triggered event at the time it fired
    columns, units = derive_columns(flown, raw, history)
    contacts = cluster_columns(flown, raw, columns, units)
    pendulum_columns(flown, raw, columns, units)
    places_last(columns, units)
    loads: dict = {}   # each deployment's load history, for the loads figure
    summary = summarize(flown, plan, raw, facts, events + contacts, columns, units,
                        opening_loads(flown, openings, columns), sequence,
                        deployment_loads(flown, traces, openings, columns, raw, loads), openings)
    return Result(columns, units, summary, scene=scene(flown, raw) if history else None, attachments=attachments,
                  loads=loads)

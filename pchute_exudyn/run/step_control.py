"""A run's steps: the one home of the step policy. Every limit is a method's (``Method.confluence_limits``,
``lumped_limit``, ``state_limits``, typed ``StepLimit``s with their cause and remedy) or a body's on its lines
(below); this module takes their minimum and never reads a method's constants.

* **A fixed step** (``stability_step``): a case that sets no step for the method runs at STEP_FRACTION of the smallest
  limit at its start; a fixed RK4 run is watched by a step monitor (``add_step_monitor``) that stops it as soon as
  the step exceeds a confluence's current limit.
* **Adaptive steps** (``AdaptiveSteps``): after every step ``after_step`` reads the bodies' velocity coordinates (one
  engine read), updates the indicator of ``physics.step_rule`` and returns the coming step, never beyond
  CAP_FRACTION of the smallest stability limit of the phase:

  * each moving body's translational mode on its lines (their stiffness and damping summed, as if they pulled along
    one direction) with its drag's damping rho V S C_A, S the drag area open now
    (``physics.linearization.body_line_step_limit``; the mass with the air it carries along its axis when it has an
    apparent mass);
  * each moving body pitching on its lines (``_rotation_limits``: a light canopy on its riser wobbles at 20 Hz);
  * each cluster's canopies on their contacts (``_contact_limits``);
  * each confluence by its method's limits at the current geometry (SP's damped mode, a full-mass confluence's
    modes), with the lines as the method damps them at that step (``Method.relaxed``), and the method's own states
    (``Method.state_limits``: a reduced canopy's drag point).

  The limits that move with the state (geometry, air speed) are checked again every CAP_INTERVAL of simulated time
  (longer while they stay put), at least CAP_STEPS steps apart. A limit below the rule's smallest step stops the
  run, naming what sets it.
"""

from __future__ import annotations

import math

import numpy as np

from ..case.model import Case
from ..engine.phase_model import Model
from ..engine.state import TensionChannel, initial_confluence_state, initial_point
from ..errors import InputError, SimulationError
from ..methods.base import Method, line_constants, unstable_step_message
from ..physics.compiled import machine_code
from ..physics.kinematics import ROW_POSITION, ROW_VELOCITY
from ..physics.linearization import body_line_step_limit, max_stable_step_rk4, spectral_step_bound
from ..physics.rk4 import RK4_IMAGINARY_LIMIT
from ..physics.step_rule import CAP_FRACTION, StepRule, extrapolation_error, next_step
from ..registries.methods import INTEGRATORS

CAP_INTERVAL = 1.0
"""Simulated time (s) between checks of the limits that move with the state, after a check that found them moved
by more than CAP_STEADY; each check that finds them steady doubles it, up to CAP_INTERVAL_LONGEST. A step whose
indicator exceeds 1 (the motion changed) brings the next check forward to CAP_STEPS steps after the last."""
CAP_INTERVAL_LONGEST = 64.0
CAP_STEADY = 0.1
"""Relative change (-) of the smallest limit below which a check counts as steady."""
CAP_STEPS = 100
"""Fewest steps between two such checks."""
ALLOWANCE_STEPS = 8
"""Steps between two looks at the relaxation's cap (``_relaxation_cap``: the lines' stretch-rate envelope fades over
seconds)."""
TAUT_LANDING = 1e-4
"""s: a slack tether this close to its line stretch (at its rate) gets a step that ends on it; farther, steps of half
the way (``_tether_cap``)."""
SNATCH_STEPS = 40
"""Fewest steps (-) over half the period of a taut tether's snatch (``_tether_cap``): its peak within 0.1 %."""
SNATCH_PERIODS = 3
"""Periods (-) after a tether comes taut in which its snatch is resolved (``_tether_cap``)."""
OPENING_STEPS = 200
"""Fewest steps (-) over a canopy's fill and its overinflation's decay, a step kept while a supersonic opening's
canopy flies faster than sound (``_opening_cap``): the drag rises from nothing to its peak within the fill and swings
the canopy on its lines, which the indicator, in a norm that a heavy vehicle dominates, does not see (MSL's 60 kg
parachute behind 3.1 t: twice the opening load at the indicator's steps; docs/models/step_control.md, "Openings")."""
RELAXATION_SHARE = 0.01
"""Largest share (-) of a line's tension that the relaxation's extra damping may add at the current stretch rates
(``_relaxation_cap``)."""


MONITOR_INTERVAL = 0.1
"""Simulated time (s) between checks of the RK4 step against the confluences' current stability limit (the limit
moves with the line loads, over seconds; a check costs about 0.3 ms). At least MONITOR_STEPS steps apart: 5 s at
SP's 1e-2 s (a check every 100 steps was 4 % of a PA1 SP run once the stages got cheap, issue 14), 0.25 s at full
mass's 5e-4 s."""
MONITOR_STEPS = 500
STEP_FRACTION = 0.5
"""A case without a step for the method runs at this fraction of the stability limit (``stability_step``): the limit
falls as the lines stretch under load (MER's confluence: by 8 % over 60 s) and the bound is taken at free length.
For MER: 1e-2 s SP (the thesis's step) and 5e-5 s full mass (the any-layout bound, 1.99e-4 s, is below the 4.28e-4 s of
the real layout; the thesis ran 1e-4 s)."""


def stability_step(case: Case, method: Method, integrator: str) -> tuple[float, float]:
    """The step (s) of a case that sets none for the method, and the stability limit (s) it comes from.

    The limit is the smallest of: each body on the lines attached to it by a bound that holds in any layout
    (``physics.linearization.spectral_step_bound``; a body's rotation is left out), and each system's confluence by
    its method's limits (``Method.lumped_limit``, and ``Method.confluence_limits`` at the case's initial geometry for
    a system present from the start): for the implicit integrator (stable at any step) the method's accuracy limit.
    The step is STEP_FRACTION of the limit, rounded down to 1, 2 or 5 x 10^k.
    """
    key = INTEGRATORS[integrator].step_key(method.name)
    limits = [math.inf]
    moving = {name for name, body in case.bodies.items() if not body.fixed}
    for system in case.systems.values():
        limits.append(_confluence_limit(case, method, integrator, system, key))
        stiffness, damping = line_constants(system)
        for body in {line.body for line in system.lines} & moving:
            own = [i for i, line in enumerate(system.lines) if line.body == body]
            limits.append(spectral_step_bound(case.bodies[body].mass, [stiffness[i] for i in own],
                                              [damping[i] for i in own]))
    for body, k, c in tether_constants(case, case.bodies):
        if body in moving:   # each end on its own mass: the pair's mode is slower (its reduced mass is larger)
            limits.append(spectral_step_bound(case.bodies[body].mass, [k], [c]))
    limit = min(limits)
    if not math.isfinite(limit):
        raise InputError(f"no step given, the case sets no simulation.steps.{key} and nothing in it limits the step "
                         "(no line stiffness on a moving body or confluence): pass --dt")
    return _round_down(STEP_FRACTION * limit), limit


def tether_constants(case: Case, present) -> list:
    """(body, stiffest slope in N/m, damping in N s/m) of each end of each tether acting between the bodies
    ``present`` (names), both ends of a tether named."""
    return [(body, tether.law.stiffest, tether.law.damping) for tether in case.tethers.values()
            if tether.acts_between(present) for body, _ in tether.ends]


def _confluence_limit(case: Case, method: Method, integrator: str, system, key: str) -> float:
    """A confluence's stability limit (s) for ``stability_step``."""
    explicit = INTEGRATORS[integrator].explicit
    bound = method.lumped_limit(system, explicit)
    limits = [math.inf if bound is None else bound.value]
    if system.deploy_time is None:   # present from the start: its initial geometry is known
        attach = np.array([initial_point(case, line.body, line.point) for line in system.lines])
        where = initial_confluence_state(case, system).position
        limits += [limit.value for limit in confluence_limits_at(method, system, attach, where, explicit)]
    elif bound is None:
        raise InputError(f"no step given and the case sets no simulation.steps.{key}: the {system.name} system, "
                         "deployed during the run, has a line with stiffness but no damping, which leaves its step "
                         "limit unknown before deployment; pass --dt")
    return min(limits)


def _round_down(value: float) -> float:
    """``value`` rounded down to 1, 2 or 5 x 10^k."""
    decade = 10.0 ** math.floor(math.log10(value))
    return max(m for m in (1.0, 2.0, 5.0, 10.0) if m * decade <= value * (1.0 + 1e-12)) * decade


_LIMITS: dict = {}
"""Confluence limits by method, system and geometry: a phase's first check, and the step chosen from the stability
limit before the run, look at the same geometry (``confluence_limits_at``)."""


def confluence_limits_at(method: Method, system, attach_position, confluence_position, explicit: bool = True) -> list:
    """``method.confluence_limits`` at this geometry (attach points and confluence, m), computed once per
    geometry."""
    key = (type(method), method.options, system, tuple(np.ravel(attach_position).tolist()),
           tuple(np.ravel(confluence_position).tolist()), explicit)
    if key not in _LIMITS:
        if len(_LIMITS) > 1000:
            _LIMITS.clear()
        _LIMITS[key] = method.confluence_limits(system, attach_position, confluence_position, explicit)
    return _LIMITS[key]


def add_step_monitor(model, method: Method, step: float, interval: float = MONITOR_INTERVAL) -> None:
    """Stop an RK4 run as soon as ``step`` (s) exceeds a confluence's current stability limit
    (``Method.confluence_limits``).

    Checked before the first step and then after a step every ``interval`` s of simulated time (about 0.25 ms per
    check; a post-step hook, so that an RK4 run needs no pre-step call), on the current geometry: lines stretch under
    load and the limit falls with them. Beyond the limit RK4 does not always
    blow up at once: it can return plausible but wrong tensions for seconds (MER case 1 at 1e-3 s gave 4.6 times the
    true peak tensions in the first 3 s without any NaN), so the run stops instead.
    """
    next_check = [0.0]

    def monitor(mbs, t):
        if t < next_check[0]:
            return
        next_check[0] = t + max(interval, MONITOR_STEPS * step)
        for system in model.systems:
            where = model.confluences[system.name].state_position()
            for limit in confluence_limits_at(method, system, model.attach_positions(system), where):
                if step > limit.value:   # t: the end of the step just taken, the start of the coming one
                    raise SimulationError(unstable_step_message(method, step, limit, t), t)

    monitor(model.mbs, model.phase.start)   # the check before the first step, before the timed solve
    model.add_post_step(monitor)


class AdaptiveSteps:
    """The step control of one phase (see the module docstring).

    Parameters
    ----------
    model : Model
        The phase's built model.
    case : Case
    method : Method
    rule : StepRule
    landing : callable, optional
        ``landing(t)``: the next time (s) after ``t`` a step must end on (a sensed trigger's sample time while it
        can fire: ``engine.trigger_monitor.TriggerMonitor.landing``); inf: none.
    """

    def __init__(self, model: Model, case: Case, method: Method, rule: StepRule, landing=None):
        self.model, self.case, self.method, self.rule = model, case, method, rule
        self.landing = landing   # t -> the next time (s) a step must end on (a trigger's sample), or None
        self.read = model.mbs.systemData.GetODE2Coordinates_t
        size = len(self.read())
        self.history, self.times, self.count = np.zeros((3, size)), np.zeros(3), 0
        self._constants = {system.name: line_constants(system) for system in model.systems}
        self.weights = model.velocity_weights()
        self.mass = sum(case.bodies[name].mass for name in model.phase.bodies)   # kg, the moving bodies
        self.last_end = model.phase.start
        self.step = min(rule.first, rule.largest)
        self.cap = math.inf
        self.cause = ""
        self.next_check, self.steps_since_check, self.interval = -math.inf, 0, CAP_INTERVAL
        self._error = machine_code(extrapolation_error, self.history, self.times, self.count,
                                   np.asarray(self.read(), float), self.weights, self.mass, float(model.phase.start),
                                   float(rule.absolute), float(rule.relative))
        self.relaxation: dict = {}   # system -> the relaxation time its lines have now (s)
        self.unrelaxed: dict = {}    # relaxing system -> the step cap (s) of its lines' own damping
        self.allowance, self.since_allowance = None, 0   # the relaxation's step cap (s), looked at every few steps
        self.smallest, self.largest, self.steps, self.total = math.inf, 0.0, 0, 0.0   # of the steps taken (s)
        self._limits: dict = {}    # (system, relaxation time) -> its confluence's StepLimit, this check's
        self._remedies: dict = {}  # a confluence limit's description -> the layout or setting its method names
        self._taut_since: dict = {}   # tether -> the time (s) it last came taut (``_tether_cap``)
        self._held = [snatch for system in model.systems if system.bag_anchor is not None
                      for snatch in self._held_snatches(system)]   # _held_snatch_cap
        self._levers: dict = {}       # (body, point) -> its lever's constants (``_lever``)
        self._relaxed: dict = {}      # (system, relaxation time) -> (the system so relaxed, its line constants)
        self._tethers = tether_constants(case, model.bodies)   # the phase's bodies and tethers are fixed
        self._contacts = None         # (limit, cause) of each cluster's contact network (``_contact_limits``)

    def after_step(self, t: float) -> float:
        """The coming step (s) after the step that ended at ``t`` (s; at the phase start, the first step)."""
        taken = t - self.last_end
        self.last_end = t
        velocities = np.asarray(self.read(), float)
        error, self.count = self._error(self.history, self.times, self.count, velocities, self.weights, self.mass, t,
                                        self.rule.absolute, self.rule.relative)
        self.steps_since_check += 1
        if error > 1.0 and self.interval > CAP_INTERVAL:   # the motion changed: check the caps soon
            self.next_check, self.interval = t, CAP_INTERVAL
        if t >= self.next_check and self.steps_since_check >= CAP_STEPS or self.next_check == -math.inf:
            self._check_caps(t)
        if taken > 0.0:
            self._count(taken)
            self.step = next_step(taken, error, CAP_FRACTION * self.cap, self.rule.largest)
        else:
            self.step = min(self.step, CAP_FRACTION * self.cap)
        coming = min(self.step, self._relaxation_cap(t), self._opening_cap(t), self._tether_cap(t),
                     self._held_snatch_cap(t))
        if self.landing is not None:
            land = self.landing(t) - t
            if land < coming:
                coming = land   # the step that ends on a trigger's sample; the rule's step stays for the next
        self._relax(coming)
        return coming

    def _tether_cap(self, t: float) -> float:
        """The step (s) the tethers allow: one that comes taut within the coming step ends near its line stretch (its
        slack taken at its rate, half the way at a time: the snatch starts on a step's end); one that came taut less
        than SNATCH_PERIODS periods 2 pi sqrt(mu / K) ago (mu its two bodies' reduced mass, K its stiffest slope)
        resolves its snatch in SNATCH_STEPS steps a half period; one hanging taut longer is left to the other caps
        (inf without tethers)."""
        cap = math.inf
        for name, state in self.model.tethers.items():
            tether = self.case.tethers[name]
            length, rate = state.length_and_rate()
            if length < tether.law.free_length:
                self._taut_since.pop(name, None)
                if rate > 0.0:   # its rate changes on the way: half the way at a time, then onto it
                    left = (tether.law.free_length - length) / rate
                    cap = min(cap, max(left if left < TAUT_LANDING else 0.5 * left, self.rule.smallest))
                continue
            since = self._taut_since.setdefault(name, t)
            half_period = math.pi * math.sqrt(self._reduced_mass(tether) / tether.law.stiffest)
            if t - since < 2.0 * SNATCH_PERIODS * half_period:
                cap = min(cap, half_period / SNATCH_STEPS)
        return cap

    def _held_snatches(self, system) -> list:
        """(system, window in s, step in s) per canopy of a static line's (pilot chute's) system: its canopies, held
        back at the aircraft's (pilot chute's) velocity, snatch on the lines as a tether's ends do, resolved the same
        way (SNATCH_STEPS steps a half period pi sqrt(m / K) for SNATCH_PERIODS periods from line stretch; m the
        canopy's mass, K its riser in series with the bridles together). Constants of the phase, worked out once."""
        stiffness, _ = self._constants[system.name]
        bridles = sum(k for k, line in zip(stiffness, system.lines) if line.body not in system.canopies)
        snatches = []
        for k, line in zip(stiffness, system.lines):
            if line.body in system.canopies:
                series = k * bridles / (k + bridles) if bridles > 0.0 else k
                half_period = math.pi * math.sqrt(self.case.bodies[line.body].mass / series)
                snatches.append((system, 2.0 * SNATCH_PERIODS * half_period, half_period / SNATCH_STEPS))
        return snatches

    def _held_snatch_cap(self, t: float) -> float:
        """The step (s) the held snatches allow (``_held_snatches``) while their windows are open, not relaxed
        (``_relax``: no longer than the lines' own damping keeps stable); inf otherwise (and for any other system:
        its canopies leave at the vehicle's velocity)."""
        cap = math.inf
        for system, window, step in self._held:
            if 0.0 <= t - system.deploy_time < window:   # the lines as they are
                cap = min(cap, step, self.unrelaxed.get(system.name, math.inf))
        return cap

    def _reduced_mass(self, tether) -> float:
        """kg: the reduced mass of a tether's two bodies (the free one's own mass when the other is fixed)."""
        masses = [self.case.bodies[body].mass for body, _ in tether.ends if not self.case.bodies[body].fixed]
        return masses[0] * masses[1] / (masses[0] + masses[1]) if len(masses) == 2 else masses[0]

    def _opening_cap(self, t: float) -> float:
        """The step (s) an opening under way allows: its fill time over OPENING_STEPS from the stage's start until
        its fill (and, for the last stage, its overinflation's decay) has ended, and while a supersonic opening's
        canopy flies faster than sound (inf otherwise; a canopy cut away no longer counts)."""
        cap = math.inf
        for (_, canopy), progress in (self.model.phase.inflation or {}).items():
            if canopy not in self.model.phase.bodies:
                continue
            last = progress.inflation.number(len(progress.inflation.stages) - 1)
            for stage, end, _, fill in progress.fill_ends():
                decay = progress.inflation.overinflation_decay if stage == last else 0.0
                if t < end + decay or progress.supersonic_flight():
                    cap = min(cap, fill / OPENING_STEPS)
        return cap

    def _count(self, taken: float) -> None:
        self.smallest, self.largest = min(self.smallest, taken), max(self.largest, taken)
        self.steps += 1
        self.total += taken

    def _relaxation_cap(self, t: float) -> float:
        if self.unrelaxed and (self.since_allowance >= ALLOWANCE_STEPS or self.allowance is None):
            self.allowance, self.since_allowance = self._allowance(t), 0
        self.since_allowance += 1
        return math.inf if self.allowance is None else self.allowance

    def _allowance(self, t: float) -> float:
        """The longest step (s) whose relaxation (``Method.relaxation``) keeps each relaxing confluence's tensions
        within RELAXATION_SHARE of their own (``Method.relaxation_cap``): its extra damping acts on the lines'
        stretch rates, nil in a steady descent, not at a cluster's flyout or a swing; never below the step the lines'
        own damping allows (``unrelaxed``)."""
        cap = math.inf
        systems = {system.name: system for system in self.model.systems}
        for name, unrelaxed in self.unrelaxed.items():
            cap = min(cap, self.method.relaxation_cap(self.model, systems[name], t, unrelaxed, RELAXATION_SHARE))
        return cap

    def _relax(self, step: float) -> None:
        """The lines as the method damps them at ``step`` (s), where that changes: not beyond their own damping at a
        step their own damping keeps stable (``unrelaxed``), so that an opening's and a swing's short steps fly the
        lines as they are."""
        for system in self.model.systems:
            own = step <= self.unrelaxed.get(system.name, 0.0)
            tau = self.method.relaxation(0.0 if own else step, system)
            if tau != self.relaxation.get(system.name, 0.0):
                self.relaxation[system.name] = tau
                self.model.confluences[system.name].relax(tau)

    def _check_caps(self, t: float) -> None:
        """The caps at the current state. Where the method relaxes the lines at long steps
        (``Method.relaxation``) their damping grows with the step, and a light body's limit on them falls
        with it: the bodies' cap is the largest limit c with c >= its own limit at the damping of a step CAP_FRACTION
        c, found by bisection (in log c, to 10 %); the confluences' limits (which grow with that damping) are then
        taken at it, twice."""
        previous = self.cap
        self._limits = {}
        drag = self._drag_damping()
        fixed = min([(self.rule.largest / CAP_FRACTION, "the largest step")] + self._rotation_limits()
                    + self._contact_limits(), key=lambda item: item[0])

        found: dict = {}   # a step's body limits depend on it only through the lines' relaxation times (a grid)

        def bodies_at(cap):
            taus = tuple(self.method.relaxation(CAP_FRACTION * cap, system) for system in self.model.systems)
            if taus not in found:
                found[taus] = min([fixed] + self._body_limits(CAP_FRACTION * cap, drag), key=lambda item: item[0])
            return found[taus]
        cap = bodies_at(fixed[0])
        relaxing = any(self.method.relaxation(CAP_FRACTION * fixed[0], s) > 0.0 for s in self.model.systems)
        if cap[0] < fixed[0] and relaxing:
            low, high = cap[0], fixed[0]
            while high > 1.1 * low:
                middle = math.sqrt(low * high)
                low, high = (middle, high) if bodies_at(middle)[0] >= middle else (low, middle)
            cap = bodies_at(low)
        for _ in range(2 if relaxing else 1):
            cap = min([cap] + self._confluence_limits(CAP_FRACTION * cap[0]), key=lambda item: item[0])
        self.unrelaxed = {system.name: CAP_FRACTION * min([math.inf] + [limit for limit, _ in
                                                                      self._confluence_limits(0.0, system)])
                          for system in self.model.systems
                          if self.method.relaxation(CAP_FRACTION * cap[0], system) > 0.0}
        self.cap, self.cause = cap
        steady = abs(self.cap - previous) <= CAP_STEADY * self.cap
        self.interval = min(2.0 * self.interval, CAP_INTERVAL_LONGEST) if steady and not self._schedules_moving() \
            else CAP_INTERVAL   # a schedule's fraction counts for two intervals (``drag_area_fraction``)
        self.next_check, self.steps_since_check = t + self.interval, 0
        if CAP_FRACTION * self.cap < self.rule.smallest:
            what = f"at t = {t:.3f} s {self.cause} limits RK4 to {self.cap:.3g} s, below the smallest adaptive step " \
                   f"{self.rule.smallest:g} s"
            remedy = self._remedies.get(self.cause)   # a layout or a setting the method names (``StepLimit.remedy``)
            raise SimulationError(f"{what}. {remedy}" if remedy else
                                  f"{what}: the model has a mode too fast to integrate explicitly (check the masses, "
                                  "inertias and line stiffnesses), or use --method full --integrator implicit", t)

    def _body_limits(self, step: float, drag: dict) -> list:
        """Each moving body's translational mode on all its lines (their stiffness and damping summed, as if they
        pulled along one direction, the damping as the method relaxes it at ``step``, s) with its drag's damping
        (``_drag_damping``): ``body_line_step_limit``."""
        lines = []
        for system in self.model.systems:
            stiffness, damping = self._constants[system.name]
            tau = self.method.relaxation(step, system)
            if tau > 0.0:   # the lines as the method damps them at that step
                stiffness, damping = self._relaxed_system(system, tau)[1]
            lines.append((system, stiffness, damping))
        return body_limits(line_sums(lines, self.model.massless, self._tethers), drag)

    def _rotation_limits(self) -> list:
        """Each moving body's pitching on its lines: the tension T of each line at its attach point p (from the centre
        of mass) turns the body back with a stiffness up to T |p| (N m/rad) about the axes across p, against the
        body's smallest moment of inertia about them; RK4's limit on the imaginary axis, RK4_IMAGINARY_LIMIT / omega."""
        stiff: dict = {}
        for system in self.model.systems:
            for line in system.lines:
                body = self.case.bodies[line.body]
                if body.fixed or line.body in self.model.massless:
                    continue
                tension = float(self.model.channels[TensionChannel(system.name, line.name)]())
                arm, inertia = self._lever(line)
                if tension > 0.0 and arm > 0.0:
                    stiff.setdefault(line.body, []).append(tension * arm / inertia)
        return [(RK4_IMAGINARY_LIMIT / math.sqrt(sum(rates)), f"body {body} pitching on its lines")
                for body, rates in stiff.items()]

    def _contact_limits(self) -> list:
        """Each cluster's canopies on their contacts (``engine.contact_loads``), every pair counted touching (the
        stiffest case; in a steady descent their envelopes touch): the modes of the mass-weighted contact network,
        each canopy also on its lines' own stiffness and damping as if the confluence were held, and RK4's limit
        along their rays. Without it a relaxed cluster's steps grow to the contacts' 5 Hz (RK4's limit at 0.09 s)
        and the canopies chatter on each other. Constants of the phase, worked out once."""
        if self._contacts is None:
            stage = self.model.stage
            self._contacts = [] if stage is None else [self._contact_limit(contact) for contact in stage.contacts]
        return self._contacts

    def _contact_limit(self, contact) -> tuple:
        """(limit in s, cause) of one cluster's contact network (``_contact_limits``)."""
        names = [load.body for load in contact.loads]
        count = len(names)
        stiffness, damping = np.zeros((count, count)), np.zeros((count, count))
        for a, b, k, c in contact.pairs:   # each pair's spring-damper between its two canopies
            for matrix, value in ((stiffness, k), (damping, c)):
                matrix[[int(a), int(b)], [int(a), int(b)]] += value
                matrix[[int(a), int(b)], [int(b), int(a)]] -= value
        for system in self.model.systems:
            for line, k, c in zip(system.lines, *self._constants[system.name]):
                if line.body in names:
                    i = names.index(line.body)
                    stiffness[i, i] += k
                    damping[i, i] += c
        scale = 1.0 / np.sqrt([self.case.bodies[name].mass for name in names])
        state = np.block([[np.zeros((count, count)), np.eye(count)],
                          [-scale[:, None] * stiffness * scale, -scale[:, None] * damping * scale]])
        return max_stable_step_rk4(np.linalg.eigvals(state)), f"the canopies {', '.join(names)} on their contacts"

    def _lever(self, line) -> tuple:
        """(|p| in m, the body's smallest moment of inertia across p in kg m^2) of a line's attach point p: constants
        of the body, worked out once (an SVD and an eigensolve each time cost the caps' check half its time)."""
        key = (line.body, line.point)
        if key not in self._levers:
            body = self.case.bodies[line.body]
            lever = np.asarray(body.points[line.point], float)
            arm = float(np.linalg.norm(lever))
            self._levers[key] = (arm, crosswise_inertia(body.inertia, lever) if arm > 0.0 else math.nan)
        return self._levers[key]

    def _relaxed_system(self, system, tau: float) -> tuple:
        """(``method.relaxed(system, tau)``, its ``line_constants``): constants of the phase for each relaxation
        time ``tau`` (s, on the method's grid), worked out once."""
        key = (system.name, tau)
        if key not in self._relaxed:
            relaxed = self.method.relaxed(system, tau)
            self._relaxed[key] = (relaxed, line_constants(relaxed))
        return self._relaxed[key]

    def _confluence_limits(self, step: float, only=None) -> list:
        """(limit, cause) of each confluence (or ``only``'s) with its lines as the method relaxes them at ``step``
        (s), kept per system and relaxation until the next check of the caps, and of the method's own states at
        ``step`` (``Method.state_limits``)."""
        limits = []
        for system in self.model.systems if only is None else [only]:
            confluence = self.model.confluences.get(system.name)
            if confluence is None:
                continue
            key = (system.name, self.method.relaxation(step, system))
            if key not in self._limits:
                relaxed = self._relaxed_system(system, key[1])[0]
                self._limits[key] = self.method.confluence_limits(relaxed, self.model.attach_positions(system),
                                                                  confluence.state_position())
            for found in self._limits[key]:
                if math.isfinite(found.value):
                    limits.append((found.value, found.cause))
                    if found.remedy:
                        self._remedies[found.cause] = found.remedy
            limits += [(found.value, found.cause) for found in self.method.state_limits(self.model, system, step)]
        return limits

    def _drag_damping(self) -> dict:
        """``drag_damping`` at the end of the last step."""
        stage = self.model.stage
        rows = stage.settled_rows() if stage is not None else None

        def state(name):
            row = rows[stage.row[name]]
            return row[ROW_POSITION], row[ROW_VELOCITY]
        return drag_damping(self.model, self.case, self.last_end, None if rows is None else state)

    def _schedules_moving(self) -> bool:
        """Whether a drag-area schedule still changes (the caps are then checked every CAP_INTERVAL)."""
        return any(member is not None and hasattr(member.schedule, "time")
                   and self.last_end - member.deployed_at < member.schedule.time[-1]
                   for member in self.model.aerodynamic_loads.values())

    def summary(self) -> dict:
        """The steps taken: smallest, largest and mean (s), and their count."""
        if not self.steps:
            return {}
        return {"smallest": self.smallest, "largest": self.largest, "mean": self.total / self.steps,
                "count": self.steps}


def drag_damping(model: Model, case: Case, t: float, state, fraction=None) -> dict:
    """Each moving body of ``model``'s phase (a reduced canopy is none) at time ``t`` (s): its mass (kg; with the air
    it carries along its axis when it has an apparent mass) and its drag's damping rho V S C_A (N s/m, the derivative
    of the drag 0.5 rho V^2 S C_A by the air speed V, S the drag area open now and for two check intervals: a reefed
    canopy's fraction of it, ``drag_area_fraction``), from ``state(name)``: its position (m) and velocity (m/s) in
    the start frame; 0 without aerodynamics, and for every body when ``state`` is None (no state known).
    ``fraction(model, name, t)``: the drag-area fraction (-) to take instead of ``drag_area_fraction``'s."""
    fraction = drag_area_fraction if fraction is None else fraction
    air = case.air_motion()
    found = {}
    for name in model.phase.bodies:
        if name in model.massless:
            continue
        body = case.bodies[name]
        mass, damping = body.mass, 0.0
        aerodynamics = body.aerodynamics
        if state is not None and case.atmosphere is not None and aerodynamics is not None and aerodynamics.enabled:
            position, velocity = state(name)
            x, y, z = position
            altitude = case.start.altitude_scalar(x, y, z)
            speed = math.dist(velocity, air(x, y, z, altitude, t))
            density = case.atmosphere.density(altitude)
            if body.apparent_mass is not None:
                mass += body.apparent_mass.masses(density)[0][0]
            open_share = fraction(model, name, t)
            damping = density * speed * open_share * aerodynamics.reference_area * largest_coefficient(aerodynamics)
        found[name] = (mass, damping)
    return found


def drag_area_fraction(model: Model, body: str, t: float) -> float:
    """The largest drag-area fraction (-) of ``body`` from ``t`` (s) until two check intervals later: a drag-area
    schedule's (reefed, disreefing), 1 for an opening whose fill is measured as it goes (``InflationProgress``: its
    future is unknown) and a body without a schedule."""
    member = model.aerodynamic_loads.get(body)
    schedule = None if member is None else member.schedule
    if schedule is None or not hasattr(schedule, "fraction"):
        return 1.0
    since = t - member.deployed_at
    until = since + 2.0 * CAP_INTERVAL
    return max([schedule(since), schedule(until)]
               + [f for time, f in zip(schedule.time, schedule.fraction) if since < time < until])


def line_sums(lines, massless, tethers) -> dict:
    """Body -> [sum K (N/m), sum C (N s/m)] of the lines on it, as if they pulled along one direction: ``lines`` is
    (system, stiffness, damping) per system, the line constants as the run flies them; a reduced canopy (in
    ``massless``) has its own limit (``Method.state_limits``); ``tethers``: ``tether_constants``."""
    sums: dict = {}
    for system, stiffness, damping in lines:
        for line, k, c in zip(system.lines, stiffness, damping):
            if line.body in massless:
                continue
            total = sums.setdefault(line.body, [0.0, 0.0])
            total[0] += k
            total[1] += c
    for body, k, c in tethers:
        total = sums.setdefault(body, [0.0, 0.0])
        total[0] += k
        total[1] += c
    return sums


def body_limits(sums, drag: dict) -> list:
    """(limit in s, cause) of each body in ``drag`` (``drag_damping``) on the lines summed in ``sums``
    (``line_sums``) and its drag: ``body_line_step_limit``."""
    limits = []
    for body, (mass, damping) in drag.items():
        k, c = sums.get(body, (0.0, 0.0))
        limit = body_line_step_limit(mass, [k], [c + damping])
        what = "its lines and its drag" if body in sums and damping > 0.0 else "its lines" if body in sums \
            else "its drag"
        limits.append((limit, f"body {body} on {what}"))
    return limits


def crosswise_inertia(inertia, lever) -> float:
    """The smallest moment of inertia (kg m^2) of a body about the axes across ``lever`` (m, body axes)."""
    unit = np.asarray(lever, float) / np.linalg.norm(lever)
    basis = np.linalg.svd(unit.reshape(1, 3))[2][1:]   # two unit vectors across the lever
    return float(np.linalg.eigvalsh(basis @ np.asarray(inertia, float) @ basis.T).min())


def largest_coefficient(aerodynamics) -> float:
    """The largest axial coefficient C_A (-) of a body's table (over Mach and angle), times the largest drag-area
    fraction an opening reaches is left to the caller's margin (CAP_FRACTION)."""
    values = np.abs(np.asarray(aerodynamics.axial_coefficient.value, float))
    return float(values.max()) if values.size else 0.0

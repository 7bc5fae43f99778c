"""The singular-perturbation method (thesis chapter 3): the confluence velocity from the line-force balance
(Eq. 3.10), with the least confluence damping that keeps the solve conditioned (Eq. 3.13) while a line is slack."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..case.method_table import OptionError
from ..engine.sp import SPConfluence, build_sp_model
from ..errors import InputError
from ..physics.linearization import (
    ILL_CONDITIONED,
    crosswise_damping_ratio,
    damped_line_step_limit,
    sp_step_limit,
)
from ..physics.singular_perturbation import SLACK_RULES, SP_ORDERS, relaxed_damping
from .base import Method, StepLimit, line_arrays, line_constants, option_field

PRESETS = {"accurate": {"kappa_max": 10.0, "order": 1, "relaxation_time": 0.0},
           "thesis": {"kappa_max": 5.0, "order": 0, "relaxation_time": 0.0},
           "any_damping": {"kappa_max": 10.0, "order": 1, "relaxation_time": 5e-3}}
"""SP presets: kappa_max, the confluence-mass order and the relaxation time they stand for. ``thesis``: the thesis's
settings (Eq. 3.10, kappa_max = 5). ``accurate`` (the default): the confluence mass to first order, which removes the
error of the massless balance where the confluence swings with a body (MER cases 5-6, PA1's rocking capsule), and
kappa_max = 10, which halves the artificial confluence damping while a line is slack (MER cases 3-4): at most 1.3 N
of tension error after 2 s in every MER case at 1e-2 s, against 82 N with the thesis's settings, at the same cost
(validation/output/benchmark_sp.md). kappa_max = 20 is as accurate at 1e-2 s but not at 2e-2 s. ``any_damping``:
accurate's settings with a relaxation time of 5e-3 s, half the thesis's step: every line is damped at least tau K in
the solve (``relaxed``), so RK4 at 1e-2 s is stable for any line damping, none included (docs/models/any_damping.md)."""


RELAXED_STEPS = 1.5
"""An adaptive step over the relaxation time it asks for (``SingularPerturbation.relaxation_for_step``): RK4 is
stable on the real mode -1/tau up to 2.785 tau: 1.86 such steps, a margin for the sideways stiffness of stretched
lines (the mode of a loaded MER or pchute new confluence runs up to 1.5 times faster than -1/tau) and the grid of
tau (9 %). More relaxation (a smaller ratio) makes a light body's mode on its damped lines faster (tau K / m) and
changes the lines' tensions more: at 1.35 a canopy under a 100 kg vehicle on three bridles was left bouncing by
7.5 % of its riser's load in a steady descent (``tests/test_step_control.py``)."""


@dataclass(frozen=True)
class SPOptions:
    """Options of the SP method (``[simulation.sp]`` in a case file).

    Attributes
    ----------
    preset : {"accurate", "thesis"}
        The kappa_max and order to use where they are not given (``PRESETS``).
    kappa_max : float or None
        Largest condition number of alpha (Eq. 3.13) accepted while a line is slack (-, > 3; the thesis used 5);
        None: the preset's.
    slack_rule : {"stretch", "force"}
        stretch: a line is slack when L <= L0 (the thesis); force: also when its tension would push (active set).
    order : {0, 1} or None
        Order in the confluence mass: 0 drops it (Eq. 3.10, the thesis), 1 keeps its weight and inertia to first
        order; None: the preset's.
    """

    preset: str = option_field("accurate", "--sp-preset", str, "kappa_max, order and relaxation time unless given: "
                               "thesis = 5, 0, 0 (the thesis's settings), accurate = 10, 1, 0 (the default), "
                               "any_damping = 10, 1, 5 ms (any line damping, none included)", tuple(PRESETS))
    kappa_max: float | None = option_field(None, "--kappa-max", float, "largest condition number of alpha (thesis "
                                           "Eq. 3.13) while a line is slack, > 3 (default: the preset's)")
    slack_rule: str = option_field("stretch", "--slack-rule", str, "when a line counts as slack: stretch = L <= L0 "
                                   "(the thesis), force = its tension would push (active set)", SLACK_RULES)
    order: int | None = option_field(None, "--sp-order", int, "0 = massless confluence (Eq. 3.10, the thesis), 1 = "
                                     "its weight and inertia kept to first order (default: the preset's)", SP_ORDERS)
    relaxation_time: float | None = option_field(None, "--sp-relaxation-time", float, "tau (s, 0 to 1): each line is "
                                                 "damped at least tau K, so the confluence relaxes no faster than "
                                                 "1/tau; RK4 is stable up to a step of about 2.5 tau for any line "
                                                 "damping (default: the preset's; 0 = off)")

    def __post_init__(self):
        if self.preset not in PRESETS:
            raise OptionError("preset", self.preset, f"must be one of: {', '.join(PRESETS)}")
        kappa = self.kappa_max
        if kappa is not None:
            if isinstance(kappa, bool) or not isinstance(kappa, (int, float)) or \
                    not (math.isfinite(kappa) and kappa > 3):
                raise OptionError("kappa_max", kappa, "must be > 3 (the Frobenius condition number of Eq. 3.13 "
                                                      "is at least 3 for any 3x3 matrix; the thesis used 5)")
            object.__setattr__(self, "kappa_max", float(kappa))
        if self.slack_rule not in SLACK_RULES:
            raise OptionError("slack_rule", self.slack_rule, f"must be one of: {', '.join(SLACK_RULES)}")
        tau = self.relaxation_time
        if tau is not None:
            if isinstance(tau, bool) or not isinstance(tau, (int, float)) or not (math.isfinite(tau) and 0 <= tau <= 1):
                raise OptionError("relaxation_time", tau, "must be within 0..1 (s): the confluence's slowest allowed "
                                                          "relaxation (0 = off)")
            object.__setattr__(self, "relaxation_time", float(tau))
        if self.order is not None:
            if isinstance(self.order, bool) or self.order not in SP_ORDERS:
                raise OptionError("order", self.order, "must be 0 (the massless balance of Eq. 3.10, the thesis) or "
                                                       "1 (the confluence mass kept to first order)")
            object.__setattr__(self, "order", int(self.order))

    @property
    def effective_kappa_max(self) -> float:
        """kappa_max in effect (-): the given one, else the preset's."""
        return PRESETS[self.preset]["kappa_max"] if self.kappa_max is None else self.kappa_max

    @property
    def effective_order(self) -> int:
        """The confluence-mass order in effect: the given one, else the preset's."""
        return PRESETS[self.preset]["order"] if self.order is None else self.order

    @property
    def effective_relaxation_time(self) -> float:
        """The relaxation time in effect (s): the given one, else the preset's."""
        return PRESETS[self.preset]["relaxation_time"] if self.relaxation_time is None else self.relaxation_time

    def summary(self) -> dict:
        tau = self.effective_relaxation_time   # only when on: summaries of runs without it keep their keys
        return {"sp_preset": self.preset, "kappa_max": self.effective_kappa_max, "slack_rule": self.slack_rule,
                "sp_order": self.effective_order, **({"sp_relaxation_time": tau} if tau > 0.0 else {})}


class SingularPerturbation(Method):
    """The confluence's position integrated in step with the engine's RK4 stages (``physics.sp_stepping``) inside the
    bodies' force item; RK4 only: an implicit solver evaluates the forces at Newton iterates and for its Jacobian,
    not at RK stages."""

    name = "sp"
    summary = "singular perturbation: the confluence velocity from the line-force balance (thesis ch. 3)"
    step_limited = True
    record_variants = ({"order": 0}, {"order": 1}, {"slack_rule": "force"})
    integrator_note = ("its confluence is integrated in step with RK4's four stages, which an implicit solver's "
                       "Newton iterations do not follow; use rk4 (--dt auto for adaptive steps), or --method full "
                       "with implicit")
    Options = SPOptions
    outputs = {name: unit for name, (unit, _) in SPConfluence.OUTPUTS.items()}

    def relaxed(self, system, relaxation_time: float = 0.0):
        """``system`` as the solve sees it: each line damped at least tau K (``physics.singular_perturbation.
        relaxed_damping``), tau the larger of the options' relaxation time and ``relaxation_time`` (s, an adaptive
        step's: ``relaxation_for_step``); itself without one."""
        tau = max(self.options.effective_relaxation_time, relaxation_time)
        if tau <= 0.0:
            return system
        stiffness, damping = line_constants(system)
        floors = relaxed_damping(stiffness, damping, tau)
        return replace(system, lines=tuple(replace(line, damping=c) for line, c in zip(system.lines, floors)))

    def relaxation_for_step(self, step: float, system) -> float:
        """At an adaptive step ``step`` (s) the lines are damped at least tau K with tau = step / RELAXED_STEPS
        beyond the options' own relaxation time (docs/models/step_control.md): the confluence's damped mode, rate K / C
        (Eq. 3.10 linearised), then never limits RK4 below 1.86 steps, and a line already damped more is as it is.
        Steps that long are taken only where the motion is smooth, where the lines stretch slowly. A pair in series
        has no confluence mode and is not relaxed. tau is rounded down to a grid of eighth octaves, so that the
        lines' damping changes only when the step has changed by 9 %. A cluster's lines are not relaxed either: its
        canopies' flyout and breathing keep them stretching, and damping them more changes how the canopies share
        the load (on ``pchute new``'s three-canopy Mars cluster the tensions left their steady values by 9 % within
        10 s with relaxed lines, by 2.3 % at a fixed 0.01 s and without relaxation)."""
        if len(system.lines) == 2:
            return 0.0
        if len(system.canopies) > 1:
            return self.options.effective_relaxation_time
        tau = step / RELAXED_STEPS   # on a grid of eighth octaves, rounded down: it changes only every 9 %
        tau = 2.0 ** (math.floor(8.0 * math.log2(tau)) / 8.0) if tau > 0.0 else 0.0
        return max(self.options.effective_relaxation_time, tau)

    def check(self, case, integrator):
        super().check(case, integrator)
        if not case.free_bodies():
            raise InputError("the sp method moves the confluence inside the moving bodies' force item, and every body "
                             "of this case is fixed (the chapter 2 system): use --method full or equilibrium")
        if self.options.effective_relaxation_time > 0.0:
            return
        undamped = [case.line_label(system, line) for system, line in case.lines() if line.damping <= 0.0]
        if undamped:
            every = "every line" if len(undamped) == len(case.lines()) else f"line(s) {', '.join(undamped)}"
            raise InputError(f"the sp method needs damping on every line, but {every} has zero damping: alpha of "
                             "Eq. 3.6 is built from the line damping and is singular whenever only undamped lines are "
                             "taut; use --sp-preset any_damping (a relaxation time), or --method full")

    def build(self, case, phase):
        if self.options.effective_relaxation_time > 0.0:
            case = replace(case, systems={name: self.relaxed(system) for name, system in case.systems.items()})
        return build_sp_model(case, phase, self.options)

    def step_limit(self, system, attach_position, confluence_position) -> StepLimit:
        if len(system.lines) == 2:   # a pair in series has no confluence mode (``solve_series``)
            return StepLimit(system.name, math.inf, complex(0.0))
        mass = system.confluence.mass if self.options.effective_order == 1 else 0.0
        lines = line_arrays(self.relaxed(system), attach_position, confluence_position)
        step, eigenvalue = sp_step_limit(attach_position, confluence_position, *lines, mass=mass,
                                         kappa_max=self.options.effective_kappa_max)
        return StepLimit(system.name, step, eigenvalue, self._cause(system, step, attach_position,
                                                                    confluence_position, lines))

    def _cause(self, system, step, attach_position, confluence_position, lines) -> str:
        """What makes a short limit short, and its remedy (``StepLimit.cause``): lines nearly collinear or in one
        plane under the massless preset, or lines damped too little for the step."""
        if step >= 1e-2:
            return ""
        ratio = crosswise_damping_ratio(attach_position, confluence_position, *lines)
        if ratio < ILL_CONDITIONED and self.options.effective_order == 0:
            return (f"The {system.name} system's lines are nearly collinear or in one plane (the damping across them "
                    f"is {ratio:.2g} of that along them), and the massless balance of the {self.options.preset} "
                    "preset has almost none there: use --sp-preset accurate (the confluence's mass to first order "
                    "damps it), or --method equilibrium")
        rates = [k / c for k, c in zip(lines[1], lines[2]) if c > 0.0]
        if rates and step <= 1.2 * 2.785 / max(rates) and self.options.effective_relaxation_time <= 0.0:
            return (f"The {system.name} system's lines are damped too little for the step (K/C up to "
                    f"{max(rates):.3g} 1/s): use --sp-preset any_damping (a relaxation time), or --dt auto "
                    "(adaptive steps)")
        return ""

    def lumped_step_limit(self, system) -> float:
        if len(system.lines) == 2:
            return math.inf
        return damped_line_step_limit(*line_constants(self.relaxed(system)))

"""SP's options (``[simulation.sp]`` in a case file, ``--sp-*`` flags) and presets, each with its default, its
validation and its meaning in one place."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...registries.methods import OptionError
from ..base import option_field
from .balance import SLACK_RULES, SP_ORDERS

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


RELAXED_BODY_MARGIN = 2.0
"""A fixed step may be up to this many times the RK4 limit of the bodies' motion on the relaxed lines
(``SingularPerturbation.check_step``): that estimate (the bodies pulled against each other through every line of a
system in series, damped tau K) is pessimistic; the runs diverged at about 3 times it (MER case 1 at 1e-2 s between
tau = 0.2 and 0.4 s, PA1 between 0.3 and 0.5 s)."""


RELAXED_STEPS = 1.5
"""An adaptive step over the relaxation time it asks for (``SingularPerturbation.relaxation``): RK4 is
stable on the real mode -1/tau up to 2.785 tau: 1.86 such steps, a margin for the sideways stiffness of stretched
lines (the mode of a loaded MER or pchute new confluence runs up to 1.5 times faster than -1/tau) and the grid of
tau (9 %). More relaxation (a smaller ratio) makes a light body's mode on its damped lines faster (tau K / m) and
changes the lines' tensions more: at 1.35 a canopy under a 100 kg vehicle on three bridles was left bouncing by
7.5 % of its riser's load in a steady descent (``tests/integration/test_step_control.py``)."""


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

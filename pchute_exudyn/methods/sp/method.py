"""The singular-perturbation method (thesis chapter 3) as the method table sees it: its checks, its model, its step
limits and how it relaxes its confluence for long adaptive steps. The package around it holds the rest of SP: its
options and presets (``options``), the confluence at run time (``confluence``, ``reduced_canopy``), the model builder
(``builder``), its compiled kernels (``balance``, ``stepping``, ``canopy_kernels``) and their named memory
(``memory``)."""

from __future__ import annotations

import math
from dataclasses import replace

from ...errors import InputError
from ...physics.linearization import (
    ILL_CONDITIONED,
    body_line_step_limit,
    crosswise_damping_ratio,
    damped_line_step_limit,
    sp_step_limit,
)
from ...physics.rk4 import RK4_REAL_LIMIT
from ..base import Method, StepLimit, line_arrays, line_constants
from .balance import relaxed_damping
from .builder import build_sp_model
from .confluence import RATE_MEMORY, SPConfluence
from .options import PRESETS, RELAXED_BODY_MARGIN, RELAXED_STEPS, SPOptions


class SingularPerturbation(Method):
    """The confluence's position integrated in step with the engine's RK4 stages (``stepping``) inside the
    bodies' force item; RK4 only: an implicit solver evaluates the forces at Newton iterates and for its Jacobian,
    not at RK stages."""

    name = "sp"
    summary = "singular perturbation: the confluence velocity from the line-force balance (thesis ch. 3)"
    step_limited = True
    flies_reduced_canopies = True
    record_variants = ({"order": 0}, {"order": 1}, {"slack_rule": "force"})
    integrator_note = ("its confluence is integrated in step with RK4's four stages, which an implicit solver's "
                       "Newton iterations do not follow; use rk4 (--dt auto for adaptive steps), or --method full "
                       "with implicit")
    Options = SPOptions
    outputs = {name: unit for name, (unit, _) in SPConfluence.OUTPUTS.items()}

    def relaxed(self, system, relaxation_time: float = 0.0):
        """``system`` as the solve sees it: each line damped at least tau K (``balance.relaxed_damping``), tau the
        larger of the options' relaxation time and ``relaxation_time`` (s, an adaptive step's: ``relaxation``);
        itself without one."""
        tau = max(self.options.effective_relaxation_time, relaxation_time)
        if tau <= 0.0:
            return system
        stiffness, damping = line_constants(system)
        floors = relaxed_damping(stiffness, damping, tau)
        return replace(system, lines=tuple(replace(line, damping=c) for line, c in zip(system.lines, floors)))

    def relaxation(self, step: float, system) -> float:
        """At an adaptive step ``step`` (s) the lines are damped at least tau K with tau = step / RELAXED_STEPS
        beyond the options' own relaxation time (docs/models/step_control.md): the confluence's damped mode, rate K / C
        (Eq. 3.10 linearised), then never limits RK4 below 1.86 steps, and a line already damped more is as it is.
        Steps that long are taken only where the motion is smooth, where the lines stretch slowly. A pair in series
        has no confluence mode and is not relaxed. tau is rounded down to a grid of eighth octaves, so that the
        lines' damping changes only when the step has changed by 9 %. A cluster's lines are relaxed as a single
        canopy's: its flyout keeps them stretching, and the relaxation's cap (``relaxation_cap``: the extra damping
        within ``run.step_control.RELAXATION_SHARE`` of each line's tension) keeps its steps short while they do,
        so the canopies share the load as at a fixed step (docs/models/step_control.md, "Clusters")."""
        if len(system.lines) == 2:
            return 0.0
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

    def check_step(self, case, step: float) -> None:
        """Refuse a fixed step (s) that the relaxation time makes unstable: tau K on every line moves the bodies
        against each other at a rate (C over their reduced mass, ``body_line_step_limit``) that rises with tau."""
        tau = self.options.effective_relaxation_time
        if tau <= 0.0:
            return
        for system in case.systems.values():
            by_body = {}
            for line, k, c in zip(system.lines, *line_constants(self.relaxed(system))):
                total = by_body.setdefault(line.body, [0.0, 0.0])
                total[0], total[1] = total[0] + k, total[1] + c
            masses = [case.bodies[b].mass for b in by_body if not case.bodies[b].fixed]
            if len(by_body) < 2 or not masses or min(sum(t) for t in by_body.values()) <= 0.0:
                continue
            series = [1.0 / sum(1.0 / t[i] for t in by_body.values()) if all(t[i] > 0 for t in by_body.values())
                      else 0.0 for i in (0, 1)]
            mass = 1.0 / sum(1.0 / m for m in masses)
            limit = body_line_step_limit(mass, [series[0]], [series[1]])
            if step > RELAXED_BODY_MARGIN * limit:
                allowed = tau * RELAXED_BODY_MARGIN * limit / step
                raise InputError(f"sp relaxation time (--sp-relaxation-time) = {tau:g} s: its damping tau K moves "
                                 f"the {system.name} system's bodies against each other at up to "
                                 f"{series[1] / mass:.3g} 1/s, too fast for the RK4 step {step:g} s (limit "
                                 f"{limit:.3g} s): use at most {float(f'{allowed:.2g}'):g} s (any_damping's "
                                 f"{PRESETS['any_damping']['relaxation_time']:g} s), or --dt "
                                 f"{float(f'{0.9 * RELAXED_BODY_MARGIN * limit:.2g}'):g}")

    def build(self, case, phase):
        if self.options.effective_relaxation_time > 0.0:
            case = replace(case, systems={name: self.relaxed(system) for name, system in case.systems.items()})
        return build_sp_model(case, phase, self.options)

    def confluence_limits(self, system, attach_position, confluence_position, explicit: bool = True) -> list:
        """The confluence's damped mode at this geometry with the lines as the solve sees them (``sp_step_limit``:
        the confluence mass in it for order 1); none for a pair in series (``physics.lines.solve_series``)."""
        if len(system.lines) == 2:
            return []
        mass = system.confluence.mass if self.options.effective_order == 1 else 0.0
        lines = line_arrays(self.relaxed(system), attach_position, confluence_position)
        step, eigenvalue = sp_step_limit(attach_position, confluence_position, *lines, mass=mass,
                                         kappa_max=self.options.effective_kappa_max)
        return [StepLimit(step, f"the {system.name} confluence ({self.name} method, mode {eigenvalue:.4g} 1/s)",
                          self._cause(system, step, attach_position, confluence_position, lines), eigenvalue,
                          system.name)]

    def lumped_limit(self, system, explicit: bool = True) -> StepLimit | None:
        """The lines' damped mode at free length (``damped_line_step_limit``; inf for a pair in series, None when
        no line is damped)."""
        value = math.inf if len(system.lines) == 2 else damped_line_step_limit(*line_constants(self.relaxed(system)))
        return None if value is None else StepLimit(value, f"the {system.name} confluence ({self.name} method)",
                                                    system=system.name)

    def state_limits(self, model, system, step: float) -> list:
        """A reduced canopy's drag point at a step ``step`` (s) (``reduced_canopy.ReducedCanopy.step_limit``)."""
        confluence = model.confluences.get(system.name)
        if confluence is None or confluence.canopy is None:
            return []
        value = confluence.canopy.step_limit(confluence.settled().work, step)
        return [StepLimit(value, f"the {system.name} system's reduced canopy", system=system.name)]

    def relaxation_cap(self, model, system, t: float, own: float, share: float) -> float:
        """RELAXED_STEPS times the relaxation time that keeps each taut line's tension within ``share`` (-) of its
        own at the lines' stretch rates (``SPConfluence.relaxation_allowed``), never below ``own`` (s); for the
        first RATE_MEMORY s of a phase (a deployment, a cut-away, a cluster's flyout) the confluence has not seen
        the lines move yet: ``own``."""
        allowed = model.confluences[system.name].relaxation_allowed(share, t)   # every look: it keeps the envelope
        return own if t - model.phase.start < RATE_MEMORY else max(own, RELAXED_STEPS * allowed)

    def _cause(self, system, step, attach_position, confluence_position, lines) -> str:
        """What makes a short limit short, and its remedy (``StepLimit.remedy``): lines nearly collinear or in one
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
        if rates and step <= 1.2 * RK4_REAL_LIMIT / max(rates) and self.options.effective_relaxation_time <= 0.0:
            return (f"The {system.name} system's lines are damped too little for the step (K/C up to "
                    f"{max(rates):.3g} 1/s): use --sp-preset any_damping (a relaxation time), or --dt auto "
                    "(adaptive steps)")
        return self._relaxed_remedy(system, step, attach_position, confluence_position)

    def _relaxed_remedy(self, system, step, attach_position, confluence_position) -> str:
        """The any_damping preset as the remedy of a limit (s) below 1e-2 s that it lifts to 1e-2 s or more (its
        design step) without a relaxation time in effect; "" otherwise."""
        if self.options.effective_relaxation_time > 0.0:
            return ""
        preset = PRESETS["any_damping"]
        lines = line_arrays(self.relaxed(system, preset["relaxation_time"]), attach_position, confluence_position)
        relaxed, _ = sp_step_limit(attach_position, confluence_position, *lines, mass=system.confluence.mass,
                                   kappa_max=preset["kappa_max"])
        if not relaxed >= 1e-2:
            return ""
        return (f"The {system.name} system's lines are damped too little for the step: use --sp-preset any_damping "
                f"(a relaxation time; its limit here: {relaxed:.3g} s), or --dt auto (adaptive steps)")

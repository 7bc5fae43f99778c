"""The method interface: what a confluence method is to the rest of the package.

A method is a class registered in the method table (``registries.methods.METHODS``): it says which integrators it
supports, owns a frozen ``Options`` type (its options, their defaults and their validation in one place), builds its
Exudyn model for a phase, gives its explicit-step limit and names the per-system quantities it reports.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import ClassVar

import numpy as np

from ..case.model import Case, ParachuteSystem
from ..engine.state import Phase
from ..registries.methods import INTEGRATORS, NoOptions, OptionError, make_options


def option(flag: str | None, parse, help: str, choices: tuple | None = None) -> dict:
    """Field metadata of a method option: its command-line ``flag`` (None: none), the function that reads the
    flag's text, its help and its choices."""
    return {"flag": flag, "parse": parse, "help": help, "choices": choices}


def option_field(default, flag: str | None, parse, help: str, choices: tuple | None = None):
    """A dataclass field for a method option (see ``option``)."""
    return field(default=default, metadata=option(flag, parse, help, choices))


@dataclass(frozen=True)
class StepLimit:
    """The largest stable RK4 step (s) one mode of a model allows, as a method reports it.

    Attributes
    ----------
    value : float
        The step (s); inf when nothing limits it.
    cause : str
        What sets it, as a message names it ("the main confluence (sp method, mode -123.4 1/s)").
    remedy : str
        What would lift it, when a layout or a setting of the method makes the mode fast (the message then says so
        instead of offering a step); "" when a smaller step is the remedy.
    eigenvalue : complex
        The limiting eigenvalue of the linearised mode (1/s), 0 when the limit is not a mode's.
    system : str
        The parachute system it belongs to.
    """

    value: float
    cause: str
    remedy: str = ""
    eigenvalue: complex = 0j
    system: str = ""


SMALLEST_SUGGESTED_STEP = 1e-6
"""s: a stability limit below it is never offered as a step (a layout or a setting is the cause: the message says
which, or that the mode is too fast for RK4)."""


class Method:
    """Base class of the confluence methods (see the module docstring).

    Parameters
    ----------
    options : Options, optional
        The method's validated options; default: the Options type's defaults.
    """

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    integrators: ClassVar[tuple] = ("rk4",)
    Options: ClassVar[type] = NoOptions
    outputs: ClassVar[dict] = {}
    """Per-system quantities the method reports: name -> unit (columns ``<name>`` or ``<system>_<name>``)."""
    integrator_note: ClassVar[str] = ""
    """Why the method runs with its integrators only (for the message refusing another)."""
    record_variants: ClassVar[tuple] = ({},)
    """Option sets under which ``tools.record_signatures`` runs the method (each option set a different kernel path)."""
    step_limited: ClassVar[bool] = False
    """Whether the method's confluences have dynamics that limit an explicit step (``confluence_limits``)."""
    flies_reduced_canopies: ClassVar[bool] = False
    """Whether a system's ``canopy_model = "reduced"`` is flown as such (every other method flies the canopy rigid)."""
    implicit_hint: ClassVar[str] = ""
    """What to suggest besides a smaller step when an RK4 step exceeds the limit (e.g. the implicit integrator)."""

    def __init__(self, options=None):
        self.options = self.Options() if options is None else options

    @classmethod
    def configure(cls, case: Case, values: dict | None = None) -> Method:
        """The method with the case's options for it, overridden by ``values`` (validated: OptionError)."""
        base = case.simulation.options.get(cls.name)
        return cls(make_options(cls.Options, values or {}, base))

    def check(self, case: Case, integrator: str) -> None:
        """Refuse an integrator the method does not support, or a case it cannot solve (OptionError)."""
        if integrator not in INTEGRATORS:
            integrators = ", ".join(INTEGRATORS)
            raise OptionError("integrator", integrator, f"must be one of: {integrators}",
                              f"unknown integrator {integrator!r}; integrators are: {integrators}")
        if integrator not in self.integrators:
            note = f": {self.integrator_note}" if self.integrator_note else ""
            raise OptionError("integrator", integrator, f"must be one of: {', '.join(self.integrators)}",
                              f"the {self.name} method runs with --integrator {' or '.join(self.integrators)} only"
                              + note)

    def check_step(self, case: Case, step: float) -> None:
        """Refuse a fixed RK4 step (s) a setting of the method makes unstable before the run (InputError); the step
        monitor checks the confluences' limit during it."""

    def build(self, case: Case, phase: Phase):  # pragma: no cover - interface
        """The method's Exudyn model of ``case`` for one phase (an ``engine.phase_model.Model``)."""
        raise NotImplementedError

    # -- the method's step limits: ``run.step_control`` takes their minimum ------------------------------------------

    def confluence_limits(self, system: ParachuteSystem, attach_position, confluence_position,
                          explicit: bool = True) -> list:
        """The StepLimits of ``system``'s confluence at this geometry (m): RK4's stability limits of its modes, or,
        for an implicit integrator (``explicit`` False), the step that resolves its fastest damped mode (the
        accuracy scale); empty when the method has no confluence dynamics. A method that runs implicitly says its
        accuracy scale here and in ``lumped_limit`` (full mass: its damped mode as the massless solve has it);
        without one, a case that sets no step has it chosen from its bodies' limits alone."""
        return []

    def lumped_limit(self, system: ParachuteSystem, explicit: bool = True) -> StepLimit | None:
        """A geometry-free bound of ``confluence_limits``, for choosing a step before any geometry exists
        (``run.step_control.stability_step``): inf when the method has no confluence dynamics; None (unknown: the
        run needs a step) for a step-limited method that cannot say."""
        if self.step_limited:
            return None
        return StepLimit(math.inf, f"the {system.name} confluence ({self.name} method)", system=system.name)

    def state_limits(self, model, system: ParachuteSystem, step: float) -> list:
        """StepLimits of the method's own states in ``model`` (an ``engine.phase_model.Model``) at a step ``step`` (s),
        beyond its confluence's modes (SP: a reduced canopy's drag point); none by default."""
        return []

    def relaxation(self, step: float, system: ParachuteSystem) -> float:
        """The relaxation time (s) of ``system``'s line damping at an adaptive step of ``step`` (s;
        ``run.step_control``): 0, none, unless the method relaxes its confluence to take steps beyond its damped
        mode."""
        return 0.0

    def relaxed(self, system: ParachuteSystem, relaxation_time: float = 0.0) -> ParachuteSystem:
        """``system`` as the method's solve sees it at ``relaxation_time`` (s): itself unless the method relaxes."""
        return system

    def relaxation_cap(self, model, system: ParachuteSystem, t: float, own: float, share: float) -> float:
        """The longest adaptive step (s) at time ``t`` (s) whose relaxation keeps ``system``'s tensions within
        ``share`` (-) of their own, never below ``own`` (s: the step the lines' own damping allows); inf when the
        method does not relax."""
        return math.inf

    def settings(self) -> dict:
        """The options as ``summary.json`` reports them."""
        report = getattr(self.options, "summary", None)
        return report() if report is not None else asdict(self.options)


def line_constants(system: ParachuteSystem) -> tuple[list, list]:
    """The stiffest constants of a system's lines: K (N/m; ``LineLaw.stiffest``) and C (N s/m)."""
    laws = [line.law for line in system.lines]
    return [law.stiffest for law in laws], [law.damping for law in laws]


def line_arrays(system: ParachuteSystem, attach_position=None, confluence_position=None) -> tuple[list, list, list]:
    """Free lengths (m), stiffnesses (N/m) and damping constants (N s/m) of a system's lines; with the geometry
    given, a line with a load-elongation table has its tangent stiffness there (``LineLaw.slope``)."""
    laws = [line.law for line in system.lines]
    stiffness = [law.stiffness for law in laws]
    if attach_position is not None and any(law.table is not None for law in laws):
        lengths = np.linalg.norm(np.asarray(attach_position, float) - np.asarray(confluence_position, float)[:3],
                                 axis=-1)
        stiffness = [law.slope(length - law.free_length) for length, law in zip(lengths, laws)]
    return [law.free_length for law in laws], stiffness, [law.damping for law in laws]


def unstable_step_message(method: Method, step: float, limit: StepLimit, time: float) -> str:
    """The error text for an RK4 step beyond a confluence's stability limit."""
    suggestion = float(f"{0.9 * limit.value:.2g}")  # below the limit even after rounding
    mode = limit.eigenvalue
    mode_text = f"{mode.real:.4g} {'+' if mode.imag >= 0 else '-'} {abs(mode.imag):.4g}i" if mode.imag else \
        f"{mode.real:.4g}"
    what = (f"the RK4 step {step:g} s exceeds the stability limit of the {limit.system} confluence ({method.name} "
            f"method) at t = {time:.3f} s ({limit.value:.3g} s, set by its mode lambda = {mode_text} 1/s, counting "
            f"every line as taut, the stiffest case): the results would be wrong")
    if limit.remedy:
        return f"{what}. {limit.remedy}"
    if suggestion < SMALLEST_SUGGESTED_STEP:
        return (f"{what}. That mode is too fast for any explicit step: check the lines' stiffness and damping and "
                f"the masses{method.implicit_hint or ', or use --method full --integrator implicit'}")
    return f"{what}. Use --dt {suggestion:g} or smaller{method.implicit_hint}"

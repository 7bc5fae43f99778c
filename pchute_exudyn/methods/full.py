"""The full-mass method (thesis Eqs. 1.1-1.7): the confluence as a 3-DoF point mass; the reference solution."""

from __future__ import annotations

from dataclasses import dataclass

from ..engine.full_model import build_full_model
from ..physics.linearization import damped_line_step_limit, full_mass_step_limit, sp_step_limit, spectral_step_bound
from ..registries.methods import OptionError
from .base import Method, StepLimit, line_arrays, line_constants, option_field

LINE_LAWS = ("symbolic", "python")


@dataclass(frozen=True)
class FullMassOptions:
    """Options of the full-mass method.

    Attributes
    ----------
    line_law : {"symbolic", "python"}
        How the tension-only line law runs in the engine: an Exudyn symbolic user function (fast, the default) or a
        Python one (exists to measure the difference).
    """

    line_law: str = option_field("symbolic", None, str, "how the line law runs in the engine", LINE_LAWS)

    def __post_init__(self):
        if self.line_law not in LINE_LAWS:
            raise OptionError("line_law", self.line_law, f"must be one of: {', '.join(LINE_LAWS)}")


class FullMass(Method):
    """The confluence as a point mass with gravity; each line an Exudyn spring-damper with the tension-only law."""

    name = "full"
    summary = "the confluence as a 3-DoF point mass (thesis Eqs. 1.1-1.7), the reference"
    integrators = ("rk4", "implicit")
    step_limited = True
    Options = FullMassOptions
    implicit_hint = ", or --integrator implicit"

    def build(self, case, phase):
        return build_full_model(case, phase, symbolic_line_law=self.options.line_law == "symbolic")

    def confluence_limits(self, system, attach_position, confluence_position, explicit: bool = True) -> list:
        """The point mass's modes on its lines at this geometry (``full_mass_step_limit``); for an implicit
        integrator, stable at any step, the step that resolves the confluence's fastest damped mode, as the massless
        solve has it (``sp_step_limit``): the step is then for accuracy."""
        lines = line_arrays(system, attach_position, confluence_position)
        if explicit:
            step, eigenvalue = full_mass_step_limit(system.confluence.mass, attach_position, confluence_position,
                                                    *lines)
        else:
            step, eigenvalue = sp_step_limit(attach_position, confluence_position, *lines)
        return [StepLimit(step, f"the {system.name} confluence ({self.name} method, mode {eigenvalue:.4g} 1/s)",
                          eigenvalue=eigenvalue, system=system.name)]

    def lumped_limit(self, system, explicit: bool = True) -> StepLimit | None:
        """A bound that holds in any layout (``spectral_step_bound``); implicit: the lines' damped mode at free length
        (``damped_line_step_limit``; None when no line is damped)."""
        constants = line_constants(system)
        value = spectral_step_bound(system.confluence.mass, *constants) if explicit else \
            damped_line_step_limit(*constants)
        return None if value is None else StepLimit(value, f"the {system.name} confluence ({self.name} method)",
                                                    system=system.name)

"""The supersonic opening of a disk-gap-band parachute: its opening-load factor, its fill distance and its breathing,
all set by the conditions at line stretch (``docs/models/supersonic_opening.md``).

The fill-constant law (``physics.inflation``) fills the canopy to C_x f_n and lets it fall back to f_n. This model
chooses C_x, the fill constant n and the area oscillation that follows from what the canopy meets at line stretch:

    C_k(M) = [C_ref + s_M (M - M_ref)] (1 - k_w d / D_0)       the opening-load factor (the fill law's C_x): the peak
                                                               drag area over the filled one with the vehicle held
                                                               at its line-stretch speed (infinite mass), M clamped
                                                               to the Mach range the constants were fitted over;
                                                               d / D_0 the forebody's diameter over the canopy's
                                                               (a blunt capsule's wake lowers the peak)
    n(M)   = the fill constant's table in Mach (or the stage's n without one): t_f = n D_0 / V
    f(s)   = f_n [1 + A(M) sin(2 pi St V_ls (s - s_b) / D_0)]  after the overinflation has decayed (s >= s_b): the
                                                               breathing, A(M) the relative amplitude against the
                                                               canopy's current Mach number, St a Strouhal number
                                                               on D_0 and the line-stretch speed

The dynamic pressure and the mass ratio act through the flight itself: the vehicle slows during the fill (finite
mass), so a light vehicle at a high q opens with a smaller peak over q S C_D than C_k. Plain floats; no engine.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .interpolation import interpolate_held
from .invalid import InvalidField


class OpeningError(InvalidField):
    """Invalid supersonic-opening input; ``field`` names its key."""


@dataclass(frozen=True)
class MachTable:
    """A quantity against Mach number, linear between the points, held at the end values outside them.

    Attributes
    ----------
    mach : tuple of float
        Strictly increasing Mach numbers (-).
    value : tuple of float
        The quantity at each (its unit is the caller's).
    """

    mach: tuple
    value: tuple

    def __call__(self, mach: float) -> float:
        return interpolate_held(self.mach, self.value, mach)


@dataclass(frozen=True)
class SupersonicOpening:
    """The opening-load factor, fill distance and breathing of a supersonic disk-gap-band (module docstring).

    Attributes
    ----------
    load_factor : float
        C_ref (-), >= 1: the opening-load factor at ``reference_mach`` without a forebody wake.
    reference_mach : float
        M_ref (-), > 0.
    mach_slope : float
        s_M (-, per unit Mach): the change of C_k with the line-stretch Mach number.
    mach_range : tuple of float
        (M_low, M_high) (-): the Mach numbers C_k is fitted over; outside, C_k holds its end value.
    wake_coefficient : float
        k_w (-), >= 0.
    forebody_diameter : float
        d (m), >= 0: the leading body's diameter.
    fill_constant : MachTable or None
        n against the line-stretch Mach number (-); None: the stage's own fill constant.
    breathing_amplitude : MachTable or None
        A against the canopy's current Mach number (-, each in [0, 1)); None: no breathing.
    breathing_strouhal : float
        St (-), > 0 with a breathing amplitude: the breathing frequency is St V_ls / D_0 (Hz).
    """

    load_factor: float
    reference_mach: float = 1.8
    mach_slope: float = 0.0
    mach_range: tuple = (1.0, 2.5)
    wake_coefficient: float = 0.0
    forebody_diameter: float = 0.0
    fill_constant: MachTable | None = None
    breathing_amplitude: MachTable | None = None
    breathing_strouhal: float = 0.2

    def __post_init__(self):
        _check(math.isfinite(self.load_factor) and self.load_factor >= 1.0, "load_factor", self.load_factor,
               "must be >= 1 (the peak drag area over the filled one)")
        _check(self.reference_mach > 0.0, "reference_mach", self.reference_mach, "must be > 0")
        low, high = self.mach_range
        _check(0.0 < low < high, "mach_range", list(self.mach_range), "must be [low, high] with 0 < low < high")
        _check(self.wake_coefficient >= 0.0, "wake_coefficient", self.wake_coefficient, "must be >= 0")
        _check(self.forebody_diameter >= 0.0, "forebody_diameter", self.forebody_diameter, "must be >= 0 (m)")
        _check(math.isfinite(self.mach_slope), "mach_slope", self.mach_slope, "must be a finite number")
        if self.breathing_amplitude is not None:
            _check(all(0.0 <= a < 1.0 for a in self.breathing_amplitude.value), "breathing_amplitude",
                   list(self.breathing_amplitude.value), "each must be in [0, 1) (relative to the filled area)")
            _check(self.breathing_strouhal > 0.0, "breathing_strouhal", self.breathing_strouhal, "must be > 0")
        if self.fill_constant is not None:
            _check(all(n > 0.0 for n in self.fill_constant.value), "fill_constant",
                   list(self.fill_constant.value), "each must be > 0")

    def law_at(self, mach: float, nominal_diameter: float) -> float:
        """The law's C_k (-) at line-stretch Mach number ``mach`` (clamped to ``mach_range``) for a canopy of nominal
        diameter D_0 (m), before ``load_factor_at`` holds it at 1 (below 1 the law is outside its validity)."""
        low, high = self.mach_range
        clamped = min(max(mach, low), high)
        wake = 1.0 - self.wake_coefficient * self.forebody_diameter / nominal_diameter
        return (self.load_factor + self.mach_slope * (clamped - self.reference_mach)) * wake

    def load_factor_at(self, mach: float, nominal_diameter: float) -> float:
        """C_k (-) at line-stretch Mach number ``mach`` for a canopy of nominal diameter D_0 (m); never below 1."""
        return max(self.law_at(mach, nominal_diameter), 1.0)

    def fill_constant_at(self, mach: float, stage_value: float) -> float:
        """n (-) at line-stretch Mach number ``mach``: the table's, or ``stage_value`` without one."""
        return stage_value if self.fill_constant is None else self.fill_constant(mach)

    def breathing(self, elapsed: float, mach: float, speed: float, nominal_diameter: float) -> float:
        """The breathing's factor on the filled drag area (-) ``elapsed`` s after it starts, at the canopy's current
        Mach number ``mach`` with line-stretch speed ``speed`` (m/s) and D_0 (m)."""
        if self.breathing_amplitude is None or elapsed <= 0.0:
            return 1.0
        frequency = self.breathing_strouhal * speed / nominal_diameter
        return 1.0 + self.breathing_amplitude(mach) * math.sin(2.0 * math.pi * frequency * elapsed)


def _check(condition: bool, field: str, value, message: str) -> None:
    if not condition:
        raise OpeningError(field, value, message)


def mass_ratio(density: float, drag_area: float, mass: float) -> float:
    """R_m = rho (C_D S)^(3/2) / m (-): the air a canopy's drag area sweeps against the vehicle's mass (density in
    kg/m^3, drag area in m^2, mass in kg); near 0 an opening is close to infinite mass."""
    return density * drag_area ** 1.5 / mass

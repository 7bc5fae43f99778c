"""Knacke's opening-force hand check: the peak force of an opening from the conditions at line stretch, with Pflanz's
force-reduction factor (T. W. Knacke, *Parachute Recovery Systems Design Manual*, NWC TP 6575, Naval Weapons
Center, March 1991, section 5.5, "Pflanz's method", the X_1 curves against A of Fig. 5-51)::

    F_o = C_x X_1 q C_D S                     q = rho v^2 / 2 at line stretch; C_x the opening-force coefficient at
                                              infinite mass (the canopy type's ``overinflation``)
    A   = 2 m / (C_D S rho v t_f)             Pflanz's ballistic parameter (-), t_f the fill time
        = sqrt(pi C_D0) / (n R_m)             with t_f = n D_0 / v and R_m = rho (C_D S)^(3/2) / m (canopy loading)

Pflanz's model behind X_1: the vehicle flies straight, without gravity, under the drag area C_D S (t / t_f)^j alone
(j the opening exponent: 2 solid cloth, 1 slotted canopies, 1/2 in Knacke's figure too). Then
v / v_ls = 1 / (1 + tau^(j+1) / ((j+1) A)) at tau = t / t_f, and the drag over q_ls C_D S is
X(tau) = tau^j / (1 + tau^(j+1) / ((j+1) A))^2; X_1 is its largest value on 0 <= tau <= 1, in closed form:

    tau_m^(j+1) = j (j+1) A / (j+2)           the peak inside the fill (tau_m < 1): X_1 = ((j+2) / (2(j+1)))^2 tau_m^j
    otherwise                                  the peak at full open (tau = 1):    X_1 = (1 + 1 / ((j+1) A))^-2

(the same closed forms as Ludtke, "A Technique for the Calculation of the Opening-Shock Forces for Several Types of
Solid Cloth Parachutes", AIAA 73-477, 1973, without his overinflation). X_1 -> 1 at infinite mass (A -> infinity,
R_m -> 0) and falls as the vehicle lightens. Plain floats; no engine.
"""

from __future__ import annotations

import math

from .invalid import InvalidField


class OpeningForceError(InvalidField):
    """Invalid opening-force input; ``field`` names the argument."""


def _positive(field: str, value: float) -> None:
    if not (math.isfinite(value) and value > 0.0):
        raise OpeningForceError(field, value, "must be a finite number > 0")


def ballistic_parameter(mass: float, drag_area: float, density: float, speed: float, fill_time: float) -> float:
    """Pflanz's A = 2 m / (C_D S rho v t_f) (-): mass in kg, the filled drag area C_D S in m^2, the air density in
    kg/m^3, the line-stretch speed in m/s and the fill time in s (Knacke, section 5.5)."""
    for field, value in (("mass", mass), ("drag_area", drag_area), ("density", density), ("speed", speed),
                         ("fill_time", fill_time)):
        _positive(field, value)
    return 2.0 * mass / (drag_area * density * speed * fill_time)


def ballistic_parameter_from_mass_ratio(mass_ratio: float, fill_constant: float, drag_coefficient: float) -> float:
    """A = sqrt(pi C_D0) / (n R_m) (-): Pflanz's A for the fill time t_f = n D_0 / v, from the canopy-loading ratio
    R_m = rho (C_D S)^(3/2) / m (-, ``supersonic_opening.mass_ratio``), the fill constant n (-) and C_D0 on the
    nominal area S_0 = pi D_0^2 / 4 (-). The speed drops out: A, and so X_1, is a function of R_m alone."""
    for field, value in (("mass_ratio", mass_ratio), ("fill_constant", fill_constant),
                         ("drag_coefficient", drag_coefficient)):
        _positive(field, value)
    return math.sqrt(math.pi * drag_coefficient) / (fill_constant * mass_ratio)


def peak_fill_fraction(ballistic: float, exponent: float) -> float:
    """tau_m = t_m / t_f (-) at which Pflanz's opening force peaks, at most 1 (the peak at full open): A (-) the
    ballistic parameter, j (-) the drag-area growth exponent."""
    _positive("ballistic", ballistic)
    _positive("exponent", exponent)
    inside = (exponent * (exponent + 1.0) * ballistic / (exponent + 2.0)) ** (1.0 / (exponent + 1.0))
    return min(inside, 1.0)


def force_reduction_factor(ballistic: float, exponent: float) -> float:
    """Pflanz's X_1 (-), in (0, 1]: the peak drag over q_ls C_D S of a vehicle of ballistic parameter A (-) whose
    drag area grows as (t / t_f)^j, j = ``exponent`` (-) (module docstring; Knacke Fig. 5-51)."""
    tau = peak_fill_fraction(ballistic, exponent)
    slowing = 1.0 + tau ** (exponent + 1.0) / ((exponent + 1.0) * ballistic)
    return tau ** exponent / slowing ** 2


def opening_force(overinflation: float, reduction: float, dynamic_pressure: float, drag_area: float) -> float:
    """Knacke's F_o = C_x X_1 q C_D S (N): C_x (-) the opening-force coefficient at infinite mass, X_1 (-) the
    force-reduction factor, q (Pa) the dynamic pressure at line stretch, C_D S (m^2) the filled drag area."""
    for field, value in (("overinflation", overinflation), ("reduction", reduction),
                         ("dynamic_pressure", dynamic_pressure), ("drag_area", drag_area)):
        _positive(field, value)
    return overinflation * reduction * dynamic_pressure * drag_area


def knacke_opening_force(mass: float, drag_area: float, density: float, speed: float, fill_time: float,
                         exponent: float, overinflation: float) -> float:
    """F_o (N) of one canopy opening at line stretch: mass (kg), filled drag area C_D S (m^2), air density (kg/m^3),
    line-stretch speed (m/s), fill time (s), drag-area growth exponent j (-) and C_x (-); X_1 by Pflanz."""
    ballistic = ballistic_parameter(mass, drag_area, density, speed, fill_time)
    reduction = force_reduction_factor(ballistic, exponent)
    return opening_force(overinflation, reduction, 0.5 * density * speed ** 2, drag_area)

"""A slender cylindrical body's aerodynamics at any angle of attack: the rocket as it hangs under its canopies
(``docs/models/slender_body.md``).

The cross-flow model of Allen & Perkins (NACA Report 1048, 1951) as Jorgensen extends it to 180 deg (NASA TR R-474,
1977): the normal-force coefficient on the reference area A_ref = pi d^2 / 4 is the slender-body potential term plus
the cross-flow drag of the body's planform A_p = L d::

    C_N(alpha) = (A_b / A_ref) sin(2 alpha) cos(alpha / 2) + eta C_dc (A_p / A_ref) sin^2(alpha)

with A_b the base area (a cylinder without boat-tail: A_ref), C_dc the cross-flow drag coefficient of an infinite
circular cylinder and eta the ratio of a finite cylinder's drag to an infinite one's at the body's L / d
(Wieselsberger's cylinders, the factor Jorgensen uses). The axial force takes the axial part of the dynamic pressure,
C_A(alpha) = C_A,0 cos^2(alpha) nose first (alpha < 90 deg) and -C_A,180 cos^2(alpha) tail first: with the axial
coefficients of a cylinder in axial flow (Hoerner, Fluid-Dynamic Drag, 1965): skin friction on the wetted area, plus
the blunt base's drag nose first, or the flat face's forebody drag tail first. Subsonic, subcritical cross flow (a
rocket under a drogue: V d / nu about 1e5). Signs as ``physics.aerodynamics`` takes a table over the total angle to
180 deg: C_A > 0 pushes toward the tail, C_N > 0 opposes the cross-flow velocity.
"""

from __future__ import annotations

import math

CROSSFLOW_DRAG = 1.2
"""C_dc (-): an infinite circular cylinder's drag coefficient in subcritical cross flow (Re 1e4 to 2e5), on its
projected area (Hoerner 1965, ch. 3; Wieselsberger's 1.20)."""
FINITE_CYLINDER_DRAG = ((1.0, 0.64), (2.0, 0.68), (3.0, 0.72), (5.0, 0.74), (10.0, 0.82), (20.0, 0.91),
                        (40.0, 0.98))
"""(L / d, C_D) of circular cylinders of finite length in subcritical cross flow (Wieselsberger's, as tabulated by
Goldstein 1938 and Hoerner 1965): eta = C_D / CROSSFLOW_DRAG, Jorgensen's finite-length factor."""
SKIN_FRICTION = 0.0037
"""C_f (-): the turbulent flat plate's mean skin friction at Re = 3e6 (Prandtl-Schlichting 0.455 / (log10 Re)^2.58;
a 2.5 m rocket at 20 m/s), on the wetted area."""
FLAT_FACE_DRAG = 0.8
"""A flat-faced cylinder's forebody pressure drag in axial flow (-, on its frontal area; Hoerner 1965, ch. 3): the
base leading, tail first."""
BASE_DRAG_CONSTANT = 0.029
"""Hoerner's subsonic base drag C_D,base = 0.029 / sqrt(C_D,forebody) (-, on the base area; Hoerner 1965, ch. 3)."""


def finite_length_factor(length: float, diameter: float) -> float:
    """eta (-): a circular cylinder's drag in cross flow at its ``length`` / ``diameter`` (m / m) over an infinite
    one's, linear in L / d between FINITE_CYLINDER_DRAG's points and held beyond them."""
    ratio = length / diameter
    points = FINITE_CYLINDER_DRAG
    if ratio <= points[0][0]:
        return points[0][1] / CROSSFLOW_DRAG
    for (low, low_drag), (high, high_drag) in zip(points, points[1:]):
        if ratio <= high:
            return (low_drag + (high_drag - low_drag) * (ratio - low) / (high - low)) / CROSSFLOW_DRAG
    return points[-1][1] / CROSSFLOW_DRAG


def crossflow_normal_coefficient(alpha_deg: float, length: float, diameter: float,
                                 crossflow_drag: float = CROSSFLOW_DRAG) -> float:
    """C_N (-, on pi d^2 / 4) of a cylinder ``length`` by ``diameter`` (m) at the total angle of attack ``alpha_deg``
    (deg, 0 to 180; module docstring), ``crossflow_drag`` the infinite cylinder's C_dc (-)."""
    alpha = math.radians(alpha_deg)
    planform = length * diameter / (math.pi * diameter**2 / 4.0)
    potential = math.sin(2.0 * alpha) * math.cos(alpha / 2.0)   # A_b / A_ref = 1: no boat-tail
    return potential + finite_length_factor(length, diameter) * crossflow_drag * planform * math.sin(alpha)**2


def axial_coefficients(length: float, diameter: float, friction: float = SKIN_FRICTION) -> tuple:
    """(C_A,0 nose first, C_A,180 tail first) (-, each > 0, on pi d^2 / 4) of a cylinder ``length`` by ``diameter``
    (m) in axial flow, ``friction`` the skin friction coefficient C_f (-): C_f on the wetted side pi d L, plus
    Hoerner's base drag nose first, or the flat face's forebody drag tail first (the nose then trailing, no base)."""
    skin = friction * 4.0 * length / diameter
    return skin + BASE_DRAG_CONSTANT / math.sqrt(skin), skin + FLAT_FACE_DRAG


def axial_coefficient(alpha_deg: float, length: float, diameter: float, friction: float = SKIN_FRICTION) -> float:
    """C_A (-, on pi d^2 / 4) at the total angle of attack ``alpha_deg`` (deg, 0 to 180): the axial coefficients
    (``axial_coefficients``) on the axial part of the dynamic pressure, cos^2(alpha); negative tail first (the force
    then pushes toward the nose, against the flow along the axis)."""
    nose_first, tail_first = axial_coefficients(length, diameter, friction)
    along = math.cos(math.radians(alpha_deg))
    return (nose_first if along >= 0.0 else -tail_first) * along * along

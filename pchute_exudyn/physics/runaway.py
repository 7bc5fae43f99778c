"""Physical bounds of a run: the air speed and rate no body of a case can reach unless the integration (or a model
that adds energy) has run away (``docs/models/conventions.md``, "Divergence").

A case gives every body at most its start speed, the speed of a fall in vacuum from its start altitude to the
ground, and the air's speed (the steady wind at its strongest, six standard deviations of turbulence and every
gust's amplitude): the case's speed scale

    V_case = v_start + sqrt(2 g (h_start - h_ground)) + W

(m/s; g the gravity at the start point). A body is running away when the start-frame speed of its aerodynamic
centre exceeds SPEED_MULTIPLE V_case plus what the planet's rotation gives a point at rest on the ground
(Omega (R_e + h_start)), or its angular rate exceeds RATE_MULTIPLE (omega_start + V_case / k), k its smallest radius
of gyration sqrt(I_min / m) (the fastest a body can turn when a point at that radius moves at V_case). Both
multiples leave room for what lines can give a light canopy (a snatch throws it at up to twice the vehicle's speed);
a divergence passes them within a few steps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

SPEED_MULTIPLE = 4.0
"""A body's speed beyond this many times the case's speed scale (``RunawayLimits``) is a runaway."""
RATE_MULTIPLE = 4.0
"""A body's angular rate beyond this many times its rate scale is a runaway."""
TURBULENCE_SIGMAS = 6.0
"""Standard deviations of turbulence counted in the air's largest speed."""
RUNAWAY = 3.0
"""Status code of ``physics.aerodynamics.aerodynamics_stage``: a body beyond its bounds (the value: its index)."""


@dataclass(frozen=True)
class RunawayLimits:
    """What the bodies of a case can reach, and beyond which a run has diverged (module docstring).

    Attributes
    ----------
    start_speed : float
        The largest start speed of any body relative to the ground (m/s).
    fall_speed : float
        sqrt(2 g drop) (m/s), the vacuum fall from the highest start altitude to the ground.
    wind_speed : float
        The air's largest speed over the ground (m/s): steady wind, turbulence and gusts.
    ground_speed : float
        The planet rotation's speed at the start altitude (m/s; the start frame is inertial).
    start_rate : float
        The largest start angular rate of any body (rad/s).
    radii : dict of str to float
        Each body's smallest radius of gyration (m).
    """

    start_speed: float
    fall_speed: float
    wind_speed: float
    ground_speed: float = 0.0
    start_rate: float = 0.0
    radii: dict = field(default_factory=dict)

    @property
    def scale(self) -> float:
        """V_case (m/s)."""
        return self.start_speed + self.fall_speed + self.wind_speed

    @property
    def speed(self) -> float:
        """The start-frame speed (m/s) no aerodynamic centre may exceed."""
        return SPEED_MULTIPLE * self.scale + self.ground_speed

    def rate(self, body: str) -> float:
        """The angular rate (rad/s) body ``body`` may not exceed (infinite when it has no radius: a fixed body)."""
        radius = self.radii.get(body)
        return math.inf if not radius else RATE_MULTIPLE * (self.start_rate + self.scale / radius)

    def message(self, body: str, quantity: str, value: float, time: float) -> str:
        """One line for body ``body`` whose ``quantity`` ("speed" or "rate") reached ``value`` (m/s or rad/s) at
        ``time`` (s)."""
        parts = (f"{self.start_speed:.3g} m/s at the start, {self.fall_speed:.3g} m/s of free fall to the ground, "
                 f"{self.wind_speed:.3g} m/s of air")
        if quantity == "speed":
            limit = f"{self.speed:.3g} m/s, {SPEED_MULTIPLE:g} times the {self.scale:.3g} m/s this case can give " \
                    f"({parts}{', plus the ground turning' if self.ground_speed else ''})"
            what = f"its speed reached {value:.3g} m/s"
        else:
            limit = (f"{self.rate(body):.3g} rad/s, {RATE_MULTIPLE:g} times what {self.scale:.3g} m/s ({parts}) "
                     f"turns it at its radius of gyration, {self.radii.get(body, math.nan):.3g} m")
            what = f"its angular rate reached {value:.3g} rad/s"
        return (f"body {body} ran away at t = {time:.4f} s: {what}, beyond {limit}; the integration diverged or "
                "the model adds energy: try a smaller step (--dt), and check the masses and inertias against the "
                "lines' stiffness and the aerodynamic tables")


def wind_bound(steady: float, turbulence_sigma: float, gusts) -> float:
    """The air's largest speed over the ground (m/s): the ``steady`` wind's largest, TURBULENCE_SIGMAS times the
    largest turbulence intensity ``turbulence_sigma`` (m/s) and the ``gusts``' amplitudes (m/s) added."""
    return steady + TURBULENCE_SIGMAS * turbulence_sigma + sum(abs(amplitude) for amplitude in gusts)


def fall_speed(gravity: float, drop: float) -> float:
    """sqrt(2 g drop) (m/s) for gravity ``gravity`` (m/s^2) and ``drop`` (m; 0 when negative)."""
    return math.sqrt(2.0 * gravity * max(drop, 0.0))

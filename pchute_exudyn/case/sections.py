"""The vehicle's sections: bodies it carries until they separate (a heat shield, a nose cone thrown off by a charge)
and the tethers that tie two bodies together (a rocket's shock cord, a static line): frozen, validated data
(``case.read_triggers`` reads ``[separations]``, ``case.read_tethers`` reads ``[tethers]``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..physics.line_materials import RatedLine
from ..physics.lines import LineLaw


@dataclass(frozen=True)
class Separation:
    """A body the vehicle carries (its mass and inertia part of the vehicle's) until it separates as its own 6-DoF
    body (heat shield, forward bay cover).

    Attributes
    ----------
    body : str
        The carried body (a body of the case without an initial state).
    position : tuple of 3 float
        Where its centre of mass rides, in vehicle body axes from the vehicle's own centre of mass (m); its axes are
        the vehicle's.
    speed : float
        Relative speed (m/s) of the two after separation, along ``direction``; momentum is conserved.
    direction : tuple of 3 float
        Unit vector in vehicle body axes: the way the body leaves.
    time : float
        Run time (s) of the separation; inf until its trigger fires (``case.events``).
    """

    body: str
    position: tuple
    speed: float
    direction: tuple
    time: float = math.inf

    def carried_at(self, time: float) -> bool:
        """Whether the body still rides with the vehicle at ``time`` (s)."""
        return time < self.time


@dataclass(frozen=True)
class Tether:
    """A tension-only line from a point of one body to a point of another, with no confluence: a rocket's shock cord
    from the booster to the nose cone, a static line. Slack (carrying nothing, or its payout resistance while it pays
    out) until its ends are its free length apart, then the line law (``physics.lines``); it acts while both bodies
    fly on their own (not while one rides in the other).

    Attributes
    ----------
    name : str
    ends : tuple of 2 (body, point)
        The bodies and their points (body axes) it ties.
    law : LineLaw
        Its tension-only law (``physics.lines``): L0 (m), K (N/m), C (N s/m), a load-elongation table, and the
        payout resistance R (N) it pulls with while slack and paying out (its ends moving apart).
    rating : RatedLine or None
        The material and breaking strength a case named.
    breaking_strength : float or None
        N: the load it is rated to; the run warns when a load exceeds it (the summary's margin).
    """

    name: str
    ends: tuple
    law: LineLaw
    rating: RatedLine | None = None
    breaking_strength: float | None = None

    def acts_between(self, bodies) -> bool:
        """Whether both its ends are among ``bodies`` (names of the free or fixed bodies a phase flies)."""
        return all(body in bodies for body, _ in self.ends) and self.ends[0][0] != self.ends[1][0]

"""Triggers that cannot fire from the case's start state: a warning when the case loads (docs/models/triggers.md,
"Triggers that cannot fire").

Only what the start state decides is judged here (a threshold whose quantity depends on the flight to come, such
as a speed that grows in free fall, is not): an altitude threshold below the ground the run ends on, and one above
the start that a vehicle not climbing never reaches. An apogee trigger is never in doubt: its first sample fires
when the vehicle already descends or hangs at apogee (``physics.triggers.Apogee``).
"""

from __future__ import annotations

from ..physics.triggers import Threshold


def unreachable_triggers(triggers: dict, initial, ground_altitude: float | None) -> tuple:
    """One warning line per trigger of ``triggers`` (event -> Trigger) that cannot fire from the vehicle's initial
    state ``initial`` (``InitialState``: altitude in m, velocity_down in m/s; None for a release, which is not judged)
    before touchdown on ``ground_altitude`` (m above the ellipsoid; None: the run has no ground)."""
    lines = []
    for trigger in triggers.values():
        condition = trigger.condition
        if not isinstance(condition, Threshold) or condition.quantity != "altitude":
            continue
        offset = (ground_altitude or 0.0) if condition.reference == "ground" else 0.0
        level = condition.value + offset   # m above the ellipsoid
        if condition.below and ground_altitude is not None and level <= ground_altitude:
            lines.append(f"{trigger.key} cannot fire: the run ends at touchdown on the ground at "
                         f"{ground_altitude:g} m before the altitude falls to {level:g} m")
        elif not condition.below and initial is not None and initial.altitude < level \
                and initial.velocity_down >= 0.0:
            lines.append(f"{trigger.key} cannot fire from the start state: the vehicle starts at "
                         f"{initial.altitude:g} m, below {level:g} m, and does not climb (vertical speed "
                         f"{0.0 - initial.velocity_down + 0.0:g} m/s)")
    return tuple(lines)

"""Triggers that cannot fire from the case's start state: a warning when the case loads (docs/models/triggers.md,
"Triggers that cannot fire").

Only what the start state decides is judged here (a threshold whose quantity depends on the flight to come, such
as a speed that grows in free fall, is not): an altitude threshold below the ground the run ends on, and one above
the start that a vehicle not climbing never reaches; a level to fall below that the start is already below fires at
its first sample (a main that opens with the drogue). An apogee trigger is never in doubt: its first sample fires
when the vehicle already descends or hangs at apogee (``triggers.definition.Apogee``).
"""

from __future__ import annotations

from ..registries.quantities import QUANTITY
from ..triggers.definition import Apogee, Threshold, UserFunction, leaves

SENSOR_ERRORS = {"pressure_noise": "pressure", "pressure_bias": "pressure", "correlation_time": "pressure",
                 "speed_noise": "speed", "speed_bias": "speed"}
"""A trigger's sensor keys of an error, and the error each is of (``registries.quantities.Quantity.error``)."""


def unreachable_triggers(triggers: dict, initial, ground_altitude: float, stop_at_ground: bool) -> tuple:
    """One warning line per trigger of ``triggers`` (event -> Trigger) that cannot fire from the vehicle's initial
    state ``initial`` (``InitialState``: altitude in m, velocity_down in m/s; None for a release, which is not judged)
    before touchdown on ``ground_altitude`` (m above the ellipsoid; ``stop_at_ground`` False: the run flies on below
    it, and a level below the ground is reached)."""
    lines = []
    for trigger in triggers.values():
        condition = trigger.condition
        if not isinstance(condition, Threshold) or condition.quantity != "altitude":
            continue
        offset = ground_altitude if condition.reference == "ground" else 0.0
        level = condition.value + offset   # m above the ellipsoid
        if condition.below and stop_at_ground and level <= ground_altitude:
            lines.append(f"{trigger.key} cannot fire: the run ends at touchdown on the ground at "
                         f"{ground_altitude:g} m before the altitude falls to {level:g} m")
        elif condition.below and initial is not None and initial.altitude <= level:
            lines.append(f"{trigger.key} is met from the start: the vehicle starts at {initial.altitude:g} m, already "
                         f"below {level:g} m{_above_ground(condition)}, so it fires at its first sample (a level "
                         "below the start is what waits for the descent)")
        elif not condition.below and initial is not None and initial.altitude < level \
                and initial.velocity_down >= 0.0:
            lines.append(f"{trigger.key} cannot fire from the start state: the vehicle starts at "
                         f"{initial.altitude:g} m, below {level:g} m, and does not climb (vertical speed "
                         f"{0.0 - initial.velocity_down + 0.0:g} m/s)")
    return tuple(lines)


def _above_ground(condition) -> str:
    return f" ({condition.value:g} m above the ground)" if condition.reference == "ground" else ""


def errors_reaching(condition) -> set:
    """The sensor errors ("pressure", "speed") that reach what ``condition`` reads: a threshold's quantity's own error
    (a derived one, Mach number and dynamic pressure, reads the sensed air speed: the speed error), both for an
    apogee (vertical velocity and altitude) and a user function (every sensed value), none for a time."""
    reached = set()
    for leaf in leaves(condition):
        if isinstance(leaf, Threshold):
            quantity = QUANTITY[leaf.quantity]
            reached.add("speed" if quantity.derive is not None else quantity.error)
        elif isinstance(leaf, (Apogee, UserFunction)):
            reached.update(("pressure", "speed"))
    return reached


def idle_sensor_key(triggers: dict, key: str) -> str | None:
    """Why case key ``key`` (full dotted) changes nothing, when it is a sensor error of a trigger in ``triggers`` that
    the trigger's condition does not read (pressure_bias on a Mach trigger); None otherwise."""
    owner, _, name = key.rpartition(".")
    error = SENSOR_ERRORS.get(name)
    for trigger in triggers.values():
        if error is not None and trigger.key == owner and error not in errors_reaching(trigger.condition):
            return f"{owner} ({trigger.describe()}) reads no value its {error} error reaches"
    return None

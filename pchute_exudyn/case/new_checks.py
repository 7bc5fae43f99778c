"""The checks of ``pchute new``'s choices (case.new, case.new_rocket): each refuses a value with one line naming
the field, the value and what is allowed (InputError)."""

from __future__ import annotations

import math

from ..errors import InputError, short_repr


def is_finite(value) -> bool:
    """Whether ``value`` is a finite int or float (an integer no float holds is not)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:   # an integer of hundreds of digits
        return False


def check_number(key, value, ok, allowed) -> None:
    """InputError unless ``value`` is a finite number and ``ok``; ``allowed`` says what is."""
    if not is_finite(value) or not ok:
        raise InputError(f"{key} = {short_repr(value)}: {allowed}")


def check_positive(key, value, optional, unit) -> None:
    """InputError unless ``value`` is a finite number > 0 (in ``unit``), or None where ``optional``."""
    if value is None and optional:
        return
    check_number(key, value, isinstance(value, (int, float)) and value > 0.0, f"must be a number > 0 ({unit})")


def check_integer(key, value, low, high) -> None:
    """InputError unless ``value`` is a whole number from ``low`` to ``high``."""
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise InputError(f"{key} = {short_repr(value)}: must be a whole number from {low} to {high}")


def check_choice(key, value, table) -> None:
    """InputError unless ``value`` is a key of ``table``."""
    if value not in table:
        raise InputError(f"{key} = {value!r}: must be one of: {', '.join(table)}")

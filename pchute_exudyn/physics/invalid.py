"""The one error type of the physics kernels' own input checks (no user-facing text: the case loader turns it into
a ``CaseError`` naming the case key)."""

from __future__ import annotations


class InvalidField(ValueError):
    """A physics object built from invalid values: ``field`` names the offending field (as the case file's key),
    ``value`` holds it, the message says what is allowed."""

    def __init__(self, field: str, value, message: str):
        super().__init__(message)
        self.field, self.value = field, value

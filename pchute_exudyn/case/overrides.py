"""The override language: dotted keys set after the case files are merged.

Overrides (``--set key=value`` on the command line, ``overrides={...}`` in Python, the varied keys of a study) are
dotted keys:

* ``bodies.vehicle.mass=800``; a body or system name may stand for its table (``vehicle.mass=800``,
  ``main.lines.riser.stiffness=6e4``);
* ``*`` matches every entry of a table (``main.lines.*.damping=0``);
* ``[i]`` indexes an array (``vehicle.inertia[0]=250``).
"""

from __future__ import annotations

import copy
import re
import sys
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

from ..errors import CaseError
from .fields import dotted
from .files import record_origins

_TOP_KEYS = ("extends", "remove", "case", "planet", "start", "atmosphere", "bodies", "systems", "failures",
             "simulation")


_KEY_PART = re.compile(r"^([^\[\]]+)((?:\[\d+\])*)$")


class Scale:
    """An override value that multiplies the value already in the case (a relative dispersion: stiffness x 1.1)."""

    def __init__(self, factor: float):
        self.factor = float(factor)

    def __repr__(self) -> str:
        return f"x{self.factor:g}"


def parse_override(text: str) -> tuple[str, Any]:
    """Split ``key=value``; the value is read as TOML (``800``, ``true``, ``[1, 2]``, ``"x"``) or else as a string."""
    if "=" not in text:
        raise CaseError(f"--set {text}", "", "an override must look like key=value, e.g. vehicle.mass=800")
    key, raw = text.split("=", 1)
    key, raw = key.strip(), raw.strip()
    if not key:
        raise CaseError(f"--set {text}", "", "the key before '=' is empty")
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw
    except RecursionError:
        raise CaseError(f"--set {key}=...", key, "the value's arrays or tables are nested too deeply") from None
    return key, value


def _split_key(key: str, source: str) -> list:
    parts: list = []
    for piece in key.split("."):
        match = _KEY_PART.match(piece)
        if not match:
            raise CaseError(source, key, "malformed key: use dotted names with optional [index], "
                                         "e.g. bodies.vehicle.inertia[0]")
        parts.append(match.group(1))
        parts.extend(int(i) for i in re.findall(r"\[(\d+)\]", match.group(2)))
    return parts


def _expand(data: Any, parts: list, done: tuple, source: str, key: str) -> list:
    """Concrete paths of ``parts`` in ``data``, with ``*`` expanded over existing table entries."""
    if not parts:
        return [done]
    head, rest = parts[0], parts[1:]
    if head == "*":
        if not isinstance(data, dict) or not data:
            raise CaseError(source, ".".join(map(str, done)) or key, "'*' needs an existing table to match in")
        return [p for name in data for p in _expand(data[name], rest, done + (name,), source, key)]
    child = data.get(head) if isinstance(data, dict) else None
    if isinstance(head, int):
        child = data[head] if isinstance(data, list) and head < len(data) else None
    return _expand(child, rest, done + (head,), source, key)


def _scaled(base: Any, factor: float) -> Any:
    """``base`` times ``factor``: a number, every number of a (nested) list, or a coefficient table's ``value``
    (its breakpoints kept); None when ``base`` holds nothing to scale."""
    if isinstance(base, bool):
        return None
    if isinstance(base, (int, float)):
        return base * factor
    if isinstance(base, list) and base:
        items = [_scaled(item, factor) for item in base]
        return None if any(item is None for item in items) else items
    if isinstance(base, dict) and "value" in base:
        values = _scaled(base["value"], factor)
        return None if values is None else {**base, "value": values}
    return None


def apply_override(data: dict, origins: dict, key: str, value: Any, source: str | None = None) -> None:
    """Set the dotted ``key`` to ``value`` in merged case ``data`` (see the module docstring for the key syntax)."""
    source = source or f"--set {key}={value}"
    parts = _split_key(key, source)
    if parts[0] in ("extends", "remove"):   # the files are merged before overrides apply: it would do nothing
        raise CaseError(source, parts[0], "cannot be overridden: it is read when the case file is "
                                          "merged; write a case file that extends this one instead")
    if parts[0] not in _TOP_KEYS:
        sections = [section for section in ("bodies", "systems")
                    if isinstance(data.get(section), dict) and parts[0] in data[section]]
        if len(sections) > 1:
            raise CaseError(source, key, f"'{parts[0]}' names both a body and a system: write bodies.{key} or "
                                         f"systems.{key}")
        if sections:
            parts = [sections[0]] + parts
    for path in _expand(data, parts, (), source, key):
        node = data
        for i, part in enumerate(path[:-1]):
            if isinstance(part, int):
                if not isinstance(node, list) or part >= len(node):
                    raise CaseError(source, dotted(path[:i + 1]), "index out of range or not an array")
                node = node[part]
                continue
            if not isinstance(node, dict):
                raise CaseError(source, dotted(path[:i]), "is not a table, so it has no key "
                                                          f"'{part}'")
            if part not in node:  # a table the override creates belongs to the override
                node[part] = {}
                origins[tuple(p for p in path[:i + 1] if not isinstance(p, int))] = source
            node = node[part]
        last = path[-1]
        if isinstance(last, int):
            if not isinstance(node, list) or last >= len(node):
                raise CaseError(source, dotted(path), "index out of range or not an array")
        elif not isinstance(node, dict):
            raise CaseError(source, dotted(path[:-1]), f"is not a table, so it has no key '{last}'")
        new = value
        if isinstance(value, Scale):   # relative: multiply what the case holds there
            base = node[last] if isinstance(last, int) else node.get(last)
            new = _scaled(base, value.factor)
            if new is None:
                raise CaseError(source, dotted(path), "a relative value needs a number in the case to scale (or "
                                                       "numbers: a list, a coefficient table's values), found "
                                                       f"{base!r}")
        node[last] = copy.deepcopy(new)
        record_origins(origins, tuple(p for p in path if not isinstance(p, int)), value, source)

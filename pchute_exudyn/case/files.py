"""Reading case files: TOML parsed once per file version, ``extends`` chains merged, ``remove`` applied.

A case file is TOML. ``extends = "base.toml"`` (a path relative to the file, or a list of them) merges the named
files first and the file's own tables on top, so shared parts are written once; ``remove = ["planet", "bodies.vehicle
.aerodynamics.center"]`` (dotted keys) deletes what the bases set before the file's own tables merge, so a child can
drop a key or replace a whole table (a flat planet by an ellipsoid). The origins map every key path to the file it
came from, for the errors.
"""

from __future__ import annotations

import copy
import re
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

from ..errors import CaseError

_PARSED: dict = {}
"""Parsed TOML files by (path, modification time, size)."""


def read_toml(path: Path, kind: str = "case") -> dict:
    """Parse one TOML file (a ``kind`` file: case, study); a missing file or a syntax error becomes a CaseError
    naming the file."""
    if not path.is_file():
        raise CaseError(str(path), "", f"{kind} file not found" if not path.exists() else "not a file")
    try:
        status = path.stat()
        stamp = (str(path.resolve()), status.st_mtime_ns, status.st_size)
        if stamp not in _PARSED:   # a study's worker loads the same files for every run: parsed once
            if len(_PARSED) > 256:
                _PARSED.clear()
            with path.open("rb") as handle:
                _PARSED[stamp] = tomllib.load(handle)
        return copy.deepcopy(_PARSED[stamp])   # the callers change what they are given
    except tomllib.TOMLDecodeError as exc:
        twice = re.search(r"Cannot declare \(([^)]*)\) twice", str(exc))
        if twice:  # e.g. two systems with the same name
            name = ".".join(part.strip(" '") for part in twice.group(1).split(","))
            raise CaseError(str(path), name, f"defined twice (names of bodies, systems and lines must be unique): "
                                             f"{exc}") from None
        raise CaseError(str(path), "", f"malformed TOML: {exc}") from None
    except UnicodeDecodeError:
        raise CaseError(str(path), "", "malformed TOML: the file is not UTF-8 text") from None
    except ValueError as exc:   # an integer beyond Python's 4300 digits for str to int
        raise CaseError(str(path), "", f"malformed TOML: {str(exc).split(';')[0]}") from None
    except RecursionError:   # tomllib and deepcopy recurse once per level of [[[...]]] or {a = {b = ...}}
        raise CaseError(str(path), "", "malformed TOML: arrays or tables nested too deeply (at most a few hundred "
                                       "levels)") from None


def record_origins(origins: dict, path: tuple, value: Any, source: str) -> None:
    origins[path] = source
    if isinstance(value, dict):
        for key, sub in value.items():
            record_origins(origins, path + (key,), sub, source)


def _merge(target: dict, data: Mapping, origins: dict, source: str, prefix: tuple = ()) -> None:
    """Deep-merge ``data`` into ``target``: tables merge key by key, every other value replaces."""
    for key, value in data.items():
        path = prefix + (key,)
        if isinstance(value, dict) and isinstance(target.get(key), dict):
            origins[path] = source
            _merge(target[key], value, origins, source, path)
        else:
            target[key] = copy.deepcopy(value)
            record_origins(origins, path, value, source)


def load_merged(path: Path, origins: dict, chain: tuple = ()) -> dict:
    path = path.resolve() if path.exists() else path
    if path in chain:
        chain_text = " -> ".join(str(p) for p in (*chain, path))
        raise CaseError(str(path), "extends", f"circular 'extends' chain: {chain_text}")
    data = read_toml(path)
    label = display_path(path)
    merged: dict = {}
    extends = data.pop("extends", [])
    if isinstance(extends, str):
        extends = [extends]
    if not isinstance(extends, list) or not all(isinstance(e, str) for e in extends):
        raise CaseError(label, "extends", "must be a file path or a list of file paths", value=extends)
    for base in extends:
        base_path = (path.parent / base)
        if not base_path.is_file():
            raise CaseError(label, "extends", f"base case file not found: {base_path}", value=base)
        _merge(merged, load_merged(base_path, origins, chain + (path,)), origins, display_path(base_path))
    _remove_keys(merged, origins, data.pop("remove", []), label)
    _merge(merged, data, origins, label)
    _resolve_file_keys(merged, path.parent)
    return merged


def _remove_keys(merged: dict, origins: dict, keys, label: str) -> None:
    """Delete the dotted ``keys`` (``remove = [...]``) from what the base files set."""
    if not isinstance(keys, list) or not all(isinstance(k, str) and k.strip() for k in keys):
        raise CaseError(label, "remove", "must be a list of dotted keys the base files set, e.g. "
                        "[\"planet.gravity\"]", value=keys)
    for key in keys:
        parts = key.strip().split(".")
        table = merged
        for part in parts[:-1]:
            table = table.get(part) if isinstance(table, dict) else None
        if not isinstance(table, dict) or parts[-1] not in table:
            raise CaseError(label, "remove", f"{key!r} is not set by the base files ('extends'); nothing to remove",
                            value=key)
        del table[parts[-1]]
        prefix = tuple(parts)
        for path in [p for p in origins if p[:len(prefix)] == prefix]:
            del origins[path]


def _resolve_file_keys(data: dict, directory: Path) -> None:
    """Make file paths inside the data absolute, relative to the file that named them."""
    atmosphere = data.get("atmosphere")
    if isinstance(atmosphere, dict) and isinstance(atmosphere.get("file"), str):
        file = Path(atmosphere["file"])
        if not file.is_absolute():
            atmosphere["file"] = str((directory / file).resolve())


def display_path(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(Path.cwd()))
    except ValueError:
        return str(path)

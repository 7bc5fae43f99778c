"""Argument checks at the public API's boundary: a wrong type or an impossible value passed from Python gets the
one-line InputError a wrong command-line argument gets, naming the argument, the value and what is allowed, instead
of an AttributeError, TypeError or OverflowError from deep inside (``pc.simulate("case.toml")``,
``pc.load_case(case)``, ``overrides={1: 2}``, a 400-digit integer, ``progress=5``)."""

from __future__ import annotations

import functools
import numbers
import os
from collections.abc import Mapping
from dataclasses import fields
from pathlib import Path

from .case import Case, parse_override
from .case import load_case as _load_case
from .errors import InputError, short_repr


def check_path(value, name: str, what: str = "file") -> Path:
    """``value`` as a Path: a non-empty str or os.PathLike; InputError naming argument ``name`` otherwise (a Case
    given where its file is expected says so)."""
    if isinstance(value, Case):
        raise InputError(f"{name} = <Case {value.name!r}>: already a loaded case; pass the path of its {what}, or use "
                         "the Case as it is")
    if isinstance(value, (str, os.PathLike)) and str(value) != "":
        return Path(value)
    raise InputError(f"{name} = {short_repr(value)}: must be the path of a {what} (a str or pathlib.Path), not "
                     f"{type(value).__name__}")


def check_case(value, name: str = "case") -> Case:
    """``value`` if it is a Case; InputError otherwise (a path says to load it first)."""
    return check_loaded(value, Case, name, "pchute_exudyn.load_case")


def check_loaded(value, kind: type, name: str, loader: str):
    """``value`` if it is a ``kind`` (a Case, a StudySpec, a FitSpec: a file loaded); InputError otherwise (a path
    says to load it first with ``loader``, e.g. 'pchute_exudyn.study.load_study')."""
    if isinstance(value, kind):
        return value
    if isinstance(value, (str, os.PathLike)):
        raise InputError(f"{name} = {short_repr(str(value))}: a path, not a {kind.__name__}; load it first: "
                         f"{loader}({short_repr(str(value))})")
    raise InputError(f"{name} = {short_repr(value)}: must be a {kind.__name__} ({loader}(path)), not "
                     f"{type(value).__name__}")


WORKERS_PER_CORE = 4
"""Local worker processes allowed per core: runs are CPU-bound, so more only share the cores, each holding its
own copy of the package (about 0.1 GB); 100 000 of them would fill the memory and fork until the machine stops."""


def most_workers() -> int:
    """The most local worker processes a study or fit may start on this machine."""
    return WORKERS_PER_CORE * (os.cpu_count() or 1)


def check_workers(value, name: str = "workers"):
    """``value`` if it is None or a whole number from 1 to ``most_workers()``; InputError naming argument ``name``
    otherwise."""
    if value is None or (isinstance(value, numbers.Integral) and not isinstance(value, bool)
                         and 1 <= int(value) <= most_workers()):   # numpy's integers too
        return None if value is None else int(value)
    raise InputError(f"{name} = {short_repr(value)}: must be None (every core) or a whole number from 1 to "
                     f"{most_workers()} ({WORKERS_PER_CORE} per core of this machine's {os.cpu_count() or 1})")


def check_executor(value, name: str = "executor"):
    """``value`` if it is None or a ``concurrent.futures.Executor`` (a process pool, a Dask client's executor)."""
    from concurrent.futures import Executor  # here: a run (it takes no executor) does without its import

    if value is None or isinstance(value, Executor):
        return value
    raise InputError(f"{name} = {short_repr(value)}: must be None (a local process pool) or a "
                     f"concurrent.futures.Executor, not {type(value).__name__}")


def check_callable(value, name: str):
    """``value`` if it is None or callable; InputError naming argument ``name`` otherwise."""
    if value is None or callable(value):
        return value
    raise InputError(f"{name} = {short_repr(value)}: must be None or a function (it is called with the simulation "
                     f"time in s), not {type(value).__name__}")


def check_flag(value, name: str) -> bool:
    """``value`` if it is a bool; InputError naming argument ``name`` otherwise."""
    if isinstance(value, bool):
        return value
    raise InputError(f"{name} = {short_repr(value)}: must be True or False")


def _too_large(value):
    """The first integer in ``value`` (a number or nested lists and tables) that no float holds, or None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int):
        try:
            float(value)
        except OverflowError:
            return value
        return None
    items = value.values() if isinstance(value, Mapping) else value if isinstance(value, (list, tuple)) else ()
    return next((found for found in map(_too_large, items) if found is not None), None)


def _check_value(key: str, value, where: str = "overrides: ") -> None:
    huge = _too_large(value)
    if huge is not None:
        raise InputError(f"{where}{key} = {short_repr(huge)}: an integer too large to be a number (a number's "
                         "magnitude is at most about 1.8e308)")


def check_overrides(overrides):
    """``overrides`` if it is a mapping of str keys or an iterable of "key=value" strings, every value a number a
    float can hold (None: no overrides); InputError naming the entry otherwise."""
    if overrides is None:
        return ()
    if isinstance(overrides, Mapping):
        for key, value in overrides.items():
            if not isinstance(key, str):
                raise InputError(f"overrides: key {short_repr(key)}: must be a str, a dotted case key such as "
                                 f"'vehicle.mass', not {type(key).__name__}")
            _check_value(key, value)
        return overrides
    if isinstance(overrides, (str, bytes)) or not hasattr(overrides, "__iter__"):
        raise InputError(f"overrides = {short_repr(overrides)}: must be a mapping of dotted keys to values "
                         "({'vehicle.mass': 800}) or a list of 'key=value' strings, not "
                         f"{type(overrides).__name__}")
    overrides = list(overrides)
    for entry in overrides:
        if not isinstance(entry, str):
            raise InputError(f"overrides: entry {short_repr(entry)}: must be a 'key=value' str, not "
                             f"{type(entry).__name__}")
        try:
            _check_value(*parse_override(entry))
        except ValueError:   # TOML's reader turning an integer of more than 4300 digits into an int
            key = entry.split("=", 1)[0].strip()
            raise InputError(f"overrides: {key} = an integer of {len(entry) - len(key) - 1} characters: too large "
                             "to be a number (a number's magnitude is at most about 1.8e308)") from None
    return overrides


@functools.wraps(_load_case)
def load_case(path, overrides=()) -> Case:
    return _load_case(check_path(path, "path", "case file (TOML)"), check_overrides(overrides))


def check_new_case_choices(choices, kwargs: dict) -> None:
    """``new_case``'s and ``new_case_text``'s arguments: a NewCase or None, keywords that are its fields, numbers a
    float holds; InputError naming the argument otherwise (NewCase itself checks each value)."""
    from .authoring.choices import NewCase

    if choices is not None and not isinstance(choices, NewCase):
        raise InputError(f"choices = {short_repr(choices)}: must be a NewCase or None (or give its fields as "
                         f"keywords), not {type(choices).__name__}")
    names = [f.name for f in fields(NewCase)]
    for key, value in kwargs.items():
        if key not in names:
            raise InputError(f"{key} = {short_repr(value)}: not a choice of a new case; the choices are: "
                             f"{', '.join(names)}")
        _check_value(key, value, "")


def _checked(writer):
    """``writer`` (``authoring.write.new_case`` or ``new_case_text``) behind the checks of its arguments."""
    @functools.wraps(writer)
    def checked(choices=None, **kwargs):
        check_new_case_choices(choices, kwargs)
        return writer(choices, **kwargs)
    return checked


def __getattr__(name: str):
    """``new_case`` and ``new_case_text``, made when first asked for (PEP 562): a run imports this module for its
    checks, and the authoring layer only when a case is written."""
    if name not in ("new_case", "new_case_text"):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    from .authoring import write

    value = globals()[name] = _checked(getattr(write, name))
    return value

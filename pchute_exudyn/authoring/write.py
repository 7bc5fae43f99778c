"""``pchute new``'s and ``new_case``'s entry points: the case text of a NewCase (given whole or as keywords), that text
read back by the case reader before ``pchute new`` writes it, and the Case it makes."""

from __future__ import annotations

from ..errors import InputError
from .choice_checks import check_needs
from .choices import NewCase
from .descent import DescentWriter
from .layout import layout
from .rocket import dual_deploy_lines
from .rocket_start import check_not_dual
from .text import aligned
from .two_section import two_section_lines


def _choices(choices: NewCase | None, kwargs: dict) -> NewCase:
    if choices is not None and kwargs:
        raise InputError(f"give a NewCase or its fields as keywords, not both (keywords: {', '.join(kwargs)})")
    return choices if choices is not None else NewCase(**kwargs)


def new_case_text(choices: NewCase | None = None, **kwargs) -> str:
    """The case file (TOML text) for ``choices`` (a NewCase, or its fields as keywords)."""
    choices = _choices(choices, kwargs)
    if choices.from_rocketpy is not None:
        raise InputError(f"from_rocketpy = {choices.from_rocketpy!r}: read by `pchute new`; from Python, start from "
                         "authoring.rocket_start.started_from(choices, results.rocketpy_export.apogee_state(path), "
                         "path)")
    if choices.dual_deploy:
        rows = two_section_lines(choices) if choices.shock_cord_length is not None else dual_deploy_lines(choices)
    else:
        rows = DescentWriter(layout(choices)).lines()
    return "\n".join(aligned(row) for row in rows) + "\n"


def new_case(choices: NewCase | None = None, **kwargs):
    """The loaded ``Case`` for ``choices`` (a NewCase, or its fields as keywords): the file ``new_case_text``
    writes, built in memory (for a notebook); ``pchute new`` writes the same text to a file."""
    from ..case.files import tomllib
    from ..case.loader import build_case

    choices = _choices(choices, kwargs)
    return build_case(tomllib.loads(new_case_text(choices)), {}, f"new_case({choices.name!r})")


def new_choices(given: dict) -> NewCase:
    """The NewCase of ``pchute new``'s options ``given`` (field -> value), each option that needs another checked
    even at its default value."""
    choices = NewCase(**given)
    check_needs(choices, given)
    check_not_dual(choices, given)
    return choices


def checked_case(choices: NewCase) -> tuple:
    """(``new_case_text(choices)``, the Case it loads as), read back by the case reader first: a file ``pchute run``
    would refuse is an InputError naming the reader's complaint, never written."""
    from ..case.files import tomllib
    from ..case.loader import build_case
    from ..errors import CaseError

    text = new_case_text(choices)
    try:
        case = build_case(tomllib.loads(text), {}, f"the case `pchute new` would write for {choices.name!r}")
    except CaseError as exc:
        raise InputError(f"these choices make a case `pchute run` refuses: {exc}") from None
    return text, case

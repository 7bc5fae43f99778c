"""``pchute new``'s options from NewCase (``authoring.choices``): each field's metavar and help from the class
docstring's Attributes (their one home), and the fields with their defaults in order (``choice_fields``)."""

from __future__ import annotations

from dataclasses import asdict, fields

from .choices import NewCase

UNIT_METAVARS = (("(kg", "KG"), ("(m^2", "M2"), ("(m/s", "M/S"), ("(m)", "M"), ("(m,", "M"), ("(deg", "DEG"),
                 ("(s,", "S"), ("(s)", "S"), ("(-)", "C"), ("(-,", "C"), ("(Pa", "PA"), ("(N,", "N"), ("(N)", "N"))
"""A command-line metavar from the unit a NewCase attribute's description names first."""


def command_help() -> dict:
    """NewCase field -> (metavar, help) of `pchute new`, from the class docstring's Attributes (their one home):
    the description with ``code`` marks and the module's constant names left out; the defaults come from NewCase."""
    text = NewCase.__doc__.split("Attributes\n    ----------\n", 1)[1]
    found, names = {}, []
    for line in text.splitlines():
        if line.startswith("    ") and not line.startswith("        ") and " : " in line:
            names, spec = line.strip().split(" : ", 1)
            names = [name.strip() for name in names.split(",")]
            for name in names:
                found[name] = [spec, ""]
        elif line.startswith("        ") and names:
            for name in names:
                found[name][1] += (" " if found[name][1] else "") + line.strip()
    out = {}
    for name, (spec, description) in found.items():
        description = description.replace("``", "")
        metavar = next((m for unit, m in UNIT_METAVARS if unit in description), None)
        metavar = "N" if spec.startswith("int") else "TEXT" if spec == "str" and name == "name" else metavar
        metavar = "MACH" if name == "mach" else metavar
        out[name] = (metavar, description[0].lower() + description[1:].rstrip("."))
    return out


def choice_fields() -> list:
    """The NewCase fields (name, default) in order, for the command line."""
    defaults = asdict(NewCase())
    return [(f.name, defaults[f.name]) for f in fields(NewCase)]

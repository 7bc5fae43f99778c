"""The text of a written case: numbers without float noise, vectors, and comments aligned at one column (the
hand-written case files' layout)."""

COMMENT_COLUMN = 44
"""Column at which the written file's comments start (the hand-written case files' layout)."""


def number(value: float) -> str:
    """A number for the file: 12 significant digits (micrometres on kilometres), no float noise."""
    text = repr(float(f"{float(value):.12g}"))
    return "0.0" if text == "-0.0" else text


def vector(values) -> str:
    """A list of numbers for the file (``number`` each)."""
    return "[" + ", ".join(number(v) for v in values) + "]"


def aligned(row: str) -> str:
    """A key line with its comment at column COMMENT_COLUMN (the case files' layout)."""
    key, mark, comment = row.partition(" # ")
    if not mark or row.startswith("#") or '"' in key:   # a quoted value may hold " # " itself
        return row
    return f"{key.rstrip():<{COMMENT_COLUMN - 1}} # {comment.strip()}"

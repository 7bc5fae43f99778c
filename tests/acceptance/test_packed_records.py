"""Packed records are read by name: outside the modules that define a packed layout, a subscript of one (SP's memory
and end-of-step record, a work or layout array, a solve's tuple) holds no bare number, so that `end_of_step[3]` or
`records[:, first + 6 + k]` cannot creep back in (issue 47)."""

import ast

from tests.helpers import ROOT

PACKAGE = ROOT / "pchute_exudyn"
PACKED = {"end_of_step", "end", "memory", "layout", "work", "record", "records", "aerodynamic_work", "status",
          "solution"}
"""Names that hold a packed record in the package (a list of records named so elsewhere is not subscripted by a
number either)."""
HOMES = {"physics/kinematics.py", "physics/aerodynamics.py", "physics/lines.py", "methods/sp/memory.py",
         "methods/sp/balance.py", "methods/sp/stepping.py", "methods/sp/canopy_kernels.py"}
"""The modules that define the packed layouts: the only places a position in one may be written as a number."""


def bare_offsets(source: str) -> list:
    """(line, text) of each subscript of a PACKED name holding an integer literal, other than the width of a
    vector slice (`a:a + 3`)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.Subscript):
            continue
        value = node.value
        name = value.id if isinstance(value, ast.Name) else value.attr if isinstance(value, ast.Attribute) else None
        if name not in PACKED:
            continue
        widths = {id(n.upper.right) for n in ast.walk(node.slice) if isinstance(n, ast.Slice)
                  and isinstance(n.upper, ast.BinOp) and isinstance(n.upper.op, ast.Add)}
        if any(isinstance(n, ast.Constant) and type(n.value) is int and id(n) not in widths
               for n in ast.walk(node.slice)):
            found.append((node.lineno, ast.unparse(node)))
    return found


def test_no_packed_record_is_read_by_a_bare_offset_outside_its_home():
    found = [f"{path.relative_to(ROOT)}:{line}: {text}" for path in sorted(PACKAGE.rglob("*.py"))
             if str(path.relative_to(PACKAGE)) not in HOMES for line, text in bare_offsets(path.read_text())]
    assert not found, "packed records read by bare offsets:\n" + "\n".join(found)


def test_the_check_catches_a_planted_offset():
    planted = ("damping = confluence.end_of_step[3]\n"
               "tensions = records[:, first + 9 + i]\n"
               "position = work[0, a:a + 3]\n"
               "flag = memory[MEMORY_DUE, 0]\n")
    assert [line for line, _ in bare_offsets(planted)] == [1, 2, 3, 4]
    named = ("damping = confluence.end_of_step[SOLVED_DAMPING]\n"
             "tensions = records[:, first + RECORD_TENSIONS + i]\n"
             "position = work[WORK_FIRST, a:a + 3]\n")
    assert bare_offsets(named) == []

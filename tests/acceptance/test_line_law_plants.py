"""A planted change in one form of the line law fails the agreement check of tests/unit/test_line_law.py: a copy of
the package with one form changed, checked in a process of its own (the kernels' Python form), fails it; the copy
unchanged passes."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest

from tests.helpers import ROOT

PLANTS = {
    "symbolic": ("pchute_exudyn/engine/line_laws.py", "esym.IfThenElse(stretch > 0, value", "esym.IfThenElse(stretch > -1e-3, value"),
    "sp solve": ("pchute_exudyn/methods/sp/balance.py", "tensions[i] = line_tension(", "tensions[i] = 1.000001 * line_tension("),
    "series damping": ("pchute_exudyn/physics/lines.py", "/ (total * total)", "/ (total * total * 1.0001)"),
}


"""file, text, planted text: one change in one form of the law."""


def check_copy(folder, plant: str | None) -> subprocess.CompletedProcess:
    """``check_every_form`` run on a copy of the package in ``folder`` with ``plant`` (a key of PLANTS) planted."""
    for part in ("pchute_exudyn", "tests"):
        shutil.copytree(ROOT / part, folder / part, ignore=shutil.ignore_patterns("__pycache__", "_compiled",
                                                                                  "data", "cases"))
    if plant is not None:
        path, old, new = PLANTS[plant]
        target = folder / path
        assert old in target.read_text(), f"{path} no longer holds {old!r}: update PLANTS"
        target.write_text(target.read_text().replace(old, new))
    script = "from tests.unit.test_line_law import check_every_form; check_every_form()"
    environment = {**os.environ, "PYTHONPATH": str(folder), "PCHUTE_KERNELS": "python"}
    return subprocess.run([sys.executable, "-c", script], cwd=folder, env=environment, capture_output=True,
                          text=True, timeout=300)


def test_the_copy_unchanged_passes_the_check(tmp_path):
    run = check_copy(tmp_path, None)
    assert run.returncode == 0, run.stderr[-2000:]


@pytest.mark.parametrize("plant", sorted(PLANTS))
def test_a_planted_change_in_one_form_fails_the_check(tmp_path, plant):
    run = check_copy(tmp_path, plant)
    assert run.returncode != 0 and "AssertionError" in run.stderr, run.stderr[-2000:]

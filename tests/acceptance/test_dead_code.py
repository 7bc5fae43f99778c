"""Dead code is removed and kept out (issue 54): vulture finds no unused function, class, variable, attribute or import
in the package, its tests, validation scripts and examples (which count as users), beyond the names
tests/dead_code_whitelist.py lists with why; a planted unused function is caught."""

from __future__ import annotations

import shutil
import subprocess
import sys

from tests.helpers import ROOT

TREES = ("pchute_exudyn", "tests", "validation", "examples", "docs_hooks.py", "setup.py")
CONFIDENCE = "60"
"""vulture's lowest confidence reported: 60 % also reports unused functions, classes and constants (the dead code the
issue found: a budget, a help string, a table of layer bases), not only unused imports and variables."""


def vulture(root) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "vulture", *TREES, "tests/dead_code_whitelist.py",
                           "--min-confidence", CONFIDENCE, "--exclude", "*/output/*,*/_compiled/*"],
                          cwd=root, capture_output=True, text=True, timeout=300)


def test_no_dead_code():
    run = vulture(ROOT)
    assert run.returncode == 0 and not run.stdout, run.stdout + run.stderr


def test_a_planted_unused_function_is_caught(tmp_path):
    for tree in TREES:
        copy = shutil.copytree if (ROOT / tree).is_dir() else shutil.copy
        copy(ROOT / tree, tmp_path / tree, **({"ignore": shutil.ignore_patterns("__pycache__", "_compiled", "output")}
                                              if (ROOT / tree).is_dir() else {}))
    target = tmp_path / "pchute_exudyn" / "physics" / "lines.py"
    target.write_text(target.read_text() + "\n\ndef forgotten_helper(stretch):\n    return 2.0 * stretch\n")
    run = vulture(tmp_path)
    assert run.returncode != 0 and "unused function 'forgotten_helper'" in run.stdout, run.stdout + run.stderr

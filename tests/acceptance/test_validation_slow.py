"""Long validations (minutes; `python -m pytest -m slow`): SP against the full-mass model on all six MER cases; the
rescue-parachute drops' page recomputed."""

import sys

import numpy as np
import pytest

from pchute_exudyn.results.compare import compare_results
from tests.helpers import ROOT

sys.path.insert(0, str(ROOT / "validation"))
import mer_compare  # noqa: E402

pytestmark = pytest.mark.slow


@pytest.mark.parametrize("case_number", range(1, 7))
def test_sp_meets_the_issue_targets_on_every_mer_case(case_number, tmp_path, monkeypatch):
    monkeypatch.setattr(mer_compare, "OUT", tmp_path)
    results = mer_compare.run_case(case_number, reuse=False)
    reference = results["full rk4 1e-4"]
    for label, result in results.items():
        if not label.startswith("sp"):
            continue
        c = compare_results(reference, result, settle_time=2.0)
        assert abs(c.final["vehicle altitude"]) < 1.0, label          # thesis: 2-10 m
        assert c.final["vehicle lateral position"] < 0.2, label       # thesis: up to 1.2 m
        if case_number == 1 and "stretch" in label:
            for line in ("bridle1", "bridle2", "bridle3"):
                assert c.lines[line]["max_settled"] < 1.0
            assert c.lines["riser"]["max_settled"] < 6.0
        if label == "sp stretch 0.001":   # the large-step phase lag of cases 3-4 is a step effect (measured 4.2 N)
            large_step = compare_results(reference, results["sp stretch 0.01"], settle_time=2.0)
            assert max(m["max_settled"] for m in c.lines.values()) \
                < 0.2 * max(m["max_settled"] for m in large_step.lines.values())
    assert np.isfinite(reference.final("vehicle_altitude"))


def test_the_rescue_drop_page_is_what_the_drops_give_now():
    """docs/validation/rescue_drops.md recomputed from the EN 12491 records (about 6 minutes): the committed page is
    the code's, so a change to the opening dynamics shows there."""
    import subprocess
    run = subprocess.run([sys.executable, str(ROOT / "validation" / "rescue_drops.py"), "--check"], cwd=ROOT,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]

"""The flown-loads validation (docs/validation/flown_loads.md, validation/flown_loads.py): the shipped cases hold the
calibration the flights give, the page is its records, the records meet the issue's targets, and a small Monte
Carlo of an opening brackets its nominal run."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import spearmanr

from tests.helpers import ROOT

sys.path.insert(0, str(ROOT / "validation"))
import flown_loads  # noqa: E402
from flown_loads_page import page  # noqa: E402

RECORDS = ROOT / "validation" / "output" / "flown_loads"


def _records():
    return json.loads((RECORDS / "calibration.json").read_text()), json.loads((RECORDS / "predictions.json").read_text())


@pytest.mark.long
def test_the_shipped_cases_hold_the_calibration_the_three_flights_give():
    calibration = flown_loads.calibrate()
    assert flown_loads.calibrated_in_case(calibration) == []
    recorded, _ = _records()
    for key, residual in recorded["residuals"].items():
        assert calibration["residuals"][key] == pytest.approx(residual, abs=1e-9)


def test_the_page_is_the_records():
    calibration, flights = _records()
    held_out = json.loads(flown_loads.HELD_OUT.read_text())
    known = {k: {"flown": f.flown, "source": f.flown_source} for k, f in flown_loads.FLIGHTS.items() if f.flown}
    assert page({"calibration": calibration, "flights": flights}, held_out, known) == flown_loads.PAGE.read_text()


def test_the_predictions_meet_the_targets_held_out_within_15_and_calibration_within_10_percent():
    _, flights = _records()
    held_out = json.loads(flown_loads.HELD_OUT.read_text())
    assert set(flights) == {"mars2020", "aspire_sr01", "aspire_sr02", "aspire_sr03", "msl"}
    for key, flight in flights.items():
        definition = flown_loads.FLIGHTS[key]
        flown = definition.flown if definition.flown else held_out[key]["flown"]
        bound = 0.10 if definition.role == "calibration" else 0.15
        assert abs(flight["median"] / flown - 1.0) <= bound, key
        assert flight["p01"] <= flown <= flight["p99"], key
        assert flight["runs"] == 400 and flight["failed"] == 0


def test_a_small_opening_monte_carlo_brackets_its_nominal_run_and_follows_the_load_factor(tmp_path, monkeypatch):
    monkeypatch.setattr(flown_loads, "OUT", tmp_path)
    nominal = flown_loads.first_peak("mars2020")["peak"]
    kept = {}
    result = flown_loads.predict("mars2020", 16, 0.11, 1, kept)
    assert result["failed"] == 0 and result["p01"] < nominal < result["p99"]
    assert abs(result["median"] / nominal - 1.0) < 0.1
    assert list(tmp_path.iterdir()) == []   # the study file and its table are the caller's to write
    (tmp_path / "runs.csv").write_bytes(kept[Path("runs") / "mars2020.csv"])
    table = np.genfromtxt(tmp_path / "runs.csv", delimiter=",", names=True, dtype=None, encoding=None)
    drawn = table["systemsmaininflationsupersonicload_factor"]
    assert spearmanr(drawn, table["peak_tension_riser"])[0] > 0.5


@pytest.mark.parametrize("arguments, line", [
    (["--runs", "0"], "flown_loads.py: --runs = 0: must be >= 1"),
    (["--runs", "-5"], "flown_loads.py: --runs = -5: must be >= 1"),
    (["--workers", "0"], "flown_loads.py: --workers = 0: must be from 1 to "),
    (["--runs", "x"], "flown_loads.py: argument --runs: invalid int value: 'x'"),
])
def test_bad_arguments_stop_in_one_line_before_anything_is_written(arguments, line):
    """Each bad argument is refused before the calibration runs: the committed outputs keep every byte."""
    before = {path: path.read_bytes() for path in RECORDS.rglob("*") if path.is_file()}
    with pytest.raises(SystemExit) as stopped:   # a message, not a number: Python prints it and exits with status 1
        flown_loads.main(arguments)
    assert str(stopped.value).startswith(line) and "\n" not in str(stopped.value)
    assert {path: path.read_bytes() for path in RECORDS.rglob("*") if path.is_file()} == before


def test_a_bad_argument_is_one_line_and_status_1_from_the_process():
    done = subprocess.run([sys.executable, str(ROOT / "validation" / "flown_loads.py"), "--runs", "0"],
                          capture_output=True, text=True, timeout=60, cwd=ROOT)
    assert (done.returncode, done.stderr) == (1, "flown_loads.py: --runs = 0: must be >= 1\n")


def test_compare_without_the_records_is_one_line(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(flown_loads, "OUT", tmp_path / "flown_loads")
    monkeypatch.setattr(flown_loads, "ROOT", tmp_path)
    with pytest.raises(SystemExit) as stopped:
        flown_loads.main(["--compare"])
    assert str(stopped.value) == ("flown_loads.py: --compare: flown_loads/calibration.json is missing: run without "
                                  "--compare first (it calibrates and predicts)")

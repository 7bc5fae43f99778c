"""A run against a flight log and a fit to one (results.log_compare, a fit's `log` target), on logs the package made
itself with noise (the figures are known) and on a real flight's excerpt."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from tests.helpers import ROOT, run_cli

sys.path.insert(0, str(ROOT / "validation"))
import synthetic_log_fit as synthetic  # noqa: E402

EXCERPT = ROOT / "tests" / "data" / "flight_logs" / "altos_nustars26_ft1_every20th.csv"


@pytest.fixture(scope="module")
def flown(tmp_path_factory):
    """The synthetic rocket's case, its truth flown (time from the apogee, height) and a 1 m noise log of it."""
    folder = tmp_path_factory.mktemp("synthetic")
    case = synthetic.write_case(folder)
    time, height = synthetic.flown(case)
    synthetic.write_log(folder / "flight.csv", time, height, seed=56)
    return folder, case


def test_a_run_against_a_log_of_itself_reads_the_same_figures(flown, tmp_path):
    folder, case = flown
    run = tmp_path / "run"
    assert run_cli("run", str(case), "--out", str(run), "--set", "main.deploy_trigger.lag=1",
                   "--set", "drogue_canopy.aerodynamics.reference_area=0.3",
                   "--set", "main_canopy.aerodynamics.reference_area=4").returncode == 0
    done = run_cli("compare", str(run), str(folder / "flight.csv"), "--out", str(tmp_path / "cmp"))
    assert done.returncode == 0, done.stderr
    rows = {r["quantity"].split(",")[0]: r for r in json.loads((tmp_path / "cmp" / "comparison.json").read_text())["rows"]}
    # a 9 s main band of 1 m noise: its Theil-Sen slope scatters 0.5 % from log to log
    for quantity, tolerance in (("descent rate under the drogue", 0.01), ("descent rate under the main", 0.02),
                                ("apogee height above the ground", 0.002)):
        assert rows[quantity]["run"] == pytest.approx(rows[quantity]["log"], rel=tolerance), quantity
    assert rows["rate change: time after apogee"]["run"] == pytest.approx(rows["rate change: time after apogee"]["log"],
                                                                         abs=0.2)
    assert rows["apogee to touchdown"]["run"] == pytest.approx(rows["apogee to touchdown"]["log"], abs=0.2)


@pytest.mark.slow   # 14 s; the one-key fit below runs the same path by default
def test_a_fit_to_a_synthetic_log_recovers_the_canopies_and_the_lag(flown):
    """From 30 % off: both C_D S within 2 %, the lag within 0.2 s, each within 3 standard errors."""
    folder, case = flown
    rows = synthetic.fit_seed(folder / "fit56", 56)
    for row in rows:
        bound = 0.2 if "lag" in row["key"] else 0.02 * row["truth"]
        assert abs(row["error"]) < bound, row
        assert abs(row["errors_in_se"]) < 3.0, row
        assert np.isfinite(row["standard_error"]) and row["standard_error"] > 0.0


@pytest.mark.long
def test_a_fit_with_the_trigger_height_free_has_a_finite_standard_error(flown, tmp_path):
    """A 0.001-of-range step moves the main's trigger by less than one of its 100 Hz samples: the step widens."""
    folder, case = flown
    truth = tmp_path / "truth.toml"   # the log's canopies, the main's height to be found
    truth.write_text(f'extends = "{case}"\n[bodies.drogue_canopy.aerodynamics]\nreference_area = 0.3\n'
                     '[bodies.main_canopy.aerodynamics]\nreference_area = 4.0\n')
    fit = tmp_path / "fit.toml"
    fit.write_text(f'[fit]\ncase = "{truth}"\nmethod = "sp"\n[free."main.deploy_trigger.below"]\nlow = 140.0\n'
                   f'high = 160.0\ninitial = 145.0\n[[targets]]\nlog = "{folder / "flight.csv"}"\nstd = 1.0\n')
    done = run_cli("fit", str(fit), "--out", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    outcome = json.loads((tmp_path / "out" / "fit.json").read_text())
    assert np.isfinite(outcome["standard_error"][0]) and outcome["standard_error"][0] > 0.0
    assert outcome["fitted"][0] == pytest.approx(150.0, abs=1.0)   # the log's main: 150 m, its lag the case's 1 s
    assert outcome["at_bound"] == [False]


def test_a_real_flight_computers_export_is_compared_without_a_map(flown, tmp_path):
    """The TeleMega excerpt (AltOS export, text state column) against a run: read by its header, no --map."""
    _, case = flown
    run = tmp_path / "run"
    assert run_cli("run", str(case), "--out", str(run)).returncode == 0
    done = run_cli("compare", str(run), str(EXCERPT))
    assert done.returncode == 0, done.stderr
    assert "against flight log" in done.stdout and "AltOS, barometric heights" in done.stdout
    assert "descent rate under the drogue" in done.stdout


def test_a_log_the_run_never_lands_for_is_refused_in_one_line(flown, tmp_path):
    folder, case = flown
    fit = tmp_path / "fit.toml"
    fit.write_text(f'[fit]\ncase = "{case}"\nmethod = "sp"\n[free."main.deploy_trigger.lag"]\nlow = 0.0\n'
                   f'high = 2.0\n[[targets]]\nlog = "{folder / "flight.csv"}"\nstd = 1.0\n')
    text = Path(case).read_text().replace("duration = ", "duration = 5.0 # ", 1)
    short = tmp_path / "short.toml"
    short.write_text(text)
    fit.write_text(fit.read_text().replace(str(case), str(short)))
    done = run_cli("fit", str(fit), "--out", str(tmp_path / "out"))
    assert done.returncode != 0
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "ends at 5 s in the air" in lines[0] and "lengthen simulation.duration" in lines[0]


def test_a_log_mapped_to_a_height_says_why_it_has_no_descent_figures(flown, tmp_path):
    """Mapped by hand to the vehicle's height (not its altitude), the old comparison says what it needs."""
    folder, case = flown
    run = tmp_path / "run"
    assert run_cli("run", str(case), "--out", str(run)).returncode == 0
    done = run_cli("compare", str(run), str(folder / "flight.csv"), "--map", "height=rocket_height")
    assert done.returncode == 0, done.stderr
    assert "No descent figures: they are read from rocket_altitude on both sides, and B has rocket_height only" \
        in done.stdout

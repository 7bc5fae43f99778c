"""`pchute fit`: bounded least squares over real runs recovers known parameters, resumes after a kill without
running recorded points again, and writes a calibrated case that reproduces the data."""

import json
import os
import signal
import subprocess
import time

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.fit import load_fit, run_fit
from pchute_exudyn.fit.report import write_report
from pchute_exudyn.fit.solve import FitOutcome
from tests.helpers import MER, ROOT, start_cli

TRUTH = {"parachute.aerodynamics.axial_coefficient": 0.5, "main.lines.riser.stiffness": 66000.0}   # case: 0.46, 6e4
FIT = """
[fit]
name = "recover C_A and the riser stiffness"
case = "{case}"
method = "sp"
step = 1e-2

[free."parachute.aerodynamics.axial_coefficient"]
low = 0.3
high = 0.7
initial = 0.44

[free."main.lines.riser.stiffness"]
low = 30000.0
high = 120000.0
initial = 58000.0

[[targets]]
history = "truth.csv"
column = "tension_riser"
map = ["riser_N=tension_riser"]
std = 1.0

[[targets]]
history = "truth.csv"
column = "vehicle_altitude"
map = ["alt_m=vehicle_altitude"]
std = 0.1

[[targets]]
final = "vehicle_altitude"
value = {final}
std = 0.1
"""
SHORT = {"simulation.duration": 6.0, "simulation.output_step": 0.05}


@pytest.fixture()
def fit_file(tmp_path):
    """Measured data made by a run with known values (MER case 1, 6 s, SP), and a fit starting 5-12 % off."""
    case_file = tmp_path / "case.toml"
    case_file.write_text(f'extends = "{(MER / "case1.toml").as_posix()}"\n[simulation]\nduration = 6.0\n'
                         'output_step = 0.05\n')
    truth = pc.simulate(pc.load_case(case_file, TRUTH), "sp", "rk4", 1e-2)
    t = truth.time
    np.savetxt(tmp_path / "truth.csv", np.column_stack([t, truth["tension_riser"], truth["vehicle_altitude"]]),
               delimiter=",", header="time,riser_N,alt_m", comments="")
    path = tmp_path / "fit.toml"
    path.write_text(FIT.format(case=case_file.as_posix(), final=truth.final("vehicle_altitude")))
    return path


def test_fit_recovers_known_drag_and_stiffness(fit_file, tmp_path):
    spec = load_fit(fit_file)
    result = run_fit(spec, tmp_path / "out", workers=2)
    for key, fitted in zip(result.keys, result.fitted):
        assert fitted == pytest.approx(TRUTH[key], rel=0.005), key
    paths = write_report(spec, result, tmp_path / "out")
    assert FitOutcome.from_dict(json.loads(paths["json"].read_text())) == result   # fit.json reads back whole
    assert all(p.is_file() for p in paths.values())
    fit_json = json.loads(paths["json"].read_text())
    assert fit_json["cost"] < 1e-6 and len(fit_json["standard_error"]) == 2
    # the calibrated case file reproduces the data it was fitted to
    again = pc.simulate(pc.load_case(paths["case"]), "sp", "rk4", 1e-2)
    data = np.loadtxt(tmp_path / "truth.csv", delimiter=",", skiprows=1)
    assert np.interp(data[:, 0], again.time, again["tension_riser"]) == pytest.approx(data[:, 1], abs=1e-3)


def test_a_killed_fit_resumes_without_running_recorded_points_again(fit_file, tmp_path):
    out = tmp_path / "killed"
    process = start_cli("fit", fit_file, "--out", out, "--workers", "1", cwd=ROOT, start_new_session=True,
                        stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    journal = out / "evaluations.jsonl"
    deadline = time.time() + 120
    while time.time() < deadline and process.poll() is None:
        if journal.is_file() and len(journal.read_text().splitlines()) >= 6:
            break
        time.sleep(0.1)
    assert process.poll() is None, "the fit ended before it could be killed"
    os.killpg(process.pid, signal.SIGKILL)
    process.wait()
    recorded = len([line for line in journal.read_text().splitlines() if line.strip()])
    assert recorded >= 6
    result = run_fit(load_fit(fit_file), out, workers=2)
    lines = [json.loads(line) for line in journal.read_text().splitlines() if line.strip()]
    keys = [tuple(line["values"]) for line in lines]
    assert len(keys) == len(set(keys))                     # no point was run twice
    assert result.runs_this_time == len(lines) - recorded
    assert result.reused >= recorded - 1                # every recorded point the fit came back to was read back
    for key, fitted in zip(result.keys, result.fitted):
        assert fitted == pytest.approx(TRUTH[key], rel=0.005), key


def test_a_budget_stops_the_search_within_it_at_the_best_point(fit_file, tmp_path):
    """max_runs = 6 (two free keys: the start, a Jacobian of 2 and one step of 3 would be 7): the search makes at
    most 6 runs and reports the least-cost point it stepped to (not the start), whose Jacobian may add one run per
    key."""
    fit_file.write_text(fit_file.read_text().replace('step = 1e-2\n', 'step = 1e-2\nmax_runs = 6\n', 1))
    spec = load_fit(fit_file)
    result = run_fit(spec, tmp_path / "out", workers=1)
    assert result.status == -2 and "max_runs" in result.message
    lines = [json.loads(line) for line in (tmp_path / "out" / "evaluations.jsonl").read_text().splitlines()]
    assert len(lines) <= spec.max_runs + len(spec.free)

    def cost(values):
        line = next(line for line in lines if line["values"] == list(values))
        return 0.5 * float(np.sum(((np.asarray(line["predictions"]) - spec.measured()) / spec.scales()) ** 2))
    assert any(line["values"] == result.fitted for line in lines[:spec.max_runs])   # a point the search ran
    assert result.cost == pytest.approx(cost(result.fitted), rel=1e-9)
    assert result.cost < cost(result.initial)

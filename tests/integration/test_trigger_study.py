"""Studies of triggered sequences: the deployment conditions and separations a study keeps of each run, their rows
in the report's percentile table, and the deployment box figure (Mach number against dynamic pressure)."""

import csv
import json
import math
from dataclasses import replace

import pytest

import pchute_exudyn as pc
from pchute_exudyn.results.summary import RunSummary
from pchute_exudyn.study import load_study, run_study
from pchute_exudyn.study.report import output_label, study_report
from pchute_exudyn.study.runner import scalar_outputs, sequence_outputs
from tests.helpers import ROOT

# PA1 with the mains deployed on a 20 Hz altitude trigger (m above the geoid) and the drogues cut away with them
TRIGGERED_PA1 = f"""
extends = "{(ROOT / 'cases' / 'cev_pa1.toml').as_posix()}"
remove = ["systems.main.deploy_time", "systems.drogue.cutaway_time", "systems.drogue.deploy_time"]
[systems.drogue]
deploy_trigger = {{ time = 3.5 }}
cutaway_trigger = {{ after = "main.deploy" }}
[systems.main]
deploy_trigger = {{ quantity = "altitude", below = 1996.0, rate = 20.0 }}
"""

STUDY = """
[study]
name = "PA1 main trigger altitude"
case = "{case}"
runs = 4
seed = 36
duration = 15.0
[[study.configurations]]
method = "sp"
steps = [1e-3]
[parameters."systems.main.deploy_trigger.below"]
distribution = "uniform"
low = 1900.0
high = 2100.0
"""


def conditions(mach, pressure, altitude):
    return {"altitude": altitude, "mach": mach, "dynamic_pressure": pressure, "airspeed": None if mach is None else 300.0 * mach}


def test_sequence_outputs_of_a_synthetic_summary():
    summary = {"events": [
        {"event": "start", "time": 0.0},
        {"event": "deploy", "time": 3.5, "system": "drogue"},   # a fixed-time deployment: no columns
        {"event": "cutaway", "time": 9.5, "system": "drogue",   # a triggered cut-away: not a deployment
         "trigger": {"quantity": "after", "conditions": conditions(0.14, 1065.0, 1995.0)}},
        {"event": "deploy", "time": 9.5, "system": "main",
         "trigger": {"quantity": "altitude", "threshold": 1996.0, "conditions": conditions(0.14, 1065.0, 1995.0)}},
        {"event": "deploy", "time": 20.0, "system": "reserve",
         "trigger": {"quantity": "mach", "conditions": conditions(None, float("nan"), 900.0)}}],
        "separations": {"heat_shield": {"time": 29.5, "relative_speed": 1.0, "clearance": 12.5,
                                        "clearance_after": 2.0},
                        "backshell": {"time": 40.0, "relative_speed": 0.5, "clearance": None,
                                      "clearance_after": 2.0}}}
    summary = RunSummary.from_dict(summary)   # a summary.json of a run, read back (what it lacks is None)
    assert sequence_outputs(summary) == {
        "deploy_mach_main": 0.14, "deploy_dynamic_pressure_main": 1065.0, "deploy_altitude_main": 1995.0,
        "deploy_time_main": 9.5,
        "deploy_mach_reserve": None, "deploy_dynamic_pressure_reserve": None, "deploy_altitude_reserve": 900.0,
        "deploy_time_reserve": 20.0,
        "separation_time_heat_shield": 29.5, "separation_clearance_heat_shield": 12.5,
        "separation_time_backshell": 40.0, "separation_clearance_backshell": None}
    assert sequence_outputs(replace(summary, events=summary.events[:3], separations={})) == {}   # nothing triggered
    labels = [output_label(name) for name in sequence_outputs(summary)][:4]
    assert labels == ["deploy_altitude_main (m)", "deploy_mach_main (-)", "deploy_dynamic_pressure_main (Pa)",
                      "deploy_time_main (s)"]   # the recorded quantities in their table's order (registries.quantities)
    assert output_label("separation_clearance_heat_shield") == "separation_clearance_heat_shield (m)"
    assert output_label("separation_time_heat_shield") == "separation_time_heat_shield (s)"


def test_a_run_without_triggers_keeps_its_columns():
    case = pc.load_case(ROOT / "cases" / "cev_pa1.toml", {"simulation.duration": 10.0})   # both systems deploy
    result = pc.simulate(case, "sp")
    assert [e.system for e in result.summary.events_of("deploy")] == ["drogue", "main"]
    assert not [k for k in scalar_outputs(result) if k.startswith(("deploy_", "separation_"))]


def write_table(folder, rows):
    keys = list(dict.fromkeys(k for row in rows for k in row))
    with open(folder / "runs.csv", "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=keys)
        writer.writeheader()
        writer.writerows(rows)


def test_report_of_a_synthetic_table_with_deployments_and_a_separation(tmp_path):
    rows = []
    for i in range(6):
        rows.append({"run": i, "status": "ok", "error": "", "final_altitude": 100.0 + i,
                     "deploy_mach_main": 0.3 + 0.01 * i, "deploy_dynamic_pressure_main": 1000.0 + 10 * i,
                     "deploy_altitude_main": 2000.0 - i, "deploy_time_main": 9.0 + 0.1 * i,
                     "deploy_mach_pilot": 1.8 + 0.02 * i, "deploy_dynamic_pressure_pilot": 500.0 + 5 * i,
                     "deploy_altitude_pilot": 9000.0 - i, "deploy_time_pilot": 2.0 + 0.1 * i,
                     "separation_time_heat_shield": 22.0 + 0.1 * i, "separation_clearance_heat_shield": 10.0 + i,
                     "peak_tension_riser": 5e4 + i})
    write_table(tmp_path, rows)
    paths = study_report(tmp_path)
    stats = json.loads(paths["percentiles"].read_text())
    # the main outputs, the deployments in the order they happen (pilot at 2 s before main at 9 s), the
    # separation, then the tensions
    assert list(stats) == ["final_altitude",
                           "deploy_mach_pilot", "deploy_dynamic_pressure_pilot", "deploy_altitude_pilot",
                           "deploy_time_pilot",
                           "deploy_mach_main", "deploy_dynamic_pressure_main", "deploy_altitude_main",
                           "deploy_time_main",
                           "separation_time_heat_shield", "separation_clearance_heat_shield", "peak_tension_riser"]
    assert stats["separation_clearance_heat_shield"]["count"] == 6
    assert stats["deploy_mach_main"]["p1_ci"][0] <= stats["deploy_mach_main"]["p1"]
    report = paths["report"].read_text()
    assert "| separation_clearance_heat_shield (m) |" in report
    assert "| deploy_dynamic_pressure_main (Pa) |" in report
    for system in ("pilot", "main"):
        assert paths[f"deployment box {system}"].is_file()
        assert f"`deployment_box_{system}.png`" in report
    assert "## Deployment box" in report


@pytest.mark.long
def test_a_small_triggered_study_keeps_the_deployment_conditions(tmp_path):
    case = tmp_path / "pa1_triggers.toml"
    case.write_text(TRIGGERED_PA1)
    study = tmp_path / "study.toml"
    study.write_text(STUDY.format(case=case.as_posix()))
    counts = run_study(load_study(study), tmp_path / "out", workers=2, progress=False)
    assert counts.executed == 4 and counts.failed == 0
    with open(tmp_path / "out" / "runs.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    for row in rows:
        threshold = float(row["systems.main.deploy_trigger.below"])
        values = {name: float(row[f"deploy_{name}_main"]) for name in ("mach", "dynamic_pressure", "altitude",
                                                                        "time")}
        assert all(math.isfinite(v) for v in values.values())
        assert threshold - 5.0 < values["altitude"] <= threshold   # 20 Hz at about 46 m/s: within 2.3 m
        assert 0.1 < values["mach"] < 0.2 and 500.0 < values["dynamic_pressure"] < 2000.0
    assert "deploy_mach_drogue" not in rows[0]   # the drogues deploy on a timer: no trigger conditions
    paths = study_report(tmp_path / "out")
    assert paths["deployment box main"].is_file() and paths["deployment box main"].stat().st_size > 0
    stats = json.loads(paths["percentiles"].read_text())
    assert {"deploy_mach_main", "deploy_dynamic_pressure_main", "deploy_altitude_main", "deploy_time_main"} <= set(stats)

"""Typed results (issues 47, 54): a run's summary is the typed RunSummary in memory, whether the run was just made or
read back from its folder, a dict only in summary.json; a study's run records and a fit's evaluations are typed too,
each written by its ``to_dict`` and read back by its ``from_dict`` line for line."""

import json

import pytest

import pchute_exudyn as pc
from pchute_exudyn.fit.evaluate import Evaluation
from pchute_exudyn.results.io import json_text
from pchute_exudyn.results.summary import DeployEvent, FinalState, RecordedEvent, RunSummary, TouchdownEvent
from pchute_exudyn.study import load_study, run_study
from pchute_exudyn.study.runner import StudyOutcome
from pchute_exudyn.study.store import RunRecord, StudyStore
from tests.helpers import ROOT


def test_a_loaded_result_has_the_typed_summary_it_was_saved_with(tmp_path):
    result = pc.simulate(pc.load_case(ROOT / "cases" / "cev_pa1_triggers.toml"), "sp")
    assert isinstance(result.summary, RunSummary) and result.vehicle == "capsule"
    result.save(tmp_path / "r", plot=False)
    loaded = pc.Result.load(tmp_path / "r")
    assert isinstance(loaded.summary, RunSummary)
    kinds = [type(event) for event in loaded.summary.events]
    assert DeployEvent in kinds and kinds[-1] is TouchdownEvent
    assert loaded.summary.touchdown == result.summary.touchdown
    assert json.loads(json_text(loaded.summary.to_dict())) == json.loads(json_text(result.summary.to_dict()))
    # the vehicle's final position: its own columns in memory, summary.json's vehicle_* keys in the file
    final = loaded.summary.final
    assert final.altitude == result.final("capsule_altitude") and final.value("{owner}_east") == final.east
    assert final.value("{owner}_altitude", "main_confluence") == result.final("main_confluence_altitude")
    written = json.loads((tmp_path / "r" / "summary.json").read_text())["final"]
    assert list(written)[:4] == ["time", "vehicle_altitude", "vehicle_east", "vehicle_north"]
    assert written["vehicle_altitude"] == final.altitude and "capsule_altitude" not in written


def test_a_summary_of_an_earlier_version_reads_back_with_what_it_has():
    earlier = {"case": "x", "method": "sp", "integrator": "rk4", "step": 0.01, "kappa_max": 5.0,
               "final": {"time": 2.0, "vehicle_altitude": 10.0, "vehicle_east": 3.0, "vehicle_north": 4.0},
               "events": [{"event": "start", "time": 0.0}, {"event": "touchdown", "time": 2.0, "speed": 5.0},
                          {"event": "a_later_kind", "time": 1.0, "system": "main"}]}
    summary = RunSummary.from_dict(earlier)
    assert (summary.case, summary.vehicle, summary.wall_time, summary.descent) == ("x", None, None, None)
    assert summary.method_settings == {"kappa_max": 5.0} and summary.steps_per_second is None
    assert summary.final == FinalState(2.0, "vehicle", {"vehicle_altitude": 10.0, "vehicle_east": 3.0,
                                                         "vehicle_north": 4.0})
    assert summary.final.lateral == 5.0
    assert summary.touchdown.speed == 5.0 and summary.touchdown.descent_rate is None
    later = summary.events[2]
    assert isinstance(later, RecordedEvent) and later.kind == "a_later_kind" and later.system == "main"
    assert later.to_dict() == earlier["events"][2]
    assert pc.Result({"time": [0.0, 1.0]}, summary=summary).vehicle == "vehicle"
    with pytest.raises(pc.InputError, match="summary: a RunSummary"):
        pc.Result({"time": [0.0, 1.0]}, summary=earlier)


def test_run_records_and_evaluations_read_back_as_they_were_written():
    record = RunRecord(3, "ok", "", {"final_time": 2.0, "peak_tension_riser": None}, "", ("a warning",), 0.5, 50,
                       0.7)
    line = record.to_dict()
    assert list(line) == ["run", "status", "error", "final_time", "peak_tension_riser", "never_fired", "warnings",
                          "wall_time", "steps", "run_time"]
    assert RunRecord.from_dict(json.loads(json.dumps(line))) == record
    failed = RunRecord(4, "failed", "executor error: x")
    assert failed.to_dict() == {"run": 4, "status": "failed", "error": "executor error: x"} and not failed.ok
    evaluation = Evaluation("ok", "", [0.5, 1.0], [1.0], [], ["time"], {"touchdown": 70.0}, 70.0, 0.3, 2)
    assert list(evaluation.to_dict())[-2:] == ["wall_time", "evaluation"]
    assert Evaluation.from_dict(json.loads(json.dumps(evaluation.to_dict()))) == evaluation
    assert Evaluation("failed", "x", [0.5]).to_dict() == {"status": "failed", "error": "x", "values": [0.5]}


def test_a_study_returns_its_outcome_with_its_table_and_failures(tmp_path):
    text = (ROOT / "validation" / "studies" / "pa1_footprint.toml").read_text()
    text = text.replace("runs = 200", "runs = 3").replace('"../../cases/', f'"{(ROOT / "cases").as_posix()}/')
    (tmp_path / "study.toml").write_text(text)
    outcome = run_study(load_study(tmp_path / "study.toml"), tmp_path / "out", workers=1, progress=False)
    assert isinstance(outcome, StudyOutcome)
    assert (outcome.planned, outcome.executed, outcome.failed) == (3, 3, 0) and outcome.failures == {}
    assert outcome.table.is_file() and not hasattr(outcome, "__getitem__")
    records = StudyStore.load_records(tmp_path / "out")
    assert all(isinstance(r, RunRecord) and r.ok and r.outputs["touchdown_speed"] > 0 for r in records.values())
    lines = (tmp_path / "out" / "runs.jsonl").read_text().splitlines()
    assert [json.loads(line)["run"] for line in lines] == [0, 1, 2]

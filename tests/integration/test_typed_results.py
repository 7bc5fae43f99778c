"""Typed results (issue 47): a saved run's summary comes back as the RunSummary it was (``Result.load``), a study
returns a StudyOutcome with its table and failures, a fit a FitOutcome."""

import json

import pchute_exudyn as pc
from pchute_exudyn.results.io import json_text
from pchute_exudyn.results.summary import DeployEvent, RunSummary, TouchdownEvent
from pchute_exudyn.study import load_study, run_study
from pchute_exudyn.study.runner import StudyOutcome
from tests.helpers import ROOT


def test_a_loaded_result_has_the_typed_summary_it_was_saved_with(tmp_path):
    result = pc.simulate(pc.load_case(ROOT / "cases" / "cev_pa1_triggers.toml"), "sp")
    result.save(tmp_path / "r", plot=False)
    loaded = pc.Result.load(tmp_path / "r")
    assert isinstance(loaded.run_summary, RunSummary)
    kinds = [type(event) for event in loaded.run_summary.events]
    assert DeployEvent in kinds and kinds[-1] is TouchdownEvent
    assert json.loads(json_text(loaded.run_summary.to_dict())) == json.loads(json_text(result.run_summary.to_dict()))


def test_a_study_returns_its_outcome_with_its_table_and_failures(tmp_path):
    text = (ROOT / "validation" / "studies" / "pa1_footprint.toml").read_text()
    text = text.replace("runs = 200", "runs = 3").replace('"../../cases/', f'"{(ROOT / "cases").as_posix()}/')
    (tmp_path / "study.toml").write_text(text)
    outcome = run_study(load_study(tmp_path / "study.toml"), tmp_path / "out", workers=1, progress=False)
    assert isinstance(outcome, StudyOutcome)
    assert (outcome.planned, outcome.executed, outcome.failed) == (3, 3, 0) and outcome.failures == {}
    assert outcome.table.is_file() and outcome["executed"] == 3 and dict(outcome)["planned"] == 3

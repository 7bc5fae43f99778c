"""The case and study formats made consistent (issue 59): ``[simulation.steps] sp = "auto"`` means what ``--dt auto``
and a study's ``"auto"`` mean; adaptive steps beside an implicit integrator are refused when the case or the study
loads, in one line; a fixed cut-away time on a system a trigger deploys loads, and the run checks it against the
deployment when that fires. Bad inputs: one line, a non-zero exit, nothing touched outside the output."""

from __future__ import annotations

import numpy as np
import pytest

import pchute_exudyn as pc
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT

ROCKET = ROOT / "cases" / "rocket" / "dual_deploy.toml"   # the main on a trigger, fired at 105.24 s
SIMPLE = (ROOT / "cases" / "simple" / "simple.toml").as_posix()
STUDY = '[study]\ncase = "{case}"\nduration = 0.5\n[[study.configurations]]\nmethod = "full"\n{more}'


def test_a_cases_auto_step_is_the_adaptive_run():
    runs = [pc.simulate(pc.load_case(ROCKET, steps), duration=2.0, history=False, step=step)
            for steps, step in (({}, None), ({"simulation.steps": {"sp": "auto"}}, None), ({}, "auto"))]
    assert runs[0].summary.step_control["count"] > 0
    assert all(np.array_equal(runs[0][k], r[k], equal_nan=True) for r in runs[1:] for k in runs[0].columns)


def _run(tmp, *sets, case=ROCKET):
    return ["run", str(case), "--out", str(tmp / "out"), "--quiet", *[a for s in sets for a in ("--set", s)]]


def _study(tmp, more: str, case: str = SIMPLE):
    if "implicit" in case:   # simple.toml flown with the implicit integrator by default
        (tmp / "implicit.toml").write_text(f'extends = "{SIMPLE}"\n[simulation]\nintegrator = "implicit"\n')
        case = (tmp / "implicit.toml").as_posix()
    (tmp / "study.toml").write_text(STUDY.format(case=case, more=more))
    return ["study", str(tmp / "study.toml"), "--out", str(tmp / "out"), "--workers", "1", "--no-progress"]


BATTERY = [
    ("implicit step auto", lambda t: _run(t, "simulation.method=full", 'simulation.steps={full_implicit = "auto"}'),
     "simulation.steps.full_implicit = 'auto': adaptive steps are RK4's; the implicit integrator needs a step > 0 "
     "(s)"),
    ("step neither a number nor auto", lambda t: _run(t, 'simulation.steps={sp = "fast"}'),
     "simulation.steps.sp = 'fast': must be a number (s) or 'auto' (adaptive steps)"),
    ("study: auto with an implicit configuration", lambda t: _study(t, 'integrator = "implicit"\nsteps = ["auto"]\n'),
     "study.configurations[0].steps = ['auto']: adaptive steps ('auto') are RK4's; the implicit integrator needs a "
     "step > 0 (s)"),
    ("study: auto with a case's implicit integrator", lambda t: _study(t, 'steps = [1e-3, "auto"]\n', "implicit"),
     "study.configurations[0].steps = [0.001, 'auto']: adaptive steps ('auto') are RK4's; the implicit integrator of "
     "case implicit.toml (its simulation.integrator) needs a step > 0 (s)"),
    ("fixed cut-away before a fixed deployment", lambda t: _run(
        t, "systems.main.deploy_trigger={time = 100.0}", "systems.main.cutaway_time=50"),
     "systems.main.cutaway_time = 50.0: must be after the deployment (deploy_time = 100 s)"),
    ("fixed cut-away before a triggered deployment", lambda t: _run(t, "systems.main.cutaway_time=50"),
     "systems.main.cutaway_time = 50 s comes before the deployment its trigger fired at 105.24 s "
     "(systems.main.deploy_trigger): cut it away by a trigger after the deployment (after = \"main.deploy\")"),
]


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_a_format_inconsistency_is_one_line(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)
    assert code == 1 and not (tmp_path / "out").exists()


@pytest.mark.parametrize("cutaway", [{"systems.main.cutaway_time": 106.0}, {"systems.main.cutaway_trigger":
                                                                            {"time": 106.0}}])
def test_a_fixed_cutaway_after_a_triggered_deployment_flies(cutaway):
    result = pc.simulate(pc.load_case(ROCKET, cutaway), duration=107.0, history=False)
    deploy, cut = ([e for e in result.summary.events if e.kind == kind and getattr(e, "system", "") == "main"]
                   for kind in ("deploy", "cutaway"))
    assert [e.time for e in deploy] == [pytest.approx(105.24)] and [e.time for e in cut] == [106.0]

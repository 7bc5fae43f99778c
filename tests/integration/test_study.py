"""Parameter studies and Monte Carlo: reproducible inputs, any executor, a store that loses nothing, reports."""

import csv
import json
import os
import signal
import subprocess
import time

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.cli import main
from pchute_exudyn.study import load_study, run_study
from pchute_exudyn.study.report import study_report
from tests.helpers import MER, ROOT, run_cli, start_cli, study_runs

MC = f"""
[study]
name = "MER dispersion"
case = "{(MER / 'case1.toml').as_posix()}"
runs = {{runs}}
seed = 20261122
duration = {{duration}}

[[study.configurations]]
method = "sp"
steps = [1e-2]

[parameters."vehicle.initial.velocity_east"]
distribution = "normal"
mean = 0.0
std = 0.5

[parameters."parachute.aerodynamics.axial_coefficient"]
distribution = "uniform"
low = 0.95
high = 1.05
relative = true

[parameters."main.lines.*.stiffness"]
distribution = "truncated_normal"
mean = 1.0
std = 0.05
low = 0.9
high = 1.1
relative = true
"""


def write_study(tmp_path, runs=20, duration=3.0, name="mc.toml", text=None):
    path = tmp_path / name
    path.write_text(text if text is not None else MC.format(runs=runs, duration=duration))
    return path


def test_draws_come_from_the_seed_sequence_by_sample_index(tmp_path):
    spec = load_study(write_study(tmp_path, runs=5))
    runs = spec.expand()
    for run in runs:
        rng = np.random.default_rng(np.random.SeedSequence(20261122).spawn(5)[run.sample])
        assert run.values["vehicle.initial.velocity_east"] == rng.normal(0.0, 0.5)
        assert run.values["parachute.aerodynamics.axial_coefficient"] == rng.uniform(0.95, 1.05)
        assert 0.9 <= run.values["main.lines.*.stiffness"] <= 1.1
    # a relative draw multiplies each line's own stiffness
    case = pc.load_case(runs[0].case_file, runs[0].overrides())
    factor = runs[0].values["main.lines.*.stiffness"]
    assert [l.stiffness for l in case.systems["main"].lines] == pytest.approx([47000 * factor] * 3 + [60000 * factor])


def test_same_results_with_one_worker_two_workers_and_a_dask_cluster(tmp_path):
    from pchute_exudyn.study import dask_executor
    spec = load_study(write_study(tmp_path, runs=20))
    run_study(spec, tmp_path / "one", workers=1, progress=False)
    run_study(spec, tmp_path / "two", workers=2, progress=False)
    executor, close = dask_executor(local_workers=2)          # a real LocalCluster, two worker processes
    try:
        run_study(spec, tmp_path / "dask", executor=executor, progress=False)
    finally:
        close()
    one = study_runs(tmp_path / "one")
    assert len(one) == 20 and all(row["status"] == "ok" for row in one)
    assert study_runs(tmp_path / "two") == one
    assert study_runs(tmp_path / "dask") == one
    for name in ("inputs.csv",):
        assert (tmp_path / "two" / name).read_text() == (tmp_path / "one" / name).read_text()
    lateral = np.array([float(row["final_lateral"]) for row in one])
    assert lateral.std() > 0.1                                    # the dispersion does disperse


def test_killed_study_resumes_without_losing_or_repeating_runs(tmp_path):
    study = write_study(tmp_path, runs=24, duration=6.0)
    out = tmp_path / "killed"
    command = ["study", study, "--workers", "1", "--out", out, "--no-progress"]
    process = start_cli(*command, cwd=ROOT, start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    journal = out / "runs.jsonl"
    deadline = time.time() + 120
    while time.time() < deadline:
        if journal.is_file() and len(journal.read_text().splitlines()) >= 5:
            break
        time.sleep(0.1)
    os.killpg(process.pid, signal.SIGKILL)                        # the whole process group, workers included
    process.wait()
    before = journal.read_text().splitlines()
    assert 5 <= len(before) < 24
    done = run_cli(*command, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    assert f"({len([line for line in before if line.endswith('}')])} already done" in done.stdout
    after = [json.loads(line) for line in journal.read_text().splitlines()]
    indices = [record["run"] for record in after]
    assert sorted(indices) == list(range(24))                     # every run once: none lost, none twice
    assert journal.read_text().splitlines()[:len(before)] == before   # finished runs were not redone
    assert len(study_runs(out)) == 24


def test_failed_runs_are_recorded_and_the_study_goes_on(tmp_path):
    text = f"""
[study]
name = "steps"
case = "{(MER / 'case1.toml').as_posix()}"
duration = 1.0
[[study.configurations]]
method = "full"
integrator = "rk4"
steps = [1e-4, 1e-3]
[[study.configurations]]
method = "sp"
steps = [1e-2, 0.05]
"""
    spec = load_study(write_study(tmp_path, text=text))
    counts = run_study(spec, tmp_path / "steps", workers=2, progress=False)
    rows = {(r["method"], float(r["step"])): r for r in study_runs(tmp_path / "steps")}
    assert counts.failed == 2 and counts.executed == 4
    assert rows[("full", 1e-3)]["status"] == "failed" and "stability limit" in rows[("full", 1e-3)]["error"]
    assert rows[("sp", 0.05)]["status"] == "failed" and "stability limit" in rows[("sp", 0.05)]["error"]
    assert rows[("full", 1e-4)]["status"] == "ok" and rows[("sp", 0.01)]["status"] == "ok"
    paths = study_report(tmp_path / "steps")
    assert "Failed runs" in paths["report"].read_text()
    # --retry-failed runs only the failed ones again; the table keeps one row per run, the latest record
    again = run_study(spec, tmp_path / "steps", workers=2, progress=False, retry_failed=True)
    assert again.skipped == 2 and again.executed == 2 and again.failed == 2
    assert sorted(int(r["run"]) for r in study_runs(tmp_path / "steps")) == [0, 1, 2, 3]


def test_a_retried_run_keeps_its_latest_record(tmp_path):
    from pchute_exudyn.study.store import StudyStore
    lines = [{"run": 0, "status": "failed", "error": "x"}, {"run": 1, "status": "ok"},
             {"run": 0, "status": "ok", "error": ""}]
    (tmp_path / "runs.jsonl").write_text("".join(json.dumps(r) + "\n" for r in lines) + '{"run": 2, "sta')
    records = StudyStore.load_records(tmp_path)
    assert sorted(records) == [0, 1] and records[0].status == "ok"      # the torn last line is ignored
    assert records[1].to_dict() == {"run": 1, "status": "ok"}            # read back as written (no entry added)


@pytest.mark.long
def test_report_of_a_grid_with_a_reference(tmp_path):
    text = f"""
[study]
name = "confluence mass"
case = "{(MER / 'case1.toml').as_posix()}"
duration = 2.0
[study.reference]
method = "sp"
step = 1e-3
[[study.configurations]]
method = "full"
integrator = "implicit"
steps = [1e-3]
[parameters."main.confluence.mass"]
values = [0.1539, 0.01539]
"""
    spec = load_study(write_study(tmp_path, text=text))
    assert len(spec.expand()) == 4 and sum(r.reference for r in spec.expand()) == 2
    run_study(spec, tmp_path / "grid", workers=2, progress=False)
    paths = study_report(tmp_path / "grid")
    errors = list(csv.DictReader(open(paths["errors"])))
    assert len(errors) == 2
    heavy, light = sorted(errors, key=lambda e: -float(e["max_tension_error"]))
    assert float(light["max_tension_error"]) < float(heavy["max_tension_error"])   # lighter m_c: closer to SP
    for key in ("histograms", "grid main.confluence.mass", "error_vs_wall_time", "percentiles"):
        assert paths[key].is_file()


def test_a_per_case_reference_runs_the_case_as_written(tmp_path):
    # kappa_max = 2 cannot be applied (must be > 3): the per-case full-mass reference must not inherit it
    text = f"""
[study]
case = "{(MER / 'case4.toml').as_posix()}"
[study.reference]
method = "full"
integrator = "rk4"
step = 1e-4
per = "case"
[[study.configurations]]
method = "sp"
steps = [1e-2]
[parameters."simulation.sp.kappa_max"]
values = [2.0, 5.0, 10.0]
"""
    runs = load_study(write_study(tmp_path, text=text)).expand()
    assert [r.reference for r in runs] == [True, False, False, False]
    assert runs[0].values == {} and runs[0].overrides() == {}
    assert [r.values["simulation.sp.kappa_max"] for r in runs[1:]] == [2.0, 5.0, 10.0]
    assert all(r.reference_run == 0 for r in runs[1:])
    assert pc.load_case(runs[0].case_file, runs[0].overrides()).simulation.options["sp"].effective_kappa_max == 5.0


@pytest.mark.parametrize("snippet, message", [
    ('[parameters."vehicle.mas"]\nvalues = [1.0]\n', 'parameters."vehicle.mas": does not apply'),
    ('[parameters."vehicle.mass"]\ndistribution = "normal"\nmean = 700.0\n', "required by distribution 'normal'"),
    ('[parameters."vehicle.mass"]\ndistribution = "normal"\nmean = 700.0\nstd = -1.0\n', "std = -1.0: must be > 0"),
    ('[parameters."vehicle.mass"]\ndistribution = "uniform"\nlow = 800.0\nhigh = 700.0\n', "must be > low"),
    ('[parameters."vehicle.mass"]\ndistribution = "lognormal"\nmean = 700.0\n', "must be one of"),
    ('[parameters."vehicle.mass"]\nvalues = []\n', "non-empty list"),
    ('[parameters."vehicle.mass"]\nlinspace = { start = 1.0, stop = 2.0, num = 1 }\n', "integer >= 2"),
])
def test_bad_parameters(tmp_path, snippet, message):
    text = f'[study]\ncase = "{(MER / "case1.toml").as_posix()}"\nseed = 1\n' + snippet
    with pytest.raises(pc.CaseError, match="mc.toml") as info:
        load_study(write_study(tmp_path, text=text))
    assert message in str(info.value)


def test_bad_study_settings(tmp_path, capsys):
    for snippet, message in (("runs = -3", "runs = -3: must be an integer >= 1"),
                             ("runs = 0", "must be an integer >= 1"),
                             ('case = "nowhere.toml"', "case file not found")):
        text = f'[study]\ncase = "{(MER / "case1.toml").as_posix()}"\n{snippet}\n'
        if snippet.startswith("case"):
            text = f"[study]\n{snippet}\n"
        code = main(["study", str(write_study(tmp_path, text=text)), "--no-progress", "--out", str(tmp_path / "x")])
        err = capsys.readouterr().err
        assert code == 1 and message in err and len(err.strip().splitlines()) == 1, err


def test_unreachable_dask_scheduler_fails_fast_with_a_clear_message(tmp_path, capsys):
    started = time.time()
    code = main(["study", str(write_study(tmp_path, runs=2)), "--dask-scheduler", "tcp://127.0.0.1:9",
                 "--dask-timeout", "2", "--out", str(tmp_path / "y")])
    err = capsys.readouterr().err
    assert code == 1 and "could not reach the Dask scheduler at 'tcp://127.0.0.1:9' within 2 s" in err
    assert time.time() - started < 30


def test_study_on_a_running_dask_scheduler_by_address(tmp_path):
    from distributed import LocalCluster
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        code = main(["study", str(write_study(tmp_path, runs=2, duration=1.0)), "--dask-scheduler",
                     cluster.scheduler_address, "--no-progress", "--out", str(tmp_path / "remote")])
    rows = study_runs(tmp_path / "remote")
    assert code == 0 and len(rows) == 2 and all(r["status"] == "ok" for r in rows)


def test_changed_study_is_not_resumed_into_the_same_folder(tmp_path):
    run_study(load_study(write_study(tmp_path, runs=2, duration=1.0)), tmp_path / "s", workers=1, progress=False)
    changed = load_study(write_study(tmp_path, runs=3, duration=1.0))
    with pytest.raises(pc.InputError, match="differ"):
        run_study(changed, tmp_path / "s", workers=1, progress=False)


@pytest.mark.long
def test_a_dask_worker_killed_mid_study_loses_and_duplicates_no_run(tmp_path):
    """A real worker process is killed (SIGKILL) while the study runs: Dask reschedules its run, and every run is
    recorded exactly once."""
    import threading

    from distributed import Client, LocalCluster

    spec = load_study(write_study(tmp_path, runs=16, duration=30.0))
    out = tmp_path / "killed"
    killed = []

    def kill_one_worker_when_runs_are_recording(client):
        records = out / "runs.jsonl"
        deadline = time.time() + 60
        while time.time() < deadline and not (records.is_file() and len(records.read_text().splitlines()) >= 2):
            time.sleep(0.05)
        pid = next(iter(client.run(os.getpid).values()))
        os.kill(pid, signal.SIGKILL)
        killed.append(pid)

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster, set_as_default=False) as client:
        killer = threading.Thread(target=kill_one_worker_when_runs_are_recording, args=(client,))
        killer.start()
        counts = run_study(spec, out, client.get_executor(pure=False), progress=False)
        killer.join()
    runs = [json.loads(line)["run"] for line in (out / "runs.jsonl").read_text().splitlines()]
    assert killed and counts.executed == 16
    assert sorted(runs) == list(range(16))                    # every run once: none lost, none twice
    assert all(row["status"] == "ok" for row in study_runs(out))


def test_a_run_without_history_skips_only_columns_nothing_reads():
    """A study run that keeps no history leaves out the columns the summary never reads and the scene: its record and
    summary are the same."""
    from pchute_exudyn.study.runner import scalar_outputs

    case = pc.load_case(ROOT / "cases" / "cev_pa1_winds.toml")
    full, lean = (pc.simulate(case, "sp", duration=12.0, history=keep) for keep in (True, False))
    assert "capsule_mach" in full and "capsule_mach" not in lean and "capsule_wind_east" not in lean
    assert "main_canopy_altitude" in full and "main_canopy_altitude" not in lean and lean.scene is None
    timing = ("wall_time", "steps_per_second", "created", "units")
    assert repr({k: v for k, v in full.summary.to_dict().items() if k not in timing}) == \
        repr({k: v for k, v in lean.summary.to_dict().items() if k not in timing})
    assert repr(scalar_outputs(full)) == repr(scalar_outputs(lean))
    for name in lean.names:
        assert np.array_equal(full[name], lean[name], equal_nan=True), name


def test_a_run_leaves_no_engine_model_behind():
    """Exudyn holds the user functions of a model's system from C++, where the garbage collector cannot see the
    cycle back to the model: each phase's system is released once read, so a study's worker does not grow with
    every run (it grew by 7 MB a PA1 run)."""
    import gc

    from pchute_exudyn.engine.phase_model import Model

    def models() -> set:
        gc.collect()
        return {id(o) for o in gc.get_objects() if isinstance(o, Model)}
    already = models()   # (other tests may keep models of their own)
    case = pc.load_case(ROOT / "cases" / "cev_pa1.toml")
    for _ in range(2):
        pc.simulate(case, "sp", duration=12.0)   # three phases: drogues, mains
    assert models() <= already


def test_a_study_setting_another_overrides_is_warned(tmp_path):
    """The third battery's: a grid on simulation.duration beside the study's duration (every run flew 2 s), and Sobol
    sampling of 3 runs, both without a word."""
    text = MC.format(runs=3, duration=2.0).replace('seed = 20261122', 'seed = 20261122\nsampling = "sobol"') \
        + '\n[parameters."simulation.duration"]\nvalues = [1.0, 3.0]\n'
    warnings = load_study(write_study(tmp_path, text=text)).warnings
    assert warnings == ["parameters.\"simulation.duration\": has no effect: the study's duration (2 s) is every run's",
                        "sampling = 'sobol' with runs = 3: a Sobol sequence keeps its balance only at a power of 2 "
                        "runs (e.g. 4 or 8)"]
    assert load_study(write_study(tmp_path, runs=4)).warnings == []

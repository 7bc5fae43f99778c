"""Reports that tell the truth (issue 34): failed runs first in a study's report (count, rate and its Wilson interval,
the runs and their inputs, what separates them, marked on the figures), the exit status of `pchute study` with
`--allow-failures`, sensitivities that skip round-off, the failures a run flew with in summary.json, no progress bar
in a redirected log, and the rate of descent on the overview figure."""

import io
import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.cli import main
from pchute_exudyn.errors import PchuteError
from pchute_exudyn.study import load_study, run_study
from pchute_exudyn.study.failures import wilson_interval
from pchute_exudyn.study.footprint import footprint_statistics
from pchute_exudyn.study.report import load_table, scatter_figure, sensitivity, study_report
from pchute_exudyn.views.progress import LogProgress, run_progress
from pchute_exudyn.views.study_figures import footprint_figure
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import MER, ROOT, run_cli

STIFF = "main.lines.*.stiffness"
STUDY = f"""
[study]
name = "stiff lines"
case = "{(MER / 'case1.toml').as_posix()}"
runs = 8
seed = 7
duration = 0.5

[[study.configurations]]
method = "sp"
steps = [1e-2]

[parameters."{STIFF}"]
distribution = "uniform"
low = {{low}}
high = {{high}}
relative = true

[parameters."vehicle.initial.velocity_east"]
distribution = "normal"
mean = 0.0
std = 0.5
"""
"""Line stiffness x 2.9 or more puts the SP step of 0.01 s above the confluence's stability limit: those runs fail
with a clear error, the others fly; the lateral velocity does not matter."""


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """A real 8-run study of which some runs fail, run as a process with standard error redirected to a file, and
    its report: (folder, process, log text, report text, runs.csv rows)."""
    tmp = tmp_path_factory.mktemp("failing")
    path = tmp / "stiff.toml"
    path.write_text(STUDY.format(low=0.5, high=3.5))
    folder = tmp / "out"
    with open(tmp / "log", "w") as log:
        process = run_cli("study", path, "--workers", "2", "--out", folder, stdout=subprocess.PIPE, stderr=log,
                          timeout=120)
    report = study_report(folder)["report"].read_text()
    return folder, process, (tmp / "log").read_text(), report, load_table(folder)


def failed_rows(rows):
    return [r for r in rows if r["status"] != "ok"]


def test_a_study_with_failed_runs_exits_1_with_the_count_and_rate(study):
    folder, process, log, _, rows = study
    failed, finished = len(failed_rows(rows)), len(rows)
    assert 0 < failed < finished == 8                   # the draws give both kinds
    assert process.returncode == 1, log
    rate = f"{100 * failed / finished:.1f} %"
    assert f"{failed} failed of 8: {rate} of the finished runs" in process.stdout
    assert log.splitlines()[-1] == (f"pchute study: {failed} of 8 finished runs failed ({rate}), more than "
                                    "--allow-failures 0 allows: `pchute study-report` lists them")


def test_allow_failures_decides_the_exit_status(study, capsys):
    folder, _, _, _, rows = study
    path = folder.parent / "stiff.toml"
    share = len(failed_rows(rows)) / len(rows)
    for allowed, expected in (("0.5", 0), ("1", 0), (f"{share - 0.01:.4f}", 1), ("0", 1)):
        code = main(["study", str(path), "--no-progress", "--out", str(folder), "--allow-failures", allowed])
        assert code == expected, (allowed, capsys.readouterr())
    assert len(load_table(folder)) == 8                # every run was already done: nothing rerun


def test_a_redirected_log_gets_lines_not_a_bar(study):
    log = study[2]
    assert "\r" not in log and "|" not in log and "it/s" not in log and "run/s" not in log
    progress = [line for line in log.splitlines() if line.startswith("study: ")]
    assert 1 <= len(progress) <= 10 and progress[-1].startswith("study: 8 of 8 runs done, failed ")


def test_the_first_table_gives_the_failure_rate_and_its_wilson_interval(study):
    _, _, _, report, rows = study
    k, n = len(failed_rows(rows)), len(rows)
    first = next(line for line in report.splitlines() if line.startswith("| "))
    assert first.startswith("| runs planned | finished | ok | failed | not run | failure rate")
    values = report.splitlines()[report.splitlines().index(first) + 2]
    # Wilson's interval as the roots of (n + z^2) p^2 - (2k + z^2) p + k^2 / n = 0
    z = 1.959963984540054
    a, b, c = n + z * z, -(2 * k + z * z), k * k / n
    roots = sorted(np.roots([a, b, c]).real)
    assert wilson_interval(k, n) == pytest.approx(roots, abs=1e-12)
    assert values == (f"| 8 | 8 | {n - k} | {k} | 0 | {100 * k / n:.1f} % [{100 * roots[0]:.1f} %, "
                      f"{100 * roots[1]:.1f} %] |")
    assert report.index("failure rate") < report.index("## Outputs") < report.index("| output | p1 |")
    assert f"Percentiles of {n - k} ok runs ({k} failed excluded" in report
    record = json.loads((study[0] / "report" / "failures.json").read_text())
    assert (record["planned"], record["failed"], record["interval"]) == (8, k, pytest.approx(roots, abs=1e-12))
    assert record["failed_runs"] == [int(r["run"]) for r in failed_rows(rows)]
    assert record["separation"][0]["parameter"] == STIFF and record["separation"][0]["rank_biserial"] == 1.0


def test_wilson_interval_edges():
    assert wilson_interval(0, 10)[0] == 0.0 and 0.0 < wilson_interval(0, 10)[1] < 0.35
    assert wilson_interval(10, 10)[1] == 1.0 and wilson_interval(10, 10)[0] > 0.65
    assert wilson_interval(0, 0) == (0.0, 1.0)


def test_failed_runs_are_listed_with_their_inputs_and_the_separating_input_is_named(study):
    _, _, _, report, rows = study
    table = report[report.index("## Failed runs"):report.index("### What separates")]
    for r in failed_rows(rows):
        line = next(line for line in table.splitlines() if line.startswith(f"| {int(r['run'])} | case1 |"))
        assert f"| {r[STIFF]:.6g} |" in line and "stability limit" in line
    assert table.count("| case1 |") == len(failed_rows(rows))
    assert f"The input that separates them best: `{STIFF}` (r = +1.00)." in report
    separation = report[report.index("### What separates"):]
    stiffness = separation[separation.index(f"| {STIFF} | "):].splitlines()[0]
    assert "| +1.00 |" in stiffness


def test_the_scatter_figure_marks_each_failed_run_at_its_drawn_value(study):
    folder, _, _, report, rows = study
    ok = [r for r in rows if r["status"] == "ok"]
    failed = failed_rows(rows)
    figure = scatter_figure(ok, failed, STIFF, "stiffness", ["final_altitude", "peak_tension_riser"])
    for ax in figure.axes:
        marks = [line for line in ax.get_lines() if line.get_marker() == "x" and line.get_color() == "red"]
        assert len(marks) == 1 and sorted(marks[0].get_xdata()) == sorted(r[STIFF] for r in failed)
    assert f"red x: {len(failed)} failed runs" in figure.get_suptitle()
    assert (folder / "report" / "scatter_main_lines_stiffness.png").is_file()


def test_the_footprint_says_how_many_failed_runs_it_does_not_show():
    points = np.array([[0.0, 0.0], [10.0, 2.0], [3.0, 8.0], [5.0, -4.0]])
    figure = footprint_figure(points, footprint_statistics(points), "drop", failed=4)
    legend = [text.get_text() for text in figure.axes[0].get_legend().get_texts()]
    assert "4 failed runs not shown: no touchdown" in legend
    assert "4 failed runs not shown" in figure.get_suptitle()
    assert not any("failed" in t for t in (text.get_text() for text in footprint_figure(
        points, footprint_statistics(points), "drop").axes[0].get_legend().get_texts()))


def test_sensitivities_skip_an_output_at_round_off():
    rng = np.random.default_rng(1)
    drawn = rng.uniform(0.0, 1.0, 12)
    rows = [{"mass": float(x), "final_east": float(1e-14 + 2.9e-13 * x), "final_altitude": float(100.0 + 3.0 * x)}
            for x in drawn]
    ranking, skipped = sensitivity(rows, ["mass"], ["final_east", "final_altitude"])
    assert skipped == ["final_east"] and "final_east" not in ranking
    assert ranking["final_altitude"] == [("mass", pytest.approx(1.0))]


def test_the_report_says_which_outputs_it_skipped_as_round_off(study):
    report, rows = study[3], study[4]
    north = [r["final_north"] for r in rows if r["status"] == "ok"]
    assert max(abs(v) for v in north) < 1e-12           # nothing pushes the runs north: round-off
    assert "| final_north (m) | skipped: its spread over the runs is round-off" in report


def test_a_study_whose_runs_all_failed_gets_a_report(tmp_path):
    path = tmp_path / "all.toml"
    path.write_text(STUDY.format(low=4.0, high=6.0).replace("runs = 8", "runs = 4"))
    counts = run_study(load_study(path), tmp_path / "all", workers=1, progress=False)
    assert counts.planned == 4 and counts.failed == 4 and counts.executed == 4
    report = study_report(tmp_path / "all")["report"].read_text()
    assert "| 4 | 4 | 0 | 4 | 0 | 100.0 % [51.0 %, 100.0 %] |" in report
    assert "No outputs: no run ended ok (4 failed)." in report and report.count("stability limit") == 4


def test_summary_records_the_failures_flown_and_the_planned_events(tmp_path, capsys):
    trio = str(ROOT / "tests" / "cases" / "cluster_trio.toml")
    args = ["run", trio, "--t-end", "0.3", "--no-plot", "--quiet", "--set", "failures.not_inflated=[\"c2\"]",
            "--set", "failures.cutaway.c3=0.2", "--out", str(tmp_path / "failing")]
    assert main(args) == 0, capsys.readouterr().err
    summary = json.loads((tmp_path / "failing" / "summary.json").read_text())
    assert summary["failures"] == {"not_inflated": ["c2"], "not_inflated_model": "absent", "trailing_fraction": 0.0,
                                   "cutaway": {"c3": 0.2}}
    assert summary["events_planned"] == {"main": {"deploy_time": 0.0, "cutaway_time": None}}
    plain = pc.simulate(pc.load_case(MER / "case1.toml"), "sp", step=1e-2, duration=0.2, history=False)
    assert plain.summary.failures == {}
    assert plain.summary.events_planned == {"main": {"deploy_time": None, "cutaway_time": None}}


def test_the_overview_has_rate_of_descent_against_altitude(tmp_path, capsys):
    from pchute_exudyn.views.plotting import plot_overview

    out = tmp_path / "r"
    assert main(["run", str(MER / "case1.toml"), "--method", "sp", "--dt", "1e-2", "--t-end", "2", "--quiet",
                 "--out", str(out)]) == 0, capsys.readouterr().err
    assert (out / "overview.png").stat().st_size > 10000
    result = pc.Result.load(out)
    axes = plot_overview(result).axes
    assert [ax.get_ylabel() for ax in axes] == ["line tension (N)", "vehicle altitude (m)", "vehicle altitude (m)"]
    panel = axes[2]
    assert panel.get_xlabel() == "rate of descent (m/s)"
    line = panel.get_lines()[0]
    assert np.array_equal(line.get_xdata(), result["vehicle_velocity_down"])
    assert np.array_equal(line.get_ydata(), result["vehicle_altitude"])


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_is_a_bar_on_a_terminal_and_lines_elsewhere():
    log = io.StringIO()
    bar = run_progress(20, 0, 0, log)
    assert isinstance(bar, LogProgress)
    for done in range(20):
        bar.update(1)
        bar.set_postfix(failed=done // 10)
    bar.close()
    lines = log.getvalue().splitlines()
    assert len(lines) == 10 and lines[0] == "study: 2 of 20 runs done, failed 0" and "\r" not in log.getvalue()
    assert lines[-1] == "study: 20 of 20 runs done, failed 1"
    terminal = _Terminal()
    bar = run_progress(3, 0, 0, terminal)
    assert not isinstance(bar, LogProgress)
    bar.update(1)
    bar.close()
    assert "\r" in terminal.getvalue()


def _study_folder(tmp: Path, runs_csv: bytes | None = None, **files) -> str:
    """A study folder holding ``runs.csv`` (bytes) and the other ``files`` (name -> text)."""
    folder = tmp / "s"
    folder.mkdir(exist_ok=True)
    if runs_csv is not None:
        (folder / "runs.csv").write_bytes(runs_csv)
    for name, text in files.items():
        (folder / name.replace("_", ".", 1)).write_text(text)
    return str(folder)


GOOD_RUNS = b"run,status,error,final_altitude\n0,ok,,100.5\n1,failed,boom,\n"


def _failing_study(tmp: Path) -> str:
    path = tmp / "stiff.toml"
    path.write_text(STUDY.format(low=3.2, high=3.5).replace("runs = 8", "runs = 2"))
    return str(path)


BATTERY = [
    ("allow-failures below 0", lambda t: ["study", _failing_study(t), "--allow-failures", "-0.1"],
     "--allow-failures = -0.1: must be a fraction of the runs from 0 to 1"),
    ("allow-failures above 1", lambda t: ["study", _failing_study(t), "--allow-failures", "1.5"],
     "--allow-failures = 1.5: must be a fraction of the runs from 0 to 1"),
    ("allow-failures NaN", lambda t: ["study", _failing_study(t), "--allow-failures", "nan"],
     "--allow-failures = nan: must be a fraction"),
    ("allow-failures infinite", lambda t: ["study", _failing_study(t), "--allow-failures", "inf"],
     "--allow-failures = inf: must be a fraction"),
    ("allow-failures not a number", lambda t: ["study", _failing_study(t), "--allow-failures", "most"],
     "argument --allow-failures: invalid float value: 'most'"),
    ("allow-failures as a percentage", lambda t: ["study", _failing_study(t), "--allow-failures", "20"],
     "--allow-failures = 20.0: must be a fraction of the runs from 0 to 1"),
    ("every run failed", lambda t: ["study", _failing_study(t), "--no-progress", "--workers", "1", "--out",
                                    t / "work" / "o"],
     "pchute study: 2 of 2 finished runs failed (100.0 %), more than --allow-failures 0 allows"),
    ("more failed than allowed", lambda t: ["study", _failing_study(t), "--no-progress", "--workers", "1",
                                            "--allow-failures", "0.9", "--out", t / "work" / "o"],
     "2 of 2 finished runs failed (100.0 %), more than --allow-failures 0.9 allows"),
    ("report of no study folder", lambda t: ["study-report", _study_folder(t)], "no runs.csv: not a study folder"),
    ("report of a file", lambda t: ["study-report", _file(t, "runs.txt", "x")], "no runs.csv: not a study folder"),
    ("report of a non-UTF-8 runs.csv", lambda t: ["study-report", _study_folder(t, b"run,status\n0,ok\xff\xfe\n")],
     "not a runs table pchute wrote (UnicodeDecodeError)"),
    ("report of a runs.csv without status", lambda t: ["study-report", _study_folder(t, b"run,x\n0,1\n")],
     "runs.csv: no status column: not a runs table pchute wrote"),
    ("report of an empty runs.csv", lambda t: ["study-report", _study_folder(t, b"")],
     "runs.csv: no run or status column"),
    ("report of a run that is not a number", lambda t: ["study-report", _study_folder(t, b"run,status\nseven,ok\n")],
     "runs.csv: run = 'seven': must be a run number"),
    ("report of a fractional run", lambda t: ["study-report", _study_folder(t, b"run,status\n1.5,ok\n")],
     "runs.csv: run = 1.5: must be a run number"),
    ("report with a broken study.toml", lambda t: ["study-report", _study_folder(t, GOOD_RUNS, study_toml="[study")],
     "its study.toml or manifest.json cannot be read (TOMLDecodeError"),
    ("report with an empty manifest", lambda t: ["study-report", _study_folder(t, GOOD_RUNS, manifest_json="")],
     "its study.toml or manifest.json cannot be read (JSONDecodeError"),
    ("report with a list manifest", lambda t: ["study-report", _study_folder(t, GOOD_RUNS, manifest_json="[1]")],
     "manifest.json: not a JSON object"),
    ("report with parameters not a table", lambda t: ["study-report", _study_folder(
        t, GOOD_RUNS, study_toml="parameters = 3\n")], "each [parameters.\"<key>\"] must be tables"),
    ("report with a parameter not a table", lambda t: ["study-report", _study_folder(
        t, GOOD_RUNS, study_toml="[parameters]\n\"vehicle.mass\" = 3\n")], "must be tables"),
    ("report folder blocked by a file", lambda t: ["study-report", _study_folder(t, GOOD_RUNS, report="x")],
     "report' is a file"),
]


def _file(tmp: Path, name: str, text: str) -> str:
    (tmp / name).write_text(text)
    return str(tmp / name)


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_bad_input_gives_one_line_and_a_nonzero_exit(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)


def test_the_report_of_a_hand_written_table_counts_failures_without_a_study_file(tmp_path):
    folder = Path(_study_folder(tmp_path, GOOD_RUNS))
    report = study_report(folder)["report"].read_text()
    assert "| 2 | 2 | 1 | 1 | 0 | 50.0 % [9.5 %, 90.5 %] |" in report and "| 1 | None |" not in report
    assert math.isclose(wilson_interval(1, 2)[0], 0.0945, abs_tol=5e-5)


def test_api_errors_of_the_report_are_project_errors(tmp_path):
    with pytest.raises(PchuteError) as info:
        study_report(_study_folder(tmp_path, b"run,status\n0,ok\xff\n"))
    assert len(str(info.value).splitlines()) == 1 and "runs.csv" in str(info.value)



def test_a_drawn_choice_gets_its_failures_per_value(tmp_path):
    text = STUDY.split("[parameters.")[0].replace("runs = 8", "runs = 6") + (
        f'[parameters."{STIFF}"]\ndistribution = "choice"\nvalues = [47000.0, 400000.0]\n')
    path = tmp_path / "choice.toml"
    path.write_text(text)
    run_study(load_study(path), tmp_path / "c", workers=1, progress=False)
    rows = load_table(tmp_path / "c")
    stiff = [r for r in rows if r[STIFF] == 400000.0]
    assert stiff and all(r["status"] == "failed" for r in stiff) and len(stiff) < len(rows)
    report = study_report(tmp_path / "c")["report"].read_text()
    assert f"Failures by `{STIFF}`:" in report
    assert f"| 400000 | {len(stiff)} | {len(stiff)} | 100.0 % |" in report
    assert f"| 47000 | {len(rows) - len(stiff)} | 0 | 0.0 % |" in report

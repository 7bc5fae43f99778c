"""Issue 49, nothing silent in studies of events, fits of events, `pchute new` and unit slips: each bad input is one
line naming the field, the value and what is allowed, a non-zero exit, no traceback and nothing touched outside the
output; each silent outcome is now said (a column, a journal line, a report section, a warning).
"""

import json
from pathlib import Path

import pytest

from pchute_exudyn.errors import InputError
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT

CASE1 = (ROOT / "cases" / "mer" / "case1.toml").as_posix()
EDL = (ROOT / "cases" / "mer" / "edl.toml").as_posix()


def _file(tmp: Path, name: str, text: str) -> Path:
    path = tmp / name
    path.write_text(text)
    return path


def _edl_study(tmp: Path, parameters: str, runs: str = "") -> list:
    """A 1-s study of the MER EDL case (its Mach trigger fires at 0.5 s with `below = 2.1`, never with 1.0)."""
    path = _file(tmp, "study.toml", f'[study]\ncase = "{EDL}"\nduration = 1.0\n{runs}[[study.configurations]]\n'
                                    f'method = "sp"\nsteps = [5e-3]\n{parameters}')
    return ["study", path, "--out", tmp / "study_out", "--workers", "1", "--no-progress"]


# -- studies of events ------------------------------------------------------------------------------------------------

def test_a_trigger_that_fires_in_some_runs_is_recorded_as_such(tmp_path):
    make = lambda t: _edl_study(t, '[parameters."main.deploy_trigger.below"]\nvalues = [2.1, 1.0]\n')  # noqa: E731
    code, err, _, touched = run_bad_input(make, tmp_path)
    assert code == 0 and not err.strip() and not touched, err
    out = tmp_path / "study_out"
    rows = (out / "runs.csv").read_text().splitlines()
    header = rows[0].split(",")
    fired, unfired = (dict(zip(header, row.split(","))) for row in rows[1:])
    assert fired["never_fired"] == "heat_shield.separation" and fired["deploy_time_main"] == "0.505"
    assert unfired["never_fired"] == "main.deploy heat_shield.separation" and unfired["deploy_time_main"] == ""
    assert "warnings" not in header   # kept in the journal
    journal = [json.loads(line) for line in (out / "runs.jsonl").read_text().splitlines()]
    assert journal[1]["warnings"][0] == "systems.main.deploy_trigger never fired (mach below 1) in the 1 s run"
    from pchute_exudyn.study.report import study_report

    study_report(out)
    report = (out / "report" / "report.md").read_text()
    assert "## Triggers that never fired" in report and "| main.deploy | 1 |" in report
    assert "| heat_shield.separation | 2 |" in report
    assert json.loads((out / "report" / "failures.json").read_text())["never_fired"] == {
        "heat_shield.separation": 2, "main.deploy": 1}


def test_a_dispersed_key_with_no_effect_warns_in_one_line(tmp_path):
    make = lambda t: _edl_study(t, '[parameters."main.deploy_trigger.pressure_bias"]\ndistribution = "normal"\n'  # noqa: E731
                                   'mean = 0.0\nstd = 10.0\n', "runs = 2\nseed = 1\n")
    code, err, _, touched = run_bad_input(make, tmp_path)
    assert code == 0 and not touched, err
    assert err.strip() == ('pchute study: warning: parameters."main.deploy_trigger.pressure_bias": has no effect in '
                           'case edl.toml: systems.main.deploy_trigger (mach below 2) reads no value its pressure '
                           'error reaches; every run draws it in vain')


def test_a_corrupt_parquet_table_is_one_line_naming_the_file(tmp_path):
    from pchute_exudyn import study

    pytest.importorskip("pyarrow")
    (tmp_path / "runs.csv").write_text("run,status\n0,ok\n")
    (tmp_path / "runs.parquet").write_bytes(b"PAR1 this is no table PAR1")
    with pytest.raises(InputError) as info:
        study.load(tmp_path)
    message = str(info.value)
    assert len(message.splitlines()) == 1 and message.startswith(f"{tmp_path / 'runs.parquet'}: not a Parquet table")
    (tmp_path / "runs.parquet").unlink()
    (tmp_path / "runs.csv").write_bytes(b"run,status\n0,\xff\xfe\n")
    with pytest.raises(InputError, match="runs.csv: not a CSV table pchute wrote"):
        study.load(tmp_path)


# -- fits of events ---------------------------------------------------------------------------------------------------

def _fit(tmp: Path, case: str, target: str, free: str = "parachute.aerodynamics.axial_coefficient") -> list:
    path = _file(tmp, "fit.toml", f'[fit]\ncase = "{case}"\nmethod = "sp"\nstep = 1e-2\n[free."{free}"]\n'
                                  f'low = 0.8\nhigh = 1.2\ninitial = 1.0\n[[targets]]\n{target}\n')
    return ["fit", path, "--out", tmp / "fit_out", "--workers", "1"]


TWO_SEPARATIONS = (f'extends = "{EDL}"\n[bodies.vehicle.points]\nballast = [0.0, 0.5, 0.0]\n[bodies.ballast]\n'
                   'mass = 5.0\ninertia = [0.1, 0.1, 0.1]\n[separations.ballast]\n'
                   'trigger = { after = "main.deploy", delay = 1.0 }\npoint = "vehicle.ballast"\nspeed = 1.0\n'
                   'direction = [0.0, 1.0, 0.0]\n')


def test_a_fit_to_separation_with_two_separating_bodies_is_refused(tmp_path):
    def make(t):
        case = _file(t, "two.toml", TWO_SEPARATIONS)
        return _fit(t, case.as_posix(), 'event = "separation"\ntime = 20.0\nstd = 0.1')

    code, err, seconds, touched = run_bad_input(make, tmp_path)
    assert_one_line(code, err, "targets[0].event = 'separation': 2 bodies separate in the case (ballast, "
                               "heat_shield): name one: 'separation ballast' or 'separation heat_shield'", touched,
                    seconds)


def test_a_fit_history_past_the_end_of_the_run_is_refused(tmp_path):
    def make(t):
        _file(t, "data.csv", "time,tension_riser\n0,0\n0.5,10\n49.5,10\n")
        case = _file(t, "short.toml", f'extends = "{CASE1}"\n[simulation]\nduration = 0.5\n')
        return _fit(t, case.as_posix(), 'history = "data.csv"\ncolumn = "tension_riser"\nstd = 1.0',
                    "parachute.aerodynamics.axial_coefficient")

    code, err, seconds, touched = run_bad_input(make, tmp_path)
    assert_one_line(code, err, "targets[0].history: samples up to 49.5 s run 49 s past the end of the run at the "
                               "starting values (0.5 s): drop them from the file or lengthen simulation.duration",
                    touched, seconds, limit=30.0)


def test_compare_refuses_an_empty_out(tmp_path):
    code, err, seconds, touched = run_bad_input(lambda t: ["compare", CASE1, CASE1, "--out", ""], tmp_path)
    assert_one_line(code, err, "--out = '': must name a folder", touched, seconds)


# -- pchute new -------------------------------------------------------------------------------------------------------

NEW = [
    ("mass 1e30", ["--mass", "1e30"], "mass = 1e+30: must be within 1e-06..1e+15 (kg) for this tool"),
    ("mass 1e-7", ["--mass", "1e-7"], "mass = 1e-07: must be within 1e-06..1e+15 (kg) for this tool"),
    ("speed 1e6", ["--speed", "1e6"], "speed = 1000000.0: must be within -20000..20000 (m/s) for this tool"),
    ("wind 1e4", ["--wind-speed", "1e4"], "wind_speed = 10000.0: must be within -1000..1000 (m/s) for this tool"),
    ("name with a newline", ["--name", "two\nlines"], "name = 'two\\nlines': must be one line of printable text"),
    ("name with a tab", ["--name", "a\tb"], "name = 'a\\tb': must be one line of printable text"),
    ("static line without a release", ["--static-line-time", "2"],
     "static_line_time = 2.0: only with release_airspeed (--release-airspeed)"),
    ("static line of its default without a release", ["--static-line-time", "1"],
     "static_line_time = 1.0: only with release_airspeed (--release-airspeed)"),
]


@pytest.mark.parametrize("name, options, expected", NEW, ids=[entry[0] for entry in NEW])
def test_pchute_new_never_writes_a_file_run_refuses(tmp_path, name, options, expected):
    code, err, seconds, touched = run_bad_input(
        lambda t: (t / "out").mkdir(exist_ok=True) or ["new", t / "out" / "new.toml", *options], tmp_path)
    assert_one_line(code, err, expected, touched, seconds)
    assert not (tmp_path / "out" / "new.toml").exists()


def test_pchute_new_writes_a_name_with_quotes_that_run_reads(tmp_path):
    from pchute_exudyn.case.loader import load_case
    from pchute_exudyn.cli import main

    assert main(["new", str(tmp_path / "q.toml"), "--name", "it's a \"quoted\" \\ name"]) == 0
    assert load_case(tmp_path / "q.toml").name == "it's a \"quoted\" \\ name"


# -- unit slips ---------------------------------------------------------------------------------------------------------

SLIPS = [
    ("mass in grams", EDL, {"vehicle.mass": 761000.0}, "bodies.vehicle.mass = 761000 kg gives a ballistic "
     "coefficient m / (C_A A) of 8.36e+04 kg/m^2, above every real vehicle's (50000): if it is in grams, give 761 kg"),
    ("mass in grams, inertia in kg m^2", CASE1, {"vehicle.mass": 761000.0}, "if the mass is in grams (the inertia "
     "in kg m^2), give 761 kg"),
    ("inertia in g cm^2", CASE1, {"vehicle.inertia": [[1e9, 0, 0], [0, 1e9, 0], [0, 0, 1e9]]},
     "if the inertia is in g cm^2, give it divided by 1e7 (kg m^2)"),
    ("spin in deg/s", CASE1, {"vehicle.initial.rate_z": 30.0}, "bodies.vehicle.initial.rate_z = 30 rad/s (4.77 "
     "revolutions per second): if it is in deg/s, give 0.523599 rad/s"),
]


@pytest.mark.parametrize("name, case, overrides, expected", SLIPS, ids=[entry[0] for entry in SLIPS])
def test_a_unit_slip_is_a_warning_naming_it(name, case, overrides, expected):
    import pchute_exudyn as pc

    assert any(expected in line for line in pc.load_case(case, overrides).warnings)


def test_a_unit_slip_reaches_the_run_line_and_the_summary(tmp_path, capsys):
    from pchute_exudyn.cli import main

    out = tmp_path / "spun"
    code = main(["run", CASE1, "--set", "vehicle.initial.rate_z=30", "--method", "sp", "--t-end", "0.2", "--no-plot",
                 "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 0 and "pchute run: warning: bodies.vehicle.initial.rate_z = 30 rad/s" in captured.err
    assert "if it is in deg/s" in json.loads((out / "summary.json").read_text())["warnings"][0]


def test_no_shipped_case_has_a_unit_slip():
    from pchute_exudyn.case.loader import load_case
    from pchute_exudyn.case.unit_slips import unit_slips

    shipped = sorted(ROOT.glob("cases/**/*.toml"))
    assert len(shipped) >= 20
    assert not {path.name: slips for path in shipped for slips in [unit_slips(_vehicle(load_case(path)))] if slips}


def _vehicle(case):
    return case.bodies[case.vehicle]

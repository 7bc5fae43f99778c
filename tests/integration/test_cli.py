"""The command line: a run writes the promised files; every user mistake is one line on stderr and a non-zero exit."""

import csv
import json

import numpy as np
import pytest

from pchute_exudyn.cli import main
from tests.helpers import MER, ROOT, run_cli

PA1 = str(ROOT / "cases" / "cev_pa1.toml")
CASE1 = str(MER / "case1.toml")


def run_in_process(capsys, *args):
    code = main(list(args))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_run_writes_files_with_named_columns(capsys, tmp_path):
    out = tmp_path / "case3"
    code, stdout, stderr = run_in_process(capsys, "run", str(MER / "case3.toml"), "--method", "full", "--integrator", "rk4",
                                   "--dt", "1e-4", "--t-end", "0.5", "--out", str(out))
    assert code == 0, stderr
    assert len(stdout.strip().splitlines()) == 1 and "MER case 3" in stdout and str(out) in stdout
    with (out / "timeseries.csv").open() as handle:
        header = next(csv.reader(handle))
    assert header[0] == "time"
    required = ["vehicle_altitude", "vehicle_east", "vehicle_north", "parachute_altitude", "confluence_altitude",
                "vehicle_velocity_north", "vehicle_velocity_east", "vehicle_velocity_down",
                "parachute_velocity_north", "parachute_velocity_east", "parachute_velocity_down",
                "vehicle_yaw_deg", "vehicle_pitch_deg", "vehicle_roll_deg",
                "parachute_yaw_deg", "parachute_pitch_deg", "parachute_roll_deg",
                "confluence_velocity_east", "confluence_velocity_north", "confluence_velocity_down",
                "tension_bridle1", "tension_bridle2", "tension_bridle3", "tension_riser"]
    assert not [c for c in required if c not in header]
    data = np.loadtxt(out / "timeseries.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 0], np.arange(51) * 0.01, atol=1e-9)
    assert data[-1, header.index("vehicle_velocity_east")] > 0.5          # case 3: thrown east at 1 m/s
    summary = json.loads((out / "summary.json").read_text())
    for key in ("case", "method", "integrator", "step", "duration", "steps", "wall_time", "final", "versions"):
        assert key in summary
    assert summary["steps"] == 5000 and summary["method"] == "full" and summary["integrator"] == "rk4"
    assert set(summary["final"]) >= {"vehicle_altitude", "vehicle_east", "vehicle_north"}
    assert set(summary["versions"]) >= {"pchute_exudyn", "exudyn", "numpy", "python"}
    npz = np.load(out / "result.npz")
    np.testing.assert_allclose(npz["tension_riser"], data[:, header.index("tension_riser")], rtol=1e-10)
    assert (out / "overview.png").stat().st_size > 10000
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]   # no temporary files left


def test_help_documents_every_option(capsys):
    with pytest.raises(SystemExit) as info:
        main(["run", "--help"])
    assert info.value.code == 0
    text = capsys.readouterr().out
    for option in ("--method", "--integrator", "--dt", "--t-end", "--out", "--set", "--no-plot"):
        assert option in text


def _bad_case(tmp_path, text):
    path = tmp_path / "bad.toml"
    path.write_text(f'extends = "{(MER / "base.toml").as_posix()}"\n' + text)
    return str(path)


@pytest.mark.parametrize("make_args, expected", [
    (lambda tmp: ["run", str(tmp / "missing.toml")], "case file not found"),
    (lambda tmp: ["run", _write(tmp, "m.toml", "[bodies.vehicle\nmass=1")], "malformed TOML"),
    (lambda tmp: ["run", _bad_case(tmp, "[bodies.vehicle]\nmasss = 3.0\n")], "unknown key"),
    (lambda tmp: ["run", _bad_case(tmp, "[bodies.vehicle]\nmass = -761.0\n")], "must be > 0 (kg)"),
    (lambda tmp: ["run", _bad_case(tmp, "[bodies.vehicle]\nmass = 0\n")], "must be > 0 (kg)"),
    (lambda tmp: ["run", _bad_case(tmp, "[bodies.vehicle]\ninertia = [1.0, 0.0, 1.0]\n")], "positive definite"),
    (lambda tmp: ["run", _bad_case(tmp, "[systems.main.lines.bridle1]\nstiffness = -1.0\n")], "must be >= 0 (N/m)"),
    (lambda tmp: ["run", _bad_case(tmp, "[systems.main.lines.bridle1]\ndamping = -1.0\n")], "must be >= 0 (N s/m)"),
    (lambda tmp: ["run", _bad_case(tmp, "[systems.main.lines.riser]\nfree_length = 0.0\n")], "must be > 0 (m)"),
    (lambda tmp: ["run", _bad_case(tmp, "[systems.main.lines.riser]\nattach = \"lander.riser\"\n")],
     "unknown body 'lander'"),
    (lambda tmp: ["run", CASE1, "--method", "magic"], "invalid choice: 'magic'"),
    (lambda tmp: ["run", CASE1, "--integrator", "euler"], "invalid choice: 'euler'"),
    (lambda tmp: ["run", CASE1, "--dt", "0"], "must be a number > 0"),
    (lambda tmp: ["run", CASE1, "--dt=-1e-4"], "must be a number > 0"),
    (lambda tmp: ["run", CASE1, "--dt", "-0.0001"], "must be a number > 0"),
    (lambda tmp: ["run", CASE1, "--dt", "61"], "must not exceed the duration"),
    (lambda tmp: ["run", CASE1, "--dt", "1e-3", "--t-end", "1e-4"], "must not exceed the duration"),
    (lambda tmp: ["run", CASE1, "--set", "vehicle.masss=800"], "unknown key"),
    (lambda tmp: ["run", CASE1, "--set", "vehicle.mass=heavy"], "must be a number"),
    (lambda tmp: ["run", CASE1, "--set", "vehicle.mass"], "key=value"),
    (lambda tmp: ["run", CASE1, "--out", str(_write(tmp, "file.txt", "x")) + "/out"], "cannot be written"),
    (lambda tmp: ["run", CASE1, "--dt", "1e-3", "--t-end", "2", "--out", str(tmp / "o")], "exceeds the stability"),
    (lambda tmp: ["run", CASE1, "--method", "sp", "--kappa-max", "1"], "must be > 3"),
    (lambda tmp: ["run", CASE1, "--method", "sp", "--integrator", "implicit"], "rk4 only"),
    (lambda tmp: ["run", CASE1, "--method", "sp", "--set", "main.lines.*.damping=0"], "every line has zero damping"),
    (lambda tmp: ["run", CASE1, "--method", "sp", "--slack-rule", "loose"], "invalid choice: 'loose'"),
    (lambda tmp: ["run", CASE1, "--method", "sp", "--t-end", "1e9"], "is 1e+11 steps; the engine counts at most "
                                                                    "2147483647"),
    (lambda tmp: ["run", CASE1, "--dt", "1e-12", "--t-end", "1e-2"], "is 1e+10 steps"),
    (lambda tmp: ["run", CASE1, "--method", "sp", "--t-end", "1e6"], "more than the 4 GB a run may hold"),
    (lambda tmp: ["run", CASE1, "--method", "full", "--sp-order", "1"], "--sp-order is an option of the sp method"),
    (lambda tmp: ["linearize", PA1], "--time = 0 s: no parachute system is present then (drogue from 3.5 s to 9.5 s; "
                                     "main from 9.5 s)"),
    (lambda tmp: ["linearize", PA1, "--time", "15", "--system", "drogue"], "system 'drogue' is not present then"),
    (lambda tmp: ["linearize", PA1, "--time", "1e6"], "must be within the case's run, 0 to 200 s"),
    (lambda tmp: ["linearize", PA1, "--time", "nan"], "must be within the case's run"),
    (lambda tmp: ["linearize", PA1, "--time", "15", "--system", "reserve"], "unknown system 'reserve'"),
])
def test_user_mistakes_give_one_line_and_nonzero_exit(capsys, tmp_path, make_args, expected):
    args = make_args(tmp_path)
    try:
        code, _, stderr = run_in_process(capsys, *args)
    except SystemExit as exc:   # argparse's own errors
        code, stderr = exc.code, capsys.readouterr().err
    assert code != 0
    assert len(stderr.strip().splitlines()) == 1, stderr
    assert expected in stderr
    assert "Traceback" not in stderr


def _write(tmp, name, text):
    path = tmp / name
    path.write_text(text)
    return str(path)


def test_console_script_entry_point():
    done = run_cli("--version", cwd=ROOT)
    assert done.returncode == 0 and "pchute-exudyn" in done.stdout


def test_a_result_folder_holds_exactly_one_runs_files(capsys, tmp_path):
    out = tmp_path / "run"
    first = ["run", CASE1, "--method", "sp", "--t-end", "1", "--out", str(out)]
    assert run_in_process(capsys, *first)[0] == 0
    assert (out / "overview.png").is_file()
    code, _, stderr = run_in_process(capsys, *first[:-2], "--no-plot", "--out", str(out))
    assert code == 1 and "holds an earlier result; pass --overwrite" in stderr
    assert (out / "overview.png").is_file()                               # refused: the earlier result is intact
    code, _, _ = run_in_process(capsys, *first[:-2], "--no-plot", "--overwrite", "--out", str(out))
    assert code == 0
    assert sorted(p.name for p in out.iterdir()) == ["result.npz", "summary.json", "timeseries.csv"]
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]    # no staging folder left beside it
    other = tmp_path / "notes"
    other.mkdir()
    (other / "todo.txt").write_text("mine")
    code, _, stderr = run_in_process(capsys, *first[:-2], "--overwrite", "--out", str(other))
    assert code == 1 and "is not empty and holds no result" in stderr and (other / "todo.txt").is_file()

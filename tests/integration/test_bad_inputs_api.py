"""Issue 34, one error boundary: result folders, `compare`, `animate`, `view`, the executor options and the Python
API. Each bad input or fault gives one line naming the input, the value and what is allowed, a non-zero exit (an
InputError from the API), no traceback, nothing touched outside the output, and no file of the user's lost.

`python tests/integration/test_bad_inputs_api.py` prints the command-line inputs and their messages as a Markdown table.
"""

import ctypes.util
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

import pchute_exudyn as pc
from pchute_exudyn.errors import PchuteError

if __name__ == "__main__":   # run as a script (python tests/integration/test_bad_inputs_api.py): the root on sys.path
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tests.bad_input_harness import assert_one_line, print_table, run_bad_input  # noqa: E402
from tests.helpers import ROOT, run_cli  # noqa: E402

CASE1 = str(ROOT / "cases" / "mer" / "case1.toml")
HUGE = "9" * 400
"""A 400-digit integer: no float holds it."""
STUDY = f'[study]\ncase = "{Path(CASE1).as_posix()}"\n[[study.configurations]]\nmethod = "sp"\nsteps = [1e-2]\n'
_SAVED: dict = {}


def _saved_run() -> Path:
    """A 0.2-s SP run of MER case 1, saved once per process (the entries copy it)."""
    if "run" not in _SAVED:
        folder = Path(tempfile.mkdtemp(prefix="pchute-bad-api-")) / "short"
        pc.simulate(pc.load_case(CASE1), "sp", "rk4", 1e-2, duration=0.2).save(folder, plot=False)
        _SAVED["run"] = folder
    return _SAVED["run"]


def _run(tmp: Path, name: str = "short", summary: str | None = None, npz: bytes | None = None,
         csv: bool = True) -> str:
    """A copy of the saved run in ``tmp/name``, its summary.json or result.npz replaced when given."""
    folder = tmp / name
    if not folder.exists():
        shutil.copytree(_saved_run(), folder)
    if summary is not None:
        (folder / "summary.json").write_text(summary)
    if npz is not None:
        (folder / "result.npz").write_bytes(npz)
    if not csv:
        (folder / "timeseries.csv").unlink()
    return str(folder)


def _truncated(tmp: Path, name: str = "truncated") -> str:
    """A result folder whose result.npz stops after 5000 bytes (power lost while copying) and has no CSV."""
    return _run(tmp, name, npz=(_saved_run() / "result.npz").read_bytes()[:5000], csv=False)


def _file(tmp: Path, name: str, text: str = "x") -> str:
    path = tmp / name
    path.write_text(text)
    return str(path)


def _folder(tmp: Path, name: str) -> str:
    (tmp / name).mkdir(exist_ok=True)
    return str(tmp / name)


def _read_only_folder(tmp: Path) -> str:
    """A folder no file can be created in even by root (sysfs on Linux); the entry is skipped without one."""
    try:
        with tempfile.NamedTemporaryFile(dir="/sys"):
            pass
    except OSError:
        return "/sys"
    pytest.skip("no read-only folder on this machine")


def _foreign(tmp: Path, summary: str) -> str:
    """A folder of the user's holding their notes and a summary.json that is not a result of this tool."""
    folder = tmp / "mine"
    folder.mkdir()
    (folder / "notes.txt").write_text("my notes")
    (folder / "summary.json").write_text(summary)
    return str(folder)


def _clashing(tmp: Path) -> str:
    """A result folder (a run without the overview) where the user put an overview.png of their own."""
    folder = _run(tmp, "clash")
    (Path(folder) / "overview.png").write_text("my figure")
    return folder


RUN = ["run", CASE1, "--method", "sp", "--t-end", "0.2", "--no-plot", "--quiet"]

BATTERY = [
    # result folders read by compare
    ("compare: empty summary.json", lambda t: ["compare", _run(t, "a"), _run(t, "b", summary="")],
     "b/summary.json: empty: not a summary written by pchute run"),
    ("compare: summary.json a list", lambda t: ["compare", _run(t, "a"), _run(t, "b", summary="[1, 2]")],
     "b/summary.json: a JSON list, not an object"),
    ("compare: summary.json not JSON", lambda t: ["compare", _run(t, "a", summary='{"case": '), _run(t, "b")],
     "a/summary.json: not JSON"),
    ("compare: truncated result.npz", lambda t: ["compare", _run(t, "a"), _truncated(t)],
     "truncated/result.npz: cannot be read (File is not a zip file): truncated or not a result.npz"),
    ("compare: a folder holding no result", lambda t: ["compare", _run(t, "a"), _folder(t, "empty")],
     "empty: a folder without timeseries.csv or result.npz: not a result folder"),
    ("compare: --settle past the common span", lambda t: ["compare", _run(t, "a"), _run(t, "b"), "--settle", "5"],
     "--settle = 5: must be before the end of the common time span (0 to 0.2 s)"),
    ("compare: --settle infinite", lambda t: ["compare", _run(t, "a"), _run(t, "b"), "--settle", "inf"],
     "--settle = inf: must be >= 0 (s) and finite"),
    ("compare: --out under a file", lambda t: ["compare", _run(t, "a"), _run(t, "b"), "--out",
                                               _file(t, "f.txt") + "/cmp"], "f.txt/cmp'"),
    # result folders read by animate
    ("animate: empty summary.json", lambda t: ["animate", _run(t, summary="")], "summary.json: empty"),
    ("animate: summary.json a list", lambda t: ["animate", _run(t, summary="[]")], "summary.json: a JSON list"),
    ("animate: truncated result.npz", lambda t: ["animate", _truncated(t)], "result.npz: cannot be read"),
    ("animate: --compare with a bad summary", lambda t: ["animate", _run(t), "--compare", _run(t, "b", summary="7")],
     "b/summary.json: a JSON int, not an object"),
    ("animate: a file for the folder", lambda t: ["animate", _file(t, "run.csv")],
     "run.csv: not a folder: give the result folder"),
    # where animate writes, checked before drawing
    ("animate: --out under a file", lambda t: ["animate", _run(t), "--out", _file(t, "f.txt") + "/a.gif"],
     "f.txt is a file, not a folder"),
    ("animate: --out an existing folder", lambda t: ["animate", _run(t), "--out", _folder(t, "frames.gif")],
     "frames.gif: is a folder; name the .gif or .mp4 file to write"),
    ("animate: --out in a missing folder", lambda t: ["animate", _run(t), "--out", str(t / "nowhere" / "a.gif")],
     "nowhere does not exist"),
    ("animate: --out on a read-only file system", lambda t: ["animate", _run(t), "--out",
                                                              _read_only_folder(t) + "/a.gif"],
     "/sys cannot be written"),
    # animate --speed
    ("animate: --speed 1e-9", lambda t: ["animate", _run(t), "--speed", "1e-9"],
     "--speed 1e-09: 0.2 s of run would be 2.4e+09 frames at 12 frames/s; at most 10000"),
    ("animate: --speed 0", lambda t: ["animate", _run(t), "--speed", "0"], "--speed 0.0: must be a finite number > 0"),
    ("animate: --speed negative", lambda t: ["animate", _run(t), "--speed", "-2"], "--speed -2.0: must be a finite"),
    ("animate: --speed nan", lambda t: ["animate", _run(t), "--speed", "nan"], "--speed nan: must be a finite"),
    ("animate: --speed inf", lambda t: ["animate", _run(t), "--speed", "inf"], "--speed inf: must be a finite"),
    # view
    ("view: truncated result.npz", lambda t: ["view", _truncated(t)], "result.npz: cannot be read"),
    ("view: a file for the folder", lambda t: ["view", _file(t, "x.npz")], "x.npz: not a folder"),
    # run: result folders written
    ("run --overwrite: an empty {} summary.json", lambda t: [*RUN, "--overwrite", "--out", _foreign(t, "{}")],
     "holds a summary.json that is not a result of pchute run"),
    ("run --overwrite: an empty summary.json", lambda t: [*RUN, "--overwrite", "--out", _foreign(t, "")],
     "holds a summary.json that is not a result of pchute run"),
    ("run --overwrite: summary.json a list", lambda t: [*RUN, "--overwrite", "--out", _foreign(t, "[1]")],
     "holds a summary.json that is not a result"),
    ("run --overwrite: a user's file named like a result's", lambda t: [*RUN, "--overwrite", "--out", _clashing(t)],
     "overview.png is not a file of the earlier result: this run would replace it"),
    ("run: --out on a read-only file system", lambda t: [*RUN, "--out", _read_only_folder(t) + "/run"],
     "cannot be written: '/sys'"),
    ("run: a 400-digit override", lambda t: [*RUN, "--set", f"vehicle.mass={HUGE}"],
     "vehicle.mass = 999999999999... (400 digits): an integer too large to be a number"),
    ("run: a 5000-digit override", lambda t: [*RUN, "--set", "vehicle.mass=" + "9" * 5000],
     "vehicle.mass = an integer of 5000 characters: too large to be a number"),
    ("linearize: a 400-digit override", lambda t: ["linearize", CASE1, "--set", f"main.lines.riser.stiffness={HUGE}"],
     "main.lines.riser.stiffness = 999999999999... (400 digits): an integer too large"),
    # executor options of study and fit, refused before a folder or a cluster is made
    ("study: --dask-timeout inf", lambda t: ["study", _file(t, "s.toml", STUDY), "--dask-timeout", "inf",
                                             "--out", str(t / "st")],
     "argument --dask-timeout: 'inf': must be a finite number of seconds > 0"),
    ("study: --dask-timeout nan", lambda t: ["study", _file(t, "s.toml", STUDY), "--dask-local", "1",
                                             "--dask-timeout", "nan", "--out", str(t / "st")],
     "argument --dask-timeout: 'nan': must be a finite number"),
    ("study: --workers 100000", lambda t: ["study", _file(t, "s.toml", STUDY), "--workers", "100000",
                                           "--out", str(t / "st")],
     f"--workers = 100000: must be <= {4 * (os.cpu_count() or 1)} (4 worker processes per core"),
    ("fit: --dask-local 100000", lambda t: ["fit", _file(t, "f.toml"), "--dask-local", "100000"],
     f"--dask-local = 100000: must be <= {4 * (os.cpu_count() or 1)}"),
    ("fit: --dask-timeout 0", lambda t: ["fit", _file(t, "f.toml"), "--dask-timeout", "0"],
     "argument --dask-timeout: '0': must be a finite number of seconds > 0"),
    ("new: a case file on a read-only file system", lambda t: ["new", _read_only_folder(t) + "/n.toml"],
     "pchute new: error: '/sys/n.toml': Permission denied"),
    ("study-report: a file for the folder", lambda t: ["study-report", _file(t, "runs.csv", "a,b\n")],
     "no runs.csv: not a study folder"),
    ("run: a 400-digit mass in the case file", lambda t: ["run", _file(t, "big.toml", f'extends = "{Path(CASE1).as_posix()}"'
                                                                   f'\n[bodies.vehicle]\nmass = {HUGE}\n')],
     "bodies.vehicle.mass = 999999999999... (400 digits): must be a finite number"),
    ("run: a 5000-digit mass in the case file", lambda t: ["run", _file(t, "huge.toml", f'extends = "{Path(CASE1).as_posix()}"'
                                                                     f'\n[bodies.vehicle]\nmass = {"9" * 5000}\n')],
     "malformed TOML: Exceeds the limit (4300 digits) for integer string conversion"),
]


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_bad_input_gives_one_line_and_a_nonzero_exit(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)
    assert "internal error" not in err


def test_the_battery_is_large_and_distinct():
    assert len(BATTERY) >= 30 and len({entry[0] for entry in BATTERY}) == len(BATTERY)


def test_a_folder_that_is_no_result_keeps_every_file(tmp_path):
    code, err, _, _ = run_bad_input(lambda t: [*RUN, "--overwrite", "--out", _foreign(t, "{}")], tmp_path)
    assert code == 1
    assert sorted(p.name for p in (tmp_path / "mine").iterdir()) == ["notes.txt", "summary.json"]
    assert (tmp_path / "mine" / "notes.txt").read_text() == "my notes"


def test_overwrite_replaces_only_the_files_of_the_earlier_result(tmp_path):
    from pchute_exudyn.cli import main

    out = tmp_path / "out"
    assert main([*RUN[:-2], "--quiet", "--out", str(out)]) == 0           # with the overview figure
    listed = json.loads((out / "summary.json").read_text())["result_files"]
    assert sorted(listed) == ["ground_track.png", "loads.png", "overview.png", "result.npz", "summary.json",
                              "timeseries.csv"]
    (out / "notes.txt").write_text("my notes")
    (out / "mine").mkdir()
    assert main([*RUN, "--t-end", "0.3", "--overwrite", "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["mine", "notes.txt", "result.npz", "summary.json",
                                                     "timeseries.csv"]   # the old figures went, the user's stayed
    assert (out / "notes.txt").read_text() == "my notes"
    assert pc.Result.load(out).final("time") == pytest.approx(0.3)
    assert "result_files" not in pc.Result.load(out).summary.to_dict()    # the folder's list is not the run's
    assert not [p.name for p in tmp_path.iterdir() if p.name.startswith(".")]


FSIZE_CHILD = """import resource, signal, sys
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)   # a write beyond the limit then fails with EFBIG, as a full disk does
resource.setrlimit(resource.RLIMIT_FSIZE, (20000, 20000))
from pchute_exudyn.cli import main
sys.exit(main(sys.argv[1:]))
"""


def _with_small_disk(tmp_path, *args) -> subprocess.CompletedProcess:
    """The command line in a process that cannot write a file beyond 20 kB (timeseries.csv of 0.2 s is 21 kB)."""
    return subprocess.run([sys.executable, "-c", FSIZE_CHILD, *args], capture_output=True, text=True, timeout=120,
                          cwd=tmp_path)


@pytest.mark.skipif(not hasattr(os, "setrlimit") and sys.platform == "win32", reason="needs resource limits")
def test_a_disk_filling_up_while_saving_leaves_nothing_and_keeps_the_earlier_result(tmp_path):
    new = tmp_path / "new"
    done = _with_small_disk(tmp_path, *RUN, "--out", str(new))
    assert done.returncode == 1 and "Traceback" not in done.stderr, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert f"output folder {str(new)!r} cannot be written: File too large" in done.stderr
    assert not new.exists() and not [p for p in tmp_path.iterdir() if p.name.startswith(".")]
    earlier = Path(_run(tmp_path, "earlier"))
    before = {p.name: p.read_bytes() for p in earlier.iterdir()}
    done = _with_small_disk(tmp_path, *RUN, "--overwrite", "--out", str(earlier))
    assert done.returncode == 1 and "File too large" in done.stderr, done.stderr
    assert {p.name: p.read_bytes() for p in earlier.iterdir()} == before
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]   # no staging folder left
    done = run_cli(*RUN, "--overwrite", "--out", earlier, timeout=120)
    assert done.returncode == 0, done.stderr                                # with space again, it goes through


def test_a_disk_filling_up_while_animating_leaves_no_partial_file(tmp_path):
    run = Path(_run(tmp_path))
    done = _with_small_disk(tmp_path, "animate", str(run), "--quiet")   # 3 frames: a GIF of about 70 kB
    assert done.returncode == 1 and len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert f"--out {run / 'animation.gif'}: cannot be written: File too large" in done.stderr
    assert not [p.name for p in run.iterdir() if "animation" in p.name]


def test_view_without_a_display_suggests_animate(tmp_path, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    code, err, seconds, touched = run_bad_input(lambda t: ["view", _run(t)], tmp_path)
    assert_one_line(code, err, "no display to open Exudyn's viewer in (DISPLAY is not set); `pchute animate", touched,
                    seconds)


@pytest.mark.skipif(not sys.platform.startswith("linux") or ctypes.util.find_library("X11") is None,
                    reason="needs libX11 to check the display")
def test_view_with_a_display_that_does_not_open_suggests_animate(tmp_path, monkeypatch):
    monkeypatch.setenv("DISPLAY", ":97")   # no X server: Exudyn's renderer would abort the process
    code, err, seconds, touched = run_bad_input(lambda t: ["view", _run(t)], tmp_path)
    assert_one_line(code, err, "the X display DISPLAY=':97' cannot be opened", touched, seconds)


def test_an_unexpected_fault_is_one_line_naming_it(tmp_path, monkeypatch):
    import pchute_exudyn.cli as cli

    def broken(args):
        raise RuntimeError("a fault nobody foresaw\nsecond line")
    monkeypatch.setattr(cli, "_view", broken)
    code, err, seconds, touched = run_bad_input(lambda t: ["view", "x"], tmp_path)
    assert_one_line(code, err, "pchute view: internal error: RuntimeError: a fault nobody foresaw (please report "
                               "this with the command line)", touched, seconds)


# -- the Python API ----------------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def case1():
    return pc.load_case(CASE1)


def _resolve_run(*args):
    from pchute_exudyn.run.simulation import resolve_run
    return resolve_run(*args)


def _study_api(name, *args, **kwargs):
    from pchute_exudyn import study
    from pchute_exudyn.study.report import study_report
    return {"study_report": study_report}.get(name, getattr(study, name, None))(*args, **kwargs)


def _fit_api(name, *args, **kwargs):
    from pchute_exudyn import fit
    return getattr(fit, name)(*args, **kwargs)


def _spec(tmp: Path):
    """A real study spec (MER case 1, one SP run), for calls whose other arguments are wrong."""
    from pchute_exudyn.study import load_study
    (tmp / "s.toml").write_text(STUDY)
    return load_study(tmp / "s.toml")


def _animate(*args, **kwargs):
    from pchute_exudyn.views.animation import animate
    return animate(*args, **kwargs)


API_CALLS = [   # (name, call(case, a saved run's folder, tmp), what the one line must hold)
    ("simulate given a path", lambda c, r, t: pc.simulate(CASE1, "sp"), f"case = {CASE1!r}: a path, not a Case"),
    ("simulate given None", lambda c, r, t: pc.simulate(None), "case = None: must be a Case"),
    ("simulate progress=5", lambda c, r, t: pc.simulate(c, "sp", progress=5),
     "progress = 5: must be None or a function"),
    ("simulate engine_solution='yes'", lambda c, r, t: pc.simulate(c, "sp", engine_solution="yes"),
     "engine_solution = 'yes': must be True or False"),
    ("simulate history=1", lambda c, r, t: pc.simulate(c, "sp", history=1), "history = 1: must be True or False"),
    ("simulate for a 400-digit duration", lambda c, r, t: pc.simulate(c, "sp", duration=int(HUGE)),
     "duration (--t-end) = 999999999999... (400 digits): must be a number > 0 (s)"),
    ("resolve_run given a path", lambda c, r, t: _resolve_run(CASE1), "a path, not a Case"),
    ("run_study given a path", lambda c, r, t: _study_api("run_study", CASE1, t / "st"),
     f"spec = {CASE1!r}: a path, not a StudySpec; load it first: pchute_exudyn.study.load_study"),
    ("run_study with workers=0", lambda c, r, t: _study_api("run_study", _spec(t), t / "st", workers=0),
     "workers = 0: must be None (every core) or a whole number from 1 to"),
    ("run_study with an executor that is none", lambda c, r, t: _study_api("run_study", _spec(t), t / "st", "pool"),
     "executor = 'pool': must be None (a local process pool) or a concurrent.futures.Executor"),
    ("run_study progress='yes'", lambda c, r, t: _study_api("run_study", _spec(t), t / "st", progress="yes"),
     "progress = 'yes': must be True or False"),
    ("load_study given a number", lambda c, r, t: _study_api("load_study", 5),
     "path = 5: must be the path of a study file (TOML)"),
    ("study_report given None", lambda c, r, t: _study_api("study_report", None),
     "folder = None: must be the path of a study folder"),
    ("run_fit given a path", lambda c, r, t: _fit_api("run_fit", "fit.toml", t / "f"),
     "spec = 'fit.toml': a path, not a FitSpec; load it first: pchute_exudyn.fit.load_fit"),
    ("load_fit given None", lambda c, r, t: _fit_api("load_fit", None), "path = None: must be the path of a fit file"),
    ("load_case given a Case", lambda c, r, t: pc.load_case(c), "path = <Case 'MER case 1'>: already a loaded case"),
    ("load_case given None", lambda c, r, t: pc.load_case(None), "path = None: must be the path of a case file"),
    ("load_case with a non-string key", lambda c, r, t: pc.load_case(CASE1, {1: 2}),
     "overrides: key 1: must be a str"),
    ("load_case with a 400-digit integer", lambda c, r, t: pc.load_case(CASE1, {"vehicle.mass": int(HUGE)}),
     "vehicle.mass = 999999999999... (400 digits): an integer too large"),
    ("load_case with a 5000-digit integer", lambda c, r, t: pc.load_case(CASE1, {"vehicle.mass": 10 ** 5000}),
     "vehicle.mass = an integer of about 5000 digits: an integer too large"),
    ("load_case with a 400-digit integer in a list",
     lambda c, r, t: pc.load_case(CASE1, [f"vehicle.inertia=[1, {HUGE}, 1]"]),
     "vehicle.inertia = 999999999999... (400 digits)"),
    ("load_case with overrides as one string", lambda c, r, t: pc.load_case(CASE1, "vehicle.mass=800"),
     "overrides = 'vehicle.mass=800': must be a mapping"),
    ("load_case with overrides as a number", lambda c, r, t: pc.load_case(CASE1, 5), "overrides = 5: must be a mapping"),
    ("load_case with a non-string override", lambda c, r, t: pc.load_case(CASE1, [b"vehicle.mass=800"]),
     "overrides: entry b'vehicle.mass=800': must be a 'key=value' str"),
    ("new_case given a number", lambda c, r, t: pc.new_case(5), "choices = 5: must be a NewCase or None"),
    ("new_case_text with an unknown choice", lambda c, r, t: pc.new_case_text(colour="red"),
     "colour = 'red': not a choice of a new case; the choices are: planet, mass"),
    ("new_case_text with a 400-digit mass", lambda c, r, t: pc.new_case_text(mass=int(HUGE)),
     "mass = 999999999999... (400 digits): an integer too large to be a number"),
    ("NewCase with a 400-digit mass", lambda c, r, t: pc.NewCase(mass=int(HUGE)),
     "mass = 999999999999... (400 digits): must be a number > 0 (kg)"),
    ("Result.load of an empty summary.json", lambda c, r, t: pc.Result.load(_run(t, "e", summary="")),
     "e/summary.json: empty"),
    ("Result.load of a list summary.json", lambda c, r, t: pc.Result.load(_run(t, "l", summary="[]")),
     "l/summary.json: a JSON list, not an object"),
    ("Result.load of a truncated result.npz", lambda c, r, t: pc.Result.load(_truncated(t)),
     "result.npz: cannot be read"),
    ("Result.load of None", lambda c, r, t: pc.Result.load(None), "path = None: must be a path"),
    ("Result.save to a number", lambda c, r, t: pc.Result.load(r).save(3), "folder = 3: must be a path"),
    ("Result.save with overwrite='yes'", lambda c, r, t: pc.Result.load(r).save(t / "o", overwrite="yes"),
     "overwrite = 'yes': must be True or False"),
    ("Result.save over a folder that is no result", lambda c, r, t: pc.Result.load(r).save(_foreign(t, "{}"),
                                                                                          overwrite=True),
     "holds a summary.json that is not a result of pchute run"),
    ("animate at speed 0", lambda c, r, t: _animate(r, t / "a.gif", speed=0),
     "--speed 0: must be a finite number > 0"),
    ("animate to a folder", lambda c, r, t: _animate(r, r), "write a .gif or an .mp4 file"),
]


@pytest.mark.parametrize("name, call, expected", API_CALLS, ids=[entry[0] for entry in API_CALLS])
def test_api_call_with_a_wrong_argument_raises_one_line_naming_it(case1, tmp_path, name, call, expected):
    run = _run(tmp_path)
    with pytest.raises(PchuteError) as info:
        call(case1, run, tmp_path)
    text = str(info.value)
    assert len(text.splitlines()) == 1 and expected in text, text


if __name__ == "__main__":   # the battery's messages as a table
    print_table(BATTERY)

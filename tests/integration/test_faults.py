"""Faults around a study's or a fit's runs, tried for real: torn and corrupt journals, empty and corrupt manifests,
derived tables that cannot be read, a folder two processes want at once, a file of the case's ``extends`` chain
edited before a resume, a full disk, an unwritable ``--out``, and SIGINT or SIGTERM to the main process or to its
whole process group (local pool and Dask). Each for the study and the fit: one line, never a traceback, never a hang,
no record lost or twice, no process left.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from pchute_exudyn.cli import main
from pchute_exudyn.errors import PchuteError
from pchute_exudyn.results.journal import FolderLock, decode
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT, run_cli, start_cli

CASE1 = ROOT / "cases" / "mer" / "case1.toml"
STUDY = """[study]
name = "faults"
case = "{case}"
runs = {runs}
seed = 7
duration = {duration}

[[study.configurations]]
method = "sp"
steps = [{step}]

[parameters."vehicle.initial.velocity_east"]
distribution = "normal"
mean = 0.0
std = 0.5
"""
FIT = """[fit]
name = "faults"
case = "{case}"
method = "sp"
step = 1e-2

[free."parachute.aerodynamics.axial_coefficient"]
low = 0.3
high = 0.7
initial = 0.44

[[targets]]
history = "truth.csv"
column = "vehicle_altitude"
map = ["alt_m=vehicle_altitude"]
std = 0.1
"""
_HELD: list = []   # locks a test holds while the command runs


@pytest.fixture(autouse=True)
def _release_locks():
    yield
    while _HELD:
        _HELD.pop().release()


# -- inputs ---------------------------------------------------------------------------------------------------------

def chain(tmp: Path, duration: float = 0.5) -> Path:
    """child.toml extends parent.toml extends MER case 1: the case a study or fit runs."""
    (tmp / "parent.toml").write_text(f'extends = "{CASE1.as_posix()}"\n[simulation]\nduration = {duration}\n'
                                     'output_step = 0.05\n')
    (tmp / "child.toml").write_text('extends = "parent.toml"\n')
    return tmp / "child.toml"


def study_file(tmp: Path, runs: int = 4, duration: float = 0.5, step: float = 1e-2) -> Path:
    path = tmp / "study.toml"
    if not path.is_file():
        path.write_text(STUDY.format(case=chain(tmp).as_posix(), runs=runs, duration=duration, step=step))
    return path


def fit_file(tmp: Path, duration: float = 1.0) -> Path:
    """A one-key fit of C_A to the altitude history of a run at C_A = 0.5 (MER case 1, SP)."""
    path = tmp / "fit.toml"
    if not path.is_file():
        import numpy as np

        import pchute_exudyn as pc
        case = chain(tmp, duration)
        truth = pc.simulate(pc.load_case(case, {"parachute.aerodynamics.axial_coefficient": 0.5}), "sp", "rk4", 1e-2,
                            duration=min(duration, 1.0))
        np.savetxt(tmp / "truth.csv", np.column_stack([truth.time, truth["vehicle_altitude"]]), delimiter=",",
                   header="time,alt_m", comments="")
        path.write_text(FIT.format(case=case.as_posix()))
    return path


def study_args(tmp: Path, *extra) -> list:
    return ["study", study_file(tmp), "--out", tmp / "out", "--workers", "1", "--no-progress", *extra]


def fit_args(tmp: Path, *extra) -> list:
    return ["fit", fit_file(tmp), "--out", tmp / "out", "--workers", "1", *extra]


def quiet_main(args) -> tuple:
    """(exit status, standard error) of the command line run in this process."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main([str(a) for a in args])
    return code, err.getvalue()


def folder_with(name: str, content: bytes, kind: str):
    """make_args: an out folder holding only ``name`` with ``content``, then the command into it."""
    def make(tmp):
        args = study_args(tmp) if kind == "study" else fit_args(tmp)
        (tmp / "out").mkdir()
        (tmp / "out" / name).write_bytes(content)
        return args
    return make


def edited_after_a_run(file_name: str, kind: str):
    """make_args: the command run once, then ``file_name`` (beside the study or fit file) edited."""
    def make(tmp):
        args = study_args(tmp) if kind == "study" else fit_args(tmp)
        assert quiet_main(args)[0] == 0
        with open(tmp / file_name, "a") as handle:
            handle.write("\n# edited\n")
        return args
    return make


def out_is_a_file(kind: str, under: bool = False, dask: bool = False):
    def make(tmp):
        args = study_args(tmp) if kind == "study" else fit_args(tmp)
        (tmp / "taken").write_text("x")
        out = tmp / "taken" / "sub" if under else tmp / "taken"
        args[args.index("--out") + 1] = out
        if dask:
            args[args.index("--workers"):args.index("--workers") + 2] = ["--dask-local", "1"]
        return args
    return make


def locked(kind: str):
    def make(tmp):
        args = study_args(tmp) if kind == "study" else fit_args(tmp)
        (tmp / "out").mkdir(exist_ok=True)
        lock = FolderLock(tmp / "out", kind)
        lock.acquire()
        _HELD.append(lock)
        return args
    return make


def _battery(kind: str) -> list:
    what = f"pchute {kind}"
    journal = "runs.jsonl" if kind == "study" else "evaluations.jsonl"
    return [
        (f"{kind}: empty manifest.json", folder_with("manifest.json", b"", kind), "manifest.json: empty"),
        (f"{kind}: manifest.json not JSON", folder_with("manifest.json", b'{"fingerprint": ', kind),
         "manifest.json: not JSON"),
        (f"{kind}: manifest.json a list", folder_with("manifest.json", b"[1, 2]", kind),
         "manifest.json: a JSON list, not the manifest's object"),
        (f"{kind}: manifest.json without its fingerprint", folder_with("manifest.json", b'{"runs": 4}', kind),
         "manifest.json: no 'fingerprint' key"),
        (f"{kind}: manifest.json not UTF-8", folder_with("manifest.json", b"\xff\xfe{}", kind),
         "manifest.json: not UTF-8 text"),
        (f"{kind}: journal without a manifest", folder_with(journal, b'{"run": 0, "status": "ok"}\n', kind),
         f"holds {journal} but no manifest.json"),
        (f"{kind}: the parent of its case edited", edited_after_a_run("parent.toml", kind),
         f"parent.toml changed since the {kind} in"),
        (f"{kind}: its own file edited", edited_after_a_run(f"{kind}.toml", kind),
         f"{kind}.toml changed since the {kind} in"),
        (f"{kind}: --out a regular file", out_is_a_file(kind), "taken' is a file"),
        (f"{kind}: --out under a regular file", out_is_a_file(kind, under=True), "is under"),
        (f"{kind}: --out a file, on a Dask cluster", out_is_a_file(kind, dask=True), "taken' is a file"),
        (f"{kind}: --out locked by another process", locked(kind),
         f"out is in use ({what}, pid {os.getpid()} on"),
    ]


BATTERY = _battery("study") + _battery("fit") + [
    ("fit: its history CSV edited", edited_after_a_run("truth.csv", "fit"), "truth.csv changed since the fit in"),
]


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_a_folder_fault_gives_one_line_and_a_nonzero_exit(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)


def test_the_fault_battery_is_distinct():
    assert len(BATTERY) >= 25 and len({entry[0] for entry in BATTERY}) == len(BATTERY)


# -- journals --------------------------------------------------------------------------------------------------------

def journal_lines(path: Path) -> list:
    """Every line of a journal as its record (each line must be whole and pass its checksum)."""
    records = []
    for line in path.read_text().splitlines():
        record, problem = decode(line)
        assert problem is None, (line, problem)
        records.append(record)
    return records


def test_a_torn_or_corrupt_study_journal_redoes_those_runs_once(tmp_path):
    args = study_args(tmp_path)
    assert quiet_main(args)[0] == 0
    journal = tmp_path / "out" / "runs.jsonl"
    lines = journal.read_text().splitlines()
    assert all('"crc32": "' in line for line in lines)                  # every record carries its checksum
    by_run = {json.loads(line)["run"]: line for line in lines}
    corrupt = by_run[1].replace('"status": "ok"', '"status": "ok "')     # one byte changed: fails its checksum
    journal.write_text("\n".join([by_run[0], corrupt, "{}", '{"run": 999, "status": "ok"}', by_run[2], by_run[0]])
                       + "\n" + by_run[3][:60])                           # power lost while writing run 3
    code, err = quiet_main(args)
    assert code == 0 and "Traceback" not in err
    assert err.splitlines() == [
        "pchute study: runs.jsonl: line 2 fails its checksum: run 1 runs again",
        "pchute study: runs.jsonl: line 3 is not a run record: skipped",
        "pchute study: runs.jsonl: line 4 records run 999 of a study of 4 runs (0 to 3): skipped",
        "pchute study: runs.jsonl: line 6 records run 0 again, already recorded as ok: the earlier record counts",
        "pchute study: runs.jsonl: line 7 torn (power loss?): run 3 runs again"]
    runs = [record["run"] for record in journal_lines(journal)]
    assert sorted(runs) == [0, 1, 2, 3]                                   # none lost, none twice
    assert len((tmp_path / "out" / "runs.jsonl.rejected").read_text().splitlines()) == 5   # set aside, not deleted
    assert quiet_main(args) == (0, "")                                    # repaired: nothing more to say


def test_a_journal_ending_in_binary_garbage_is_reported_in_a_few_lines(tmp_path):
    args = study_args(tmp_path)
    assert quiet_main(args)[0] == 0
    journal = tmp_path / "out" / "runs.jsonl"
    with open(journal, "ab") as handle:
        handle.write(bytes(range(256)) * 40 + b"\n" * 30)
    code, err = quiet_main(args)
    assert code == 0 and len(err.splitlines()) <= 11 and "Traceback" not in err
    assert err.splitlines()[-1].endswith("more lines set aside in runs.jsonl.rejected")
    assert sorted(r["run"] for r in journal_lines(journal)) == [0, 1, 2, 3]


def test_a_journal_of_an_earlier_version_without_checksums_still_resumes(tmp_path):
    args = study_args(tmp_path)
    assert quiet_main(args)[0] == 0
    journal = tmp_path / "out" / "runs.jsonl"
    records = journal_lines(journal)
    journal.write_text("".join(json.dumps(r) + "\n" for r in records if r["run"] != 2))   # as 0.x wrote it
    code, err = quiet_main(args)
    assert (code, err) == (0, "")
    assert sorted(json.loads(line)["run"] for line in journal.read_text().splitlines()) == [0, 1, 2, 3]


def test_a_torn_or_corrupt_fit_journal_loses_and_repeats_nothing(tmp_path):
    args = fit_args(tmp_path)
    assert quiet_main(args)[0] == 0
    journal = tmp_path / "out" / "evaluations.jsonl"
    lines = journal.read_text().splitlines()
    broken = [lines[0], lines[1].replace('"status": "ok"', '"status": "ok "'), "{}",
              '{"status": "ok", "values": [1, 2, 3], "predictions": []}', *lines[2:-1], lines[-1][:50]]
    journal.write_text("\n".join(broken))
    code, err = quiet_main(args)
    assert code == 0 and "Traceback" not in err
    notes = err.splitlines()
    assert notes[0] == "pchute fit: evaluations.jsonl: line 2 fails its checksum: that run runs again if the fit needs it"
    assert "line 3 is not an evaluation record" in notes[1] and "line 4 does not hold one number per free key" \
        in notes[2] and notes[-1].startswith(f"pchute fit: evaluations.jsonl: line {len(broken)} torn (power loss?)")
    values = [tuple(r["values"]) for r in journal_lines(journal)]
    assert len(values) == len(set(values)) >= len(lines) - 2              # no point twice, the lost ones redone


def test_unreadable_derived_tables_are_rebuilt_from_the_journal(tmp_path):
    args = study_args(tmp_path)
    assert quiet_main(args)[0] == 0
    out = tmp_path / "out"
    (out / "runs.csv").write_bytes(b"\xff\xfe\x00run,status\n")
    (out / "runs.parquet").write_bytes(b"not parquet")
    code, err = quiet_main(args)
    assert code == 0 and err.splitlines() == [
        "pchute study: runs.csv is not UTF-8 text: rebuilt from runs.jsonl",
        "pchute study: runs.parquet is not a Parquet file: rebuilt from runs.jsonl when the study ends"]
    assert (out / "runs.csv").read_text().count("\n") == 5
    assert (out / "runs.parquet").read_bytes()[:4] == b"PAR1"
    from pchute_exudyn.study import load
    assert sorted(load(out)["run"]) == [0, 1, 2, 3]


# -- locks -----------------------------------------------------------------------------------------------------------

def test_a_lock_left_by_a_dead_process_does_not_block(tmp_path):
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / ".pchute.lock").write_text("pchute study, pid 999999 on elsewhere, started long ago")
    assert quiet_main(study_args(tmp_path)) == (0, "")


def test_the_api_refuses_a_locked_folder_in_one_line(tmp_path):
    from pchute_exudyn.fit import load_fit, run_fit
    from pchute_exudyn.study import load_study, run_study

    locked("study")(tmp_path)
    for call in (lambda: run_study(load_study(study_file(tmp_path)), tmp_path / "out", workers=1, progress=False),
                 lambda: run_fit(load_fit(fit_file(tmp_path)), tmp_path / "out", workers=1)):
        with pytest.raises(PchuteError) as caught:
            call()
        assert len(str(caught.value).splitlines()) == 1 and "is in use (pchute study, pid" in str(caught.value)
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [".pchute.lock"]   # nothing else written


def _start(args: list, cwd: Path, **options) -> subprocess.Popen:
    return start_cli(*args, cwd=cwd, start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                     **options)


@pytest.mark.parametrize("kind", ["study", "fit"])
def test_two_processes_started_at_once_into_one_folder_run_each_run_once(tmp_path, kind):
    args = study_args(tmp_path) if kind == "study" else fit_args(tmp_path)
    first, second = _start(args, tmp_path), _start(args, tmp_path)
    outcomes = [p.communicate(timeout=120) + (p.returncode,) for p in (first, second)]
    refused = [err for _, err, code in outcomes if code != 0]
    assert all(len(err.splitlines()) == 1 and f"is in use (pchute {kind}, pid" in err for err in refused), outcomes
    assert len(refused) <= 1 and not any("Traceback" in err for _, err, _ in outcomes)
    journal = tmp_path / "out" / ("runs.jsonl" if kind == "study" else "evaluations.jsonl")
    keys = [r["run"] if kind == "study" else tuple(r["values"]) for r in journal_lines(journal)]
    assert len(keys) == len(set(keys)) and (kind == "fit" or sorted(keys) == [0, 1, 2, 3])


# -- full disks and unwritable folders -------------------------------------------------------------------------------

def _file_size_limit(size: int):
    """preexec_fn: files of this process may not grow past ``size`` bytes (writes beyond fail with EFBIG, as on a
    full disk; SIGXFSZ ignored so that the write fails rather than the process dying)."""
    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))
    return limit


def _no_half_files(folder: Path) -> None:
    assert not [p.name for p in folder.iterdir() if p.name.endswith(".tmp")]


@pytest.mark.parametrize("kind", ["study", "fit"])
def test_a_full_disk_is_one_line_and_the_same_command_resumes_after(tmp_path, kind):
    args = study_args(tmp_path) if kind == "study" else fit_args(tmp_path)
    journal = tmp_path / "out" / ("runs.jsonl" if kind == "study" else "evaluations.jsonl")
    process = _start(args, tmp_path, preexec_fn=_file_size_limit(2500 if kind == "study" else 5000))
    _, err = process.communicate(timeout=120)
    assert process.returncode == 1 and err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(f"pchute {kind}: error: file too large writing {tmp_path / 'out'}") and \
        err.endswith(": free space and rerun the same command to resume\n"), err
    recorded = journal_lines(journal)                                    # whole lines only: the torn one cut back
    assert recorded
    _no_half_files(tmp_path / "out")
    assert quiet_main(args) == (0, "")                                   # space freed: the same command resumes
    keys = [r["run"] if kind == "study" else tuple(r["values"]) for r in journal_lines(journal)]
    assert keys[:len(recorded)] == [r["run"] if kind == "study" else tuple(r["values"]) for r in recorded]
    assert len(keys) == len(set(keys)) and (kind == "fit" or sorted(keys) == [0, 1, 2, 3])


@contextlib.contextmanager
def _tmpfs(folder: Path, options: str):
    """A small tmpfs mounted at ``folder`` (root only; skips the test where mounting is not allowed)."""
    folder.mkdir()
    if os.geteuid() != 0 or subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(folder)],
                                           capture_output=True).returncode != 0:
        pytest.skip("mounting a tmpfs needs root")
    try:
        yield folder
    finally:
        subprocess.run(["umount", "-l", str(folder)], check=False)


def test_a_really_full_disk_during_a_study(tmp_path):
    """ENOSPC on a 400 kB tmpfs, histories kept (each run writes its result.npz in a worker)."""
    text = study_file(tmp_path, runs=8).read_text().replace('duration = 0.5', 'duration = 0.5\nhistories = true')
    (tmp_path / "study.toml").write_text(text)
    with _tmpfs(tmp_path / "disk", "size=400k") as disk:
        args = ["study", tmp_path / "study.toml", "--out", disk / "out", "--workers", "1", "--no-progress"]
        code, err = quiet_main(args)
        assert code == 1 and err.count("\n") == 1 and "no space left on device" in err.lower(), err
        done = journal_lines(disk / "out" / "runs.jsonl")
        assert all(r["status"] == "ok" for r in done) and len(done) < 8  # no run recorded as failed for the disk
        _no_half_files(disk / "out")
        subprocess.run(["mount", "-o", "remount,size=4m", str(disk)], check=True)    # space freed
        assert quiet_main(args) == (0, "")
        runs = [r["run"] for r in journal_lines(disk / "out" / "runs.jsonl")]
        assert sorted(runs) == list(range(8)) and (disk / "out" / "histories" / "run_00007" / "result.npz").is_file()


@pytest.mark.parametrize("kind", ["study", "fit"])
def test_a_read_only_out_is_one_line_before_any_work(tmp_path, kind):
    args = study_args(tmp_path) if kind == "study" else fit_args(tmp_path)
    with _tmpfs(tmp_path / "ro", "size=16k,ro") as read_only:
        for out in (read_only, read_only / "new"):
            args[args.index("--out") + 1] = out
            started = time.perf_counter()
            code, err = quiet_main(args)
            assert code == 1 and err == f"pchute {kind}: error: output folder {str(out)!r} cannot be written: " \
                                        "Read-only file system\n"
            assert time.perf_counter() - started < 5


# -- interrupts ------------------------------------------------------------------------------------------------------

def _descendants(pid: int) -> list:
    """The processes under ``pid`` (psutil; an empty list without it: the command-line scan still runs)."""
    try:
        import psutil
        return psutil.Process(pid).children(recursive=True)
    except Exception:  # no psutil, or the process already gone
        return []


def _alive(processes: list) -> list:
    import psutil
    alive = []
    for process in processes:
        try:
            if process.is_running() and process.status() != psutil.STATUS_ZOMBIE:
                alive.append(process.pid)
        except psutil.NoSuchProcess:
            pass
    return alive


def _mentioning(text: str) -> list:
    """Pids of the processes whose command line holds ``text`` (a forked pool worker keeps its parent's)."""
    pids = []
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit() and text in (entry / "cmdline").read_bytes().decode(errors="replace"):
                pids.append(int(entry.name))
        except OSError:
            pass
    return pids


SIGNALS = [(kind, number, to, "--workers") for kind in ("study", "fit") for number in (signal.SIGINT, signal.SIGTERM)
           for to in ("main", "group")]
SIGNALS += [("study", signal.SIGINT, "group", "--dask-local"), ("fit", signal.SIGTERM, "main", "--dask-local")]
"""Each signal to the main process and to the group, for a study and a fit on local workers; and on a Dask
cluster."""


@pytest.mark.parametrize("kind, number, to, executor", SIGNALS,
                         ids=[f"{k}-{n.name}-{t}-{e.strip('-')}" for k, n, t, e in SIGNALS])
def test_a_signal_stops_workers_keeps_finished_runs_and_exits_cleanly(tmp_path, kind, number, to, executor):
    if kind == "study":   # runs of ~0.5 s: the signal finds runs running and runs waiting (cancelled)
        study_file(tmp_path, runs=12, duration=5.0, step=1e-3)
        args = ["study", tmp_path / "study.toml", "--out", tmp_path / "out", executor, "2", "--no-progress"]
        journal = tmp_path / "out" / "runs.jsonl"
    else:
        args = ["fit", fit_file(tmp_path, duration=12.0), "--out", tmp_path / "out", executor, "2"]
        journal = tmp_path / "out" / "evaluations.jsonl"
    scratch = tmp_path / "scratch"   # the processes' temporary folder: left empty (issue 59)
    scratch.mkdir()
    # as from an interactive shell: SIGINT at its default (a test runner may have been started with it ignored)
    process = _start(args, tmp_path, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
                     env={**os.environ, "TMPDIR": str(scratch)})
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not (journal.is_file() and journal.read_text().count("\n") >= 2):
        time.sleep(0.02)
    assert process.poll() is None, process.communicate()
    workers = _descendants(process.pid)
    os.killpg(process.pid, number) if to == "group" else process.send_signal(number)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 128 + number
    assert err.endswith("interrupted; " + ("finished runs are recorded in" if kind == "study" else
                                           "the runs so far are recorded in") + f" {tmp_path / 'out'}: rerun the "
                        "same command to resume\n") and err.count("\n") == 1, err
    time.sleep(0.3)
    assert not _alive(workers) and not _mentioning(str(tmp_path / "out"))   # no process left
    # no temporary folder left (Dask keeps its shared dask-scratch-space after any cluster, interrupted or not)
    assert [p.name for p in scratch.iterdir() if p.name != "dask-scratch-space"] == []
    records = journal_lines(journal)                                       # every line whole
    keys = [r["run"] if kind == "study" else tuple(r["values"]) for r in records]
    assert len(keys) == len(set(keys)) >= 2


def test_the_api_refuses_an_unwritable_out_before_any_worker_starts(tmp_path):
    from pchute_exudyn.fit import load_fit, run_fit
    from pchute_exudyn.study import load_study, run_study

    (tmp_path / "taken").write_text("x")
    study, fit = load_study(study_file(tmp_path)), load_fit(fit_file(tmp_path))
    before = {p.pid for p in _descendants(os.getpid())}
    for call in (lambda out: run_study(study, out, workers=2, progress=False),
                 lambda out: run_fit(fit, out, workers=2)):
        for out in (tmp_path / "taken", tmp_path / "taken" / "sub"):
            with pytest.raises(PchuteError) as caught:
                call(out)
            assert len(str(caught.value).splitlines()) == 1 and repr(str(out)) in str(caught.value)
    assert {p.pid for p in _descendants(os.getpid())} <= before      # no worker was started


def test_pool_workers_die_with_a_killed_study(tmp_path):
    """SIGKILL to the main process alone (no clean-up can run): its workers die with it (PR_SET_PDEATHSIG)."""
    if not sys.platform.startswith("linux"):
        pytest.skip("PR_SET_PDEATHSIG is Linux's")
    study_file(tmp_path, runs=60, duration=3.0)
    process = _start(["study", tmp_path / "study.toml", "--out", tmp_path / "out", "--workers", "2", "--no-progress"],
                     tmp_path)
    journal, deadline = tmp_path / "out" / "runs.jsonl", time.monotonic() + 60
    while time.monotonic() < deadline and not (journal.is_file() and journal.read_text().count("\n") >= 2):
        time.sleep(0.02)
    workers = _descendants(process.pid)
    assert process.poll() is None and workers
    process.kill()
    process.wait(timeout=30)
    time.sleep(0.3)
    assert not _alive(workers) and not _mentioning(str(tmp_path / "out"))
    assert len({r["run"] for r in journal_lines(journal)}) == len(journal_lines(journal)) >= 2


@pytest.mark.parametrize("kind, fault", [("study", "a file"), ("study", "locked"), ("fit", "locked")])
def test_a_refused_folder_leaves_no_worker_holding_the_output_pipes(tmp_path, kind, fault):
    """A command refused after its pool started must not leave workers behind: orphans holding its standard error
    would keep a caller that reads it (a CI job, `subprocess.run(capture_output=True)`) waiting forever."""
    args = study_args(tmp_path) if kind == "study" else fit_args(tmp_path)
    args[args.index("--workers") + 1] = "2"
    if fault == "a file":
        args = out_is_a_file(kind)(tmp_path)
    else:
        locked(kind)(tmp_path)
    done = run_cli(*args, cwd=tmp_path, timeout=60)
    assert done.returncode == 1 and done.stderr.count("\n") == 1 and "Traceback" not in done.stderr, done.stderr
    assert not _mentioning(str(tmp_path))


def test_a_worker_forked_while_the_folder_is_locked_does_not_keep_it_locked(tmp_path):
    """A pool whose workers start after the lock was taken (a pool passed in by the caller starts them at its first
    submit) and outlive the study: once the study lets go, the folder is free (the workers close their copy of the
    lock's descriptor at fork)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    lock = FolderLock(tmp_path, "study")
    lock.acquire()
    pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("fork"))
    try:
        assert pool.submit(os.getpid).result(timeout=30) != os.getpid()   # the worker lives on, forked under the lock
        lock.release()
        again = FolderLock(tmp_path, "study")
        again.acquire()                                                  # not "in use" by the worker
        again.release()
    finally:
        pool.shutdown()


def test_allow_failures_compares_the_rate_exactly():
    from pchute_exudyn.cli import _failures_status
    from pchute_exudyn.study.runner import StudyOutcome

    def outcome(failed):
        return StudyOutcome(100, 0, 100, failed, 1.0, "study", Path("study") / "runs.csv", {}, None)
    assert _failures_status(outcome(29), 0.29) == 0   # 0.29 x 100 = 28.999...
    assert _failures_status(outcome(30), 0.29) == 1

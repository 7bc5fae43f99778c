"""User trigger functions that misbehave (issue 49): a Ctrl-C or SIGTERM stops a run within a second whatever the
function does (a real signal to a real `pchute run` whose function sleeps 100 s); a function past its time limit,
one that calls sys.exit or raises KeyboardInterrupt, a module named by a path, and a function on an atmosphere
without a speed of sound each give one line naming the trigger and the function (bad-input harness)."""

import re
import signal
import subprocess
import threading
import time
from pathlib import Path

import pytest

from pchute_exudyn.triggers.user_calls import IDLE, CallTimedOut, UserCalls
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT, start_cli

TRIGGERS = (ROOT / "cases" / "cev_pa1_triggers.toml").as_posix()
SLEEPS = """import pathlib, time
def fire(now, sensed, state):
    if now > 1.0:
        pathlib.Path(__file__).with_name("asleep").touch()
        time.sleep(100)
    return False
"""


def _case(tmp: Path, module: str, body: str, trigger: str = "", extra: str = "") -> Path:
    """cev_pa1_triggers.toml with the main's deployment fired by ``module``'s function ``fire`` (its source
    ``body``), ``trigger`` more keys of the trigger table, ``extra`` more of the case."""
    (tmp / f"{module}.py").write_text(body)
    case = tmp / "case.toml"
    case.write_text(f'extends = "{TRIGGERS}"\nremove = ["systems.main.deploy_trigger"]\n{extra}[systems.main]\n'
                    f'deploy_trigger = {{ function = "{module}:fire", rate = 10.0{trigger} }}\n')
    return case


SLOW = "import time\ndef fire(now, sensed, state):\n    if now > 0.5:\n        time.sleep(100)\n    return False\n"
QUIET = "def fire(now, sensed, state):\n    return False\n"


def _run(case, tmp: Path, function: str | None = None, csv: str | None = None) -> list:
    """The command's arguments; ``function``: a --set of the main's trigger; ``csv``: air.csv's text."""
    if csv is not None:
        (tmp / "air.csv").write_text(csv)
    sets = [] if function is None else ["--set", f"main.deploy_trigger.{function}"]
    return ["run", str(case), "--method", "sp", "--out", str(tmp / "out"), "--quiet", "--no-plot", *sets]


@pytest.mark.parametrize("sent, status, words", [(signal.SIGINT, 130, "interrupted"),
                                                 (signal.SIGTERM, 143, r"terminated \(SIGTERM\)")])
def test_a_signal_stops_a_run_whose_trigger_function_sleeps_within_a_second(tmp_path, sent, status, words):
    case = _case(tmp_path, "sleeps_49", SLEEPS)
    process = start_cli(*_run(case, tmp_path), cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                        text=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + 60
        while not (tmp_path / "asleep").exists() and time.monotonic() < deadline and process.poll() is None:
            time.sleep(0.02)
        assert (tmp_path / "asleep").exists(), process.communicate(timeout=5)
        sent_at = time.monotonic()
        process.send_signal(sent)
        _, err = process.communicate(timeout=30)
        stopped_in = time.monotonic() - sent_at
    finally:
        process.kill()
    assert process.returncode == status, err
    assert stopped_in < 2.0, stopped_in
    assert re.fullmatch(rf"pchute run: {words} at t = 1\.0\d\d s of 200 s; no result files were written", err.strip())
    assert not (tmp_path / "out").exists()


BATTERY = [
    ("function past its time limit",
     lambda t: _run(_case(t, "slow_49", SLOW, ", time_limit = 0.3"), t),
     "systems.main.deploy_trigger: the function slow_49:fire took longer than its time limit of 0.3 s per call "
     "(time_limit) at t = 0.5000 s"),
    ("function calling sys.exit",
     lambda t: _run(_case(t, "exits_49", "import sys\ndef fire(now, sensed, state):\n    sys.exit(3)\n"), t),
     "systems.main.deploy_trigger: the function exits_49:fire called sys.exit(3) instead of returning True or "
     "False at t = 0.0100 s"),
    ("function raising KeyboardInterrupt",
     lambda t: _run(_case(t, "ctrl_c_49", "def fire(now, sensed, state):\n    raise KeyboardInterrupt\n"), t),
     "pchute run: interrupted at t = 0.020 s of 200 s (systems.main.deploy_trigger: the function ctrl_c_49:fire "
     "raised KeyboardInterrupt); no result files were written"),
    ("module named by a path",
     lambda t: _run(_case(t, "plain_49", QUIET).with_name("case.toml"), t, "function=..tmp.plain_49:fire"),
     "systems.main.deploy_trigger.function = '..tmp.plain_49:fire': must be \"module:function\" with a plain module "
     "name (names joined by dots, no path, no leading dot): a module.py in the case's folder or a module on the "
     "import path"),
    ("module named by a file path",
     lambda t: _run(_case(t, "plain_49", QUIET).with_name("case.toml"), t, "function=../lib/plain_49:fire"),
     "systems.main.deploy_trigger.function = '../lib/plain_49:fire': must be \"module:function\" with a plain "
     "module name"),
    ("function on an atmosphere without a speed of sound",
     lambda t: _run(_case(t, "quiet_49", QUIET, extra='[atmosphere]\nmodel = "table"\nfile = "air.csv"\n'), t,
                    csv="altitude,density\n-1000,1.35\n20000,0.09\n"),
     "systems.main.deploy_trigger: the function quiet_49:fire is given pressure and mach, which need an atmosphere "
     "with a temperature (speed of sound): the atmosphere 'table' has no temperature; add a temperature column (K) "
     "or give atmosphere.speed_of_sound (m/s)"),
]


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_misbehaving_trigger_function_gives_one_line(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)
    assert code == (130 if "KeyboardInterrupt" in name else 1)
    assert not (tmp_path / "out").exists()


def test_the_thread_of_a_user_function_answers_and_ends_when_idle():
    """``triggers.user_calls``: answers and exceptions come back, a call past its limit is left behind, and no
    worker thread outlives its work by more than IDLE s (a study's process runs thousands of runs)."""
    calls, before = UserCalls(), set(threading.enumerate())   # (a test before may have left a sleeping call)
    assert calls.call(lambda a: a + 1, (1,), 1.0) == 2
    with pytest.raises(ValueError):
        calls.call(int, ("x",), 1.0)
    started = time.monotonic()
    with pytest.raises(CallTimedOut):
        calls.call(time.sleep, (0.3,), 0.1)
    assert time.monotonic() - started < 0.2
    assert calls.call(lambda: True, (), 1.0) is True   # a new worker
    deadline = time.monotonic() + IDLE + 2.0
    while set(threading.enumerate()) - before and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not set(threading.enumerate()) - before

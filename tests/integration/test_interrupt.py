"""Ctrl-C and progress, tried on real processes: a real SIGINT to a real `pchute run` that is mid-solve, and its
standard error on a real pseudo-terminal."""

import os
import pty
import select
import signal
import subprocess
import sys
import time

import pytest

from tests.helpers import MER, run_cli, start_cli

RUN = ["run", MER / "case1.toml", "--method", "full", "--t-end", "20", "--no-plot"]
"""The command's arguments (``run_cli``, ``start_cli``): 20 s of full-mass RK4 at the thesis's step, long enough
to interrupt."""


def _start_on_terminal(arguments, cwd):
    """Start ``arguments`` with standard error on a pseudo-terminal; returns the process and the terminal's end."""
    terminal, child = pty.openpty()
    # as from an interactive shell: SIGINT at its default (a test runner may have been started with it ignored)
    process = start_cli(*arguments, cwd=cwd, stdout=subprocess.PIPE, stderr=child, text=True,
                        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    os.close(child)
    return process, terminal


def _read_until(terminal, text: str, timeout: float) -> str:
    seen, deadline = "", time.monotonic() + timeout
    while text not in seen and time.monotonic() < deadline:
        ready, _, _ = select.select([terminal], [], [], 0.2)
        if ready:
            try:
                seen += os.read(terminal, 4096).decode(errors="replace")
            except OSError:   # the process closed the terminal
                break
    return seen


def _drain(terminal) -> str:
    seen = ""
    while select.select([terminal], [], [], 0.5)[0]:
        try:
            chunk = os.read(terminal, 4096)
        except OSError:
            break
        if not chunk:
            break
        seen += chunk.decode(errors="replace")
    return seen


def _signal_mid_run(tmp_path, sent) -> tuple:
    """(exit status, last line, all it printed, output folder) of `pchute run` sent ``sent`` mid-solve."""
    out = tmp_path / "run"
    process, terminal = _start_on_terminal(RUN + ["--out", str(out)], tmp_path)
    try:
        shown = _read_until(terminal, "s left", timeout=60)        # the progress line: the solve is running
        assert "t = " in shown and "s left" in shown, shown
        process.send_signal(sent)
        process.wait(timeout=30)
        error = shown + _drain(terminal)
    finally:
        process.kill()
        os.close(terminal)
    last = [line for line in error.replace("\x1b[K", "").replace("\r", "\n").splitlines() if line.strip()][-1]
    return process.returncode, last, error, out


def test_ctrl_c_mid_run_exits_130_with_one_line_and_no_divergence_claim(tmp_path):
    status, last, error, out = _signal_mid_run(tmp_path, signal.SIGINT)
    assert status == 130
    assert last.startswith("pchute run: interrupted at t = ") and last.endswith("of 20 s; no result files were written")
    assert "diverged" not in error and "Traceback" not in error
    assert not out.exists()                                       # no empty result folder left behind


def test_sigterm_mid_run_exits_143_with_one_line_and_nothing_written(tmp_path):
    """SIGTERM to `pchute run` mid-solve (issue 49: it ended with -15 and no word): stopped as Ctrl-C is."""
    status, last, error, out = _signal_mid_run(tmp_path, signal.SIGTERM)
    assert status == 143
    assert last.startswith("pchute run: terminated (SIGTERM) at t = ") and last.endswith(
        "of 20 s; no result files were written"), last
    assert "Traceback" not in error and not out.exists()


@pytest.mark.long
def test_progress_only_on_a_terminal_and_not_with_quiet(tmp_path):
    short = RUN[:-3] + ["--t-end", "3", "--no-plot"]
    process, terminal = _start_on_terminal(short + ["--quiet", "--out", str(tmp_path / "a")], tmp_path)
    process.wait(timeout=120)
    quiet = _drain(terminal)
    os.close(terminal)
    assert process.returncode == 0 and "s left" not in quiet
    piped = run_cli(*short, "--out", tmp_path / "b", cwd=tmp_path, timeout=120)
    assert piped.returncode == 0 and piped.stderr == ""             # not a terminal: no progress line
    assert piped.stdout.startswith("MER case 1: full/rk4 step 0.0001 s, ended at 3.00 s")


def test_a_failed_run_leaves_no_empty_folder(tmp_path):
    out = tmp_path / "unstable"
    run = run_cli(*RUN[:-3], "--dt", "1e-3", "--t-end", "2", "--out", out, cwd=tmp_path, timeout=120)
    assert run.returncode == 1 and "exceeds the stability limit" in run.stderr
    assert not out.exists()


SLOW_MODULE = """
import os, signal, time
os.kill(os.getpid(), signal.SIGINT)   # Ctrl-C in the middle of this import
deadline = time.monotonic() + 0.2
while time.monotonic() < deadline:
    pass
DONE = True
"""
CHILD = """
import sys, time
sys.path.insert(0, sys.argv[1])
from pchute_exudyn import _interrupt
_interrupt.install()
try:
    import slow_module
    while True:             # the deferred interrupt arrives once the import is over
        time.sleep(0.005)
except KeyboardInterrupt:
    print("whole" if getattr(sys.modules.get("slow_module"), "DONE", False) else "half")
"""


def test_ctrl_c_inside_an_import_of_the_command_waits_for_the_import_to_finish(tmp_path):
    """The command's SIGINT handler (``_interrupt``): a Ctrl-C that arrives inside an import is raised once the import
    is over, so no module is left half imported (Exudyn's import turned it into an ImportError about its wheel)."""
    (tmp_path / "slow_module.py").write_text(SLOW_MODULE)
    done = subprocess.run([sys.executable, "-c", CHILD, str(tmp_path)], capture_output=True, text=True, timeout=30,
                          preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert done.stdout.strip() == "whole", done.stderr


def test_ctrl_c_while_the_command_starts_is_an_interrupt(tmp_path):
    """SIGINT to `pchute run` while it imports numpy, Exudyn and the package (after the interpreter's own start):
    exit 130 and one line, never a traceback, a wrong error or a reported divergence."""
    for delay in (0.3, 0.45, 0.6):
        process = start_cli(*RUN, cwd=tmp_path, stderr=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
        time.sleep(delay)
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=60)
        assert process.returncode == 130 and len(err.strip().splitlines()) == 1, (delay, err)
        assert "interrupted" in err and "diverged" not in err


def test_sigterm_while_the_command_starts_is_a_clean_stop(tmp_path):
    """SIGTERM to `pchute run` while it imports (issue 49: -15 and no word): exit 143 and one line."""
    for delay in (0.3, 0.6):
        process = start_cli(*RUN, cwd=tmp_path, stderr=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        time.sleep(delay)
        process.send_signal(signal.SIGTERM)
        _, err = process.communicate(timeout=60)
        assert process.returncode == 143 and len(err.strip().splitlines()) == 1, (delay, err)
        assert "terminated (SIGTERM)" in err and "Traceback" not in err


SWALLOWED = """
import sys, time
from pchute_exudyn import _interrupt
_interrupt.install()

class Closing:
    def __del__(self):          # where Python can only print an exception ("Exception ignored in"), as in
        raise KeyboardInterrupt  # logging's at-fork callback when a Ctrl-C lands while a pool forks a worker

try:
    Closing()
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline:
        time.sleep(0.005)
    print("lost")
except KeyboardInterrupt:
    print("raised again")
"""


def test_a_ctrl_c_python_can_only_print_is_raised_again(tmp_path):
    """An interrupt raised inside a __del__ or an at-fork callback is printed and dropped by Python (a fit went on to
    its end, exit 0, after a Ctrl-C during its pool's start): the command's hook raises it again."""
    done = subprocess.run([sys.executable, "-c", SWALLOWED], capture_output=True, text=True, timeout=30, cwd=tmp_path,
                          preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))   # as the tests above
    assert done.stdout.strip() == "raised again" and "Exception ignored" not in done.stderr, done.stderr

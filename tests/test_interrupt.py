"""Ctrl-C and progress, tried on real processes: a real SIGINT to a real `pchute run` that is mid-solve, and its
standard error on a real pseudo-terminal."""

import os
import pty
import select
import signal
import subprocess
import sys
import time

from .conftest import MER

RUN = [sys.executable, "-m", "pchute_exudyn", "run", str(MER / "case1.toml"), "--method", "full", "--t-end", "20",
       "--no-plot"]


def _start_on_terminal(arguments, cwd):
    """Start ``arguments`` with standard error on a pseudo-terminal; returns the process and the terminal's end."""
    terminal, child = pty.openpty()
    # as from an interactive shell: SIGINT at its default (a test runner may have been started with it ignored)
    process = subprocess.Popen(arguments, cwd=cwd, stdout=subprocess.PIPE, stderr=child, text=True,
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


def test_ctrl_c_mid_run_exits_130_with_one_line_and_no_divergence_claim(tmp_path):
    out = tmp_path / "run"
    process, terminal = _start_on_terminal(RUN + ["--out", str(out)], tmp_path)
    try:
        shown = _read_until(terminal, "s left", timeout=60)        # the progress line: the solve is running
        assert "t = " in shown and "s left" in shown, shown
        process.send_signal(signal.SIGINT)
        process.wait(timeout=30)
        error = shown + _drain(terminal)
    finally:
        process.kill()
        os.close(terminal)
    last = [line for line in error.replace("\x1b[K", "").replace("\r", "\n").splitlines() if line.strip()][-1]
    assert process.returncode == 130
    assert last.startswith("pchute run: interrupted at t = ") and last.endswith("of 20 s; no result files were written")
    assert "diverged" not in error and "Traceback" not in error
    assert not out.exists()                                       # no empty result folder left behind


def test_progress_only_on_a_terminal_and_not_with_quiet(tmp_path):
    short = RUN[:-3] + ["--t-end", "3", "--no-plot"]
    process, terminal = _start_on_terminal(short + ["--quiet", "--out", str(tmp_path / "a")], tmp_path)
    process.wait(timeout=120)
    quiet = _drain(terminal)
    os.close(terminal)
    assert process.returncode == 0 and "s left" not in quiet
    piped = subprocess.run(short + ["--out", str(tmp_path / "b")], cwd=tmp_path, capture_output=True, text=True,
                           timeout=120)
    assert piped.returncode == 0 and piped.stderr == ""             # not a terminal: no progress line
    assert piped.stdout.startswith("MER case 1: full/rk4 step 0.0001 s, ended at 3.00 s")


def test_a_failed_run_leaves_no_empty_folder(tmp_path):
    out = tmp_path / "unstable"
    run = subprocess.run(RUN[:-3] + ["--dt", "1e-3", "--t-end", "2", "--out", str(out)], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 1 and "exceeds the stability limit" in run.stderr
    assert not out.exists()

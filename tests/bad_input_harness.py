"""Run one bad input through the command line in this process and report what it did: its exit status, its standard
error, its time, and every file it touched outside its output.

Shared by ``test_bad_inputs.py`` and its friends (``test_faults.py`` ...): every entry asserts one line, a non-zero
exit, no traceback, and that no file outside the output (``--out``, or the default output folder under the working
folder) was created, changed or removed.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import os
import time
from pathlib import Path

from tests.helpers import ROOT

WATCHED = [ROOT / "cases", ROOT / "tests" / "cases", ROOT / "examples"]
"""The repository's input folders: a command must never write there."""


def snapshot(folders) -> dict:
    """Path -> (size, digest of the content) of every file under ``folders``."""
    files = {}
    for folder in folders:
        if not Path(folder).exists():
            continue
        for dirpath, _, names in os.walk(folder):
            for name in names:
                path = Path(dirpath) / name
                try:
                    data = path.read_bytes()
                except OSError:
                    continue
                files[path] = (len(data), hashlib.sha1(data).hexdigest())
    return files


def allowed_outputs(args: list, work: Path) -> list:
    """Where the command may write: its ``--out``, the working folder (default outputs) and, for ``animate`` without
    ``--out``, its default file in the result folder."""
    allowed = [work]
    if "--out" in args and args.index("--out") + 1 < len(args):
        allowed.append(Path(args[args.index("--out") + 1]))
    if args[:1] == ["animate"] and "--out" not in args and len(args) > 1:
        allowed.append(Path(args[1]) / "animation.gif")
    return [p.absolute() for p in allowed]


def _inside(path: Path, allowed: list) -> bool:
    path = path.absolute()
    return any(path == a or a in path.parents for a in allowed)


def touched_outside(before: dict, after: dict, allowed: list) -> list:
    """Files created, changed or removed between two snapshots, outside the ``allowed`` paths."""
    changed = {p for p in before.keys() | after.keys() if before.get(p) != after.get(p)}
    return sorted(str(p) for p in changed if not _inside(p, allowed))


def run_bad_input(make_args, tmp: Path) -> tuple:
    """(exit code, standard error, seconds, files touched outside the output) of the command line on one bad input,
    run in this process from the working folder ``tmp/work``."""
    from pchute_exudyn.cli import main

    work = tmp / "work"
    work.mkdir(exist_ok=True)
    args = [str(a) for a in make_args(tmp)]
    watched = [tmp, *WATCHED]
    before = snapshot(watched)
    err = io.StringIO()
    here = os.getcwd()
    started = time.perf_counter()
    os.chdir(work)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            try:
                code = main(args)
            except SystemExit as exc:   # argparse's own one-line errors
                code = exc.code
    finally:
        os.chdir(here)
    seconds = time.perf_counter() - started
    return code, err.getvalue(), seconds, touched_outside(before, snapshot(watched), allowed_outputs(args, work))


def assert_one_line(code, err: str, expected: str, touched: list, seconds: float, limit: float = 10.0) -> None:
    """The battery's assertion: a non-zero exit, one line holding ``expected``, no traceback, nothing touched
    outside the output, within ``limit`` s."""
    assert code not in (0, None), err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert expected in err, err
    assert not touched, f"files touched outside the output: {touched}"
    assert seconds < limit, seconds


def print_table(battery) -> None:
    """The battery's inputs, exit statuses, times and messages as a Markdown table (a test file run as a script)."""
    import tempfile

    print("| input | exit | seconds | message |\n|---|---|---|---|")
    for name, make_args, _ in battery:
        with tempfile.TemporaryDirectory() as folder:
            code, err, seconds, _ = run_bad_input(make_args, Path(folder))
        message = err.strip().replace("|", "\\|").replace(folder, "TMP")
        print(f"| {name} | {code} | {seconds:.2f} | {message} |")

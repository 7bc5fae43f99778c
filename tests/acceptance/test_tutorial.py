"""docs/tutorial.md runs as written: every `$` command (in-process, through the CLI's entry point), every file it
shows and every Python block, in order, in a fresh folder holding only what a clone has that it uses."""

import os
import re
import shlex
from pathlib import Path

import pytest

from pchute_exudyn.cli import main
from tests.helpers import ROOT

TUTORIAL = ROOT / "docs" / "tutorial.md"
BLOCK = re.compile(r"^```(?P<info>[^\n]*)\n(?P<body>.*?)^```", re.S | re.M)


def tutorial_steps(text: str) -> list:
    """(kind, payload) in order: ("command", argv), ("file", (name, text)), ("python", source)."""
    steps = []
    for block in BLOCK.finditer(text):
        info, body = block["info"].split(), block["body"]
        if info[:1] == ["console"]:
            steps += [("command", [os.path.expandvars(word) for word in shlex.split(line[2:])])
                      for line in body.splitlines() if line.startswith("$ ")]
        elif info[:1] == ["python"]:
            steps.append(("python", body))
        elif len(info) > 1 and info[1].startswith("file="):
            steps.append(("file", (info[1].removeprefix("file="), body)))
    return steps


def test_the_tutorial_shows_commands_of_every_kind():
    kinds = [argv[1] for kind, argv in tutorial_steps(TUTORIAL.read_text()) if kind == "command"]
    for command in ("new", "run", "animate", "study", "study-report", "compare"):
        assert command in kinds, command
    assert "docs/tutorial.md" in (ROOT / "README.md").read_text()


@pytest.mark.long
def test_every_tutorial_command_runs(tmp_path, monkeypatch, capsys):
    # from a folder outside the repository, the clone named as the tutorial says: through PCHUTE_REPO
    monkeypatch.setenv("PCHUTE_REPO", str(ROOT))
    monkeypatch.chdir(tmp_path)
    assert not (tmp_path / "validation").exists() and ROOT not in tmp_path.parents
    for kind, payload in tutorial_steps(TUTORIAL.read_text()):
        if kind == "file":
            Path(payload[0]).write_text(payload[1])
        elif kind == "python":
            exec(compile(payload, "tutorial", "exec"), {})
        else:
            assert payload[0] == "pchute"
            assert main(payload[1:]) == 0, (payload, capsys.readouterr().err)
    out = capsys.readouterr().out
    assert "sp/rk4 adaptive steps " in out                                        # the case sets no step
    assert "full/rk4 adaptive steps " in out                                      # no step set: adaptive
    for path in ("results/payload_sp/start.gif", "results/vs_rocketpy/descent_rate.png",
                 "results/vs_rocketpy/vehicle_altitude.png", "results/vs_rocketpy/comparison.md",
                 "results/sp_vs_full/comparison.md", "studies/payload_study/runs.csv"):
        assert Path(path).is_file(), path
    report = Path("results/vs_rocketpy/comparison.md").read_text()
    assert "| time to ground (s) |" in report and "| rate of descent at 1500 m (m/s) |" in report
    # the tutorial's figures: touchdown about 418.5 s; RocketPy 0.08 % slower, 0.36 s later (both normal gravity)
    descent = __import__("json").loads(Path("results/vs_rocketpy/comparison.json").read_text())["descent"]
    assert descent["a"]["ground_time"] == pytest.approx(418.5, abs=0.5)
    assert descent["b"]["ground_time"] - descent["a"]["ground_time"] == pytest.approx(0.36, abs=0.05)
    for ours, theirs in zip(descent["a"]["rates"], descent["b"]["rates"]):
        assert theirs / ours - 1.0 == pytest.approx(-0.0008, abs=0.0003)

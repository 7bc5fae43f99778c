"""The overview figure drawn by a process of its own (started with `pchute run`): the same file the command's own
process draws, and the command's own drawing when that process cannot."""

from __future__ import annotations

import pchute_exudyn as pc
from pchute_exudyn.views.figure_process import FigureProcess
from pchute_exudyn.views.plotting import save_figure
from tests.helpers import ROOT


def test_the_figure_process_writes_the_figure_the_command_draws(tmp_path):
    result = pc.simulate(pc.load_case(ROOT / "cases" / "mer" / "case1.toml"), "sp", duration=5.0)
    process = FigureProcess()
    assert process.process is not None   # this machine has two cores
    assert process.draw(result, tmp_path / "process.png")
    save_figure(result.plot(), tmp_path / "here.png")
    assert (tmp_path / "process.png").read_bytes() == (tmp_path / "here.png").read_bytes()
    assert process.process is None   # ended


def test_without_the_process_the_result_draws_its_own_figure(tmp_path):
    result = pc.simulate(pc.load_case(ROOT / "cases" / "mer" / "case1.toml"), "sp", duration=1.0)
    process = FigureProcess()
    process.close()                      # gone before the save (as on one core)
    assert not process.draw(result, tmp_path / "never.png")
    paths = result.save(tmp_path / "result", draw=process.draw)
    assert paths["plot"].is_file() and not (tmp_path / "never.png").exists()

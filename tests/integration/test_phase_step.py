"""A fixed step checked at every phase (issue 59, docs/models/step_control.md): the rocket's main canopy flown rigid
at 0.17 kg, deployed at 20-odd m/s, is damped by its drag at over 1000 1/s; at a fixed 0.01 s the run stops at the
main's deployment, before the first step, naming the canopy, its limit and the remedies, instead of running away; a
step within the margin (1.34 times the limit) runs, with the loads of a small step; a canopy opening by its fill law is not stopped."""

import json
import re

import pytest

from pchute_exudyn.cli import main
from pchute_exudyn.run.phase_step import PHASE_STEP_MARGIN
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT

ROCKET = ROOT / "cases" / "rocket" / "dual_deploy.toml"
LIGHT_MAIN = ["--set", "main.canopy_model=rigid", "--set", "main_canopy.mass=0.17",
              "--set", "main.deploy_trigger.below=2300"]   # m above the ground: the main about 10 s after apogee


def _run(tmp_path, name, *options) -> dict:
    out = tmp_path / name
    assert main(["run", str(ROCKET), *LIGHT_MAIN, *options, "--no-plot", "--quiet", "--out", str(out)]) == 0
    return json.loads((out / "summary.json").read_text())


def _main_peak(summary) -> float:
    return summary["peak_tension"]["main_riser"]


@pytest.fixture(scope="module")
def inside(tmp_path_factory):
    """The light main at 0.0032 s, 1.34 times its limit (inside the margin), and at 0.002 s, to 0.8 s past its
    deployment (its peak load at 0.15 s)."""
    tmp = tmp_path_factory.mktemp("inside")
    return _run(tmp, "inside", "--dt", "0.0032", "--t-end", "11.5"), _run(tmp, "small", "--dt", "0.002", "--t-end",
                                                                          "11.5")


def test_a_step_too_long_for_the_light_main_stops_at_its_deployment(tmp_path, inside):
    out = tmp_path / "o"
    code, err, seconds, touched = run_bad_input(
        lambda t: ["run", ROCKET, *LIGHT_MAIN, "--set", "simulation.steps.sp=0.01", "--no-plot", "--out", out], tmp_path)
    assert_one_line(code, err, "the fixed RK4 step 0.01 s is too long for body main_canopy on its lines and its drag",
                    touched, seconds)
    assert code == 1 and not out.exists()   # nothing written: the run stopped before its first output
    deployed = next(e["time"] for e in inside[0]["events"] if e["event"] == "deploy" and e.get("system") == "main")
    stop = float(re.search(r"deployed at t = ([0-9.]+) s", err).group(1))
    assert stop == pytest.approx(deployed, abs=0.01)   # at the deployment (a sensed trigger's: within a step)
    limit = float(re.search(r"its stability limit there is ([0-9.e-]+) s", err).group(1))
    assert 2e-3 < limit < 0.01 / PHASE_STEP_MARGIN and 0.0032 <= PHASE_STEP_MARGIN * limit
    # the remedies, each the package's own: adaptive steps, the reduced canopy model, a step below the limit
    assert "--dt auto (adaptive steps)" in err and 'systems.main.canopy_model = "reduced"' in err
    suggested = float(re.search(r"or --dt ([0-9.e-]+) or smaller", err).group(1))
    assert suggested < limit


def test_a_step_inside_the_margin_runs_with_the_loads_of_a_small_step(inside):
    at_margin, small = inside
    assert at_margin["end"] == "duration" and any(e.get("system") == "main" for e in at_margin["events"])
    assert _main_peak(at_margin) == pytest.approx(_main_peak(small), rel=0.01)


def test_a_canopy_opening_by_its_fill_law_is_not_stopped(tmp_path):
    """The airdrop cluster's canopies open by the fill-constant law from line stretch at 1 s: at 0.0125 s (2.3 times
    the limit the full drag area would set at the release speed) its peak load is a small step's within 0.1 %."""
    out = tmp_path / "airdrop"
    assert main(["run", str(ROOT / "cases" / "airdrop" / "cluster_600m.toml"), "--dt", "0.0125", "--t-end", "1.05",
                 "--no-plot", "--quiet", "--out", str(out)]) == 0

"""A study's worker keeps what its runs share (modules, kernels, remembered constants) and still gives every run the
record a fresh process gives it; the shortcuts a run's steps take give the numbers the long way gives."""

import json
import math
from concurrent.futures import ProcessPoolExecutor

from pchute_exudyn.case.model import DragAreaSchedule
from pchute_exudyn.case.plausible import range_of
from pchute_exudyn.engine.aero_loads import held_end
from pchute_exudyn.study import load_study, run_study
from tests.helpers import ROOT

STUDY = f"""
[study]
name = "PA1 in wind, short"
case = "{(ROOT / 'cases' / 'cev_pa1_winds.toml').as_posix()}"
runs = 2
seed = 20261129
duration = 11.0                            # s: the drogues' inflation held at its end, the mains deployed and reefed

[[study.configurations]]
method = "sp"
preset = "accurate"
steps = ["auto"]

[parameters."atmosphere.wind.speed"]
distribution = "uniform"
low = 2.0
high = 8.0

[parameters."atmosphere.turbulence.seed"]
distribution = "seed"

[parameters."main_canopy.aerodynamics.axial_coefficient"]
distribution = "uniform"
low = 0.95
high = 1.05
relative = true
"""

TIMINGS = ("wall_time", "run_time", "crc32")


def records(folder):
    """runs.jsonl's records by run, without what differs between two executions of a run (timings, checksum)."""
    lines = [json.loads(line) for line in (folder / "runs.jsonl").read_text().splitlines()]
    return {r["run"]: {k: v for k, v in r.items() if k not in TIMINGS} for r in lines}


def test_a_worker_running_one_run_after_another_records_what_fresh_processes_record(tmp_path):
    path = tmp_path / "short.toml"
    path.write_text(STUDY)
    spec = load_study(path)
    run_study(spec, tmp_path / "kept", workers=1, progress=False)   # one worker: the second run reuses the first's
    with ProcessPoolExecutor(1, max_tasks_per_child=1) as fresh:     # a new process for every run
        run_study(spec, tmp_path / "fresh", executor=fresh, progress=False)
    kept, alone = records(tmp_path / "kept"), records(tmp_path / "fresh")
    assert sorted(kept) == [0, 1] and all(r["status"] == "ok" for r in kept.values())
    assert kept == alone                                               # every output, bit for bit, and the steps
    assert kept[0]["final_east"] != kept[1]["final_east"]              # the draws differ: two different runs
    assert 0.0 < kept[0]["final_time"] <= 11.0 + 1e-9


def test_a_drag_area_table_held_past_its_end_is_the_number_the_table_gives():
    reefed = DragAreaSchedule((0.0, 1.5, 8.0, 9.0, 16.0, 18.0), (0.0, 0.08, 0.08, 0.25, 0.25, 1.0 / 3.0 * 3.0))
    since, value = held_end(reefed)
    assert since == 18.0
    for later in (18.0, 18.000001, 25.0, 1e6):
        assert value == reefed(later)                                  # exactly: the same arithmetic, done once
    assert held_end(DragAreaSchedule((0.0,), (0.4,))) == (0.0, 0.4)   # a constant fraction from the start
    assert held_end(lambda since: 1.0)[0] == math.inf                  # an opening measured as it goes: never held


def test_a_remembered_plausibility_range_is_the_one_the_patterns_give():
    for key in ("bodies.vehicle.mass", "atmosphere.gusts[0].amplitude", "systems.main.lines.riser.stiffness",
                "no.such.key"):
        assert range_of(key) is range_of.__wrapped__(key)

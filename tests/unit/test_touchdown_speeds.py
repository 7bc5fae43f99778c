"""The touchdown velocity's parts (``results.summary.TouchdownEvent``): down the local vertical and across it, their
squares adding up to the total speed's, beside the start point's axes' split kept as it was; and the run line and
the figures' event marks that read them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pchute_exudyn.results.run_line import touchdown_text
from pchute_exudyn.results.summary import RunSummary, TouchdownEvent, event_from_dict
from pchute_exudyn.views.plotting import event_marks


@pytest.mark.parametrize("tilt", [0.0, 1e-3, 0.3])
def test_descent_rate_and_horizontal_speed_split_the_velocity_along_the_local_vertical(tilt):
    velocity = np.array([4.0, -3.0, -6.5])   # m/s east, north, up: 5 m/s over the ground, 6.5 m/s down
    down = np.array([math.sin(tilt), 0.0, -math.cos(tilt)])   # the local vertical, tilted east by ``tilt`` rad
    event = TouchdownEvent.from_crossing(12.5, velocity, down)
    assert event.descent_rate == pytest.approx(6.5 * math.cos(tilt) + 4.0 * math.sin(tilt), rel=1e-14)
    assert event.descent_rate ** 2 + event.horizontal_speed_over_ground ** 2 == pytest.approx(event.speed ** 2,
                                                                                             rel=1e-14)
    assert (event.speed, event.vertical_speed, event.horizontal_speed) == (   # the start point's axes, as before
        float(np.linalg.norm(velocity)), 6.5, float(np.hypot(4.0, -3.0)))
    if tilt == 0.0:
        assert (event.descent_rate, event.horizontal_speed_over_ground) == (6.5, 5.0)


def test_a_summary_from_before_the_split_reads_back_without_it():
    old = {"event": "touchdown", "time": 3.0, "speed": 5.0, "vertical_speed": 4.0, "horizontal_speed": 3.0}
    event = event_from_dict(old)
    assert isinstance(event, TouchdownEvent) and event.descent_rate is None
    assert event.to_dict() == old
    assert touchdown_text(event) == "" and touchdown_text(None) == ""


def test_the_run_line_names_each_speed():
    event = TouchdownEvent.from_crossing(440.0, [5.0, 0.0, -6.06], [0.0, 0.0, -1.0])
    assert touchdown_text(event) == ("; at touchdown descent rate 6.06 m/s, horizontal speed 5.00 m/s, total speed "
                                       "7.86 m/s (over the ground)")


def test_the_figures_mark_deployments_separations_cutaways_disreefs_and_the_touchdown():
    events = [{"event": "start", "time": 0.0}, {"event": "deploy", "time": 2.75, "system": "main"},
              {"event": "stage_start", "time": 2.75, "system": "main", "stage": 1},
              {"event": "disreef", "time": 8.0, "system": "main", "stage": 2, "canopy": "main_a"},
              {"event": "separation", "time": 22.75, "body": "heat_shield"},
              {"event": "cutaway", "time": 30.0, "system": "drogue"},
              {"event": "descent_rate", "time": 40.0, "value": 9.144}, {"event": "touchdown", "time": 112.3}]
    assert event_marks(RunSummary.from_dict({"events": events})) == [(2.75, "main deployment"), (8.0, "main_a disreef 2"),
                                               (22.75, "heat_shield separation"), (30.0, "drogue cut-away"),
                                               (112.3, "touchdown")]


def test_a_studys_touchdown_histograms_show_the_total_speed_and_the_descent_rate():
    from pchute_exudyn.study.footprint import touchdown_histogram_panels

    rows = [{"touchdown_time": 70.0 + i, "touchdown_speed": 7.5 + 0.1 * i, "touchdown_descent_rate": 6.0 + 0.1 * i,
             "peak_tension_riser": 1e4 + i} for i in range(10)]
    labels = [label for _, label, _ in touchdown_histogram_panels(rows, ["peak_tension_riser"])]
    assert labels == ["touchdown speed, total over the ground (m/s)",
                      "touchdown descent rate, down the local vertical (m/s)", "riser: peak load (kN)"]
    earlier = [{k: v for k, v in row.items() if k != "touchdown_descent_rate"} for row in rows]   # recorded before
    assert len(touchdown_histogram_panels(earlier, [])) == 1

"""A sensed trigger's samples under adaptive steps: a step that passes a sample time without ending on it (the engine
merged a short step with the next) still takes that sample, at its end (``triggers.watch.Watch.passed``)."""

from pchute_exudyn.triggers.definition import Sensor, Threshold, Trigger
from pchute_exudyn.triggers.watch import Watch


def _watch():
    return Watch("main.deploy", Trigger(Threshold("altitude", True, 300.0), Sensor(rate=100.0)), seed=0)


def test_a_step_that_passes_a_sample_time_has_passed_it():
    watch = _watch()
    watch.index = 10500   # 105.00 s is the next sample not taken
    assert watch.passed(104.995, 105.005)
    assert not watch.passed(104.990, 104.999)      # ends before it
    assert not watch.passed(104.995, 105.0)        # ends on it: on_sample takes it
    assert watch.on_sample(105.0)

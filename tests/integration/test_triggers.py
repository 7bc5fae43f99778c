"""Triggers, sensors and separations (issue 36): closed forms on a body falling or thrown in vacuum over a flat
planet, the sensor noise propagated to the fired altitude, the PA1 sequence by triggers against its fixed times, a
user function against the built-in trigger it equals, and a separation's momentum."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pchute_exudyn import SimulationError, load_case, simulate
from pchute_exudyn.physics.atmosphere import US76
from pchute_exudyn.triggers.definition import Sensor, Threshold, Trigger
from pchute_exudyn.triggers.watch import Watch
from tests.helpers import ROOT

G = 9.80665
VACUUM = """
[case]
name = "vacuum"
vehicle = "vehicle"
[planet]
model = "flat"
gravity = {g}
[atmosphere]
model = "us76"
[bodies.vehicle]
mass = 100.0
inertia = [10.0, 10.0, 10.0]
points.shield = [0.0, 0.5, 0.0]          # beside the CM: the pair's CM is at the altitude of the vehicle's
[bodies.vehicle.initial]
altitude = {altitude}
velocity_down = {down}
[bodies.shield]
mass = 25.0
inertia = [2.0, 1.5, 1.5]
[separations.shield]
trigger = {trigger}
point = "vehicle.shield"
speed = {speed}
direction = [1.0, 0.0, 0.0]
[simulation]
duration = {duration}
output_step = 0.01
method = "full"
steps.full = 0.01
stop_at_ground = false
"""


def _vacuum(tmp_path: Path, trigger: str, altitude=3000.0, down=0.0, duration=12.0, speed=0.0):
    path = tmp_path / "vacuum.toml"
    path.write_text(VACUUM.format(g=G, altitude=altitude, down=down, trigger=trigger, duration=duration, speed=speed))
    return load_case(path)


def _separation(result):
    return result.summary.events_of("separation")[0]


@pytest.mark.parametrize("rate, lag", [(None, 0.0), (None, 0.37), (20.0, 0.25)])
def test_an_altitude_trigger_fires_at_the_analytic_crossing_plus_the_lag(tmp_path, rate, lag):
    sensor = f", rate = {rate}" if rate else ""
    case = _vacuum(tmp_path, f'{{ quantity = "altitude", below = 2700.0, lag = {lag}{sensor} }}')
    event = _separation(simulate(case))
    crossing = math.sqrt(2.0 * 300.0 / G)   # 7.82 s
    if rate is None:   # every step, the crossing interpolated (cubic Hermite: exact under constant gravity)
        assert event.trigger["time"] == pytest.approx(crossing, abs=1e-9)
    else:              # the first sample at or after the crossing
        assert 0.0 <= event.trigger["time"] - crossing <= 1.0 / rate
    assert event.time == pytest.approx(event.trigger["time"] + lag, abs=1e-12)   # the lag exactly
    assert event.trigger["true"] == pytest.approx(2700.0, abs=1e-6 if rate is None else G * crossing / rate)
    assert event.time == pytest.approx(crossing + lag, abs=1e-9 if rate is None else 1.0 / rate)


def test_an_apogee_trigger_fires_at_v0_over_g(tmp_path):
    case = _vacuum(tmp_path, '{ quantity = "apogee" }', down=-30.0, duration=5.0)
    event = _separation(simulate(case))
    assert event.time == pytest.approx(30.0 / G, abs=1e-9)
    assert abs(event.trigger["true"]) < 1e-9


def test_a_separation_conserves_momentum_and_parts_at_its_speed(tmp_path):
    case = _vacuum(tmp_path, '{ time = 1.0 }', speed=2.0, duration=1.5)
    result = simulate(case)
    i = int(np.searchsorted(result["time"], 1.2))
    vehicle = np.array([result[f"vehicle_velocity_{a}"][i] for a in ("east", "north", "down")])
    shield = np.array([result[f"shield_velocity_{a}"][i] for a in ("east", "north", "down")])
    # body +x is east at zero attitude angles? the direction is the vehicle's +x: the relative speed is 2 m/s
    assert np.linalg.norm(shield - vehicle) == pytest.approx(2.0, rel=1e-9)
    pair = (100.0 * vehicle + 25.0 * shield) / 125.0   # the pair's centre of mass falls freely
    assert pair == pytest.approx([0.0, 0.0, G * result["time"][i]], abs=1e-9)
    assert result.summary.separations["shield"].relative_speed == 2.0


def noise_draws(draws: int = 500) -> tuple:
    """(true altitudes at firing over ``draws`` seeds, the propagated sigma_p / (rho g)) of a barometric trigger at
    2000 m on a 10 m/s descent, sigma_p = 50 Pa, 100 Hz, AR(1) noise slow against the crossing (each draw one offset)."""
    atmosphere = US76()
    threshold, sigma_p, rate, speed = 2000.0, 50.0, 100.0, 10.0

    def truth(h):
        rho, sound = atmosphere.state(h)
        return {"altitude": h, "altitude_ground": h, "pressure": rho * sound ** 2 / 1.4, "density": rho,
                "speed_of_sound": sound, "vertical_velocity": -speed, "speed": speed, "airspeed": speed,
                "mach": speed / sound, "dynamic_pressure": 0.5 * rho * speed ** 2, "gravity": G,
                "position": np.zeros(3), "velocity": np.zeros(3)}

    def pressure_at(h):
        rho, sound = atmosphere.state(h)
        return rho * sound ** 2 / 1.4, rho

    sensor = Sensor(rate=rate, pressure_noise=sigma_p, correlation_time=1000.0)
    trigger = Trigger(Threshold("altitude", True, threshold), sensor, "test")
    fired = []
    for seed in range(draws):
        watch = Watch("shield.separation", trigger, seed)
        k = 0
        while True:
            t = k / rate
            firing = watch.observe(t, truth(threshold + 30.0 - speed * t), {}, pressure_at)   # 6 sigma above
            if firing is not None:
                fired.append(firing.record["true"])
                break
            k += 1
    return np.array(fired), sigma_p / (atmosphere.state(threshold)[0] * G)


def test_altitude_noise_propagates_to_the_fired_altitude():
    """500 seeded draws: the true altitude at firing spreads as the propagated sigma_p / (rho g)."""
    fired, propagated = noise_draws(500)
    assert np.std(fired, ddof=1) == pytest.approx(propagated, rel=0.10)
    assert np.mean(fired) == pytest.approx(2000.0, abs=3.0 * propagated / math.sqrt(500) + 0.1)


PA1 = ROOT / "cases" / "cev_pa1.toml"
PA1_TRIGGERS = ROOT / "cases" / "cev_pa1_triggers.toml"


def _events(result) -> dict:
    return {(e.kind, getattr(e, "system", None)): e.time for e in result.summary.events
            if e.kind in ("deploy", "cutaway", "touchdown")}


@pytest.mark.parametrize("method", ["sp", pytest.param("full", marks=pytest.mark.slow)])
def test_pa1_by_triggers_reproduces_its_fixed_sequence(method):
    fixed = _events(simulate(load_case(PA1), method=method))
    triggered = simulate(load_case(PA1_TRIGGERS), method=method)
    assert not triggered.summary.warnings
    events = _events(triggered)
    assert events.keys() == fixed.keys()
    for key, time in fixed.items():
        assert abs(events[key] - time) <= (0.2 if key[0] == "touchdown" else 0.05), key


FIRE_MAIN = '''
def fire_main(time, sensed, state):
    return sensed["altitude_ground"] <= 796.0 and sensed["vertical_velocity"] < 0.0
'''


def test_a_user_function_equal_to_the_builtin_trigger_gives_the_same_run_bitwise(tmp_path):
    (tmp_path / "avionics_36.py").write_text(FIRE_MAIN)
    case = tmp_path / "user.toml"
    case.write_text(f'extends = "{PA1_TRIGGERS.as_posix()}"\nremove = ["systems.main.deploy_trigger"]\n'
                    '[systems.main]\ndeploy_trigger = { function = "avionics_36:fire_main", rate = 20.0 }\n')
    builtin = simulate(load_case(PA1_TRIGGERS), method="sp", duration=15.0)
    user = simulate(load_case(case), method="sp", duration=15.0)
    assert list(user.columns) == list(builtin.columns)
    for name in builtin.columns:
        assert np.array_equal(user[name], builtin[name], equal_nan=True), name
    assert next(e for e in user.summary.events if getattr(e, "system", None) == "main").trigger["quantity"] == \
        "function"


def test_a_trigger_that_never_fires_is_a_warning(tmp_path):
    case = _vacuum(tmp_path, '{ quantity = "altitude", below = 100.0, rate = 10.0 }', duration=1.0)
    result = simulate(case)
    assert result.summary.warnings == ("separations.shield.trigger never fired (altitude below 100) in the 1 s run",)
    assert "shield" not in result.summary.separations


PA1_INFLATION = ROOT / "cases" / "cev_pa1_inflation.toml"
PA1_CLUSTER = ROOT / "cases" / "cev_pa1_cluster.toml"


def _written(tmp_path: Path, base: Path, text: str) -> Path:
    path = tmp_path / f"{base.stem}_triggered.toml"
    path.write_text(f'extends = "{base.as_posix()}"\n{text}')
    return path


def test_disreefs_by_triggers_time_the_stages_as_their_fixed_starts(tmp_path):
    """cev_pa1_inflation.toml's disreefs at 8 and 16 s after line stretch, fired by time-after triggers: the same
    stage starts, fill times and loads (the stage start is t_f - t_deploy, so equal to rounding)."""
    path = _written(tmp_path, PA1_INFLATION, '[systems.main.inflation]\nstage_start = [0.0]\ndisreef_triggers = '
                                             '[{ after = "main.deploy", delay = 8.0 }, { after = "main.disreef2", '
                                             'delay = 8.0 }]\n')
    fixed = simulate(load_case(PA1_INFLATION), method="sp", duration=30.0)
    triggered = simulate(load_case(path), method="sp", duration=30.0)
    stages = [[(e.kind, e.stage, e.time, e.fill_time) for e in r.summary.events
               if e.kind in ("stage_start", "disreef") and e.system == "main"] for r in (fixed, triggered)]
    assert [s[:2] for s in stages[0]] == [s[:2] for s in stages[1]] == [("stage_start", 1), ("disreef", 2),
                                                                          ("disreef", 3)]
    for a, b in zip(*stages):
        assert b[2] == pytest.approx(a[2], abs=1e-9) and b[3] == pytest.approx(a[3], rel=1e-9)
    np.testing.assert_allclose(triggered["tension_main_riser"], fixed["tension_main_riser"], rtol=1e-6, atol=1e-3)
    disreef = next(e for e in triggered.summary.events_of("disreef") if e.stage == 3)
    assert disreef.trigger["event"] == "main.disreef2"


def test_a_canopy_cut_away_by_a_sensed_trigger_leaves_at_the_firing_time(tmp_path):
    """One main of the PA1 cluster cut away when the capsule descends through 1700 m (geoid), sampled at 10 Hz with a
    0.3 s lag: the canopy's cut-away is at the sample's time plus the lag, the sample is the first at or below 1700 m,
    and the other mains fly on."""
    path = _written(tmp_path, PA1_CLUSTER, '[failures.cutaway_trigger]\nmain3 = { quantity = "altitude", '
                                           'below = 1700.0, rate = 10.0, lag = 0.3 }\n')
    result = simulate(load_case(path), method="sp", duration=25.0)
    cut = next(e for e in result.summary.events_of("cutaway") if e.canopy == "main3")
    record = cut.trigger
    assert cut.time == pytest.approx(record["time"] + 0.3, abs=1e-12)
    assert record["true"] <= 1700.0 and record["time"] == pytest.approx(round(record["time"] * 10) / 10, abs=1e-9)
    i = int(np.searchsorted(result["time"], record["time"] - 0.1 - 1e-9))   # the sample before: still above
    assert result["capsule_altitude"][i] > 1700.0
    after = result["time"] > cut.time + 0.5
    assert np.isnan(result["tension_main_riser3"][after]).all() and np.isfinite(result["tension_main_riser1"][after]).all()


def _air(time: float) -> dict:
    """True values of a body slowing through Mach 2 at 1 Mach per second (sound at 250 m/s, density 0.01 kg/m^3)."""
    speed = 250.0 * (3.0 - time)
    return {"altitude": 9000.0, "altitude_ground": 9000.0, "pressure": 500.0, "density": 0.01,
            "speed_of_sound": 250.0, "vertical_velocity": -50.0, "speed": speed, "airspeed": speed,
            "mach": speed / 250.0, "dynamic_pressure": 0.005 * speed ** 2, "gravity": 3.71,
            "position": np.zeros(3), "velocity": np.zeros(3)}


def _fire_time(trigger: Trigger, fired: dict, step: float = 0.01) -> float:
    watch = Watch("main.deploy", trigger, 7)
    for k in range(1, 400):
        if watch.due(k * step, step):
            firing = watch.observe(k * step, _air(k * step), fired, None)
            if firing is not None:
                return firing.time
    return math.inf


def test_all_any_and_speed_sensing():
    from pchute_exudyn.triggers.definition import After, AllOf, AnyOf
    below_two = Threshold("mach", True, 2.0)
    assert _fire_time(Trigger(below_two, Sensor(rate=100.0)), {}) == pytest.approx(1.0, abs=1e-9)
    waits = AllOf((below_two, After("drogue.deploy", 1.0)))
    assert _fire_time(Trigger(waits, Sensor(rate=100.0)), {"drogue.deploy": 0.5}) == pytest.approx(1.5, abs=1e-9)
    either = AnyOf((below_two, Threshold("dynamic_pressure", True, 0.005 * 250.0 ** 2 * 1.5 ** 2)))
    assert _fire_time(Trigger(either, Sensor(rate=100.0)), {}) == pytest.approx(1.0, abs=1e-9)   # q falls later
    # a speed bias of +25 m/s reads 0.1 Mach high: fires 0.1 s late; the lag adds exactly
    biased = Trigger(below_two, Sensor(rate=100.0, lag=0.5, speed_bias=25.0))
    assert _fire_time(biased, {}) == pytest.approx(1.6, abs=1e-9)
    assert _fire_time(Trigger(Threshold("speed", False, 600.0), Sensor()), {}) == pytest.approx(0.01)  # above: first


def test_a_density_scale_multiplies_the_density_alone():
    scaled = load_case(PA1, ["atmosphere.density_scale=1.1"]).atmosphere
    plain = load_case(PA1).atmosphere
    for altitude in (0.0, 1500.0, 11000.0):
        assert scaled.density(altitude) == pytest.approx(1.1 * plain.density(altitude), rel=1e-15)
        assert scaled.speed_of_sound(altitude) == plain.speed_of_sound(altitude)
    assert load_case(PA1, ["atmosphere.density_scale=1.0"]).atmosphere is not None


def test_the_run_line_names_a_trigger_that_never_fired(tmp_path, capsys):
    from pchute_exudyn.cli import main
    case = tmp_path / "late.toml"
    case.write_text(f'extends = "{PA1_TRIGGERS.as_posix()}"\n')
    code = main(["run", str(case), "--method", "sp", "--t-end", "5", "--no-plot", "--quiet", "--out",
                 str(tmp_path / "out"), "--set", "main.deploy_trigger.below=-5"])
    captured = capsys.readouterr()
    assert code == 0
    assert "pchute run: warning: systems.main.deploy_trigger never fired (altitude above the ground below -5)" \
        in captured.err
    assert "systems.drogue.cutaway_trigger never fired (0 s after main.deploy)" in captured.err
    assert "pchute run: warning: systems.main.deploy_trigger cannot fire: the run ends at touchdown" in captured.err
    assert "(3 warning(s): see summary.json)" in captured.out


def test_a_cut_away_trigger_senses_only_once_its_system_is_out(tmp_path):
    """cev_pa1.toml's drogues deploy at a fixed 3.5 s; a cut-away trigger that holds from the start (speed below
    1000 m/s) must wait for the deployment and fire at the first sample after it."""
    path = _written(tmp_path, PA1, 'remove = ["systems.drogue.cutaway_time"]\n[systems.drogue]\n'
                                   'cutaway_trigger = { quantity = "speed", below = 1000.0, rate = 20.0 }\n')
    result = simulate(load_case(path), method="sp", duration=6.0)
    events = {e.kind: e.time for e in result.summary.events if getattr(e, "system", None) == "drogue"}
    assert events["deploy"] == 3.5 and 3.5 < events["cutaway"] <= 3.5 + 0.05


def test_a_trigger_firing_in_the_touchdown_step_is_kept_when_it_comes_first(tmp_path):
    path = _written(tmp_path, PA1_TRIGGERS, '[failures.cutaway_trigger]\nmain_canopy = { quantity = "altitude", '
                                            'below = 0.02, reference = "ground" }\n')
    result = simulate(load_case(path), method="sp")
    events = {e.kind: e for e in result.summary.events if e.kind in ("cutaway", "touchdown")
              and (getattr(e, "canopy", None) or "main_canopy") == "main_canopy"}
    assert not result.summary.warnings
    assert events["cutaway"].time < events["touchdown"].time
    assert events["cutaway"].trigger["true"] == pytest.approx(0.02, abs=1e-6)


def test_a_separation_at_the_start_leaves_from_the_vehicles_own_state(tmp_path):
    case = _vacuum(tmp_path, '{ time = 0.0 }', duration=0.5, speed=1.0)
    result = simulate(case)
    assert (result["vehicle_altitude"][0], result["vehicle_east"][0], result["vehicle_north"][0]) == \
        pytest.approx((3000.0, 0.0, 0.0), abs=1e-9)
    offset = [result[f"shield_{a}"][0] - result[f"vehicle_{a}"][0] for a in ("east", "north", "altitude")]
    assert np.linalg.norm(offset) == pytest.approx(0.5, abs=1e-9)


def test_the_disreef_of_a_system_present_from_the_start_has_its_time_known():
    """``after = "main.disreef2"`` can wait on a fixed disreef of a system there from the start: its time counts
    from t = 0 (case.events.known_times, the one home of the fixed event times)."""
    from dataclasses import replace

    from pchute_exudyn.case.events import known_times
    case = load_case(PA1_INFLATION)
    present = {name: replace(system, deploy_time=None) if name == "main" else system
               for name, system in case.systems.items()}
    times = known_times(present, case.failures, case.separations)
    assert times["main.disreef2"] == 8.0 and times["main.disreef3"] == 16.0
    assert known_times(case.systems, case.failures, case.separations)["main.disreef2"] == 9.5 + 8.0


@pytest.mark.parametrize("down", [0.0, 4.0])
def test_an_apogee_trigger_fires_at_the_first_sample_from_a_start_at_or_past_apogee(tmp_path, down):
    """The state another tool hands over (vertical speed 0) or a start already descending: the first sample (taken
    at the end of the first step, 0.01 s here) fires, the event comes the lag later."""
    case = _vacuum(tmp_path, '{ quantity = "apogee", rate = 20.0, lag = 0.5 }', down=down, duration=1.0)
    assert not case.warnings
    event = _separation(simulate(case))
    assert event.trigger["time"] == pytest.approx(0.01, abs=1e-12)
    assert event.time == pytest.approx(0.01 + 0.5, abs=1e-12)


ROCKET = ROOT / "cases" / "rocket" / "dual_deploy.toml"


def test_a_trigger_that_cannot_fire_from_the_start_state_is_a_warning_when_the_case_loads():
    above = load_case(ROCKET, overrides={"systems.drogue.deploy_trigger": {"quantity": "altitude", "above": 5000.0}})
    assert above.warnings == ("systems.drogue.deploy_trigger cannot fire from the start state: the vehicle starts "
                              "at 3900 m, below 5000 m, and does not climb (vertical speed 0 m/s)",)
    below = load_case(ROCKET, overrides={"systems.main.deploy_trigger.below": -5.0})   # under the ground
    assert below.warnings == ("systems.main.deploy_trigger cannot fire: the run ends at touchdown on the ground at "
                              "1400 m before the altitude falls to 1395 m",)
    shipped = [path for path in sorted((ROOT / "cases").rglob("*.toml")) if path.name != "base.toml"]
    assert not [(path.name, w) for path in shipped for w in load_case(path).warnings if "cannot fire" in w]


def test_a_run_that_dies_names_the_trigger_that_never_fired():
    """The drogue's trigger waits for an altitude the rocket never climbs to: the main opens in free fall and a line
    over-stretches; the message says the drogue never deployed."""
    case = load_case(ROCKET, overrides={"systems.drogue.deploy_trigger": {"quantity": "altitude", "above": 5000.0,
                                                                          "rate": 100.0}})
    with pytest.raises(SimulationError) as failure:
        simulate(case)
    assert str(failure.value).endswith("; by then this trigger had not fired: systems.drogue.deploy_trigger "
                                       "(altitude above 5000)")

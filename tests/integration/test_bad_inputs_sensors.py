"""Bad sensor, trigger and relaxation settings (issue 49, items 2 and 3): one line naming the key or the option, a
non-zero exit, no traceback, nothing touched outside the output; a run that fails because of a sensor setting names
the trigger and the setting."""

from pathlib import Path

import pytest

from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT

TRIGGERS = (ROOT / "cases" / "cev_pa1_triggers.toml").as_posix()
INFLATION = (ROOT / "cases" / "cev_pa1_inflation.toml").as_posix()
MER1 = (ROOT / "cases" / "mer" / "case1.toml").as_posix()
MER3 = (ROOT / "cases" / "mer" / "case3.toml").as_posix()
KEY = "systems.main.deploy_trigger"


def _run(tmp: Path, text: str | None = None, *extra) -> list:
    case = TRIGGERS
    if text is not None:
        case = tmp / "case.toml"
        case.write_text(text)
    return ["run", str(case), "--method", "sp", "--out", str(tmp / "out"), "--quiet", *extra]


def _main(trigger: str) -> str:
    """cev_pa1_triggers.toml with the main's deployment fired by ``trigger``."""
    return f'extends = "{TRIGGERS}"\nremove = ["systems.main.deploy_trigger"]\n[systems.main]\ndeploy_trigger = ' \
           f'{trigger}\n'


DISREEFS = f'extends = "{INFLATION}"\n[systems.main.inflation]\nstage_start = [0.0]\ndisreef_triggers = ' \
           '[{ after = "main.disreef3", delay = 1.0 }, { after = "main.deploy", delay = 8.0 }]\n'
EARLY_DISREEF = DISREEFS.replace('{ after = "main.disreef3", delay = 1.0 }, { after = "main.deploy", delay = 8.0 }',
                                  '{ after = "main.deploy", delay = 10.0 }, { after = "main.deploy", delay = 5.0 }')
SEPARATION = f'extends = "{MER1}"\n[bodies.ballast]\nmass = 10.0\ninertia = [1.0, 1.0, 1.0]\n' \
             '[separations.ballast]\ntrigger = { time = 2.0 }\npoint = "vehicle.bridle1"\nspeed = 1.0\n' \
             'direction = [1e308, 1e308, 0.0]\n'
DAMPING_10 = [a for line, c in (("bridle1", 47), ("bridle2", 47), ("bridle3", 47), ("riser", 60))
              for a in ("--set", f"main.lines.{line}.damping={c}")]

BATTERY = [
    ("sampling rate of 1e8 Hz with pressure noise",
     lambda t: _run(t, _main('{ quantity = "altitude", below = 796.0, reference = "ground", rate = 1e8, '
                             'pressure_noise = 20.0 }')),
     f"{KEY}.rate = 1e+08 Hz: 200 s at that rate is 2e+10 samples; a trigger takes at most 1e+07 in a run"),
    ("disreef triggers out of order", lambda t: _run(t, DISREEFS),
     "systems.main.inflation.disreef_triggers.0 = 'main.disreef3': waits on main.disreef3, a later stage of its "
     "inflation"),
    ("a deployment after its own cut-away", lambda t: _run(t, f'extends = "{TRIGGERS}"\nremove = '
                                                             '["systems.main.deploy_trigger"]\n[systems.main]\n'
                                                             'deploy_trigger = { after = "main.cutaway" }\n'
                                                             'cutaway_trigger = { quantity = "speed", below = 5.0, '
                                                             'rate = 20.0 }\n'),
     "systems.main.deploy_trigger = 'main.deploy': waits on itself through main.deploy -> main.cutaway -> "
     "main.deploy"),
    ("timed disreef before the stage before it", lambda t: _run(t, EARLY_DISREEF, "--t-end", "30"),
     "systems.main.inflation.disreef_triggers.1: places main.disreef3 at 14.5 s, not after main.disreef2 at 19.5 s: "
     "the stages of an inflation start in order"),
    ("altitude below 1e300 m", lambda t: _run(t, _main('{ quantity = "altitude", below = 1e300, rate = 20.0 }')),
     f"{KEY}.below = 1e+300: must be within -50000..1e+07 (m)"),
    ("Mach below 1e6", lambda t: _run(t, _main('{ quantity = "mach", below = 1e6, rate = 20.0 }')),
     f"{KEY}.below = 1000000.0: must be within 0..1000 (-)"),
    ("speed bias of -100 m/s", lambda t: _run(t, _main('{ quantity = "speed", below = 20.0, rate = 20.0, '
                                                       'speed_bias = -100.0 }')),
     f"{KEY}: speed_bias = -100 m/s makes the sensed speed negative"),
    ("separation direction of [1e308, 1e308, 0]", lambda t: _run(t, SEPARATION),
     "separations.ballast.direction = [1e+308, 1e+308, 0.0]: must be a non-zero vector of finite length"),
    ("relaxation time of 1 s", lambda t: ["run", MER1, "--method", "sp", "--sp-relaxation-time", "1", "--out",
                                          str(t / "out"), "--quiet"],
     "sp relaxation time (--sp-relaxation-time) = 1 s: its damping tau K moves the main system's bodies"),
    ("MER case 3 with its line damping at 10 %", lambda t: ["run", MER3, "--method", "sp", *DAMPING_10, "--out",
                                                             str(t / "out"), "--quiet"],
     "use --sp-preset any_damping"),
]


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_bad_sensor_input_gives_one_line_and_a_nonzero_exit(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)


def test_noise_that_leaves_the_atmosphere_names_the_trigger_and_the_noise(tmp_path):
    """pressure_noise = 1e5 Pa (documented as possible, warned as implausible): the warning, then the run stops on
    one line naming the trigger and the sensor's pressure settings (was: "altitude -14215.3 m is outside the US76
    atmosphere", naming neither)."""
    code, err, seconds, touched = run_bad_input(lambda t: _run(t, _main(
        '{ quantity = "altitude", below = 796.0, reference = "ground", rate = 20.0, pressure_noise = 1e5 }')),
        tmp_path)
    warning, error = err.strip().splitlines()
    assert warning == f"pchute run: warning: {KEY}.pressure_noise = 100000.0 is implausible: outside 0..10000 (Pa)"
    assert_one_line(code, error, f"{KEY}: the sensed pressure", touched, seconds)
    assert "pressure_noise = 100000 Pa, pressure_bias = 0 Pa) has no barometric altitude: altitude" in error


def test_a_short_limit_the_any_damping_preset_lifts_names_it(tmp_path, monkeypatch):
    """Where no layout rule explains a short SP limit, the preset that lifts it to its design step is still named
    (MER case 3 at 10 % line damping with only that rule: 0.0139 s relaxed against 0.00279 s)."""
    from pchute_exudyn.methods.sp import SingularPerturbation

    monkeypatch.setattr("pchute_exudyn.run.step_control._LIMITS", {})   # limits are kept by geometry, with their cause
    monkeypatch.setattr(SingularPerturbation, "_cause", lambda self, system, step, attach, confluence, lines:
                        self._relaxed_remedy(system, step, attach, confluence))
    code, err, seconds, touched = run_bad_input(lambda t: ["run", MER3, "--method", "sp", *DAMPING_10, "--out",
                                                           str(t / "out"), "--quiet"], tmp_path)
    assert_one_line(code, err, "use --sp-preset any_damping (a relaxation time; its limit here: 0.0139 s)", touched,
                    seconds)

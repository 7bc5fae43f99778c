"""Bad trigger and separation input (issue 36): one line naming the key, a non-zero exit, no traceback, nothing
touched outside the output; a user trigger function that raises stops the run with its message and the time."""

from pathlib import Path

import pytest

from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT

TRIGGERS = (ROOT / "cases" / "cev_pa1_triggers.toml").as_posix()
PA1 = (ROOT / "cases" / "cev_pa1.toml").as_posix()
SEPARATION = '[separations.{body}]\ntrigger = {{ time = 2.0 }}\npoint = "capsule.bridle1"\nspeed = 1.0\n' \
             'direction = [1.0, 0.0, 0.0]\n'


MER1 = (ROOT / "cases" / "mer" / "case1.toml").as_posix()
BALLAST = "[bodies.ballast]\nmass = 10.0\ninertia = [1.0, 1.0, 1.0]\n[bodies.ballast.initial]\naltitude = 8000.0\n"


def _run(tmp: Path, text: str | None = None, *sets) -> list:
    case = TRIGGERS
    if text is not None:
        case = tmp / "case.toml"
        case.write_text(text)
    return ["run", str(case), "--method", "sp", "--out", str(tmp / "out"), "--quiet",
            *[a for s in sets for a in ("--set", s)]]


def _extends(base: str, body: str) -> str:
    return f'extends = "{base}"\n{body}'


CYCLE = _extends(TRIGGERS, 'remove = ["systems.drogue.deploy_trigger", "systems.main.deploy_trigger"]\n'
                           '[systems.drogue]\ndeploy_trigger = { after = "main.deploy", delay = 1.0 }\n'
                           '[systems.main]\ndeploy_trigger = { after = "drogue.deploy", delay = 1.0 }\n')
RAISES = "def fire(time, sensed, state):\n    if time > 2.0:\n        raise ValueError('flight computer fault')\n" \
         "    return False\n"


def _main(trigger: str) -> str:
    """cev_pa1_triggers.toml with the main's deployment fired by ``trigger``."""
    return _extends(TRIGGERS, f'remove = ["systems.main.deploy_trigger"]\n[systems.main]\ndeploy_trigger = {trigger}\n')


def _raising(tmp: Path) -> list:
    (tmp / "raises_36.py").write_text(RAISES)
    return _run(tmp, _main('{ function = "raises_36:fire", rate = 10.0 }'))


BATTERY = [
    ("unknown quantity", lambda t: _run(t, None, "main.deploy_trigger.quantity=velocity"),
     "systems.main.deploy_trigger.quantity = 'velocity': must be one of: altitude, speed, airspeed, mach, "
     "dynamic_pressure, apogee"),
    ("after an event that does not exist", lambda t: _run(t, None, "drogue.cutaway_trigger.after=mains.deploy"),
     "systems.drogue.cutaway_trigger = 'mains.deploy': names an event the case does not have"),
    ("after in a cycle", lambda t: _run(t, CYCLE),
     "waits on itself through drogue.deploy -> main.deploy -> drogue.deploy"),
    ("rate of zero", lambda t: _run(t, None, "main.deploy_trigger.rate=0"),
     "systems.main.deploy_trigger.rate = 0: must be > 0 (Hz)"),
    ("negative lag", lambda t: _run(t, None, "main.deploy_trigger.lag=-0.1"),
     "systems.main.deploy_trigger.lag = -0.1: must be >= 0 (s)"),
    ("noise without a rate", lambda t: _run(t, _main('{ quantity = "altitude", below = 796.0, pressure_noise = 20.0 }')),
     "systems.main.deploy_trigger.rate: required (Hz) with pressure_noise or speed_noise"),
    ("separation of the vehicle", lambda t: _run(t, _extends(PA1, SEPARATION.format(body="capsule"))),
     "separations.capsule = 'capsule': must name a body of the case other than the vehicle"),
    ("separation of a canopy", lambda t: _run(t, _extends(MER1, SEPARATION.format(body="parachute")
                                                          .replace("capsule.bridle1", "vehicle.bridle1"))),
     "separations.parachute = 'parachute': body 'parachute' hangs on a system's lines (a canopy)"),
    ("separation of a body that flies on its own", lambda t: _run(t, _extends(MER1, BALLAST + SEPARATION.format(
        body="ballast").replace("capsule.bridle1", "vehicle.bridle1"))),
     "body 'ballast' is carried by the vehicle until it separates: remove its [bodies.<name>.initial] table"),
    ("separation after the end of the run", lambda t: _run(t, _extends(MER1, BALLAST.replace(
        "[bodies.ballast.initial]\naltitude = 8000.0\n", "") + SEPARATION.format(body="ballast").replace(
        "capsule.bridle1", "vehicle.bridle1").replace("time = 2.0", "time = 500.0"))),
     "separations.ballast.trigger = 500.0: time must be before the end of the run (simulation.duration = 60 s)"),
    ("user function that cannot be imported", lambda t: _run(t, _main('{ function = "nosuch_36:fire" }')),
     "systems.main.deploy_trigger.function = 'nosuch_36:fire': cannot import module 'nosuch_36': "
     "ModuleNotFoundError"),
    ("fixed cut-away before a triggered deployment", lambda t: _run(t, _extends(TRIGGERS, "[failures]\n"
                                                                                        "cutaway.main_canopy = 5.0\n")),
     "failures.cutaway.main_canopy = 5 s comes before the deployment its trigger fired at 9.5 s"),
    ("time trigger after the end of the run", lambda t: _run(t, _extends(
        TRIGGERS, 'remove = ["systems.drogue.deploy_trigger"]\n[systems.drogue]\ndeploy_trigger = { time = 500.0 }\n')),
     "systems.drogue.deploy_trigger.time = 500.0: must be before the end of the run (simulation.duration = 200 s)"),
    ("density scale of zero", lambda t: _run(t, None, "atmosphere.density_scale=0"),
     "atmosphere.density_scale = 0: must be > 0"),
    ("user function that raises", _raising,
     "systems.main.deploy_trigger: the function raises_36:fire raised ValueError: flight computer fault at "
     "t = 2.0000 s"),
]


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_bad_trigger_input_gives_one_line_and_a_nonzero_exit(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)

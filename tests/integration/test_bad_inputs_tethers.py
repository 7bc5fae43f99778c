"""Bad tether and ejection input (issue 55): one line naming the key, the value and what is allowed, a non-zero
exit, no traceback, nothing written; a load above a rated breaking strength and a payout resistance that stops the
ejection are warned in one line each."""

import json
import subprocess
import sys

import pytest

from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT

ROCKET = (ROOT / "cases" / "rocket" / "two_section.toml").as_posix()
AIRDROP = (ROOT / "cases" / "airdrop" / "static_line.toml").as_posix()
SKYDIVER = (ROOT / "cases" / "skydiver" / "pilot_chute.toml").as_posix()


def _run(tmp, *sets, duration="3", case=ROCKET):
    return ["run", str(case), "--out", str(tmp / "out"), "--quiet", "--t-end", duration,
            *[a for s in sets for a in ("--set", s)]]


def _cut(tmp, case: str, table: str, next_table: str) -> str:
    """``case`` (a path under cases/) written to ``tmp`` with its ``table`` cut out up to ``next_table``: the
    airdrop without its ``[start.release]``, the skydiver without the pilot chute's throw."""
    text = (ROOT / "cases" / case).read_text()
    start = text.index(f"\n{table}")
    path = tmp / "cut.toml"
    path.write_text(text[:start] + text[text.index(f"\n{next_table}", start):])
    return path.as_posix()


BATTERY = [
    ("a cord shorter than the sections are apart", lambda t: _run(t, "tethers.shock_cord.free_length=0.05"),
     "tethers.shock_cord.free_length = 0.05: is shorter than its ends are apart (0.1 m) while 'nose' rides in "
     "'booster': it would start stretched"),
    ("an ejection into the vehicle", lambda t: _run(t, "separations.nose.direction=[-1.0, 0.0, 0.0]"),
     "separations.nose.direction = [-1.0, 0.0, 0.0]: points into the vehicle"),
    ("both ends on one body", lambda t: _run(t, "tethers.shock_cord.ends=['booster.harness', 'booster.nose_seat']"),
     "tethers.shock_cord.ends = ['booster.harness', 'booster.nose_seat']: must be points of two different bodies"),
    ("an unknown point", lambda t: _run(t, "tethers.shock_cord.ends=['booster.harness', 'nose.tip']"),
     "tethers.shock_cord.ends = 'nose.tip': body 'nose' has no point 'tip'"),
    ("an unknown material", lambda t: _run(t, "tethers.shock_cord.material='silk'"),
     "tethers.shock_cord.material = 'silk': unknown line material"),
    ("a negative payout resistance", lambda t: _run(t, "tethers.shock_cord.payout_resistance=-1"),
     "tethers.shock_cord.payout_resistance = -1"),
    ("a static line and a deploy time", lambda t: _run(t, "systems.main.deploy_time=1.0", case=AIRDROP),
     "systems.main.static_line: a system deployed by a static line deploys at its line stretch: give static_line or "
     "deploy_time/deploy_trigger, not both"),
    ("a static line of no length", lambda t: _run(t, "systems.main.static_line.length=0", case=AIRDROP),
     "systems.main.static_line.length = 0: must be > 0 (m)"),
    ("a static line without a release", lambda t: _run(t, case=_cut(t, "airdrop/static_line.toml", "[start.release]",
                                                                            "[atmosphere]")),
     "systems.main.static_line: needs start.release: the aircraft the static line is anchored in"),
    ("a static line and a pilot chute", lambda t: _run(t, "systems.main.pilot_chute.length=2.5", case=AIRDROP),
     "systems.main.pilot_chute: the bag is held by a static line or a pilot chute: give static_line or pilot_chute, "
     "not both"),
    ("a pilot chute and a deploy time", lambda t: _run(t, "systems.main.deploy_time=1.0", case=SKYDIVER),
     "systems.main.pilot_chute: a system deployed by a pilot chute deploys at its line stretch: give pilot_chute or "
     "deploy_time/deploy_trigger, not both"),
    ("a pilot chute and a deploy trigger", lambda t: _run(t, "systems.main.deploy_trigger={time=1.0}", case=SKYDIVER),
     "systems.main.pilot_chute: a system deployed by a pilot chute deploys at its line stretch"),
    ("a pilot chute of an unknown body", lambda t: _run(t, "systems.main.pilot_chute.body='drogue'", case=SKYDIVER),
     "systems.main.pilot_chute.body = 'drogue': unknown body; bodies are: vehicle, pilot_chute, canopy"),
    ("a pilot chute that is the canopy", lambda t: _run(t, "systems.main.pilot_chute.body='canopy'", case=SKYDIVER),
     "systems.main.pilot_chute.body = 'canopy': is the system's own canopy"),
    ("a pilot chute that is the vehicle", lambda t: _run(t, "systems.main.pilot_chute.body='vehicle'", case=SKYDIVER),
     "systems.main.pilot_chute.body = 'vehicle': is the vehicle"),
    ("a pilot chute without aerodynamics", lambda t: _run(t, "bodies.pilot_chute.aerodynamics.enabled=false",
                                                          case=SKYDIVER),
     "systems.main.pilot_chute.body = 'pilot_chute': has no aerodynamics (enabled)"),
    ("a reduced canopy on a pilot chute", lambda t: _run(t, "systems.main.canopy_model='reduced'", case=SKYDIVER),
     "systems.main.canopy_model = 'reduced': reduced has no canopy mass for the pilot chute's snatch to act on"),
    ("a pilot chute's bridle of no length", lambda t: _run(t, "systems.main.pilot_chute.length=0", case=SKYDIVER),
     "systems.main.pilot_chute.length = 0: must be > 0 (m)"),
    ("a pilot chute never thrown", lambda t: _run(t, case=_cut(t, "skydiver/pilot_chute.toml",
                                                                     "[separations.pilot_chute]", "[bodies.canopy]")),
     "bodies.pilot_chute.initial: required (only a canopy deployed at line stretch has none)"),
    ("pchute new: a static line without a release", lambda t: ["new", str(t / "new.toml"),
                                                              "--static-line-length", "4"],
     "static_line_length = 4.0: only with release_airspeed (--release-airspeed)"),
    ("pchute new: a static line's length and time", lambda t: ["new", str(t / "new.toml"), "--release-airspeed", "60",
                                                              "--static-line-length", "4", "--static-line-time", "2"],
     "static_line_time = 2.0: not with static_line_length (--static-line-length)"),
]


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_bad_tether_input_gives_one_line_and_a_nonzero_exit(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)


def _warnings(tmp_path, *sets, case=ROCKET) -> list:
    done = subprocess.run([sys.executable, "-m", "pchute_exudyn", *_run(tmp_path, *sets, case=case)], capture_output=True,
                          text=True, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    return json.loads((tmp_path / "out" / "summary.json").read_text())["warnings"]


def test_a_breaking_strength_below_the_snatch_is_warned(tmp_path):
    case = tmp_path / "rated.toml"   # a cord of given stiffness rated at 300 N: its snatch is about 400 N
    case.write_text(f'extends = "{ROCKET}"\nremove = ["tethers.shock_cord.material"]\n[tethers.shock_cord]\n'
                    'stiffness = 5000.0\nbreaking_strength = 300.0\n')
    warnings = _warnings(tmp_path, case=case)
    assert any(w.startswith("tethers.shock_cord: peak load") and "exceeds its breaking strength 300 N" in w
               for w in warnings), warnings


def test_a_payout_resistance_that_stops_the_ejection_is_warned(tmp_path):
    warnings = _warnings(tmp_path, "tethers.shock_cord.payout_resistance=200")
    assert any(w.startswith("tethers.shock_cord: its payout resistance 200 N stops the 5 m/s separation of 'nose'")
               for w in warnings), warnings

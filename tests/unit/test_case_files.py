"""Case files: the MER cases load as the thesis tables say, inheritance and overrides work, bad input is refused."""

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.errors import CaseError
from pchute_exudyn.physics.rotations import attitude_matrix
from tests.helpers import MER


@pytest.mark.parametrize("number", range(1, 7))
def test_every_mer_case_loads(number):
    case = pc.load_case(MER / f"case{number}.toml")
    assert case.name == f"MER case {number}"
    vehicle, parachute = case.bodies["vehicle"], case.bodies["parachute"]
    assert (vehicle.mass, parachute.mass, case.systems["main"].confluence.mass) == (761.0, 16.0, 0.1539)
    np.testing.assert_allclose(np.diag(vehicle.inertia), [238.02, 179.13, 212.51])
    lines = {line.name: line for line in case.systems["main"].lines}
    assert (lines["riser"].free_length, lines["riser"].stiffness, lines["riser"].damping) == (1.832, 6e4, 600.0)
    assert (lines["bridle2"].free_length, lines["bridle2"].stiffness, lines["bridle2"].damping) == (0.7152, 47e3, 470.0)
    assert case.planet.equatorial_radius == 3393940.0 and case.planet.rotation_rate == 0.0
    assert case.simulation.duration == 60.0


@pytest.mark.parametrize("number", range(1, 7))
def test_lines_start_at_free_length_except_case2_riser(number):
    """Table 3.4-3.8 positions with mer.md's points put every line at free length (case 2: riser 1 cm slack)."""
    case = pc.load_case(MER / f"case{number}.toml")
    frame = case.start

    def point(body_name, point_name):
        body = case.bodies[body_name]
        i = body.initial
        attitude = attitude_matrix(i.yaw_deg, i.pitch_deg, i.roll_deg)
        return frame.local_position(i.altitude, i.east, i.north) + attitude @ np.array(body.points[point_name])

    ci = case.systems["main"].confluence.initial
    confluence = frame.local_position(ci.altitude, ci.east, ci.north)
    for line in case.systems["main"].lines:
        length = np.linalg.norm(point(line.body, line.point) - confluence)
        expected = line.free_length - (0.01 if (number == 2 and line.name == "riser") else 0.0)
        assert length == pytest.approx(expected, abs=2e-6), line.name


def test_cases_share_one_base():
    texts = [(MER / f"case{n}.toml").read_text() for n in range(1, 7)]
    assert all('extends = "base.toml"' in t for t in texts)
    assert all("stiffness" not in t for t in texts)   # line data lives only in base.toml


def test_override_forms(mer_case1):
    case = pc.load_case(MER / "case1.toml", ["vehicle.mass=800", "main.lines.*.damping=0",
                                             "bodies.vehicle.inertia[0]=250", "simulation.duration=5"])
    assert case.bodies["vehicle"].mass == 800.0
    assert all(line.damping == 0.0 for line in case.systems["main"].lines)
    assert case.bodies["vehicle"].inertia[0, 0] == 250.0
    assert case.simulation.duration == 5.0
    assert mer_case1.bodies["vehicle"].mass == 761.0   # the file itself is untouched
    case = pc.load_case(MER / "case1.toml", {"parachute.aerodynamics.enabled": False})
    assert case.bodies["parachute"].aerodynamics.enabled is False


def _write(tmp_path, text, name="case.toml"):
    path = tmp_path / name
    path.write_text(f'extends = "{(MER / "base.toml").as_posix()}"\n' + text)
    return path


@pytest.mark.parametrize("text, field, message", [
    ("[bodies.vehicle]\nmass = 0.0\n", "bodies.vehicle.mass", "must be > 0"),
    ("[bodies.vehicle]\nmass = -761.0\n", "bodies.vehicle.mass", "must be > 0"),
    ("[bodies.vehicle]\nmass = \"heavy\"\n", "bodies.vehicle.mass", "must be a number"),
    ("[bodies.vehicle]\ninertia = [100.0, -1.0, 100.0]\n", "bodies.vehicle.inertia", "positive definite"),
    ("[bodies.vehicle]\ninertia = [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n", "bodies.vehicle.inertia",
     "positive definite"),
    ("[bodies.vehicle]\ninertia = [[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n", "bodies.vehicle.inertia",
     "symmetric"),
    ("[systems.main.lines.riser]\nstiffness = -6e4\n", "systems.main.lines.riser.stiffness", "must be >= 0"),
    ("[systems.main.lines.riser]\ndamping = -1.0\n", "systems.main.lines.riser.damping", "must be >= 0"),
    ("[systems.main.lines.riser]\nfree_length = 0.0\n", "systems.main.lines.riser.free_length", "must be > 0"),
    ("[systems.main.lines.riser]\nfree_length = -1.0\n", "systems.main.lines.riser.free_length", "must be > 0"),
    ("[systems.main.lines.riser]\nattach = \"canopy.riser\"\n", "systems.main.lines.riser.attach",
     "unknown body 'canopy'"),
    ("[systems.main.lines.riser]\nattach = \"parachute.apex\"\n", "systems.main.lines.riser.attach",
     "has no point 'apex'"),
    ("[bodies.vehicle]\nmas = 700.0\n", "bodies.vehicle.mas", "unknown key"),
    ("[simulation]\nduration = 0.0\n", "simulation.duration", "must be > 0"),
    ("[simulation.steps]\nfull = 100.0\n", "simulation.steps.full", "must be <= 60"),
    ("[simulation.steps]\nfull = 0.0\n", "simulation.steps.full", "must be > 0"),
    ("[simulation]\nmethod = \"magic\"\n", "simulation.method", "must be one of"),
    ("[simulation.sp]\norder = 2\n", "simulation.sp.order", "must be 0"),
    ("[simulation.sp]\norder = \"first\"\n", "simulation.sp.order", "or 1 (the confluence mass"),
    ("[atmosphere]\nmodel = \"venus\"\n", "atmosphere.model", "must be one of"),
    ("[planet]\npolar_radius = 4e6\n", "planet.polar_radius", "must be <= equatorial_radius"),
    ("[bodies.parachute.aerodynamics.normal_coefficient]\nalpha_deg = [0.0, 45.0]\nvalue = [0.0, 0.1]\n",
     "normal_coefficient.alpha_deg", "from 0 to 90"),
    ("[systems.main.lines.riser]\nattach = \"vehicle.bridle1\"\n", "systems.main.lines",
     "every line attaches to body 'vehicle': the system would join that body to itself"),
    ("[bodies.bag]\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n[bodies.bag.points]\np = [0.0, 0.0, 0.0]\n"
     "[bodies.bag.initial]\naltitude = 8390.0\n[systems.main]\ncanopy = \"parachute\"\n"
     + "".join(f"[systems.main.lines.bridle{i}]\nattach = \"bag.p\"\n" for i in (1, 2, 3)),
     "systems.main.canopy", "canopy 'parachute' is not connected to the vehicle 'vehicle'"),
])
def test_bad_fields_name_file_field_value_and_rule(tmp_path, text, field, message):
    path = _write(tmp_path, text)
    with pytest.raises(CaseError) as info:
        pc.load_case(path)
    text_of_error = str(info.value)
    assert str(path.name) in text_of_error          # the file the bad value came from
    assert field in text_of_error
    assert message in text_of_error


def test_error_names_the_base_file_when_the_bad_value_lives_there(tmp_path):
    base = tmp_path / "base.toml"
    base.write_text((MER / "base.toml").read_text().replace("mass = 16.0", "mass = -16.0"))
    child = tmp_path / "child.toml"
    child.write_text('extends = "base.toml"\n')
    with pytest.raises(CaseError, match=r"base\.toml: bodies\.parachute\.mass = -16\.0: must be > 0"):
        pc.load_case(child)


def test_file_level_errors(tmp_path):
    with pytest.raises(CaseError, match="case file not found"):
        pc.load_case(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[bodies.vehicle\nmass = 1\n")
    with pytest.raises(CaseError, match="malformed TOML"):
        pc.load_case(bad)
    loop = tmp_path / "loop.toml"
    loop.write_text('extends = "loop.toml"\n')
    with pytest.raises(CaseError, match="circular"):
        pc.load_case(loop)
    orphan = tmp_path / "orphan.toml"
    orphan.write_text('extends = "nowhere.toml"\n')
    with pytest.raises(CaseError, match="base case file not found"):
        pc.load_case(orphan)


@pytest.mark.parametrize("override, message", [
    ("vehicle.masss=800", "unknown key"),
    ("nothing.here=1", "unknown key"),
    ("vehicle.mass=abc", "must be a number"),
    ("vehicle.mass=true", "must be a number"),
    ("vehicle.inertia[7]=1", "index out of range"),
    ("vehicle.mass", "key=value"),
    ("vehicle.mass.kg=3", "is not a table"),
])
def test_bad_overrides(override, message):
    with pytest.raises(CaseError, match=message) as info:
        pc.load_case(MER / "case1.toml", [override])
    assert "--set" in str(info.value)

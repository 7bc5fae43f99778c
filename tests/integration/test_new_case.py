"""`pchute new` / `new_case`, steps from the stability limit, `remove` in an extends chain, other tools' CSV dialects
and the descent cross-check of `pchute compare`."""

import math
import re

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.authoring.choices import NewCase
from pchute_exudyn.authoring.layout import layout
from pchute_exudyn.authoring.rules import LINE_STRAIN
from pchute_exudyn.case.canopy_choice import LIGHT_CANOPY_TIME
from pchute_exudyn.cli import main
from pchute_exudyn.engine.state import initial_body_state, initial_confluence_state, initial_point
from pchute_exudyn.physics.atmosphere import US76
from pchute_exudyn.registries.methods import METHODS
from pchute_exudyn.results.compare import compare_results, descent_metrics
from pchute_exudyn.results.csv_dialects import parse_column_map, read_csv_columns
from pchute_exudyn.results.summary import RunSummary
from pchute_exudyn.run.step_control import stability_step
from tests.helpers import ROOT

ROCKETPY = ROOT / "validation" / "rocketpy" / "descent.csv"
PAYLOAD = ["--planet", "earth", "--mass", "100", "--drag-area", "40", "--altitude", "3000"]   # all non-default


@pytest.fixture(scope="module")
def payload(tmp_path_factory):
    """The issue's new case, written by the command line, and its SP run to touchdown."""
    folder = tmp_path_factory.mktemp("payload")
    assert main(["new", str(folder / "payload.toml"), *PAYLOAD]) == 0
    assert main(["run", str(folder / "payload.toml"), "--no-plot", "--quiet", "--out", str(folder / "sp")]) == 0
    return folder / "payload.toml", pc.Result.load(folder / "sp")


def test_new_case_descends_at_the_closed_form_rate(payload):
    path, result = payload
    case = pc.load_case(path)
    assert result.summary.end == "touchdown"
    mass = sum(body.mass for body in case.bodies.values()) + case.systems["main"].confluence.mass
    assert mass == pytest.approx(layout(NewCase(planet="earth", mass=100.0, drag_area=40.0)).total_mass, abs=1e-5)
    for altitude in (2500.0, 1500.0, 500.0):
        when = np.interp(-altitude, -result["vehicle_altitude"], result.time)
        rate = np.interp(when, result.time, result["vehicle_velocity_down"])
        canopy = np.interp(when, result.time, result["canopy_altitude"])   # the drag acts in the canopy's air
        gravity = math.hypot(*case.start.gravity_scalar(*case.start.local_position(altitude, 0.0, 0.0)))   # normal
        closed_form = math.sqrt(2.0 * mass * gravity / (US76().density(canopy) * 40.0))
        assert rate == pytest.approx(closed_form, rel=1e-3), altitude
        assert rate == pytest.approx(closed_form, rel=3e-4), altitude   # measured 1.2e-4 to 1.5e-4 (quasi-steady)


@pytest.mark.parametrize("method, integrator", [(m.name, i) for m in METHODS.values() for i in m.integrators])
def test_new_case_runs_with_each_method_as_written(payload, method, integrator, tmp_path, capsys):
    args = ["run", str(payload[0]), "--method", method, "--integrator", integrator, "--t-end", "8", "--no-plot",
            "--quiet", "--out", str(tmp_path / "r")]
    assert main(args) == 0
    printed = capsys.readouterr().out
    case = pc.load_case(payload[0])
    step, limit = stability_step(case, METHODS[method](), integrator)
    if integrator == "rk4":   # the case sets no step: adaptive steps (physics.step_rule)
        assert f"{method}/rk4 adaptive steps " in printed
    else:
        assert f"step {step:g} s (none set: from the stability limit {limit:.3g} s)" in printed
        assert 0.2 * limit <= step <= 0.5 * limit     # half, rounded down to 1, 2 or 5 x 10^k
    sp = payload[1]
    result = pc.Result.load(tmp_path / "r")
    # every method on the same descent: 8 s later the vehicle is where SP has it, within centimetres (full mass
    # 2e-4 m; the equilibrium point, which ignores line damping, 0.055 m)
    assert result.final("vehicle_altitude") == pytest.approx(np.interp(8.0, sp.time, sp["vehicle_altitude"]),
                                                             abs=0.1)


@pytest.mark.parametrize("canopies, step", [(1, 0.01), (1, None), (3, 0.01), (3, None)])
def test_lines_start_at_their_steady_stretch_and_canopies_on_their_risers(canopies, step):
    """The start is the steady descent: every line stretched LINE_STRAIN by its steady load, so the run's tensions
    start at their steady values and stay there (no start-up bounce in the peak tensions), at the thesis's fixed
    step and at the adaptive steps the file's run takes."""
    case = pc.new_case(planet="mars", canopies=canopies, bridles=4)
    system = case.systems["main"]
    confluence = initial_confluence_state(case, system).position
    for name in system.canopies:       # each canopy's +x along its riser, toward the confluence
        state = initial_body_state(case, case.bodies[name])
        toward = (confluence - state.position) / np.linalg.norm(confluence - state.position)
        assert state.attitude[:, 0] @ toward == pytest.approx(1.0, abs=1e-9)
    for line in system.lines:
        length = np.linalg.norm(initial_point(case, line.body, line.point) - confluence)
        assert length == pytest.approx(line.free_length * (1.0 + LINE_STRAIN), abs=1e-5)
    result = pc.simulate(case, "sp", duration=1.0, step=step)   # (on Mars the rate then slows as the air thickens)
    for line in system.lines:
        tension = result[f"tension_{line.name}"]
        steady = line.stiffness * LINE_STRAIN * line.free_length
        assert np.max(np.abs(tension[1:] / steady - 1.0)) < 1e-2


def test_two_bridles_sit_on_opposite_sides_and_one_light_canopy_on_one_bridle_is_reduced():
    """Two bridles: opposite ends of a diameter of the attach circle. One bridle and one canopy: reduced when its
    drag's time constant m / (rho C_D0 S0 V) is below LIGHT_CANOPY_TIME (a light canopy on Earth), rigid when heavy
    (Mars's thin air) and after a release (it opens by an inflation, which a reduced canopy refuses)."""
    points = pc.new_case(planet="earth", mass=100.0, drag_area=10.0, bridles=2, altitude=100.0).bodies["vehicle"].points
    assert np.allclose(np.add(points["bridle1"], points["bridle2"]), [-1.3, 0.0, 0.0])   # both on the top face
    assert np.linalg.norm(points["bridle1"][1:]) == pytest.approx(0.35 * 2.6)
    earth = dict(planet="earth", mass=100.0, drag_area=10.0, bridles=1, altitude=100.0)
    plan = layout(NewCase(**earth))
    assert plan.canopy_drag_time(plan.steady_rate(100.0)) < LIGHT_CANOPY_TIME
    assert pc.new_case(**earth).systems["main"].canopy_model == "reduced"
    text = pc.new_case_text(**earth)
    assert 'canopy_model = "reduced"' in text and "[simulation.steps]\n" not in text
    mars = NewCase(planet="mars", mass=100.0, drag_area=10.0, bridles=1, altitude=100.0)
    assert layout(mars).canopy_drag_time(layout(mars).steady_rate(100.0)) > LIGHT_CANOPY_TIME
    assert "canopy_model" not in pc.new_case_text(mars)
    released = dict(earth, altitude=400.0, release_airspeed=40.0)
    assert "# canopy_model: rigid (the default), though light" in pc.new_case_text(**released)
    assert pc.new_case(**released).systems["main"].canopy_model == "rigid"
    for choices in (dict(earth, bridles=3), dict(earth, canopies=2)):
        assert pc.new_case(**choices).systems["main"].canopy_model == "rigid"


def test_cluster_shares_the_load_evenly(tmp_path):
    case = pc.new_case(planet="earth", mass=300.0, drag_area=30.0, canopies=3, altitude=2000.0)
    result = pc.simulate(case, "sp", duration=15.0)
    risers = np.array([result[f"tension_riser_canopy{i}"][-1] for i in (1, 2, 3)])
    assert risers.min() > 0.0 and risers.max() / risers.min() - 1.0 < 1e-6
    # the three canopies together hold the vehicle: the risers' vertical sum is its weight (steady descent)
    # (2 s before the end: adaptive steps longer than the output step make the time column the step ends)
    two_seconds_before = np.interp(result.time[-1] - 2.0, result.time, result["vehicle_velocity_down"])
    assert result["vehicle_velocity_down"][-1] == pytest.approx(two_seconds_before, rel=2e-3)


def test_bad_choices_are_one_line_errors():
    for choices, message in ((dict(planet="flat", altitude=1e5), "altitude = 100000.0: outside the us76 atmosphere"),
                             (dict(altitude=1e9), "outside the mars_grc atmosphere"),
                             (dict(canopies=8, suspension_line_length=8.0, riser_length=1e-3), "cannot sit side by"),
                             (dict(mass=-1.0), "mass = -1.0: must be a number > 0 (kg)")):
        with pytest.raises(pc.InputError, match=re.escape(message)):
            pc.new_case(**choices)
    with pytest.raises(pc.InputError, match="not both"):
        pc.new_case_text(NewCase(), mass=3.0)


def test_names_and_small_vehicles_survive_the_file():
    case = pc.new_case(name='rocket "B" # 2', planet="earth", mass=0.05, diameter=0.03, drag_area=0.05,
                       altitude=300.0)
    assert case.name == 'rocket "B" # 2'
    assert case.bodies["vehicle"].mass == 0.05
    assert case.bodies["vehicle"].inertia[0, 0] == pytest.approx(0.05 * 0.015**2 / 2.0, rel=1e-9)


def test_python_api_builds_what_the_file_holds(tmp_path):
    choices = dict(planet="flat", mass=250.0, canopy_diameter=12.0, canopy_type="ringsail", altitude=1500.0,
                   name="api")
    (tmp_path / "api.toml").write_text(pc.new_case_text(**choices))
    from_file = pc.simulate(pc.load_case(tmp_path / "api.toml"), "sp", duration=3.0)
    in_memory = pc.simulate(pc.new_case(**choices), "sp", duration=3.0)
    for name in from_file.names:
        assert np.array_equal(from_file[name], in_memory[name], equal_nan=True), name


@pytest.mark.parametrize("name", ["mer/case1", "mer/case3", "mer/case5", "mer/case6", "simple/simple", "cev_pa1"])
def test_stability_steps_stay_below_the_limit_at_the_start(name):
    """The chosen step is at most half the method's own RK4 limit at the initial geometry of every system present
    from the start; MER's SP step is the thesis's."""
    case = pc.load_case(ROOT / "cases" / f"{name}.toml", {"simulation.steps": {}})
    for method in (METHODS["full"](), METHODS["sp"]()):
        step, _ = stability_step(case, method, "rk4")
        for system in case.systems.values():
            if system.deploy_time is None:
                attach = np.array([initial_point(case, line.body, line.point) for line in system.lines])
                where = initial_confluence_state(case, system).position
                assert step <= 0.5 * min(limit.value for limit in method.confluence_limits(system, attach, where))
    if name.startswith("mer"):
        assert stability_step(case, METHODS["sp"](), "rk4")[0] == 1e-2
        assert stability_step(case, METHODS["full"](), "rk4")[0] == 5e-5


def test_an_undamped_line_in_a_later_system_needs_a_step():
    case = pc.load_case(ROOT / "cases" / "cev_pa1.toml", {"simulation.steps": {}, "main.lines.*.damping": 0.0})
    with pytest.raises(pc.InputError, match="has a line with stiffness but no damping"):
        stability_step(case, METHODS["sp"](), "rk4")


def test_extends_can_remove_a_key(tmp_path):
    child = tmp_path / "child.toml"
    child.write_text(f'extends = "{ROOT / "cases" / "simple" / "simple.toml"}"\nremove = ["planet"]\n[planet]\n'
                     'name = "Earth"\ngravitational_parameter = 3.986004418e14\nequatorial_radius = 6378137.0\n'
                     "polar_radius = 6356752.314\n")
    assert type(pc.load_case(child).planet).__name__ == "Planet"
    child.write_text(child.read_text().replace('remove = ["planet"]', 'remove = ["planet.radius"]'))
    with pytest.raises(pc.CaseError, match="'planet.radius' is not set by the base files"):
        pc.load_case(child)


def test_csv_dialects(tmp_path):
    columns, units, headers = read_csv_columns(ROCKETPY)    # RocketPy's export, unedited: '# Time (s),Z (m),...'
    assert list(columns)[:3] == ["time", "Z", "Vz"] and units["Z"] == "m" and headers["Vz"] == "Vz (m/s)"
    assert columns["Z"][0] == 3000.0 and np.all(np.diff(columns["time"]) > 0)
    openrocket = tmp_path / "openrocket.csv"
    openrocket.write_text("# OpenRocket simulation export\n# 3 data points written for 3 variables.\n"
                          "# Time (s),Altitude (ft),Vertical velocity (ft/s)\n0,100,-10\n"
                          "# Event PARACHUTE occurred at t=0.5 seconds\n1,90,-10\n2,80,-10\n")
    columns, units, _ = read_csv_columns(openrocket)
    assert units["Altitude"] == "ft" and list(columns["Altitude"]) == [100.0, 90.0, 80.0]
    semicolons = tmp_path / "semicolons.csv"
    semicolons.write_text("t [s];alt [m]\n0;5\n1;4\n")
    assert list(read_csv_columns(semicolons)[0]) == ["time", "alt"]
    mapping = parse_column_map(["Altitude=vehicle_altitude*0.3048+1200", "Vertical velocity (ft/s)=x*-0.3048",
                                "a=b-2.5e-1"])
    assert mapping == {"Altitude": ("vehicle_altitude", 0.3048, 1200.0),
                       "Vertical velocity (ft/s)": ("x", -0.3048, 0.0), "a": ("b", 1.0, -0.25)}
    result = pc.Result.load(openrocket, {k: v for k, v in mapping.items() if k != "a"})
    assert result["vehicle_altitude"][0] == pytest.approx(100 * 0.3048 + 1200.0)
    assert result["x"][0] == pytest.approx(3.048)


def test_descent_metrics_closed_form():
    """A linear descent at 5 m/s from 1000 m against one at 4 m/s ending 2 m above the ground."""
    t = np.linspace(0.0, 200.0, 2001)
    a = pc.Result({"time": t, "vehicle_altitude": 1000.0 - 5.0 * t})
    tb = np.linspace(0.0, 249.5, 500)
    b = pc.Result({"time": tb, "vehicle_altitude": 1000.0 - 4.0 * tb})
    d = descent_metrics(a, b, altitudes=[800.0, 300.0])
    assert d["a"]["rates"] == pytest.approx([5.0, 5.0]) and d["b"]["rates"] == pytest.approx([4.0, 4.0])
    assert d["a"]["ground_time"] == pytest.approx(200.0) and d["b"]["ground_time"] == pytest.approx(250.0)
    assert "extrapolated" in d["b"]["note"] and d["a"]["note"] == ""
    c = compare_results(a, b)
    assert c.columns["vehicle_altitude"]["max"] == pytest.approx(200.0)      # at A's last sample, t = 200 s
    assert c.columns["vehicle_altitude"]["time"] == pytest.approx(200.0)


def test_compare_against_rocketpy(payload, tmp_path, capsys):
    """RocketPy's unedited export of the same descent: a report of rates, time to ground and figures, no sed."""
    out = tmp_path / "cmp"
    args = ["compare", str(payload[0].parent / "sp"), str(ROCKETPY), "--map", "Z=vehicle_altitude", "--map",
            "Vz (m/s)=vehicle_velocity_down*-1", "--altitudes", "2500,1500,500", "--out", str(out)]
    assert main(args) == 0
    assert "| time to ground (s) |" in capsys.readouterr().out
    report = __import__("json").loads((out / "comparison.json").read_text())["descent"]
    for ours, theirs in zip(report["a"]["rates"], report["b"]["rates"]):
        # RocketPy: drag at the point mass (-0.085 %); both normal gravity since issue 48 (spherical: -0.177 %)
        assert theirs / ours - 1.0 == pytest.approx(-0.00083, abs=3e-4)
    assert report["b"]["ground_time"] - report["a"]["ground_time"] == pytest.approx(0.36, abs=0.1)   # spherical: 0.76
    for name in ("comparison.md", "descent_rate.png", "vehicle_altitude.png", "vehicle_velocity_down.png"):
        assert (out / name).is_file()


def test_a_map_with_nothing_to_compare_is_an_error(tmp_path, capsys):
    t = np.linspace(0.0, 10.0, 11)
    pc.Result({"time": t, "tension_reserve": np.full(11, np.nan), "vehicle_altitude": 100.0 - t},
              summary=RunSummary.from_dict({"case": "synthetic"})).save(tmp_path / "ours", plot=False)
    theirs = tmp_path / "theirs.csv"
    theirs.write_text("time,T\n" + "".join(f"{v:g},{v:g}\n" for v in t))
    assert main(["compare", str(tmp_path / "ours"), str(theirs), "--map", "T=tension_reserve"]) == 1
    err = capsys.readouterr().err
    assert "--map T=tension_reserve: no time in the common span" in err and len(err.strip().splitlines()) == 1

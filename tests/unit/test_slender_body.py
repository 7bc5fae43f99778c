"""The rocket as it hangs (issue 56): a slender cylinder's coefficients at every angle of attack
(``physics.slender_body``: Allen & Perkins / Jorgensen cross flow, Hoerner's axial coefficients) in closed form, the
table `pchute new --dual-deploy` writes from them, its harness, lag, opening and canopy-size options, and each option
a dual deploy refuses in one line."""

import math

import pytest

from pchute_exudyn.authoring.write import new_case_text
from pchute_exudyn.case.files import tomllib
from pchute_exudyn.errors import InputError
from pchute_exudyn.physics.slender_body import (
    CROSSFLOW_DRAG,
    FINITE_CYLINDER_DRAG,
    axial_coefficient,
    axial_coefficients,
    crossflow_normal_coefficient,
    finite_length_factor,
)
from tests.bad_input_harness import assert_one_line, run_bad_input

LENGTH, DIAMETER = 2.6, 0.1   # m: a 4 in rocket, L/d = 26
REFERENCE = math.pi * DIAMETER**2 / 4.0
ROCKET = dict(dual_deploy=True, planet="earth", canopy_type="flat_circular", mass=12.8, diameter=DIAMETER,
              length=LENGTH, drogue_diameter=0.6096, drogue_drag_coefficient=1.6, main_drag_area=4.0,
              main_height=100.0, height=800.0, ground_elevation=200.0)


def test_broadside_the_normal_coefficient_is_the_finite_cylinders_crossflow_drag_on_its_planform():
    eta = (0.91 + (0.98 - 0.91) * (26.0 - 20.0) / 20.0) / 1.2   # Wieselsberger's L/d 20 and 40, linear between
    assert finite_length_factor(LENGTH, DIAMETER) == pytest.approx(eta, rel=1e-14)
    assert crossflow_normal_coefficient(90.0, LENGTH, DIAMETER) == pytest.approx(
        eta * 1.2 * LENGTH * DIAMETER / REFERENCE, rel=1e-14)
    assert CROSSFLOW_DRAG == 1.2


def test_along_its_axis_there_is_no_normal_force_and_the_potential_term_is_jorgensens():
    assert crossflow_normal_coefficient(0.0, LENGTH, DIAMETER) == 0.0
    assert abs(crossflow_normal_coefficient(180.0, LENGTH, DIAMETER)) < 1e-12
    alpha = math.radians(20.0)
    crossflow = finite_length_factor(LENGTH, DIAMETER) * 1.2 * LENGTH * DIAMETER / REFERENCE
    assert crossflow_normal_coefficient(20.0, LENGTH, DIAMETER) == pytest.approx(
        math.sin(2 * alpha) * math.cos(alpha / 2) + crossflow * math.sin(alpha)**2, rel=1e-14)


def test_eta_is_wieselsbergers_table_over_the_infinite_cylinder_and_held_beyond_it():
    for ratio, drag in FINITE_CYLINDER_DRAG:
        assert finite_length_factor(ratio * 0.1, 0.1) == pytest.approx(drag / 1.2, rel=1e-12)
    assert finite_length_factor(0.05, 0.1) == pytest.approx(0.64 / 1.2)
    assert finite_length_factor(10.0, 0.1) == pytest.approx(0.98 / 1.2)


def test_the_axial_coefficient_is_hoerners_nose_first_and_tail_first_on_the_axial_dynamic_pressure():
    nose_first, tail_first = axial_coefficients(LENGTH, DIAMETER)
    skin = 0.0037 * 4.0 * 26.0                                   # C_f on pi d L over pi d^2 / 4
    assert nose_first == pytest.approx(skin + 0.029 / math.sqrt(skin), rel=1e-14)
    assert tail_first == pytest.approx(skin + 0.8, rel=1e-14)
    assert axial_coefficient(0.0, LENGTH, DIAMETER) == nose_first
    assert axial_coefficient(180.0, LENGTH, DIAMETER) == -tail_first   # pushes toward the nose: against the flow
    assert abs(axial_coefficient(90.0, LENGTH, DIAMETER)) < 1e-30
    assert axial_coefficient(60.0, LENGTH, DIAMETER) == pytest.approx(nose_first / 4.0, rel=1e-12)


def test_the_written_body_table_is_the_kernel_at_every_angle_and_goes_to_180_deg():
    data = tomllib.loads(new_case_text(**ROCKET))
    aero = data["bodies"]["rocket"]["aerodynamics"]
    assert aero["reference_area"] == pytest.approx(REFERENCE, rel=1e-11) and aero["center"] == [0.0, 0.0, 0.0]
    normal, axial = aero["normal_coefficient"], aero["axial_coefficient"]
    assert normal["alpha_deg"][0] == 0.0 and normal["alpha_deg"][-1] == 180.0
    for alpha, value in zip(normal["alpha_deg"], normal["value"]):
        assert value == pytest.approx(crossflow_normal_coefficient(alpha, LENGTH, DIAMETER), rel=1e-11, abs=1e-12)
    for alpha, value in zip(axial["alpha_deg"], axial["value"]):
        assert value == pytest.approx(axial_coefficient(alpha, LENGTH, DIAMETER), rel=1e-11, abs=1e-12)
    assert "aerodynamics" not in tomllib.loads(new_case_text(**ROCKET, body_drag="off"))["bodies"]["rocket"]


def test_each_canopy_takes_its_own_diameter_and_drag_coefficient():
    data = tomllib.loads(new_case_text(**ROCKET))
    drogue = data["bodies"]["drogue_canopy"]["aerodynamics"]
    assert drogue["reference_area"] == pytest.approx(math.pi * 0.6096**2 / 4.0, rel=1e-11)   # 24 in
    assert drogue["axial_coefficient"]["value"][0] == pytest.approx(1.6, rel=1e-11)
    main = data["bodies"]["main_canopy"]["aerodynamics"]   # C_D S 4 m^2 at the flat circular's C_D0 0.77
    assert main["reference_area"] * main["axial_coefficient"]["value"][0] == pytest.approx(4.0, rel=1e-11)
    assert main["reference_area"] == pytest.approx(4.0 / 0.77, rel=1e-11)
    both = tomllib.loads(new_case_text(**{**ROCKET, "main_diameter": 2.0}))["bodies"]["main_canopy"]["aerodynamics"]
    assert both["reference_area"] == pytest.approx(math.pi, rel=1e-11)   # C_D = C_D S / S0 = 4 / pi
    assert both["axial_coefficient"]["value"][0] == pytest.approx(4.0 / math.pi, rel=1e-11)


def test_the_drogue_stays_on_its_harness_unless_cut_and_the_main_takes_its_lag_and_opening():
    systems = tomllib.loads(new_case_text(**ROCKET))["systems"]
    assert "cutaway_trigger" not in systems["drogue"] and "drag_area_schedule" not in systems["main"]
    assert "lag" not in systems["main"]["deploy_trigger"]
    systems = tomllib.loads(new_case_text(**ROCKET, drogue_after_main="cut", main_lag=0.6,
                                          main_opening_time=1.6))["systems"]
    assert systems["drogue"]["cutaway_trigger"] == {"after": "main.deploy"}
    assert systems["main"]["deploy_trigger"]["lag"] == 0.6
    schedule = systems["main"]["drag_area_schedule"]   # the flat circular's opening exponent 2: (t / 1.6 s)^2
    assert schedule["time"][0] == 0.0 and schedule["time"][-1] == 1.6 and schedule["fraction"][-1] == 1.0
    assert schedule["fraction"][4] == pytest.approx(0.25, rel=1e-12) and schedule["time"][4] == pytest.approx(0.8)


def test_a_harness_offset_puts_the_bags_at_the_harness():
    """Given, the harness is that far aft of the centre of mass and the bags ride there (at 0: every force of the
    descent through the centre of mass); not given, HARNESS_FRACTION aft with the bags a bridle's length further."""
    points = tomllib.loads(new_case_text(**ROCKET, harness_offset=0.0))["bodies"]["rocket"]["points"]
    assert points["harness"] == [0.0, 0.0, 0.0] and points["line_stretch"] == [0.0, 0.0, 0.0]
    points = tomllib.loads(new_case_text(**ROCKET, harness_offset=0.25))["bodies"]["rocket"]["points"]
    assert points["harness"][0] == -0.25 and points["line_stretch"][0] == -0.25
    points = tomllib.loads(new_case_text(**ROCKET))["bodies"]["rocket"]["points"]
    assert points["harness"][0] == pytest.approx(-0.12 * LENGTH)
    assert points["line_stretch"][0] == pytest.approx(-0.12 * LENGTH - 0.4 * LENGTH)


FORM = ["--dual-deploy", "--planet", "earth", "--mass", "12.8", "--diameter", "0.1", "--length", "2.6",
        "--main-drag-area", "4", "--main-height", "100", "--height", "800"]
DROGUE = ["--drogue-drag-area", "0.47"]
BAD = [
    (FORM + DROGUE + ["--canopy-diameter", "2"],
     "canopy_diameter = 2.0: not with dual_deploy (--dual-deploy): each canopy's: --drogue-diameter, --main-diameter"),
    (FORM + DROGUE + ["--drag-area", "2"], "drag_area = 2.0: not with dual_deploy (--dual-deploy): each canopy's"),
    (FORM + DROGUE + ["--canopy-mass", "0.2"], "canopy_mass = 0.2: not with dual_deploy"),
    (FORM + DROGUE + ["--bridles", "3"], "bridles = 3: not with dual_deploy (--dual-deploy): a dual deploy hangs"),
    (FORM, "drogue_drag_area: required with dual_deploy (m^2), or drogue_diameter (m)"),
    (FORM + DROGUE + ["--drogue-diameter", "0.61", "--drogue-drag-coefficient", "1.6"],
     "drogue_drag_coefficient = 1.6: not with both drogue_drag_area and drogue_diameter"),
    (FORM + DROGUE + ["--drogue-diameter", "0.61", "--drag-coefficient", "0.8"],
     "drag_coefficient = 0.8: not with both drogue_drag_area and drogue_diameter"),
    (FORM + DROGUE + ["--main-drag-coefficient", "2.2", "--drag-coefficient", "0.8"],
     "main_drag_coefficient = 2.2 and drag_coefficient = 0.8: give one"),
    (FORM + DROGUE + ["--drogue-diameter", "0.1"],
     "drogue_drag_area = 0.47 and drogue_diameter = 0.1: imply C_D = 59.8 on S0 = pi D0^2 / 4, above 3"),
    (FORM + DROGUE + ["--main-diameter", "-1"], "main_diameter = -1.0: must be a number > 0 (m)"),
    (FORM + DROGUE + ["--main-drag-coefficient", "0"], "main_drag_coefficient = 0.0: must be a number > 0 (-)"),
    (FORM + DROGUE + ["--main-lag", "-0.5"], "main_lag = -0.5: must be a number >= 0 (s)"),
    (FORM + DROGUE + ["--main-opening-time", "0"], "main_opening_time = 0.0: must be a number > 0 (s)"),
    (FORM + DROGUE + ["--main-opening-time", "1", "--shock-cord-length", "6"],
     "main_opening_time = 1.0: not with shock_cord_length (--shock-cord-length)"),
    (FORM + DROGUE + ["--body-drag", "maybe"], "argument --body-drag: invalid choice: 'maybe'"),
    (FORM + DROGUE + ["--drogue-after-main", "kept"], "argument --drogue-after-main: invalid choice: 'kept'"),
    (FORM + DROGUE + ["--harness-offset", "1.4"],
     "harness_offset = 1.4: must be a number within half the rocket's length, 1.3 m, of its centre of mass"),
    (FORM + DROGUE + ["--harness-offset", "0", "--shock-cord-length", "6"],
     "harness_offset = 0.0: not with shock_cord_length (--shock-cord-length)"),
    (["--body-drag", "off"], "body_drag = 'off': only with dual_deploy (--dual-deploy)"),
    (["--main-lag", "1"], "main_lag = 1.0: only with dual_deploy"),
    (["--drogue-after-main", "cut"], "drogue_after_main = 'cut': only with dual_deploy"),
]


@pytest.mark.parametrize("options, message", BAD, ids=[" ".join(o[-2:]) + f" {i}" for i, (o, _) in enumerate(BAD)])
def test_a_wrong_hanging_option_gives_one_line(options, message, tmp_path):
    code, err, seconds, touched = run_bad_input(lambda t: ["new", str(t / "rocket.toml"), *options], tmp_path)
    assert_one_line(code, err, message, touched, seconds)


def test_the_python_form_refuses_a_word_it_does_not_know():
    with pytest.raises(InputError, match="body_drag = 'yes': must be one of: on, off"):
        new_case_text(**ROCKET, body_drag="yes")

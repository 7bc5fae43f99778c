"""`pchute new --dual-deploy`'s closed forms and RocketPy's export (issue 48): the slender-body inertia, the nose's
attitude, the apogee state read from validation/rocketpy's exports (SI units, as RocketPy reported them)."""

import math

import numpy as np
import pytest

from pchute_exudyn.authoring.choices import NewCase
from pchute_exudyn.authoring.rocket_start import nose_attitude_deg, nose_direction, start_height
from pchute_exudyn.physics.rotations import attitude_matrix
from pchute_exudyn.physics.shapes import hemispherical_shell_inertia, solid_cylinder_inertia
from pchute_exudyn.results import rocketpy_export
from tests.helpers import ROOT

FLIGHT = ROOT / "validation" / "rocketpy" / "dual_deploy_flight.csv"
DESCENT = ROOT / "validation" / "rocketpy" / "descent.csv"


def test_the_rocket_is_a_solid_cylinder_about_its_axis_and_across():
    mass, diameter, length = 20.0, 0.15, 2.5
    axial, across, across2 = solid_cylinder_inertia(mass, diameter, length)
    assert axial == pytest.approx(mass * 0.075**2 / 2.0, rel=1e-15)          # 0.05625 kg m^2
    assert across == across2 == pytest.approx(mass * (3.0 * 0.075**2 + 2.5**2) / 12.0, rel=1e-15)
    assert across == pytest.approx(10.4447917, rel=1e-7)                      # cases/rocket/dual_deploy.toml's
    assert hemispherical_shell_inertia(0.17, 0.4311) == pytest.approx([0.0210626, 0.0131641, 0.0131641], rel=1e-4)


@pytest.mark.parametrize("nose", [(0, 0, 1), (1, 0, 0), (0, -1, 0), (0.6, 0.0, 0.8), (0.36, -0.48, 0.8),
                                  (-0.6, 0.0, -0.8)])
def test_the_nose_attitude_puts_body_x_on_the_nose(nose):
    assert attitude_matrix(*nose_attitude_deg(nose))[:, 0] == pytest.approx(nose, abs=1e-9)


def test_the_nose_heads_along_the_horizontal_velocity_unless_given():
    choices = NewCase(dual_deploy=True, planet="earth", mass=20.0, diameter=0.15, length=2.5, drogue_drag_area=1.0,
                      main_drag_area=10.0, main_height=300.0, height=2500.0, velocity_north=-5.0)
    assert nose_direction(choices) == pytest.approx([0.0, -1.0, 0.0], abs=1e-12)
    assert start_height(choices) == 2500.0


def test_rocketpy_apogee_is_found_between_rows_in_si_units():
    state = rocketpy_export.apogee_state(FLIGHT)
    # make_dual_deploy.py printed: apogee 3456.491 m at t = 14.1946 s; the ground at 1400 m (its Environment)
    assert state.at_apogee and state.time == pytest.approx(14.1946, abs=2e-3)
    assert state.altitude == pytest.approx(3456.491, abs=0.01)
    assert state.ground_elevation == pytest.approx(1400.0, abs=1e-6)
    assert state.velocity_up == 0.0 and state.velocity_east == pytest.approx(12.89, abs=0.01)
    assert abs(state.velocity_north) < 0.1
    assert state.latitude_deg == pytest.approx(32.99, abs=1e-4) and state.longitude_deg == pytest.approx(-106.968, abs=1e-3)
    # its initial quaternion tilts the nose east, 84.6 deg above the horizontal (no fins: it keeps it)
    assert state.nose_pitch_deg == pytest.approx(math.degrees(math.atan2(160.0, 15.0)), abs=0.01)
    assert state.nose_heading_deg == pytest.approx(90.0, abs=1e-6)


def test_a_rocketpy_export_that_only_descends_starts_at_its_first_row():
    state = rocketpy_export.apogee_state(DESCENT)
    assert not state.at_apogee and state.time == 0.0
    assert (state.altitude, state.velocity_up) == (3000.0, -7.73735)
    assert state.nose_pitch_deg is None and state.ground_elevation is None


def test_rocketpy_solver_state_export_is_read_by_position(tmp_path):
    # export_data(path) with no variables: 14 values a row under an 11-name header (RocketPy's own)
    path = tmp_path / "solution.csv"
    rows = np.array([[0.0, 0, 0, 100.0, 1.0, 2.0, 10.0, 1, 0, 0, 0, 0, 0, 0],
                     [1.0, 1, 2, 105.0, 1.0, 2.0, -10.0, 1, 0, 0, 0, 0, 0, 0]])
    np.savetxt(path, rows, fmt="%.6f", delimiter=",", header=rocketpy_export.SOLVER_HEADER)
    columns, units, _ = rocketpy_export.read_columns(path)
    assert list(columns["Vy"]) == [2.0, 2.0] and units["Vz"] == "m/s"
    state = rocketpy_export.apogee_state(path)
    assert state.time == pytest.approx(0.5) and state.altitude == pytest.approx(102.5)
    assert state.nose_pitch_deg == pytest.approx(90.0)

"""Aerodynamic databases: closed forms through the engine (a body pivoted at its centre of mass in a steady wind:
static moment, pitch damping, roll damping; drag over Mach number), coefficient tables (interpolation, edges, folded
and total angles), the speed of sound, tables equal to constants, and the bad inputs of a table."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.physics.aerodynamics import CoefficientTable, CoefficientTableError
from pchute_exudyn.physics.atmosphere import MARS_GAMMA, MARS_R, US76, US76_R, MarsGRC
from tests.helpers import ROOT, TEST_CASES

CASES = TEST_CASES
PIVOT = CASES / "pivot_wind.toml"

# the pivot case's numbers (tests/cases/pivot_wind.toml)
DENSITY, WIND, AREA, LENGTH, INERTIA, ROLL_INERTIA, SOUND = 0.02, 20.0, 2.0, 1.5, 10.0, 5.0, 300.0
PRESSURE = 0.5 * DENSITY * WIND ** 2
MOMENT_SLOPE = -0.5   # C_malpha, per rad


def crossings(time, signal):
    """Times where ``signal`` changes sign (linear between samples)."""
    i = np.flatnonzero((signal[:-1] < 0.0) != (signal[1:] < 0.0))
    return time[i] - signal[i] * (time[i + 1] - time[i]) / (signal[i + 1] - signal[i])


def swing(overrides=None, method="full"):
    """The pivoted body's yaw from the wind's line (deg; -90 deg yaw is the air-relative velocity's direction) and
    the run's columns."""
    result = pc.simulate(pc.load_case(PIVOT, overrides or {}), method)
    return result.columns["time"], result.columns["body_yaw_deg"] + 90.0, result.columns


def closed_form_omega() -> float:
    return math.sqrt(-PRESSURE * AREA * LENGTH * MOMENT_SLOPE / INERTIA)


@pytest.mark.parametrize("method", ["full", "sp"])
def test_a_pivoted_body_swings_at_the_closed_form_frequency(method):
    """C_m = C_malpha alpha: omega^2 = -q S d C_malpha / I (to 1e-3; the equations are linear, so it holds at any
    amplitude)."""
    time, angle, _ = swing(method=method)
    period = 2.0 * np.mean(np.diff(crossings(time, angle)))
    assert 2.0 * math.pi / period == pytest.approx(closed_form_omega(), rel=1e-3)
    assert np.max(np.abs(angle)) == pytest.approx(5.0, rel=1e-9)   # no damping: the amplitude stays


def test_pitch_damping_gives_the_closed_form_damping_ratio():
    """With C_mq: zeta = -q S d^2 C_mq / (4 V I omega) (to 2 %), from the decay of the swing's peaks."""
    pitch_damping = -2.0
    time, angle, _ = swing({"bodies.body.aerodynamics.pitch_damping": pitch_damping})
    inner = np.abs(angle[1:-1])
    peaks = np.flatnonzero((inner > np.abs(angle[:-2])) & (inner >= np.abs(angle[2:]))) + 1
    decay = -np.polyfit(time[peaks], np.log(np.abs(angle[peaks])), 1)[0]          # zeta omega (1/s)
    damped = 2.0 * math.pi / (2.0 * np.mean(np.diff(crossings(time, angle))))        # omega_d (rad/s)
    zeta = decay / math.hypot(damped, decay)
    omega = closed_form_omega()
    expected = -PRESSURE * AREA * LENGTH ** 2 * pitch_damping / (4.0 * WIND * INERTIA * omega)
    assert len(peaks) >= 6
    assert zeta == pytest.approx(expected, rel=0.02)


def test_roll_damping_decays_the_roll_rate_at_the_closed_form_rate():
    """Aligned with the wind and spinning: p(t) = p0 exp(-lambda t), lambda = -q S d^2 C_lp / (2 V I_xx)."""
    roll_damping = -2.0
    _, _, columns = swing({"bodies.body.initial.yaw_deg": -90.0, "bodies.body.initial.rate_x": 1.0,
                           "bodies.body.aerodynamics.roll_damping": roll_damping, "simulation.duration": 10.0})
    rate = -np.polyfit(columns["time"], np.log(columns["body_rate_x"]), 1)[0]
    expected = -PRESSURE * AREA * LENGTH ** 2 * roll_damping / (2.0 * WIND * ROLL_INERTIA)
    assert rate == pytest.approx(expected, rel=1e-6)
    assert np.max(np.abs(columns["body_angle_of_attack_deg"])) < 1e-9   # the spin does not tip it


MACH_DRAG = {"mach": [0.3, 0.8, 1.2, 2.0], "value": [0.9, 1.0, 1.5, 1.3]}


@pytest.mark.parametrize("wind, mach_number, axial", [
    (150.0, 0.5, 0.9 + (0.5 - 0.3) / (0.8 - 0.3) * (1.0 - 0.9)),   # between breakpoints: linear
    (330.0, 1.1, 1.0 + (1.1 - 0.8) / (1.2 - 0.8) * (1.5 - 1.0)),
    (750.0, 2.5, 1.3),                                               # beyond the table: held at its end
])
def test_mach_dependent_drag_gives_the_closed_form_force(wind, mach_number, axial):
    """The stage kernel's force and the engine's single evaluation of it: |F| = q S C_A(M) along -e (to 1e-9)."""
    from pchute_exudyn.engine.solver import integrate
    from pchute_exudyn.methods.full import FullMass
    from pchute_exudyn.run.phases import initial_phase

    case = pc.load_case(PIVOT, {"atmosphere.wind.east": wind, "bodies.body.initial.yaw_deg": -90.0,
                                "bodies.body.aerodynamics.axial_coefficient": MACH_DRAG})
    model = FullMass().build(case, initial_phase(case))
    integrate(model, "rk4", 1e-3, 1e-3, 1e-3)
    stage, member = model.stage, model.stage.loads.members[0]
    stage.refresh(1e-3)
    stage.loads.apply(1e-3)
    row = stage.states[stage.row["body"]]
    relative = row[12:15] - np.array([wind, 0.0, 0.0])   # the start frame's axes: east, north, up
    speed = np.linalg.norm(relative)
    expected = 0.5 * DENSITY * speed ** 2 * AREA * axial
    force, _, pressure, mach, _ = member.evaluate(1e-3)
    assert speed / SOUND == pytest.approx(mach_number, rel=1e-9)
    assert mach == pytest.approx(speed / SOUND, rel=1e-12)
    for value in (np.asarray(force), stage.loads.values[0, :3]):
        assert np.linalg.norm(value) == pytest.approx(expected, rel=1e-9)
        np.testing.assert_allclose(value / np.linalg.norm(value), -row[[3, 6, 9]], atol=1e-12)   # along -e
    assert pressure == pytest.approx(0.5 * DENSITY * speed ** 2, rel=1e-12)



# -- coefficient tables -----------------------------------------------------------------------------------------------

def test_a_table_is_bilinear_and_held_at_its_edges():
    table = CoefficientTable((0.0, 10.0, 90.0), ((1.0, 2.0, 4.0), (3.0, 6.0, 8.0)), mach=(0.5, 1.5))
    assert table(5.0, 1.0) == pytest.approx(0.5 * 1.5 + 0.5 * 4.5, rel=1e-15)   # midway in both
    assert table(10.0, 0.5) == 2.0 and table(10.0, 1.5) == 6.0                  # on breakpoints: exact
    assert table(10.0, 0.1) == 2.0 and table(10.0, 3.0) == 6.0                  # held beyond the Mach ends
    assert table(170.0, 1.5) == table(10.0, 1.5)                                  # folded: alpha' = 180 - alpha
    total = CoefficientTable((0.0, 90.0, 180.0), (0.0, 1.0, 4.0))
    assert total(135.0) == 2.5 and total(45.0) == 0.5                            # total angle: not folded
    assert CoefficientTable.constant(0.7)(33.0, 4.0) == 0.7


@pytest.mark.parametrize("kwargs, key", [
    (dict(angle_deg=(0.0, 45.0, 40.0, 90.0), value=(0, 1, 2, 3)), "alpha_deg"),        # not increasing
    (dict(angle_deg=(0.0, 90.0), value=((0, 1), (2, 3)), mach=(1.0, 0.5)), "mach"),     # Mach not increasing
    (dict(angle_deg=(0.0, 90.0), value=((0, 1), (2,)), mach=(0.5, 1.0)), "value"),      # ragged
    (dict(angle_deg=(0.0, 90.0), value=(0.0, float("nan"))), "value"),                  # NaN
    (dict(angle_deg=(0.0, 90.0), value=(0.0, 1.0), mach=(float("nan"), 1.0)), "mach"),
    (dict(angle_deg=(5.0, 90.0), value=(0.0, 1.0)), "alpha_deg"),                       # not from 0
])
def test_bad_tables_name_their_key(kwargs, key):
    with pytest.raises(CoefficientTableError) as error:
        CoefficientTable(**kwargs)
    assert error.value.field == key


def test_the_speed_of_sound_follows_the_temperature():
    us76 = US76()
    for altitude in (0.0, 5000.0, 11000.0, 20000.0):
        assert us76.speed_of_sound(altitude) == pytest.approx(
            math.sqrt(1.4 * US76_R * us76.temperature(altitude)), rel=1e-14)
    assert us76.speed_of_sound(0.0) == pytest.approx(340.294, abs=1e-3)   # the standard's sea-level value
    mars = MarsGRC()
    assert mars.speed_of_sound(7000.0) == pytest.approx(
        math.sqrt(MARS_GAMMA * MARS_R * (mars.temperature(7000.0) + 273.1)), rel=1e-14)


def test_a_table_equal_to_the_constants_gives_the_same_run():
    """MER case 1 with C_A as a Mach table that is constant and C_N as a (Mach, alpha) table of the same rows: the
    same run as the constants, to 1e-12."""
    case_file = ROOT / "cases" / "mer" / "case1.toml"
    base = pc.load_case(case_file)
    normal = base.bodies["parachute"].aerodynamics.normal_coefficient
    axial = base.bodies["parachute"].aerodynamics.axial_coefficient.value
    tables = {"bodies.parachute.aerodynamics.axial_coefficient": {"mach": [0.0, 3.0], "value": [axial, axial]},
              "bodies.parachute.aerodynamics.normal_coefficient": {
                  "mach": [0.0, 3.0], "alpha_deg": list(normal.angle_deg), "value": [list(normal.value)] * 2}}
    one = pc.simulate(base, "sp", duration=10.0).columns
    two = pc.simulate(pc.load_case(case_file, tables), "sp", duration=10.0).columns
    for key, column in one.items():
        if key.endswith("_mach"):
            continue
        np.testing.assert_allclose(two[key], column, rtol=1e-12, atol=1e-12 * max(1.0, np.nanmax(np.abs(column))),
                                   err_msg=key)


# -- outputs and the shipped databases ----------------------------------------------------------------------------------

def test_swing_amplitude_is_the_mean_of_the_peaks():
    from pchute_exudyn.run.analysis import swing_amplitude
    time = np.linspace(0.0, 20.0, 20001)
    assert swing_amplitude(np.abs(3.0 * np.sin(1.3 * time))) == pytest.approx(3.0, rel=1e-5)   # a planar swing
    assert swing_amplitude(np.full(50, 7.0)) == 7.0                                           # coning: no peak
    assert swing_amplitude([]) is None


def test_pa1_with_databases_sp_agrees_with_full_mass_and_reports_mach():
    """cases/cev_pa1_aero.toml: SP and full mass implicit agree on touchdown (0.2 s) and on the capsule's swing
    amplitude under the mains (0.5 deg); the Mach column is the air speed over the standard's speed of sound."""
    case = pc.load_case(ROOT / "cases" / "cev_pa1_aero.toml")
    sp, full = pc.simulate(case, "sp"), pc.simulate(case, "full", "implicit")

    def touchdown(result):
        return result.summary.touchdown.time
    assert abs(touchdown(sp) - touchdown(full)) < 0.2
    for kind in ("vertical", "airspeed"):
        key = f"amplitude_{kind}_deg"
        assert abs(getattr(sp.summary.pendulum, key) - getattr(full.summary.pendulum, key)) < 0.5
    assert sp.summary.pendulum.start == 27.5   # the mains' drag-area schedule ends at 9.5 + 18 s
    columns, atmosphere = sp.columns, US76()
    i = len(columns["time"]) // 2
    sound = atmosphere.speed_of_sound(columns["capsule_altitude"][i])   # the centre of mass: within 1 m of the centre
    speed = math.sqrt(2.0 * columns["capsule_dynamic_pressure"][i] / atmosphere.density(columns["capsule_altitude"][i]))
    assert columns["capsule_mach"][i] == pytest.approx(speed / sound, rel=1e-3)
    assert sp.summary.units["capsule_mach"] == "-"


def test_the_compiled_hypot_is_cpythons_to_the_last_bit():
    """``physics.planet.hypot`` (compiled in the tests) reproduces ``math.hypot`` exactly: the compiled altitude and
    turbulence kernels then give the bits the Python they replaced gave."""
    from pchute_exudyn.physics.compiled import MODE
    from pchute_exudyn.physics.planet import hypot_port as hypot
    assert MODE != "python" and hypot is not math.hypot
    rng = np.random.default_rng(7)
    a = rng.uniform(-1e7, 1e7, 20000) * 10.0 ** rng.integers(-300, 300, 20000)
    b = rng.uniform(-1e7, 1e7, 20000)
    assert all(hypot(float(x), float(y)) == math.hypot(x, y) for x, y in zip(a, b))
    for x, y in ((0.0, 0.0), (3.0, 4.0), (1e-310, 2e-310), (5e-324, 0.0), (1e308, 1e308), (math.inf, 1.0)):
        assert hypot(x, y) == math.hypot(x, y)
    assert math.isnan(hypot(math.nan, 1.0))


@pytest.mark.parametrize("name, trim_deg", [("case5_aero.toml", 0.0), ("case5_aero_trim.toml", 5.0)])
def test_a_disk_gap_band_settles_on_its_trim_angle(name, trim_deg):
    """The shipped MER case 5 canopies: case5_aero's is stable about zero angle of attack, case5_aero_trim's crosses
    zero in C_N and C_m at 5 deg with the restoring slope (the tables), and in flight it settles there and glides."""
    case = pc.load_case(ROOT / "cases" / "mer" / name)
    aero = case.bodies["parachute"].aerodynamics
    normal, moment = aero.normal_coefficient, aero.moment_coefficient
    assert normal(trim_deg) == 0.0 and moment(trim_deg) == 0.0
    # restoring about the trim: the normal force turns the canopy back (its centre is aft), C_m > 0 raises alpha
    assert normal(trim_deg + 1.0) > 0.0 and moment(trim_deg + 1.0) < 0.0
    if trim_deg:
        assert normal(trim_deg - 1.0) < 0.0 and moment(trim_deg - 1.0) > 0.0
    result = pc.simulate(case, "sp", duration=20.0)
    settled = result["time"] >= 15.0
    alpha = result["parachute_angle_of_attack_deg"][settled]
    assert abs(np.mean(alpha) - trim_deg) < 0.1
    # trimmed, the canopy's force leans off the airspeed and the system glides away from its start; untrimmed it
    # hangs and drifts by its initial swing only (case5_aero: 0.18 m in 20 s, trimmed: 6.2 m and gaining 1.2 m/s)
    glide_speed = abs(result["vehicle_velocity_east"][-1])
    assert glide_speed > 0.5 if trim_deg else glide_speed < 0.05

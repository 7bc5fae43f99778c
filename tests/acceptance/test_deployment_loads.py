"""Deployment loads against closed forms (docs/models/deployment_loads.md): two bodies in vacuum on a tether that
comes taut (undamped: the snatch v sqrt(k mu); damped: the oscillator's first peak; paying out against a constant
resistance: line stretch from the kinematics), with full mass and SP; an infinite-mass opening of each canopy type
(the drag-area history is the fill law, the peak q S C_D C_x); the rocket's openings under SP's reduced canopy
against the full-mass reference (recorded values)."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from pchute_exudyn import load_case, simulate
from pchute_exudyn.physics.inflation import Inflation, InflationStage, nominal_diameter
from pchute_exudyn.registries.canopy_types import CANOPY_TYPE_LIST

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "validation"))
import canopy_checks  # noqa: E402

M1, M2, STIFFNESS, SPEED, LENGTH, GAP = 10.0, 2.0, 2000.0, 5.0, 3.0, 1.0
MU = M1 * M2 / (M1 + M2)
TETHERED = f'''
[case]
name = "two bodies on a cord"
vehicle = "a"
[planet]
model = "flat"
gravity = 0.0
[bodies.a]
mass = {M1}
inertia = [1.0, 1.0, 1.0]
points.end = [0.0, 0.0, 0.0]
initial = {{ altitude = 1000.0 }}
[bodies.b]
mass = {M2}
inertia = [0.2, 0.2, 0.2]
points.end = [0.0, 0.0, 0.0]
initial = {{ altitude = 1000.0, east = {GAP}, velocity_east = {SPEED} }}
[tethers.cord]
ends = ["a.end", "b.end"]
free_length = {LENGTH}
stiffness = {STIFFNESS}
[simulation]
duration = 0.8
output_step = 0.1
steps = {{ full = 1.0e-4, sp = 1.0e-4 }}
'''
METHODS = ("full", "sp")


def _tethered(tmp_path, **keys):
    path = tmp_path / "tethered.toml"
    path.write_text(TETHERED)
    return load_case(path, {f"tethers.cord.{key}": value for key, value in keys.items()})


def _cord(result):
    (deployment,) = result.summary.deployments
    assert deployment.kind == "tether" and deployment.system == "cord"
    return deployment


@pytest.mark.parametrize("method", METHODS)
def test_an_undamped_cord_comes_taut_at_l_over_v_and_snatches_at_v_sqrt_k_mu(tmp_path, method):
    cord = _cord(simulate(_tethered(tmp_path), method))
    assert cord.line_stretch_time == pytest.approx((LENGTH - GAP) / SPEED, abs=1.5e-4)   # a step
    assert cord.snatch_load == pytest.approx(SPEED * math.sqrt(STIFFNESS * MU), rel=1e-3)
    assert cord.opening_load == cord.snatch_load


@pytest.mark.parametrize("method", METHODS)
def test_a_damped_cord_peaks_as_the_damped_oscillator(tmp_path, method):
    damping = 20.0
    cord = _cord(simulate(_tethered(tmp_path, damping=damping), method))
    natural = math.sqrt(STIFFNESS / MU)
    ratio = damping / (2.0 * math.sqrt(STIFFNESS * MU))
    damped = natural * math.sqrt(1.0 - ratio ** 2)
    s = np.linspace(0.0, math.pi / damped, 200001)   # x(0) = 0, x'(0) = v: T = k x + c x'
    decay = np.exp(-ratio * natural * s)
    stretch = SPEED / damped * decay * np.sin(damped * s)
    rate = SPEED * decay * (np.cos(damped * s) - ratio * natural / damped * np.sin(damped * s))
    assert cord.snatch_load == pytest.approx(float(np.max(STIFFNESS * stretch + damping * rate)), rel=1e-3)


@pytest.mark.parametrize("method", METHODS)
def test_a_payout_resistance_sets_line_stretch_by_the_kinematics(tmp_path, method):
    resistance = 10.0
    result = simulate(_tethered(tmp_path, payout_resistance=resistance), method)
    cord = _cord(result)
    slowing = resistance / MU
    stretch_speed = math.sqrt(SPEED ** 2 - 2.0 * slowing * (LENGTH - GAP))
    assert cord.line_stretch_time == pytest.approx((SPEED - stretch_speed) / slowing, abs=1.5e-4)
    assert cord.snatch_load == pytest.approx(stretch_speed * math.sqrt(STIFFNESS * MU), rel=1e-3)
    # paying out it pulls with R: the samples before line stretch
    tension, time = result.columns["tension_cord"], result.columns["time"]
    paying = (time > 0.0) & (time < cord.line_stretch_time - 1e-3)
    assert np.all(tension[paying] == resistance)


SUBSONIC = [canopy for canopy in CANOPY_TYPE_LIST]


@pytest.mark.parametrize("canopy", SUBSONIC, ids=[canopy.name for canopy in SUBSONIC])
def test_an_infinite_mass_opening_follows_the_fill_law_to_q_s_cd_cx(tmp_path, canopy):
    """canopy_checks' towed canopy (1e9 kg, constant air) opening by the type's fill constant, exponent and C_x,
    its speed chosen so that the fill ends on an output sample."""
    fill_time = 0.5   # s
    area = canopy_checks.AREA
    speed = canopy.fill_constant * nominal_diameter(area) / fill_time
    overinflation = canopy.overinflation
    decay = 0.3 if overinflation > 1.0 else 0.0
    opening = (f"{{stage_start = [0.0], fraction = [1.0], fill_constant = [{canopy.fill_constant}], exponent = "
               f"[{canopy.opening_exponent}], overinflation = {overinflation}, overinflation_decay = {decay}}}")
    path = tmp_path / "towed.toml"
    path.write_text(canopy_checks.TOWED.format(air=(ROOT / "tests" / "cases" / "constant_air.csv").as_posix(),
                                               speed=speed, area=area,
                                               axial_coefficient=canopy.drag_coefficient))
    case = load_case(path, [f"systems.tow.inflation={opening}", "simulation.duration=1.5",
                            "simulation.output_step=0.005"])
    columns = simulate(case, "sp").columns
    law = Inflation((InflationStage(0.0, 1.0, canopy.fill_constant, canopy.opening_exponent),),
                    overinflation=overinflation, overinflation_decay=decay)
    q = 0.5 * canopy_checks.DENSITY * speed ** 2
    expected = q * area * canopy.drag_coefficient * np.array([law.fraction(t, [fill_time]) for t in columns["time"]])
    force = columns["canopy_aerodynamic_force"]
    assert np.max(np.abs(force - expected)) <= 1e-6 * expected.max()
    assert force.max() == pytest.approx(q * area * canopy.drag_coefficient * overinflation, rel=1e-6)


FULL_MASS_OPENINGS = {"drogue": 242.924, "main": 408.443}
"""N: the opening loads of the shipped dual deploy with both canopies opening by the flat circular's law (n = 8,
exponent 2, C_x 1.7; decay 0.1 s and 0.3 s), flown by full mass (rigid canopies), recorded with
``pchute run <that case> --method full`` (the case: this test's overrides of cases/rocket/dual_deploy.toml)."""


def test_the_rocket_s_reduced_canopies_open_as_full_mass_within_two_percent(tmp_path):
    case = load_case(ROOT / "cases" / "rocket" / "dual_deploy.toml", [
        f"systems.{name}.inflation={{stage_start = [0.0], fraction = [1.0], fill_constant = [8.0], exponent = [2.0], "
        f"overinflation = 1.7, overinflation_decay = {decay}}}" for name, decay in (("drogue", 0.1), ("main", 0.3))])
    loads = {d.system: d for d in simulate(case, "sp").summary.deployments}
    for name, reference in FULL_MASS_OPENINGS.items():
        assert loads[name].opening_load == pytest.approx(reference, rel=0.02), name
        assert loads[name].knacke_opening_load is not None


def test_a_study_keeps_each_deployment_s_loads_and_reports_their_design_percentiles(tmp_path):
    """The study's outputs of a run (``study.runner.scalar_outputs``) carry the tether's snatch, opening load and
    breaking strength, and the report's loads section gives their percentiles and the margin to the 99.87th."""
    from pchute_exudyn.study.report import loads_section
    from pchute_exudyn.study.runner import scalar_outputs
    rows = []
    for speed in (4.0, 5.0, 6.0):
        case = load_case(_write(tmp_path), [
            f"bodies.b.initial.velocity_east={speed}", "tethers.cord.breaking_strength=1000.0"])
        outputs = scalar_outputs(simulate(case, "sp"))
        assert outputs["snatch_load_cord"] == pytest.approx(speed * math.sqrt(STIFFNESS * MU), rel=1e-3)
        assert outputs["breaking_strength_cord"] == 1000.0
        rows.append(outputs)
    table = [line for line in loads_section(rows) if line.startswith("| cord | opening")]
    (opening,) = table
    design = float(np.percentile([r["opening_load_cord"] for r in rows], 99.87))
    assert opening.rstrip(" |").endswith(f"{1000.0 / design - 1.0:.3g}")


def _write(tmp_path):
    path = tmp_path / "tethered.toml"
    path.write_text(TETHERED)
    return path


TWO_SECTION_FULL_MASS = {"shock_cord": (454.162, 454.162), "main": (146.773, 1246.697)}
"""N: (snatch, opening) of cases/rocket/two_section.toml flown 64 s by full mass (rigid canopy), recorded with
``simulate(load_case(...), "full", duration=64.0)`` (22 s of wall time here)."""


@pytest.mark.parametrize("canopy_model", ["reduced", "rigid"])
def test_the_two_section_rocket_s_loads_under_sp_are_full_mass_s_within_two_percent(canopy_model):
    """The shock cord's snatch and the main's opening load at the chute release (the main's own first peak, as
    its bundle comes out, rests on the confluence's mass: docs/models/deployment_loads.md)."""
    case = load_case(ROOT / "cases" / "rocket" / "two_section.toml", {"systems.main.canopy_model": canopy_model})
    loads = {d.system: d for d in simulate(case, "sp", duration=64.0).summary.deployments}
    cord, main = TWO_SECTION_FULL_MASS["shock_cord"], TWO_SECTION_FULL_MASS["main"]
    assert loads["shock_cord"].snatch_load == pytest.approx(cord[0], rel=0.02)
    assert loads["shock_cord"].opening_load == pytest.approx(cord[1], rel=0.02)
    assert loads["main"].opening_load == pytest.approx(main[1], rel=0.02)


AIRDROP = ROOT / "cases" / "airdrop" / "static_line.toml"
AIRDROP_FULL_MASS = {"snatch_averaged": 27820.598, "opening": 80381.154}
"""N: the snatch averaged over 20 ms (``physics.load_peaks.averaged_peak`` within 0.4 s of line stretch) and the
opening load of cases/airdrop/static_line.toml flown 4.5 s by full mass, recorded with ``simulate(load_case(AIRDROP),
"full", duration=4.5)`` (17 s of wall time here; its raw first peak, 29511.7 N, carries the confluence's chatter)."""


def test_a_static_line_comes_to_line_stretch_by_the_kinematics_with_the_canopy_at_the_aircraft_s_speed():
    """Without the container's drag it falls straight away from the anchor 1.5 m above it (the aircraft and the
    container keep the release's horizontal velocity): line stretch at d(t) = 1.5 + g t^2 / 2 = reach, and the canopy,
    held back by the bag, starts at the aircraft's 67 m/s through the still air."""
    case = load_case(AIRDROP, ["bodies.vehicle.aerodynamics.enabled=false"])
    result = simulate(case, "sp", duration=3.0)
    (deploy,) = [e for e in result.summary.events if e.kind == "deploy"]
    reach = deploy.trigger["threshold"]
    start = case.bodies[case.vehicle].initial
    gravity = math.hypot(*case.start.gravity_scalar(*case.start.local_position(start.altitude, 0.0, 0.0)))
    assert deploy.time == pytest.approx(math.sqrt(2.0 * (reach - 1.5) / gravity), rel=1e-3)
    (deployment,) = result.summary.deployments
    assert deployment.line_stretch_time == deploy.time
    assert deployment.line_stretch_speed == pytest.approx(67.0, abs=1e-9)


def test_the_airdrop_s_loads_under_sp_are_full_mass_s():
    """The opening load within 2 %; the snatch, as a load cell averaging over 20 ms reads it, within 2.5 %: the canopy
    held at the aircraft's speed jerks the lines into a hump of 0.2 s, on which the full-mass confluence chatters
    between its bridles at hundreds of hertz, a mode SP leaves out by design (docs/models/deployment_loads.md,
    "Static line": the raw first peaks differ by 7 %, the averaged ones by 2.0 %, by 0.1 % on a single sling)."""
    from pchute_exudyn.physics.load_peaks import averaged_peak
    result = simulate(load_case(AIRDROP), "sp", duration=4.5)
    (deployment,) = result.summary.deployments
    times, loads = result.loads["main"]
    averaged = averaged_peak(times, loads, deployment.line_stretch_time, 0.4, 0.02)
    assert deployment.opening_load == pytest.approx(AIRDROP_FULL_MASS["opening"], rel=0.02)
    assert averaged == pytest.approx(AIRDROP_FULL_MASS["snatch_averaged"], rel=0.025)
    assert deployment.knacke_opening_load == pytest.approx(AIRDROP_FULL_MASS["opening"], rel=0.05)


SKYDIVER = ROOT / "cases" / "skydiver" / "pilot_chute.toml"
SKYDIVER_FULL_MASS = {"opening": 17645.592, "snatch_averaged": 13090.619}
"""N: the opening load (the snatch of the canopy held back by the pilot chute, the largest) and the snatch averaged
over 20 ms (``physics.load_peaks.averaged_peak`` within 0.4 s of line stretch) of cases/skydiver/pilot_chute.toml
flown 3 s by full mass, recorded with ``simulate(load_case(SKYDIVER), "full", duration=3.0)`` (3 s of wall time
here)."""


def test_a_pilot_chute_comes_to_line_stretch_at_its_reach_with_the_canopy_at_its_velocity():
    """The skydiver's centre of mass is the bridle, the canopy's reach and the deploy point's offset from the pilot
    chute's at the deploy event (the columns at that time; the gear not packed in the skydiver, so his column is
    the centre the trigger sensed); the canopy starts with the pilot chute's velocity, and fills at the skydiver's
    speed through the still air then."""
    result = simulate(load_case(SKYDIVER, ["systems.main.packed=false"]), "sp", duration=1.0)
    (deploy,) = [e for e in result.summary.events if e.kind == "deploy"]
    columns = result.columns
    (row,) = np.flatnonzero(columns["time"] == deploy.time)
    apart = [columns[f"pilot_chute_{axis}"][row] - columns[f"vehicle_{axis}"][row]
             for axis in ("altitude", "east", "north")]
    assert deploy.time > 0.5   # after the throw
    assert math.hypot(*apart) == pytest.approx(deploy.trigger["threshold"], rel=1e-3)
    for axis in ("north", "east", "down"):
        assert columns[f"canopy_velocity_{axis}"][row] == pytest.approx(columns[f"pilot_chute_velocity_{axis}"][row],
                                                                        abs=1e-9)
    (deployment, _) = result.summary.deployments
    assert deployment.line_stretch_speed == pytest.approx(
        math.hypot(*[columns[f"vehicle_velocity_{axis}"][row] for axis in ("north", "east", "down")]), rel=1e-9)


def test_the_skydiver_s_loads_under_sp_are_full_mass_s():
    """The opening load (the snatch of the canopy held back near the air's speed) and the snatch as a load cell
    averaging over 20 ms reads it, within 2 % of full mass's (docs/models/deployment_loads.md, "Pilot chute")."""
    from pchute_exudyn.physics.load_peaks import averaged_peak
    result = simulate(load_case(SKYDIVER), "sp", duration=3.0)
    deployment = {d.system: d for d in result.summary.deployments}["main"]
    times, loads = result.loads["main"]
    averaged = averaged_peak(times, loads, deployment.line_stretch_time, 0.4, 0.02)
    assert deployment.opening_load == pytest.approx(SKYDIVER_FULL_MASS["opening"], rel=0.02)
    assert averaged == pytest.approx(SKYDIVER_FULL_MASS["snatch_averaged"], rel=0.02)

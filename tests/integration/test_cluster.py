"""Clusters (docs/models/cluster.md): every canopy its own body on its own riser, canopy-canopy contact, the cluster
drag efficiency and the failures a parachute system is qualified against. Closed forms through the engine with every
method, the kernels against direct formulas, and the PA1 cluster's SP run against full mass."""

import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.physics.cluster import (
    DEFAULT_DRAG_EFFICIENCY,
    drag_efficiency,
    flyout_angles,
    load_share,
    spread_directions,
    touching_spread,
)
from pchute_exudyn.physics.contact import contact_forces, default_stiffness_damping, envelope_radius, overlaps
from pchute_exudyn.physics.deployment import cluster_placement
from pchute_exudyn.physics.inflation import Inflation, InflationStage, skipping, with_disreef_delays
from pchute_exudyn.results.summary import CutawayEvent
from tests.helpers import ROOT, study_runs

CASES = ROOT / "tests" / "cases"
PAIR, SINGLE, TRIO, BUMP = (CASES / f"{name}.toml" for name in ("cluster_pair", "cluster_pair_as_one",
                                                                 "cluster_trio", "canopy_bump"))
PA1_CLUSTER = ROOT / "cases" / "cev_pa1_cluster.toml"
MAIN_OUT = ROOT / "cases" / "cev_pa1_cluster_main_out.toml"
MAINS = ("main1", "main2", "main3")
RHO = 0.02                                   # kg/m^3, tests/cases/constant_air.csv
G = 9.81


# -- kernels ---------------------------------------------------------------------------------------------------------

def test_contact_kernel_pushes_along_the_centre_line_and_never_pulls():
    motion = np.array([[0.0, 0.0, 0.0, 1.0, 0.0, 0.0], [9.0, 0.0, 0.0, -1.0, 0.0, 0.0], [30.0, 0.0, 0.0, 0, 0, 0]])
    radii, forces = np.array([5.0, 5.0, 5.0]), np.zeros((3, 3))
    pairs = np.array([[0, 1, 1000.0, 50.0], [0, 2, 1000.0, 50.0], [1, 2, 1000.0, 50.0]])
    deepest = contact_forces(motion, radii, pairs, forces)
    assert deepest == pytest.approx(1.0)                                       # 5 + 5 - 9
    assert forces[0].tolist() == pytest.approx([-(1000.0 * 1.0 + 50.0 * 2.0), 0.0, 0.0])   # closing at 2 m/s
    assert forces[1].tolist() == pytest.approx([1000.0 * 1.0 + 50.0 * 2.0, 0.0, 0.0])
    assert forces[2].tolist() == [0.0, 0.0, 0.0]                               # 21 m away: untouched
    motion[0, 3], motion[1, 3] = -20.0, 20.0                                   # parting fast: the damper would pull
    contact_forces(motion, radii, pairs, forces)
    assert not forces.any()
    motion[1, :3] = motion[0, :3]                                              # coincident: no direction, no force
    contact_forces(motion, radii, pairs, forces)
    assert not forces[:2].any()


def test_envelope_radius_and_overlap_forms_agree():
    fractions = np.array([0.0, 0.08, 0.25, 1.1, -0.01])
    assert envelope_radius(12.0, fractions).tolist() == pytest.approx([envelope_radius(12.0, float(f))
                                                                       for f in fractions])
    assert envelope_radius(12.0, 0.25) == 6.0 and envelope_radius(12.0, -1.0) == 0.0
    a, b = np.zeros((2, 3)), np.array([[9.0, 0.0, 0.0], [12.0, 0.0, 0.0]])
    assert overlaps(a, b, [5.0, 5.0], [5.0, 5.0]).tolist() == [1.0, -2.0]
    stiffness, damping = default_stiffness_damping(10.0, 10.0)
    assert math.sqrt(stiffness / 5.0) == pytest.approx(2 * math.pi * 5.0)     # 5 Hz on the reduced mass
    assert damping == pytest.approx(0.5 * 2 * math.sqrt(stiffness * 5.0))


def test_cluster_geometry_flyout_load_share_and_efficiency():
    theta = math.radians(16.0)
    directions = spread_directions([0, 0, -1], [1, 0, 0], theta, 3)
    centres = -50.0 * np.array(directions)                                      # canopies 50 m up their risers
    assert flyout_angles(np.zeros((1, 3)), centres[None]).ravel() == pytest.approx([16.0] * 3)
    spread = touching_spread(12.0, 50.0, 3)
    touching = -50.0 * np.array(spread_directions([0, 0, -1], [1, 0, 0], spread, 3))
    assert np.linalg.norm(touching[0] - touching[1]) == pytest.approx(24.0)   # just touching: 2 r apart
    assert touching_spread(12.0, 50.0, 1) == 0.0
    assert math.sin(touching_spread(3.0, 20.0, 2)) == pytest.approx(3.0 / 20.0)
    tensions = np.array([[10.0, 10.0, 10.0], [30.0, 0.0, 0.0], [5.0, 15.0, np.nan], [0.0, 0.0, 0.0]])
    assert load_share(tensions)[:3].tolist() == pytest.approx([1.0, 3.0, 1.5])
    assert np.isnan(load_share(tensions)[3])
    assert drag_efficiency(DEFAULT_DRAG_EFFICIENCY, 1) == 1.0
    assert drag_efficiency((1.0, 0.9), 5) == 0.9                               # held beyond the table


def test_cluster_placement_puts_every_riser_at_free_length_on_the_cone():
    risers = [(12.0, (35.0, 0.0, 0.0))] * 3
    confluence, _, canopies = cluster_placement(np.zeros(3), np.eye(3), np.array([40.0, 0, -5.0]), np.zeros(3),
                                                (-4.0, 0.0, 0.0), np.array([40.0, 0.0, -5.0]), risers,
                                                math.radians(15.0))
    axis = np.array([40.0, 0.0, -5.0]) / np.linalg.norm([40.0, 0.0, -5.0])
    for position, attitude, _ in canopies:
        attach = position + attitude @ np.array([35.0, 0.0, 0.0])
        assert np.linalg.norm(attach - confluence) == pytest.approx(12.0)
        assert np.degrees(np.arccos(attitude[:, 0] @ axis)) == pytest.approx(15.0)   # +x along its own riser
        assert attitude.T @ attitude == pytest.approx(np.eye(3))


def test_skipped_stages_and_cutter_delays():
    law = Inflation((InflationStage(0.0, 0.08, 1.0, 2.0), InflationStage(8.0, 0.25, 0.8, 2.0),
                     InflationStage(16.0, 1.0, 0.9, 2.0)), overinflation=1.1, overinflation_decay=1.0)
    assert [s.start for s in with_disreef_delays(law, (-1.5, 0.5)).stages] == [0.0, 6.5, 16.5]
    assert with_disreef_delays(law, (0.0, 0.0)) == law                         # zero delays change nothing
    skipped = skipping(law, [2])
    assert [(s.start, s.fraction, s.fill_constant) for s in skipped.stages] == [(0.0, 0.08, 1.0), (8.0, 1.0, 0.9)]
    assert [s.start for s in skipping(law, [1, 2]).stages] == [0.0]            # straight to full at line stretch
    with pytest.raises(ValueError, match="full canopy"):
        skipping(law, [3])
    with pytest.raises(ValueError, match="out of order"):
        with_disreef_delays(law, (9.0, 0.0))


# -- closed forms through the engine -----------------------------------------------------------------------------------

def _rate(result, seconds: float = 5.0) -> float:
    """The payload's mean rate of descent (m/s) over the run's last ``seconds``."""
    window = result["time"] >= result["time"][-1] - seconds
    return float(np.mean(result["payload_velocity_down"][window]))


@pytest.mark.parametrize("method, integrator, duration", [("sp", "rk4", None), ("full", "implicit", None),
                                                          ("equilibrium", "rk4", None), ("full", "rk4", 4.0)])
def test_two_identical_canopies_share_the_load_exactly_and_fly_as_one_of_twice_the_size(method, integrator, duration):
    pair = pc.simulate(pc.load_case(PAIR), method, integrator, duration=duration)
    tension = np.stack([pair["tension_r1"], pair["tension_r2"]])
    assert np.nanmax(np.abs(tension[0] - tension[1])) <= 1e-9 * np.nanmax(tension)   # mirror-symmetric start
    assert pair.summary.cluster["main"].flyout_deg["c1"]["max"] == pytest.approx(10.0, rel=0.05)
    if duration is not None:
        return
    assert np.nanmax(np.abs(pair["c1_flyout_deg"][-500:])) < 0.01            # swung in onto the cluster axis
    one = pc.simulate(pc.load_case(SINGLE), method, integrator)
    assert _rate(pair) == pytest.approx(_rate(one), rel=1e-4)
    massless = method == "equilibrium" or (method == "sp" and pair.summary.method_settings["sp_order"] == 0)
    weight = (200.0 + 2 * 10.0 + (0.0 if massless else 0.5)) * G
    assert _rate(pair) == pytest.approx(math.sqrt(2 * weight / (RHO * 0.8 * 200.0)), rel=1e-4)


def test_two_of_three_canopies_descend_faster_by_the_square_root_of_the_drag_ratio():
    """Contact off: the canopies swing onto the cluster axis, so only the count, the weight and eta differ."""
    rates = {}
    for failed in ("", "c3"):
        case = pc.load_case(TRIO, {"failures.not_inflated": failed})
        rates[failed] = _rate(pc.simulate(case, "sp"))
    eta3, eta2 = DEFAULT_DRAG_EFFICIENCY[2], DEFAULT_DRAG_EFFICIENCY[1]
    # the failed canopy stays packed in the payload, so the weight is the same: sqrt(3/2) but for eta
    assert rates["c3"] / rates[""] == pytest.approx(math.sqrt(1.5) * math.sqrt(eta3 / eta2), rel=1e-4)


@pytest.mark.parametrize("method, integrator", [("sp", "rk4"), ("full", "rk4"), ("full", "implicit"),
                                                ("equilibrium", "rk4")])
def test_canopies_pushed_together_bounce_apart_within_the_documented_overlap(method, integrator):
    result = pc.simulate(pc.load_case(BUMP), method, integrator)
    stiffness, reduced, closing = 1000.0, 5.0, 2.0
    bound = closing * math.sqrt(reduced / stiffness)                           # undamped: v sqrt(mu / k)
    assert np.nanmax(result["c1_c2_overlap"]) == pytest.approx(bound, rel=1e-3)
    assert result["c1_velocity_east"][-1] == pytest.approx(-1.0, rel=1e-4)      # elastic: they part as they met
    assert result["c2_velocity_east"][-1] == pytest.approx(1.0, rel=1e-4)
    events = [e for e in result.summary.events if e.kind.startswith("contact")]
    assert [e.kind for e in events] == ["contact_start", "contact_end"]
    assert events[0].time == pytest.approx(1.0, abs=2e-3)
    assert events[1].time - events[0].time == pytest.approx(math.pi * math.sqrt(reduced / stiffness), rel=1e-2)
    assert events[1].overlap == pytest.approx(bound, rel=1e-3)


def test_damped_contact_overlaps_less_and_still_parts():
    result = pc.simulate(pc.load_case(BUMP, {"main.contact.damping": 60.0}), "sp")
    assert 0.0 < np.nanmax(result["c1_c2_overlap"]) < 2.0 * math.sqrt(5.0 / 1000.0)
    assert 0.0 < result["c2_velocity_east"][-1] < 1.0                            # lost speed, but apart
    assert result["c1_c2_overlap"][-1] < 0.0


def test_a_cluster_without_contact_lets_canopies_pass_through_each_other():
    result = pc.simulate(pc.load_case(BUMP, {"main.contact.enabled": False, "simulation.duration": 8.0}), "sp")
    assert "c1_c2_overlap" not in result.columns
    assert result["c1_east"][-1] == pytest.approx(2.0) and result["c2_east"][-1] == pytest.approx(-2.0)   # crossed


# -- failures ----------------------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def pa1_cluster_sp():
    return pc.simulate(pc.load_case(PA1_CLUSTER), "sp")


@pytest.fixture(scope="module")
def pa1_main_out_sp():
    return pc.simulate(pc.load_case(MAIN_OUT), "sp")


@pytest.mark.long
def test_pa1_cluster_sp_agrees_with_full_mass(pa1_cluster_sp):
    """Full mass implicit here (about 6 s); full mass RK4 in validation/cev_pa1_cluster.py."""
    full = pc.simulate(pc.load_case(PA1_CLUSTER), "full", "implicit")
    touchdown = {name: r.summary.touchdown.time for name, r in (("sp", pa1_cluster_sp), ("full", full))}
    assert abs(touchdown["sp"] - touchdown["full"]) < 0.2
    for canopy in ("main1", "main2", "main3"):
        sp_peak = pa1_cluster_sp.summary.cluster["main"].riser_peak[canopy]["tension"]
        full_peak = full.summary.cluster["main"].riser_peak[canopy]["tension"]
        assert sp_peak == pytest.approx(full_peak, rel=0.03)


def test_pa1_cluster_outputs(pa1_cluster_sp):
    r, summary = pa1_cluster_sp, pa1_cluster_sp.summary
    for column in ("main_load_share", "main1_flyout_deg", "main1_main2_overlap", "drogue1_drogue2_overlap",
                   "main2_drag_area_fraction", "capsule_pendulum_deg", "capsule_pendulum_airspeed_deg"):
        assert column in r.columns
    main = summary.cluster["main"]
    assert 1.0 <= main.peak_load_share < 3.0
    for canopy in ("main1", "main2", "main3"):   # evenly spread: the same flyout, the touching angle of the envelopes
        assert main.flyout_deg[canopy]["mean"] == pytest.approx(main.flyout_deg["main1"]["mean"], rel=1e-3)
        assert 10.0 < main.flyout_deg[canopy]["mean"] < 25.0
    kinds = [e.kind for e in summary.events]
    assert "contact_start" in kinds and "contact_end" in kinds
    assert {e.canopy for e in summary.events_of("disreef")} == {"main1", "main2", "main3"}
    assert set(summary.opening_loads) == {"drogue1", "drogue2", "main1", "main2", "main3"}
    assert 0.0 < summary.pendulum.max_vertical_deg < 10.0
    assert 0.0 < max(main.max_overlap.values()) < 0.05 * 0.67 * 35.36 / 2   # within 5 % of the radius


def test_one_main_out_descends_faster_and_loads_the_other_two_more(pa1_cluster_sp, pa1_main_out_sp):
    nominal, out = pa1_cluster_sp.summary, pa1_main_out_sp.summary
    assert out.descent.mean_rate > 1.15 * nominal.descent.mean_rate
    assert out.cluster["main"].riser_peak["main3"] is None
    for canopy in ("main1", "main2"):
        assert out.cluster["main"].riser_peak[canopy]["tension"] > \
            1.2 * nominal.cluster["main"].riser_peak[canopy]["tension"]
    assert np.isnan(pa1_main_out_sp["main3_altitude"]).all()                   # never left the capsule


def test_skipped_stage_delayed_cutter_and_cutaway_of_one_canopy():
    case = pc.load_case(PA1_CLUSTER, {"failures.skipped_stages.main1": 2, "failures.disreef_delay.main2": [-2.0, 1.0],
                                      "failures.cutaway.main3": 40.0, "simulation.duration": 45.0})
    result = pc.simulate(case, "sp")
    events = result.summary.events
    disreefs = {(e.canopy, e.stage, round(e.time - 9.5, 6)) for e in result.summary.events_of("disreef")}
    assert disreefs == {("main1", 3, 8.0), ("main2", 2, 6.0), ("main2", 3, 17.0), ("main3", 2, 8.0),
                        ("main3", 3, 16.0)}                                  # a skipped stage keeps the numbers
    assert [s["stage"] for s in result.summary.opening_loads["main1"]] == [1, 3]
    full_open = result["main1_drag_area_fraction"][np.searchsorted(result["time"], 9.5 + 14.0)]
    assert full_open == pytest.approx(1.0, abs=1e-9) or full_open > 1.0         # main1 skipped its 25 % stage
    assert CutawayEvent(40.0, "main", "main3") in events
    assert max(e.time for e in result.summary.events_of("fill_end") if e.canopy == "main3") < 40.0
    after = result["time"] > 40.0
    assert np.isnan(result["tension_main_riser3"][after]).all() and np.isfinite(result["tension_main_riser1"][after]).all()
    assert np.isnan(result["main3_altitude"][after]).all()


def test_a_trailing_canopy_that_never_inflates_keeps_its_fraction():
    case = pc.load_case(PA1_CLUSTER, {"failures.not_inflated": "main2", "failures.not_inflated_model": "trailing",
                                      "failures.trailing_fraction": 0.05, "simulation.duration": 30.0})
    result = pc.simulate(case, "sp")
    present = np.isfinite(result["main2_drag_area_fraction"])
    assert present.any() and np.all(result["main2_drag_area_fraction"][present] == 0.05)
    assert np.isfinite(result["main2_altitude"][result["time"] > 10.0]).all()
    assert not [e for e in result.summary.events_of("disreef") if e.canopy == "main2"]


# -- studies -------------------------------------------------------------------------------------------------------------

CLUSTER_STUDY = f"""
[study]
name = "trio failures"
case = "{TRIO.as_posix()}"
runs = 8
seed = 2026
duration = 20.0

[[study.configurations]]
method = "sp"
steps = [1e-2]

[parameters."main.contact.enabled"]               # contact on, the canopies spread a little beyond touching
values = [true]

[parameters."main.cluster.deploy_spread_deg"]
values = [20.0]

[parameters."failures.not_inflated"]              # which canopy fails, or none
distribution = "choice"
values = ["", "c1", "c2", "c3"]
weights = [2, 1, 1, 1]

[parameters."c1.aerodynamics.axial_coefficient"]
distribution = "uniform"
low = 0.95
high = 1.05
relative = true
"""


@pytest.mark.long
def test_a_cluster_study_draws_the_failed_canopy_and_reports_load_share_flyout_and_pendulum(tmp_path):
    from pchute_exudyn.study import dask_executor, load_study, run_study
    from pchute_exudyn.study.report import study_report

    path = tmp_path / "study.toml"
    path.write_text(CLUSTER_STUDY)
    spec = load_study(path)
    drawn = [run.values["failures.not_inflated"] for run in spec.expand()]
    assert set(drawn) <= {"", "c1", "c2", "c3"} and len(set(drawn)) > 1
    run_study(spec, tmp_path / "two", workers=2, progress=False)
    executor, close = dask_executor(local_workers=2)          # a real LocalCluster, two worker processes
    try:
        run_study(spec, tmp_path / "dask", executor=executor, progress=False)
    finally:
        close()
    rows = study_runs(tmp_path / "two")
    assert study_runs(tmp_path / "dask") == rows and all(row["status"] == "ok" for row in rows)
    for row in rows:                                           # a failed canopy has no flyout; the others do
        for canopy in ("c1", "c2", "c3"):
            assert (row[f"max_flyout_{canopy}"] == "") == (row["failures.not_inflated"] == canopy)
        assert 1.0 <= float(row["peak_load_share_main"]) <= (3.0 if row["failures.not_inflated"] == "" else 2.0)
    rates = {row["failures.not_inflated"]: float(row["descent_rate"]) for row in rows}
    assert max(v for k, v in rates.items() if k) > rates.get("", min(rates.values()))   # two canopies: faster
    report = (study_report(tmp_path / "two")["report"]).read_text()
    for output in ("peak_load_share_main (-)", "max_flyout_main (deg)", "pendulum_max_deg (deg)",
                   "descent_rate (m/s)", "## By failures.not_inflated"):
        assert output in report


def test_a_system_whose_canopies_all_stay_packed_deploys_nothing():
    lumped = ROOT / "cases" / "cev_pa1.toml"
    case = pc.load_case(lumped, {"failures.not_inflated": "main_canopy"})
    assert case.mass_of("capsule", 9.0) == 7500.0 and case.mass_of("capsule", 9.5) == 7500.0 + 423.0
    result = pc.simulate(case, "sp")
    assert np.isnan(result["main_confluence_altitude"]).all() and np.isnan(result["tension_main_riser"]).all()
    assert not [e for e in result.summary.events_of("deploy") if e.system == "main"]
    assert result.summary.events[-1].kind == "touchdown"   # fast, under nothing but the capsule's own drag


def test_canopies_that_trim_off_axis_fly_out_by_their_own_aerodynamics():
    """Contact off: a stable canopy (C_N > 0 off zero) swings onto the cluster axis (the pair test above); one whose
    C_N changes sign at 8 deg flies out near that angle and stays there."""
    trimming = {f"{c}.aerodynamics.normal_coefficient.{key}": value for c in ("c1", "c2")
                for key, value in (("alpha_deg", [0.0, 8.0, 16.0, 90.0]), ("value", [-0.06, 0.0, 0.06, 0.0]))}
    result = pc.simulate(pc.load_case(PAIR, trimming), "sp")
    late = result["time"] > 30.0
    assert 6.0 < np.min(result["c1_flyout_deg"][late]) and np.max(result["c1_flyout_deg"][late]) < 12.0
    assert result["c1_flyout_deg"][-1] == pytest.approx(result["c2_flyout_deg"][-1], rel=1e-9)


def test_apparent_mass_and_turbulence_on_every_canopy_of_a_cluster():
    """The canopy features work per canopy of a cluster: apparent mass on each main, PA1's wind and turbulence;
    SP against full mass implicit on each main's riser peak."""
    over = {"simulation.duration": 25.0}
    for canopy in MAINS:
        over.update({f"{canopy}.apparent_mass.{key}": value for key, value in
                     (("projected_radius", 11.85), ("axial", 1.0), ("lateral", 0.5), ("rotational", 0.1))})
    case = pc.load_case(ROOT / "cases" / "cev_pa1_cluster_winds.toml", over)
    peaks = {}
    for method, integrator in (("sp", "rk4"), ("full", "implicit")):
        summary = pc.simulate(case, method, integrator).summary
        peaks[method] = [summary.cluster["main"].riser_peak[c]["tension"] for c in MAINS]
    assert peaks["sp"] == pytest.approx(peaks["full"], rel=0.03)


def test_a_canopy_cut_away_while_it_fills_reports_no_fill_end():
    case = pc.load_case(PA1_CLUSTER, {"failures.cutaway.main2": 9.5 + 16.5, "simulation.duration": 30.0})
    events = pc.simulate(case, "sp").summary.events
    main2 = [(e.kind, e.stage) for e in events if getattr(e, "canopy", None) == "main2" and hasattr(e, "stage")]
    assert ("disreef", 3) in main2 and ("fill_end", 3) not in main2          # cut 0.5 s into its last fill
    assert ("fill_end", 3) in [(e.kind, e.stage) for e in events if getattr(e, "canopy", None) == "main1"
                               and hasattr(e, "stage")]

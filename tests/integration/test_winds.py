"""Winds, Dryden turbulence and gusts (docs/models/winds.md): the generated turbulence's statistics against the
Dryden forms, reproducibility from the seed, no turbulence leaving runs exactly as they were, a gust's drift against
its closed form, and the landing footprint's statistics."""

import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.physics.air import AirMotion
from pchute_exudyn.physics.wind import (
    FOOT,
    DrydenTurbulence,
    Gust,
    PowerLawWind,
    dryden_correlation,
    gust_velocity,
    low_altitude_scales,
    wind_from_direction,
)
from pchute_exudyn.study.footprint import footprint_statistics
from tests.helpers import ROOT, study_runs

PA1_WINDS = ROOT / "cases" / "cev_pa1_winds.toml"
SIGMA, LENGTH = (2.0, 1.5, 1.0), (120.0, 120.0, 60.0)


def sample_correlation(x: np.ndarray, lag: int) -> float:
    x = x - x.mean()
    return float(np.mean(x[:-lag] * x[lag:]) / x.var())


@pytest.mark.parametrize("seed", [3, 11])
def test_dryden_variance_and_correlation_at_one_scale_length(seed):
    """Over 3000 scale lengths of record (a variance estimate good to about 3 %), each component's variance is
    within 10 % of sigma^2 and its correlation at a lag of one scale length within 0.1 of the Dryden value:
    exp(-1) = 0.368 for u, exp(-1) / 2 = 0.184 for v and w."""
    turbulence = DrydenTurbulence(seed, sigma=SIGMA, length=LENGTH)
    turbulence.components(3000 * max(LENGTH))
    for k, component in enumerate("uvw"):
        record = np.array(turbulence.values[k])
        assert record.var() == pytest.approx(SIGMA[k] ** 2, rel=0.10)
        lag = round(LENGTH[k] / turbulence.cell)
        expected = dryden_correlation(component, LENGTH[k], LENGTH[k])
        assert abs(sample_correlation(record, lag) - expected) < 0.1
        # and the shape: at half and twice the scale length too
        for factor in (0.5, 2.0):
            lag = round(factor * LENGTH[k] / turbulence.cell)
            assert abs(sample_correlation(record, lag) - dryden_correlation(component, factor * LENGTH[k],
                                                                           LENGTH[k])) < 0.1


def test_a_descending_body_sees_the_dryden_correlation_in_time():
    """Frozen along the height: a point descending at V sees correlation exp(-1) for u at a lag of L_u / V
    seconds. Sampled through AirMotion, with the mean wind from the west orienting u east."""
    class Start:   # a non-rotating start frame is all AirMotion needs
        import numpy as _np
        rotation_vector, planet_center = _np.zeros(3), _np.array([0.0, 0.0, -6.4e6])

        class planet:
            rotation_rate = 0.0
    turbulence = DrydenTurbulence(5, sigma=SIGMA, length=LENGTH)
    air = AirMotion(Start, PowerLawWind(4.0, 0.0, 10.0, 0.0), turbulence)
    speed, dt = 8.0, 0.25                                  # m/s, s
    times = np.arange(0.0, 3000 * LENGTH[0] / speed, dt)
    altitudes = 1000.0 + 3000 * LENGTH[0] - speed * times
    east = np.array([air(0.0, 0.0, h, h, t)[0] for h, t in zip(altitudes, times)]) - 4.0
    assert east.var() == pytest.approx(SIGMA[0] ** 2, rel=0.10)
    assert abs(sample_correlation(east, round(LENGTH[0] / speed / dt)) - math.exp(-1.0)) < 0.1


def test_low_altitude_forms():
    """MIL-F-8785C low altitude: at 1000 ft every intensity is 0.1 W20 and every scale 1000 ft; at 100 ft
    L_w = 100 ft, L_u = 100 / (0.177 + 0.0823)^1.2 ft; above 2000 ft the scales are 1750 ft."""
    (su, sv, sw), (lu, lv, lw) = low_altitude_scales(1000 * FOOT, 10.0)
    assert (su, sv, sw) == pytest.approx((1.0, 1.0, 1.0)) and (lu, lv, lw) == pytest.approx((1000 * FOOT,) * 3)
    (su, _, sw), (lu, _, lw) = low_altitude_scales(100 * FOOT, 10.0)
    assert sw == pytest.approx(1.0) and su == pytest.approx(1.0 / 0.2593 ** 0.4)
    assert lw == pytest.approx(100 * FOOT) and lu == pytest.approx(100 / 0.2593 ** 1.2 * FOOT)
    assert low_altitude_scales(5000.0, 10.0)[1] == pytest.approx((1750 * FOOT,) * 3)
    assert low_altitude_scales(0.0, 10.0) == low_altitude_scales(10 * FOOT, 10.0)


def test_steady_wind_forms_and_gust_pulse():
    assert wind_from_direction(5.0, 270.0) == pytest.approx((5.0, 0.0))        # from the west: blows east
    assert wind_from_direction(5.0, 0.0) == pytest.approx((0.0, -5.0))         # from the north: blows south
    profile = PowerLawWind(4.0, 3.0, 10.0, 0.25, ground_altitude=1200.0)
    assert profile.at(1210.0) == pytest.approx((4.0, 3.0))
    assert profile.at(1360.0) == pytest.approx((4.0 * 16 ** 0.25, 3.0 * 16 ** 0.25))
    assert profile.at(1190.0) == (0.0, 0.0)
    gust = Gust(6.0, 10.0, 4.0, (0.0, 1.0, 0.0))
    assert gust_velocity([gust], 12.0) == pytest.approx((0.0, 6.0, 0.0))      # the peak at mid-pulse
    assert gust_velocity([gust], 9.99) == (0.0, 0.0, 0.0) and gust_velocity([gust], 14.01) == (0.0, 0.0, 0.0)
    mean = np.mean([gust.speed(t) for t in np.linspace(10.0, 14.0, 4001)])
    assert mean == pytest.approx(3.0, rel=1e-3)                                 # A/2 over T


def short_pa1(**overrides):
    return pc.load_case(PA1_WINDS, {"simulation.duration": 12.0, **overrides})


def test_same_seed_same_run_bitwise_another_seed_another_run():
    first = pc.simulate(short_pa1(), "sp", "rk4", 1e-2)
    again = pc.simulate(short_pa1(), "sp", "rk4", 1e-2)
    other = pc.simulate(short_pa1(**{"atmosphere.turbulence.seed": 2}), "sp", "rk4", 1e-2)
    for key in ("capsule_altitude", "capsule_east", "tension_main_riser" if "tension_main_riser" in first.columns
                else "tension_drogue_riser", "capsule_turbulence_east"):
        assert np.array_equal(first.columns[key], again.columns[key], equal_nan=True), key
    assert not np.array_equal(first.columns["capsule_turbulence_east"], other.columns["capsule_turbulence_east"])
    assert not np.array_equal(first.columns["capsule_east"], other.columns["capsule_east"])


def test_no_turbulence_leaves_the_run_exactly_as_it_was():
    """Zero intensities and a zero-amplitude gust: bitwise the run of the same case without them (the steady
    wind's own path)."""
    base = short_pa1(**{"atmosphere.turbulence.wind_speed_6m": 0.0})
    still = pc.load_case(ROOT / "cases" / "cev_pa1.toml", {
        "simulation.duration": 12.0, "atmosphere.wind.profile": "power_law", "atmosphere.wind.speed": 5.0,
        "atmosphere.wind.from_deg": 270.0, "atmosphere.wind.reference_height": 10.0,
        "atmosphere.wind.exponent": 0.142857})
    a = pc.simulate(base, "sp", "rk4", 1e-2)
    b = pc.simulate(still, "sp", "rk4", 1e-2)
    for key in b.columns:
        if not key.endswith(("_turbulence_east", "_turbulence_north", "_turbulence_up")):
            assert np.array_equal(a.columns[key], b.columns[key], equal_nan=True), key
    assert np.all(np.nan_to_num(a.columns["capsule_turbulence_up"]) == 0.0)


def test_a_sideways_gust_drifts_the_capsule_by_its_integral():
    """A capsule under its full mains hit by a north 1 - cos gust (A = 5 m/s, T = 4 s from 40 s): the lateral
    velocity follows the air through a stable response of unit static gain (the drag acts on the velocity relative
    to the air), so the extra drift settles at the gust's integral, A T / 2 = 10 m (final value theorem:
    x(inf) = G(0) W(0)). The system swings about its new track with a period of about 14 s and little damping, so
    the settled value is the mean over 50-69 s, more than one swing after the gust."""
    case = pc.load_case(ROOT / "cases" / "cev_pa1.toml", {"simulation.duration": 70.0})
    calm = pc.simulate(case, "sp", "rk4", 1e-2)
    windy_case = pc.load_case(ROOT / "tests" / "data" / "pa1_gust.toml", {"simulation.duration": 70.0})
    windy = pc.simulate(windy_case, "sp", "rk4", 1e-2)
    t = calm.columns["time"]
    settled = (t >= 50.0) & (t <= 69.0)
    for body in ("capsule", "main_canopy"):
        drift = windy.columns[f"{body}_north"] - calm.columns[f"{body}_north"]
        assert np.all(np.nan_to_num(drift[t < 40.0]) == 0.0)   # NaN: the mains not yet deployed
        assert drift[settled].mean() == pytest.approx(0.5 * 5.0 * 4.0, rel=0.10), body
        assert np.nanmax(np.abs(np.gradient(drift, t))) < 5.0   # never faster than the gust's peak


def test_footprint_statistics_of_a_known_normal_spread():
    """4000 points of a normal with principal deviations 300 m and 100 m, major axis 30 deg east of north:
    recovered within a few per cent, and the ellipses hold their normal shares of the points."""
    rng = np.random.default_rng(1)
    angle = math.radians(30.0)
    major, minor = np.array([math.sin(angle), math.cos(angle)]), np.array([math.cos(angle), -math.sin(angle)])
    points = np.array([500.0, -200.0]) + np.outer(rng.normal(0, 300.0, 4000), major) + \
        np.outer(rng.normal(0, 100.0, 4000), minor)
    stats = footprint_statistics(points)
    assert stats["mean_east"] == pytest.approx(500.0, abs=15.0) and stats["mean_north"] == pytest.approx(-200.0,
                                                                                                         abs=15.0)
    assert stats["sigma_major"] == pytest.approx(300.0, rel=0.05)
    assert stats["sigma_minor"] == pytest.approx(100.0, rel=0.05)
    assert stats["major_axis_azimuth_deg"] == pytest.approx(30.0, abs=2.0)
    for e in stats["ellipses"].values():
        assert e["share_inside"] == pytest.approx(e["normal_share"], abs=0.03)


FOOTPRINT = f"""
[study]
name = "PA1 footprint (small)"
case = "{PA1_WINDS.as_posix()}"
runs = 4
seed = 7

[[study.configurations]]
method = "sp"
steps = [1e-2]

[parameters."atmosphere.wind.speed"]
distribution = "truncated_normal"
mean = 5.0
std = 2.0
low = 0.0
high = 12.0

[parameters."atmosphere.wind.from_deg"]
distribution = "normal"
mean = 270.0
std = 30.0

[parameters."atmosphere.turbulence.seed"]
distribution = "seed"

[parameters."main_canopy.aerodynamics.axial_coefficient"]
distribution = "uniform"
low = 0.95
high = 1.05
relative = true
"""


@pytest.mark.long
def test_footprint_study_same_on_one_and_two_workers_and_dask_and_reported(tmp_path):
    """A small version of validation/studies/pa1_footprint.toml: per-run turbulence seeds from the study's seed
    sequence, identical stored results on 1 and 2 worker processes and a Dask LocalCluster, and a report with the
    landing footprint."""
    from pchute_exudyn.study import dask_executor, load_study, run_study
    from pchute_exudyn.study.report import study_report

    path = tmp_path / "footprint.toml"
    path.write_text(FOOTPRINT)
    spec = load_study(path)
    seeds = [run.values["atmosphere.turbulence.seed"] for run in spec.expand()]
    assert all(isinstance(s, int) for s in seeds) and len(set(seeds)) == 4
    run_study(spec, tmp_path / "one", workers=1, progress=False)
    run_study(spec, tmp_path / "two", workers=2, progress=False)
    executor, close = dask_executor(local_workers=2)
    try:
        run_study(spec, tmp_path / "dask", executor=executor, progress=False)
    finally:
        close()
    one = study_runs(tmp_path / "one")
    assert len(one) == 4 and all(row["status"] == "ok" and row["touchdown_time"] for row in one)
    assert study_runs(tmp_path / "two") == one and study_runs(tmp_path / "dask") == one
    paths = study_report(tmp_path / "one")
    assert paths["footprint"].is_file() and paths["touchdown"].is_file()
    report = paths["report"].read_text()
    assert "## Landing footprint" in report and "| 3 sigma |" in report and "peak_tension_main_riser (N)" in report
    east = np.array([float(row["final_east"]) for row in one])
    assert east.std() > 10.0                                       # the winds do disperse the landing point


def test_footprint_of_a_study_where_only_some_runs_land(tmp_path):
    """A study over two cases of which only one touches down (different lines in each): the footprint uses the
    landed runs and their lines only."""
    from pchute_exudyn.study.report import study_report
    rows = ["run,status,reference,case,final_east,final_north,touchdown_time,touchdown_speed,peak_tension_a,"
            "peak_tension_b"]
    rng = np.random.default_rng(3)
    for i in range(5):
        rows.append(f"{i},ok,False,landing,{rng.normal(100, 30):.3f},{rng.normal(0, 20):.3f},70,7.5,{1000 + i},")
    for i in range(5, 8):
        rows.append(f"{i},ok,False,flying,{rng.normal(0, 3):.3f},{rng.normal(0, 3):.3f},,,,{200 + i}")
    (tmp_path / "runs.csv").write_text("\n".join(rows) + "\n")
    paths = study_report(tmp_path)
    report = paths["report"].read_text()
    assert "5 touchdowns" in report and "peak_tension_a (N)" in report
    assert "peak_tension_b (N) |" not in report.split("## Landing footprint")[1]

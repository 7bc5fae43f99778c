"""Space-filling designs for studies (Latin hypercube, scrambled Sobol), truncated normals by inverse CDF, how sure
the reported percentiles are, the input ranking, and the study table as a DataFrame."""

import numpy as np
import pytest

from pchute_exudyn.study import dask_executor, load, load_study, run_study
from pchute_exudyn.study.report import study_report
from pchute_exudyn.study.statistics import bootstrap_interval, rank_correlations, runs_needed
from tests.helpers import MER, study_runs

DESIGN = f"""
[study]
name = "design"
case = "{(MER / 'case1.toml').as_posix()}"
runs = {{runs}}
seed = 11
duration = 2.0
sampling = "{{sampling}}"

[[study.configurations]]
method = "sp"
steps = [1e-2]

[parameters."vehicle.initial.velocity_east"]
distribution = "normal"
mean = 0.0
std = 0.5

[parameters."parachute.aerodynamics.axial_coefficient"]
distribution = "uniform"
low = 0.95
high = 1.05
relative = true

[parameters."main.lines.*.stiffness"]
distribution = "truncated_normal"
mean = 1.0
std = 0.2
low = 0.9
high = 1.1
relative = true
"""


def spec_for(tmp_path, sampling, runs):
    path = tmp_path / f"{sampling}.toml"
    path.write_text(DESIGN.format(sampling=sampling, runs=runs))
    return load_study(path)


@pytest.mark.parametrize("sampling", ["latin_hypercube", "sobol"])
def test_designs_fill_the_space_and_map_through_the_inverse_cdf(tmp_path, sampling):
    from scipy.stats import norm
    spec = spec_for(tmp_path, sampling, 64)
    runs = spec.expand()
    u = norm.cdf([r.values["vehicle.initial.velocity_east"] for r in runs], 0.0, 0.5)
    c_a = np.array([r.values["parachute.aerodynamics.axial_coefficient"] for r in runs])
    k = np.array([r.values["main.lines.*.stiffness"] for r in runs])
    # one point in each of the 64 equal-probability strata of every input (exact for the Latin hypercube; the
    # scrambled Sobol sequence at a power of 2 has the same one-dimensional balance)
    for values in (u, (c_a - 0.95) / 0.1):
        assert sorted(np.floor(values * 64).astype(int).tolist()) == list(range(64))
    assert k.min() >= 0.9 and k.max() <= 1.1                  # truncated by the inverse CDF: no draw outside
    assert spec.expand()[5].values == runs[5].values          # the same design every time


@pytest.mark.long
def test_designs_give_identical_results_with_one_and_two_workers_and_dask(tmp_path):
    for sampling in ("latin_hypercube", "sobol"):
        spec = spec_for(tmp_path, sampling, 8)
        run_study(spec, tmp_path / f"{sampling}_one", workers=1, progress=False)
        run_study(spec, tmp_path / f"{sampling}_two", workers=2, progress=False)
        executor, close = dask_executor(local_workers=2)
        try:
            run_study(spec, tmp_path / f"{sampling}_dask", executor=executor, progress=False)
        finally:
            close()
        one = study_runs(tmp_path / f"{sampling}_one")
        assert len(one) == 8 and all(row["status"] == "ok" for row in one)
        assert study_runs(tmp_path / f"{sampling}_two") == one and study_runs(tmp_path / f"{sampling}_dask") == one
    # the two designs differ, and the table loads as a DataFrame equal to runs.csv
    assert study_runs(tmp_path / "latin_hypercube_one") != study_runs(tmp_path / "sobol_one")
    frame = load(tmp_path / "sobol_one")
    assert (tmp_path / "sobol_one" / "runs.parquet").is_file()
    assert len(frame) == 8 and frame["final_altitude"].tolist() == pytest.approx(
        [float(row["final_altitude"]) for row in study_runs(tmp_path / "sobol_one")], rel=1e-11)
    report = study_report(tmp_path / "sobol_one")["report"].read_text()
    assert "## Sensitivity" in report and "[" in report.split("| final_altitude (m) |")[1].splitlines()[0]


def test_bootstrap_interval_of_the_median_matches_its_normal_theory():
    """For n normal values the median's standard error is sigma sqrt(pi / (2 n)): the 95 % bootstrap interval is
    about 2 x 1.96 of that wide and holds the true median."""
    values = np.random.default_rng(5).normal(10.0, 2.0, 2000)
    low, high = bootstrap_interval(values, 50)
    assert low < 10.0 < high
    assert high - low == pytest.approx(2 * 1.96 * 2.0 * np.sqrt(np.pi / (2 * 2000)), rel=0.25)
    assert runs_needed(99) == 1000 and runs_needed(50) == 20


def test_rank_correlation_ranks_the_input_that_drives_the_output_first():
    rng = np.random.default_rng(2)
    a, b = rng.normal(size=300), rng.normal(size=300)
    ranked = rank_correlations({"a": a, "b": b, "flat": np.ones(300)}, 3.0 * b + 0.3 * a)
    assert [name for name, _ in ranked] == ["b", "a"] and ranked[0][1] > 0.9

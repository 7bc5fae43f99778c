"""`pchute release-point`: the solved release point lands a light airdrop on its target through a sheared wind (checked
on a fresh `pchute run` of the rewritten case), the Monte Carlo footprint around it is centred on the target, the site
conversion is the ellipsoid's, and bad input is one line."""

import json
import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.airdrop import release_footprint, solve_release_point
from pchute_exudyn.airdrop.placement import local_to_site, site_to_local
from pchute_exudyn.airdrop.release_files import write_release_case
from pchute_exudyn.cli import main
from tests.helpers import MER, run_cli

TARGET = (150.0, -40.0)   # m east, north of the start point
HEADING = 60.0            # deg: the aircraft's heading
# 2 m/s from the west at the ground, turning to 10.8 m/s from the north-west at 400 m
SHEAR = """extends = "base.toml"
[atmosphere.wind]
altitude = [0.0, 100.0, 200.0, 400.0]
east = [2.0, 5.0, 7.0, 9.0]
north = [0.0, 2.0, -3.0, -6.0]
"""


def _light_airdrop(**site) -> str:
    """A 20 kg load under a 4 m flat circular canopy on a 1 s static line, released at 40 m/s from 300 m: a run takes
    0.2 s."""
    return pc.new_case_text(planet=site.pop("planet", "earth"), mass=20.0, diameter=0.4, canopy_type="flat_circular",
                            canopy_diameter=4.0, altitude=300.0, release_airspeed=40.0, release_heading_deg=HEADING,
                            **site)


def _strict(text: str) -> dict:
    def refuse(constant):
        raise AssertionError(f"not strict JSON: {constant}")
    return json.loads(text, parse_constant=refuse)


@pytest.fixture(scope="module")
def airdrop(tmp_path_factory):
    """The release point of the sheared-wind airdrop with 12 Monte Carlo runs around it, by the command."""
    folder = tmp_path_factory.mktemp("airdrop")
    (folder / "base.toml").write_text(_light_airdrop(latitude=35.0, longitude=-117.0))
    (folder / "shear.toml").write_text(SHEAR)
    out = folder / "release"
    done = run_cli("release-point", folder / "shear.toml", "--target-east", TARGET[0], "--target-north", TARGET[1],
                   "--runs", 12, "--workers", 2, "--out", out)
    assert done.returncode == 0, done.stderr
    return folder, out, _strict((out / "release_point.json").read_text())


def test_a_fresh_run_of_the_release_case_lands_on_the_target(airdrop):
    folder, out, data = airdrop
    solved = data["release_point"]
    assert solved["converged"] and solved["miss"] <= 0.1 and len(solved["iterations"]) <= 4
    assert solved["iterations"][0]["miss"] > 100.0   # released at the start point it lands far off
    run = run_cli("run", out / "release_case.toml", "--no-plot", "--out", folder / "run")
    assert run.returncode == 0, run.stderr
    result = pc.Result.load(folder / "run")
    landed = result.summary.touchdown.time
    east, north = (float(np.interp(landed, result.time, result[f"vehicle_{axis}"])) for axis in ("east", "north"))
    assert math.hypot(east - TARGET[0], north - TARGET[1]) < 1.0
    # released where the file says, at the case's altitude and heading; release + drift is where it landed
    case = pc.load_case(out / "release_case.toml")
    start = case.bodies["vehicle"].initial
    assert (start.east, start.north, start.altitude) == (solved["release_east"], solved["release_north"], 300.0)
    assert (case.release.heading_deg, case.release.airspeed) == (HEADING, 40.0)
    assert solved["release_east"] + solved["drift_east"] == pytest.approx(east, abs=1e-6)
    assert solved["release_north"] + solved["drift_north"] == pytest.approx(north, abs=1e-6)
    # the drift less the wind's (the air's motion at the canopy, which carries the drag, summed over the run; the
    # vehicle's before the canopy is out) is the load's own motion through the air: the forward throw, along the
    # aircraft's heading (within 6 deg: through the shear the load lags the wind it reaches)
    heights = np.where(np.isfinite(result["canopy_altitude"]), result["canopy_altitude"], result["vehicle_altitude"])
    air = np.array([case.wind.at(h) for h in heights])
    keep = result.time <= landed
    carried = [np.trapezoid(air[keep, i], result.time[keep]) for i in (0, 1)]
    throw = (east - solved["release_east"] - carried[0], north - solved["release_north"] - carried[1])
    assert math.degrees(math.atan2(*throw)) == pytest.approx(HEADING, abs=6.0)


def test_the_footprint_is_centred_on_the_target(airdrop):
    folder, out, data = airdrop
    footprint = data["footprint"]
    assert (footprint["runs"], footprint["failed"], footprint["statistics"]["count"]) == (12, 0, 12)
    points = np.array(footprint["touchdown_points"])
    assert (footprint["centre_east"], footprint["centre_north"]) == pytest.approx(tuple(points.mean(axis=0)))
    interval = footprint["centre_interval_95"]
    for (low, high), target in zip((interval["east"], interval["north"]), TARGET):
        assert low <= target <= high
    assert footprint["target_inside_interval"]
    # 15 % on each wind component moves the landing by 15 % of the wind's own drift (about 270 m east)
    assert 25.0 < math.sqrt(footprint["statistics"]["covariance"][0][0]) < 60.0
    assert len((out / "monte_carlo" / "runs.csv").read_text().splitlines()) == 13
    assert "Landing footprint" in (out / "release_point.md").read_text()


def test_the_release_point_goes_on_a_map(airdrop):
    """The case has a site: map.geojson (valid GeoJSON) holds the target and the release point where the JSON puts
    them, the 12 Monte Carlo touchdowns and the footprint's ellipses around the target."""
    import geojson

    _, out, data = airdrop
    solved = data["release_point"]
    text = (out / "map.geojson").read_text()
    assert geojson.loads(text).is_valid
    mapped = json.loads(text)   # the coordinates as written (the geojson library rounds them to 1e-6 deg)
    named = {f["properties"]["name"]: f["geometry"]["coordinates"] for f in mapped["features"]}
    assert named["target"][:2] == pytest.approx([solved["target_longitude_deg"], solved["target_latitude_deg"]],
                                                abs=1e-9)
    assert named["release point"][:2] == pytest.approx([solved["longitude_deg"], solved["latitude_deg"]], abs=1e-9)
    layers = [f["properties"]["layer"] for f in mapped["features"]]
    assert layers.count("landing") == 12 and layers.count("ellipse") >= 2
    assert {"map.kml", "map.gpx", "map.html"} <= {p.name for p in out.iterdir()}


def test_the_site_is_the_ellipsoids():
    """1 km north at 35 deg is 1000 / M of latitude, M = a (1 - e^2) / (1 - e^2 sin^2)^1.5 the meridian's radius;
    and a target given by latitude and longitude goes back to its east and north."""
    start = pc.load_case(MER / "case1.toml").start   # any ellipsoid start frame; here Mars's
    planet = start.planet
    e2 = 1.0 - (planet.polar_radius / planet.equatorial_radius) ** 2
    phi = math.radians(start.latitude_deg)
    meridian = planet.equatorial_radius * (1.0 - e2) / (1.0 - e2 * math.sin(phi) ** 2) ** 1.5
    latitude, longitude = local_to_site(start, 0.0, 1000.0, 0.0)
    assert latitude - start.latitude_deg == pytest.approx(math.degrees(1000.0 / meridian), rel=1e-3)
    assert longitude == pytest.approx(start.longitude_deg, abs=1e-9)
    assert site_to_local(start, *local_to_site(start, 321.0, -654.0, 0.0), 0.0) == pytest.approx((321.0, -654.0),
                                                                                                   abs=1e-6)


def test_a_target_by_latitude_and_longitude_is_the_same_target(airdrop):
    """The JSON's target latitude and longitude, given back from Python, solve the same release point; each run is
    reported as it ends; a study file of one's own gives the footprint there."""
    folder, _, data = airdrop
    solved = data["release_point"]
    runs = []
    again = solve_release_point(folder / "shear.toml", target_latitude_deg=solved["target_latitude_deg"],
                                target_longitude_deg=solved["target_longitude_deg"], report=runs.append)
    assert (again.target_east, again.target_north) == pytest.approx(TARGET, abs=1e-6)
    assert (again.release_east, again.release_north) == pytest.approx((solved["release_east"],
                                                                       solved["release_north"]), abs=0.2)
    assert [i.miss for i in runs] == [i.miss for i in again.iterations] and again.converged
    # a study file of one's own runs at it, the release case in place of its case
    (folder / "mine.toml").write_text('[study]\ncase = "shear.toml"\nruns = 4\nseed = 7\nsampling = "latin_hypercube"\n'
                                      '[parameters."canopy.aerodynamics.axial_coefficient"]\ndistribution = "normal"\n'
                                      'mean = 1.0\nstd = 0.05\nrelative = true\n')
    (folder / "mine").mkdir()
    write_release_case(folder / "mine", again)
    footprint = release_footprint(folder / "mine", again, study_file=folder / "mine.toml", workers=2)
    assert (footprint.runs, len(footprint.points), footprint.dispersions) == (
        4, 4, ("canopy.aerodynamics.axial_coefficient",))
    assert "release_case.toml" in (folder / "mine" / "monte_carlo" / "manifest.json").read_text()
    assert footprint.target_inside   # the drag changes the descent time, and so the drift, by 2.5 % at most


def test_bad_input_is_one_line(tmp_path, capsys):
    (tmp_path / "earth.toml").write_text(_light_airdrop(latitude=35.0, longitude=-117.0))
    (tmp_path / "flat.toml").write_text(_light_airdrop(planet="flat"))
    (tmp_path / "nowhere.toml").write_text('extends = "earth.toml"\nremove = ["start.latitude_deg", '
                                           '"start.longitude_deg"]\n')
    (tmp_path / "two.toml").write_text('[study]\ncase = ["earth.toml", "flat.toml"]\n')
    site = ["--target-latitude", "35.001", "--target-longitude", "-117.0"]
    for case, extra, message in (
            ("earth.toml", [], "no target: give --target-east and --target-north"),
            ("earth.toml", ["--target-east", "5"], "--target-north is missing"),
            ("flat.toml", site, "flat planet, which has no latitude or longitude"),
            ("nowhere.toml", site, "has no site ([start] latitude_deg, longitude_deg)"),
            (MER / "case1.toml", ["--target-east", "5", "--target-north", "5"], "no [start.release]"),
            ("earth.toml", ["--target-east", "5", "--target-north", "5", "--runs", "12", "--wind-error", "0.2"],
             "--wind-error = 0.2: case"),
            ("earth.toml", ["--target-east", "5", "--target-north", "5", "--runs", "12", "--wind-direction-error", "5"],
             "has no from_deg to turn"),
            ("earth.toml", ["--target-east", "5", "--target-north", "5", "--runs", "2"], "--runs = 2: must be"),
            ("earth.toml", ["--target-east", "5", "--target-north", "5", "--airspeed", "-4"],
             "--airspeed = -4: must be >= 0 (m/s)"),
            ("earth.toml", ["--target-east", "5", "--target-north", "5", "--monte-carlo", str(tmp_path / "two.toml")],
             "the study runs 2 case files")):
        code = main(["release-point", str(tmp_path / case), "--out", str(tmp_path / "out"), *extra])
        err = capsys.readouterr().err
        assert code == 1 and err.count("\n") == 1 and message in err and "Traceback" not in err, err
    assert not (tmp_path / "out").exists()

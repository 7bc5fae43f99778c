"""`pchute new`'s site for every form (issue 57): the start point and the ground written, the descent steady under
the planet's gravity there, and a site out of range refused in one line."""

import pytest

import pchute_exudyn as pc
from pchute_exudyn.authoring.write import new_case_text, new_choices
from pchute_exudyn.errors import InputError

SITE = dict(planet="earth", altitude=3000.0, latitude=47.3, longitude=8.5, ground_elevation=400.0)


def test_a_descent_is_written_at_its_site_over_its_ground():
    text = new_case_text(**SITE)
    assert "latitude_deg = 47.3" in text and "longitude_deg = 8.5" in text and "ground_altitude = 400.0" in text


def test_the_descent_starts_steady_under_the_gravity_of_its_latitude(tmp_path):
    """Written at 47.3 deg N, the descent starts in steady fall: its first 0.2 s decelerate only as the air thickens
    (0.002 m/s^2). The same state flown at the equator, whose gravity is 0.26 % weaker, is not steady there: it
    decelerates at 0.028 m/s^2."""
    text = new_case_text(**SITE)
    (tmp_path / "site.toml").write_text(text)
    (tmp_path / "equator.toml").write_text(text.replace("latitude_deg = 47.3", "latitude_deg = 0.0"))
    slopes = {}
    for name in ("site", "equator"):
        result = pc.simulate(pc.load_case(tmp_path / f"{name}.toml"), "sp", duration=0.2)
        rate = result["vehicle_velocity_down"]
        slopes[name] = (rate[-1] - rate[0]) / (result.time[-1] - result.time[0])
    assert abs(slopes["site"]) < 0.005
    assert abs(slopes["equator"]) > 5.0 * abs(slopes["site"])


@pytest.mark.parametrize("given, message", [
    (dict(latitude=95.0), "latitude = 95.0: must be a number from -90 to 90 (deg)"),
    (dict(ground_elevation=3500.0), "altitude = 3000.0: must be above ground_elevation = 3500.0 (m)"),
])
def test_a_site_out_of_range_is_refused_in_one_line(given, message):
    with pytest.raises(InputError) as caught:
        new_choices({**SITE, **given})
    assert str(caught.value) == message

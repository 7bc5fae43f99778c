"""The compare command and module on CSV files with known differences."""

import numpy as np
import pytest

from pchute_exudyn.cli import main
from pchute_exudyn.errors import InputError
from pchute_exudyn.results.compare import compare_results
from pchute_exudyn.results.result import Result, parse_column_map


def write_csv(path, columns):
    names = list(columns)
    np.savetxt(path, np.column_stack([columns[n] for n in names]), delimiter=",", header=",".join(names),
               comments="")
    return str(path)


@pytest.fixture
def pair(tmp_path):
    t = np.linspace(0.0, 10.0, 1001)
    a = {"time": t, "vehicle_altitude": 1000.0 - 5.0 * t, "vehicle_east": 0.1 * t, "vehicle_north": 0 * t,
         "tension_riser": 100.0 + t, "confluence_velocity_east": np.sin(t), "confluence_velocity_north": 0 * t}
    # B: another tool, half the sample rate, feet and pounds-force, riser 2 N high after 3 s, confluence 0.3 m/s off
    tb = np.linspace(1.0, 12.0, 221)
    b = {"t": tb, "alt_ft": (1000.0 - 5.0 * tb + 0.5) / 0.3048, "east_m": 0.1 * tb + 3.0, "north_m": 4.0 + 0 * tb,
         "riser_lbf": (100.0 + tb + 2.0 * (tb > 3.0)) / 4.4482216152605,
         "vc_e": np.sin(tb) + 0.3, "vc_n": 0 * tb}
    return write_csv(tmp_path / "a.csv", a), write_csv(tmp_path / "b.csv", b)


MAP = ["t=time", "alt_ft=vehicle_altitude*0.3048", "east_m=vehicle_east", "north_m=vehicle_north",
       "riser_lbf=tension_riser*4.4482216152605", "vc_e=confluence_velocity_east",
       "vc_n=confluence_velocity_north"]


def test_known_differences(pair):
    a = Result.load(pair[0])
    b = Result.load(pair[1], parse_column_map(MAP))
    c = compare_results(a, b, settle_time=5.0)
    assert c.time[0] == pytest.approx(1.0) and c.time[-1] == pytest.approx(10.0)    # the common span
    assert c.final["vehicle altitude"] == pytest.approx(0.5, abs=1e-9)
    assert c.final["vehicle lateral position"] == pytest.approx(5.0, abs=1e-9)       # 3-4-5
    riser = c.lines["riser"]
    assert riser["max"] == pytest.approx(2.0, abs=1e-9)
    assert riser["max_settled"] == pytest.approx(2.0, abs=1e-9) and riser["rms_settled"] == pytest.approx(2.0)
    fraction = np.mean(c.time > 3.0 + 0.02)                                           # B jumps within its 0.05 s grid
    assert riser["rms"] == pytest.approx(2.0 * np.sqrt(fraction), rel=0.02)
    assert c.confluence_velocity["max"] == pytest.approx(0.3, abs=2e-3)               # linear interpolation of sin


def test_compare_cli_writes_table_and_plots(pair, tmp_path, capsys):
    args = ["compare", pair[0], pair[1], "--out", str(tmp_path / "cmp"), "--settle", "5"]
    for entry in MAP:
        args += ["--map", entry]
    assert main(args) == 0
    printed = capsys.readouterr().out
    assert "| final vehicle altitude | +0.5 m |" in printed
    figures = ("tensions.png", "confluence_velocity.png", "descent_rate.png", "vehicle_altitude.png",
               "vehicle_east.png", "vehicle_north.png")
    assert f"wrote comparison.md, comparison.json, {', '.join(figures)} in {tmp_path / 'cmp'}" in printed
    for name in ("comparison.md", "comparison.json", *figures):
        assert (tmp_path / "cmp" / name).is_file()


def test_compare_errors(pair, tmp_path, capsys):
    t = np.linspace(20.0, 30.0, 11)
    late = write_csv(tmp_path / "late.csv", {"time": t, "tension_riser": t})
    with pytest.raises(InputError, match="share no time span"):
        compare_results(Result.load(pair[0]), Result.load(late))
    other = write_csv(tmp_path / "other.csv", {"time": np.linspace(0, 5, 6), "foo": np.zeros(6)})
    with pytest.raises(InputError, match="share no column besides 'time'"):
        compare_results(Result.load(pair[0]), Result.load(other))
    untimed = write_csv(tmp_path / "untimed.csv", {"seconds": t, "x": t})
    for args, expected in ((["compare", pair[0], untimed], "no 'time' column (name it with a column map"),
                           (["compare", pair[0], pair[1]], "share no column besides 'time'"),
                           (["compare", pair[0], pair[1], "--map", "t=time"], "share no column besides 'time'"),
                           (["compare", pair[0], pair[1], "--map", "nothere=tension_riser"], "does not have"),
                           (["compare", pair[0], pair[1], "--map", "riser_lbf"], "THEIRS=OURS"),
                           (["compare", pair[0], pair[1], "--map", "riser_lbf=tension_riser*x"], "not a number"),
                           (["compare", pair[0], str(tmp_path / "missing")], "result not found"),
                           (["compare", pair[0], late], "share no time span")):
        assert main(args) == 1
        err = capsys.readouterr().err
        assert expected in err and len(err.strip().splitlines()) == 1, err


def _bad_copy(tmp_path, name, change):
    t = np.linspace(0.0, 10.0, 101)
    columns = {"time": t, "vehicle_altitude": 1000.0 - t, "tension_riser": 100.0 + t}
    change(columns)
    return write_csv(tmp_path / name, columns)


def _set(column, index, value):
    def change(columns):
        columns[column] = columns[column].copy()
        columns[column][index] = value
    return change


@pytest.mark.parametrize("change, extra, expected", [
    (_set("time", 50, 2.0), [], "time goes back at sample 51 (2 s after 4.9 s)"),
    (_set("time", 50, 4.9), [], "time repeats at sample 51"),
    (_set("time", 7, np.nan), [], "time is not a finite number at sample 8"),
    (_set("tension_riser", 20, np.nan), [], "column tension_riser is nan at t = 2 s"),
    (_set("vehicle_altitude", 30, np.inf), [], "column vehicle_altitude is inf at t = 3 s"),
    (_set("vehicle_altitude", 30, 1e300), [], "bad.csv: column vehicle_altitude is 1e+300 at t = 3 s (sample 31); "
                                              "compared values must be within +-1e+15"),
    (_set("tension_riser", 30, -2e15), [], "column tension_riser is -2e+15 at t = 3 s (sample 31)"),
    (lambda c: c["time"].__setitem__(1, 1e-320), [], "bad.csv: rate of descent -d(vehicle_altitude)/dt is inf m/s at "
                                                     "t = 0 s; it must be within +-1e+15 (are the times too close?)"),
    (lambda c: None, ["--ground", "5e6"], "a.csv never descends to 5e+06 m (its vehicle_altitude is at most 1000 "
                                          "m): must be below the highest altitude of both sides"),
    (lambda c: None, ["--ground=-1e9"], "ground (--ground) = -1e+09: must be within -50000..1e+07 (m) for this tool"),
    (lambda c: c.update(vehicle_altitude=c["vehicle_altitude"] - 1.0), ["--ground", "999"],
     "bad.csv never descends to 999 m (its vehicle_altitude is at most 999 m)"),
    (lambda c: None, ["--map", "tension_riser=tension_riser*nan"], "the factor must be a finite, non-zero number"),
    (lambda c: None, ["--map", "tension_riser=tension_riser*inf"], "the factor must be a finite, non-zero number"),
    (lambda c: None, ["--map", "tension_riser=tension_riser*0"], "the factor must be a finite, non-zero number"),
    (lambda c: None, ["--map", "tension_riser=tension_risr"], "--map tension_riser=tension_risr: A has no column "
                                                              "'tension_risr'"),
    (lambda c: None, ["--map-a", "vehicle_altitude=altitude"], "--map-a vehicle_altitude=altitude: B has no column "
                                                               "'altitude'"),
    # the second battery's: a report folder that is a file was refused only after the report was printed
    (lambda c: None, ["--out", __file__], "must name a folder for the report"),
])
@pytest.mark.filterwarnings("error")   # no numpy warning on the way to the one line
def test_compare_refuses_bad_input(pair, tmp_path, capsys, change, extra, expected):
    bad = _bad_copy(tmp_path, "bad.csv", change)
    assert main(["compare", pair[0], bad, *extra]) == 1
    out, err = capsys.readouterr()
    assert expected in err and len(err.strip().splitlines()) == 1, err
    assert out == ""   # refused before any of the report is printed


@pytest.mark.filterwarnings("error")
def test_compare_ground_checked_in_the_api_and_no_overflow(pair, tmp_path):
    """compare_results refuses a ground above a side as the CLI does; a last rate of descent near 0 (1e-307 m/s)
    gives no time to the ground (noted) rather than an overflow warning and an infinite time."""
    a = Result.load(pair[0])
    with pytest.raises(InputError, match=r"^ground \(--ground\) = 2000: A never descends to 2000 m"):
        compare_results(a, a, ground=2000.0)
    t = np.linspace(0.0, 10.0, 101)
    rate = np.full_like(t, 1.0)
    rate[-1] = 1e-307   # 990 m / 1e-307 m/s overflows
    slow = Result.load(write_csv(tmp_path / "slow.csv", {"time": t, "vehicle_altitude": 1000.0 - t,
                                                         "vehicle_velocity_down": rate}))
    side = compare_results(a, slow, ground=0.0).descent["b"]
    assert np.isnan(side["ground_time"]) and side["note"] == "does not reach the ground (lowest 990 m)"

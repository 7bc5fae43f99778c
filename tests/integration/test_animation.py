"""`pchute animate`: frames rendered headless from a result folder alone, drawn where the result files say."""

import numpy as np
import pytest
from PIL import Image

import pchute_exudyn as pc
from pchute_exudyn.cli import main
from pchute_exudyn.results.result import load_scene
from pchute_exudyn.views.animation import Animation, Run
from tests.helpers import MER, ROOT


@pytest.fixture(scope="module")
def mer_runs(tmp_path_factory):
    """MER case 3 (slack at the start) for 4 s with SP and with the full-mass model, saved as result folders."""
    folder = tmp_path_factory.mktemp("animate")
    case = pc.load_case(MER / "case3.toml")
    sp, full = folder / "sp", folder / "full"
    pc.simulate(case, "sp", "rk4", 1e-2, duration=4.0).save(sp, plot=False)
    pc.simulate(case, "full", "implicit", 1e-3, duration=4.0).save(full, plot=False)
    return sp, full


def test_frames_have_their_size_change_over_time_and_draw_lines_at_the_attach_points(mer_runs):
    sp, full = mer_runs
    run, other = Run.load(sp), Run.load(full)
    animation = Animation(run, other, speed=1.0)
    frames = {t: animation.frame(t) for t in (0.5, 2.0, 3.5)}
    height, width = (round(5.2 * 90), round(8.0 * 90))
    assert all(f.shape == (height, width, 3) for f in frames.values())
    assert np.mean(frames[0.5] != frames[3.5]) > 0.005 and np.mean(frames[2.0] != frames[3.5]) > 0.005
    # the last frame drawn (t = 3.5 s): each line from its stored attach point to the stored confluence, both
    # relative to the followed vehicle's stored position, at the sample nearest 3.5 s
    i = run.index(3.5)
    assert abs(run.time[i] - 3.5) < 1e-9
    origin = run.arrays["vehicle/position"][i]
    assert len(animation.lines) == 4
    for (system, line), artist in animation.lines.items():
        xs, ys, zs = artist.get_data_3d()
        drawn = np.column_stack([xs, ys, zs])
        assert drawn[0] == pytest.approx(run.arrays[f"{system}/{line}"][i] - origin, abs=1e-9)
        assert drawn[1] == pytest.approx(run.arrays[f"{system}/confluence"][i] - origin, abs=1e-9)
    # the stored attach points are the body points carried by the stored attitudes
    case = pc.load_case(MER / "case3.toml")
    riser = case.bodies["parachute"].points[case.systems["main"].lines[3].point]
    expected = run.arrays["parachute/position"][i] + run.arrays["parachute/rotation"][i] @ riser
    assert run.arrays["main/riser"][i] == pytest.approx(expected, abs=1e-9)


def test_slack_lines_are_drawn_grey_and_dashed(mer_runs):
    run = Run.load(mer_runs[0])
    animation = Animation(run)
    t = 1.5   # bridle 3 slack, the others taut (validation/output/animations/frames.md)
    animation.draw(t)
    i = run.index(t)
    for (_system, line), artist in animation.lines.items():
        slack = not run.tensions[f"tension_{line}"][i] > 1.0
        assert (artist.get_linestyle() == "--") == slack, line
        assert (artist.get_color() == "0.6") == slack, line


@pytest.mark.long
def test_animate_writes_a_gif_and_an_mp4(mer_runs, tmp_path):
    sp, full = mer_runs
    gif = tmp_path / "clip.gif"
    assert main(["animate", str(sp), "--out", str(gif), "--from", "1", "--to", "2", "--speed", "1",
                 "--compare", str(full), "--quiet"]) == 0
    with Image.open(gif) as image:
        assert image.n_frames == 13 and image.size == (720, 468)
    pytest.importorskip("imageio_ffmpeg")   # in the test extra; MP4 is optional for users
    mp4 = tmp_path / "clip.mp4"
    assert main(["animate", str(sp), "--out", str(mp4), "--from", "1", "--to", "1.5", "--quiet"]) == 0
    assert mp4.stat().st_size > 1000 and not list(tmp_path.glob(".*partial*"))


def test_result_files_keep_the_scene(tmp_path):
    """The scene is in result.npz, not in timeseries.csv."""
    pc.simulate(pc.load_case(ROOT / "cases" / "mer" / "case1.toml"), "sp", "rk4", 1e-2, duration=1.0).save(
        tmp_path / "r", plot=False)
    header = (tmp_path / "r" / "timeseries.csv").read_text().splitlines()[0]
    assert "scene" not in header
    time, arrays, description = load_scene(tmp_path / "r")
    assert arrays["vehicle/rotation"].shape == (len(time), 3, 3)
    assert description["bodies"]["parachute"]["role"] == "canopy"


def test_exudyn_viewer_replay_draws_the_stored_attach_points(tmp_path):
    """`pchute view`'s display model and solution file (PA1 over its drogue and main phases): loaded back with
    Exudyn's own reader and set into the model, every drawn attach point is where the result files put it."""
    import exudyn as exu
    from exudyn.utilities import LoadSolutionFile, SetSolutionState

    from pchute_exudyn.views.viewer import prepare
    folder = tmp_path / "pa1"
    pc.simulate(pc.load_case(ROOT / "cases" / "cev_pa1.toml"), "sp", "rk4", 1e-2, duration=12.0).save(folder,
                                                                                                     plot=False)
    model = prepare(folder, tmp_path / "display.txt")
    solution = LoadSolutionFile(str(tmp_path / "display.txt"), verbose=False)
    time, arrays, _ = load_scene(folder)
    assert solution["nRows"] == len(time)
    checked = 0
    for row in (50, 500, 1100):   # before the drogues, under them, under the mains (after 9.5 s)
        SetSolutionState(model.mbs, solution, row, exu.ConfigurationType.Current)
        for system, line in model.markers:
            stored = arrays[f"{system}/{line}"][row]
            if np.isfinite(stored).all():
                assert model.attach_position(system, line) == pytest.approx(stored, abs=1e-5)
                checked += 1
    assert checked >= 12


def test_view_without_a_display_is_a_one_line_error(mer_runs, monkeypatch, capsys):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr("sys.platform", "linux")
    assert main(["view", str(mer_runs[0])]) != 0
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "no display" in err and "pchute animate" in err


def test_a_run_can_keep_exudyns_own_solution_file(tmp_path):
    """--exudyn-solution: the engine's file of each phase, beside the result; its vehicle coordinates (reference +
    displacement) are the result's vehicle positions at the output times."""
    from exudyn.utilities import LoadSolutionFile
    case = pc.load_case(MER / "case1.toml")
    result = pc.simulate(case, "sp", "rk4", 1e-2, duration=1.0, engine_solution=True)
    result.save(tmp_path / "r", plot=False)
    path = tmp_path / "r" / "exudyn_solution_phase0.txt"
    solution = LoadSolutionFile(str(path), verbose=False)
    data = solution["data"]
    assert solution["nRows"] == 101 and data[:, 0] == pytest.approx(result.time, abs=1e-9)
    stored = result.scene_arrays["vehicle/position"]
    start = stored[0]
    # the vehicle is the first node: its first three coordinates are its displacement from the start
    assert data[:, 1:4] + start == pytest.approx(stored, abs=1e-6)
    plain = pc.simulate(case, "sp", "rk4", 1e-2, duration=1.0)
    assert not plain.attachments and np.array_equal(plain.columns["tension_riser"], result.columns["tension_riser"])

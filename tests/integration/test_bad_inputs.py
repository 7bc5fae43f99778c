"""A battery of bad inputs across `run`, `compare`, `linearize`, `study` and case files: each gives one line that
names the problem, a non-zero exit, no traceback, and returns within 10 s.

`python tests/integration/test_bad_inputs.py` prints the inputs and the messages as a Markdown table.
"""

import sys
from pathlib import Path

import pytest

if __name__ == "__main__":   # run as a script (python tests/integration/test_bad_inputs.py): the root on sys.path
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tests.bad_input_harness import assert_one_line, print_table, run_bad_input  # noqa: E402
from tests.helpers import ROOT  # noqa: E402

CASE1 = str(ROOT / "cases" / "mer" / "case1.toml")
PA1 = str(ROOT / "cases" / "cev_pa1.toml")
PA1_INFLATION = str(ROOT / "cases" / "cev_pa1_inflation.toml")
PA1_WINDS = str(ROOT / "cases" / "cev_pa1_winds.toml")
TURBULENCE = "atmosphere.turbulence."
GUST = "atmosphere.gusts[0]."
APPARENT = str(ROOT / "cases" / "mer" / "case1_apparent_mass.toml")
MAIN_INFLATION = "systems.main.inflation."
CLUSTER = str(ROOT / "cases" / "cev_pa1_cluster.toml")
EXTRA_LINE = ["--set", "main.lines.extra.free_length=12", "--set", "main.lines.extra.stiffness=1e5", "--set",
              "main.lines.extra.damping=1e3"]
RISER_TABLE = "systems.main.lines.riser.load_elongation."
GOOD_CSV = "time,tension_riser,vehicle_altitude\n0,1,100\n1,2,99\n2,3,98\n"
STUDY = """[study]
case = "{case}"
{extra}
[[study.configurations]]
method = "sp"
steps = [1e-2]
"""


def _file(tmp: Path, name: str, text: str) -> str:
    path = tmp / name
    path.write_text(text)
    return str(path)


def _study(tmp: Path, extra: str = "", body: str = "") -> str:
    return _file(tmp, "study.toml", STUDY.format(case=CASE1, extra=extra) + body)


def _gusty(tmp: Path) -> str:
    """PA1 in wind with one gust from the north (its keys then exist for --set)."""
    return _file(tmp, "gust.toml", f'extends = "{Path(PA1_WINDS).as_posix()}"\n[[atmosphere.gusts]]\namplitude = 5.0\n'
                                   'start = 40.0\nlength = 4.0\ndirection = [0.0, 1.0, 0.0]\n')


def _fit(tmp: Path, free: str = "low = 0.3\nhigh = 0.7", target: str = 'event = "start"\ntime = 0.0\nstd = 1.0') -> str:
    """A fit file of MER case 1 (1 s) with the given free-key table body and target table body."""
    (tmp / "data.csv").write_text("time,tension_riser\n0,0\n0.5,10\n")
    case = tmp / "short.toml"
    case.write_text(f'extends = "{Path(CASE1).as_posix()}"\n[simulation]\nduration = 1.0\n')
    path = _file(tmp, "fit.toml", f'[fit]\ncase = "{case.as_posix()}"\nmethod = "sp"\nstep = 1e-2\n'
                                  f'[free."parachute.aerodynamics.axial_coefficient"]\n{free}\n'
                                  f'[[targets]]\n{target}\n')
    return [path, "--out", str(tmp / "fit_out")]


def _sceneless(tmp: Path) -> str:
    """A result saved without the scene an animation needs (as by a version before it was stored)."""
    from pchute_exudyn.results.result import Result
    folder = tmp / "old"
    Result({"time": [0.0, 1.0], "tension_riser": [1.0, 2.0]}, {"time": "s", "tension_riser": "N"}).save(folder,
                                                                                                     plot=False)
    return str(folder)


def _short_run(tmp: Path) -> str:
    """A 0.2-s SP run of MER case 1, saved (once per test's folder)."""
    folder = tmp / "short"
    if not folder.is_dir():
        import pchute_exudyn as pc
        pc.simulate(pc.load_case(CASE1), "sp", "rk4", 1e-2, duration=0.2).save(folder, plot=False)
    return str(folder)


def _result_folder(tmp: Path) -> str:
    folder = tmp / "earlier"
    folder.mkdir()
    # a run's summary as an older version wrote it (an empty {} is not a result: --overwrite would not replace it)
    (folder / "summary.json").write_text('{"case": "x", "method": "sp", "integrator": "rk4", "step": 0.01}')
    (folder / "timeseries.csv").write_text(GOOD_CSV)
    return str(folder)


BATTERY = [
    # fit
    ("fit: free key without bounds", lambda t: ["fit", *_fit(t, free="initial = 0.5")],
     "free.parachute.aerodynamics.axial_coefficient.low: required but missing"),
    ("fit: a local Dask cluster of no workers", lambda t: ["fit", *_fit(t), "--dask-local", "0"],
     "--dask-local = 0: must be >= 1"),
    ("fit: bounds reversed", lambda t: ["fit", *_fit(t, free="low = 0.7\nhigh = 0.3")],
     "free.parachute.aerodynamics.axial_coefficient.high = 0.3: must be > low (0.7)"),
    ("fit: target column not in the data", lambda t: ["fit", *_fit(t, target='history = "data.csv"\ncolumn = "nope"\n'
                                                                       'std = 1.0')],
     "targets[0].column = 'nope': data.csv has no column 'nope' (after the map); it has: tension_riser"),
    ("fit: target column the run lacks", lambda t: ["fit", *_fit(t, target='final = "vehicle_altitudes"\n'
                                                                        'value = 8000.0\nstd = 1.0')],
     "targets[0].final = 'vehicle_altitudes': the run has no such column"),
    ("fit: target event that never happens", lambda t: ["fit", *_fit(t, target='event = "touchdown"\ntime = 50.0\n'
                                                                             'std = 1.0')],
     "targets[0].event = 'touchdown': never happens in the run at the starting values; its events are: start"),
    # animate
    ("animate a folder without a scene", lambda t: ["animate", _result_folder(t)],
     "no result.npz: not a result folder of `pchute run`"),
    ("animate a result without a scene", lambda t: ["animate", _sceneless(t)],
     "result.npz holds no scene (body attitudes and attach points); rerun the case with this version"),
    ("animate an empty window", lambda t: ["animate", _short_run(t), "--from", "5", "--to", "9"],
     "the time window 5 s to 9 s is empty: the run spans 0 s to 0.2 s"),
    ("animate a reversed window", lambda t: ["animate", _short_run(t), "--from", "0.15", "--to", "0.1"],
     "the time window 0.15 s to 0.1 s is empty"),
    ("animate an unknown body", lambda t: ["animate", _short_run(t), "--follow", "rover"],
     "--follow rover: no such body; the bodies are: vehicle, parachute"),
    ("animate to a PNG", lambda t: ["animate", _short_run(t), "--out", str(t / "a.png")],
     "write a .gif or an .mp4 file"),
    # map (docs/results.md, Maps)
    ("map a result without latitudes", lambda t: ["map", _result_folder(t)],
     "the run has no vehicle_latitude column: a run on a flat planet has no latitude and longitude"),
    ("map a folder that holds no result", lambda t: ["map", str(t / "work")],
     "neither a result folder of `pchute run` (no summary.json) nor a study folder (no runs.csv)"),
    # winds, turbulence and gusts (docs/models/winds.md)
    ("negative turbulence intensity", lambda t: ["run", CASE1, "--set", TURBULENCE + "seed=1", "--set",
                                                 TURBULENCE + "sigma_u=-1", "--set", TURBULENCE + "sigma_v=1", "--set",
                                                 TURBULENCE + "sigma_w=1"],
     "atmosphere.turbulence.sigma_u = -1: must be >= 0 (m/s)"),
    ("negative scale length", lambda t: ["run", CASE1, "--set", TURBULENCE + "seed=1", "--set",
                                         TURBULENCE + "sigma_u=1", "--set", TURBULENCE + "sigma_v=1", "--set",
                                         TURBULENCE + "sigma_w=1", "--set", TURBULENCE + "length_u=100", "--set",
                                         TURBULENCE + "length_v=-50", "--set", TURBULENCE + "length_w=30"],
     "atmosphere.turbulence.length_v = -50: must be > 0 (m)"),
    ("negative wind at 6 m", lambda t: ["run", PA1_WINDS, "--set", TURBULENCE + "wind_speed_6m=-3"],
     "atmosphere.turbulence.wind_speed_6m = -3: must be >= 0 (m/s)"),
    ("seed not an integer", lambda t: ["run", PA1_WINDS, "--set", TURBULENCE + "seed=1.5"],
     "atmosphere.turbulence.seed = 1.5: must be an integer >= 0"),
    ("seed as text", lambda t: ["run", PA1_WINDS, "--set", TURBULENCE + "seed=lucky"],
     "atmosphere.turbulence.seed = 'lucky': must be an integer >= 0"),
    ("gust of zero length", lambda t: ["run", _gusty(t), "--set", GUST + "length=0"],
     "atmosphere.gusts[0].length = 0: must be > 0 (s)"),
    ("gust without a direction", lambda t: ["run", _gusty(t), "--set", GUST + "direction=[0, 0, 0]"],
     "atmosphere.gusts[0].direction = [0, 0, 0]: must be a non-zero [east, north, up] vector"),
    ("profile exponent above 1", lambda t: ["run", PA1_WINDS, "--set", "atmosphere.wind.exponent=1.5"],
     "atmosphere.wind.exponent = 1.5: must be <= 1"),
    ("profile exponent below 0", lambda t: ["run", PA1_WINDS, "--set", "atmosphere.wind.exponent=-0.2"],
     "atmosphere.wind.exponent = -0.2: must be >= 0"),
    ("wind by components and speed", lambda t: ["run", PA1_WINDS, "--set", "atmosphere.wind.east=3"],
     "give either east and north or speed and from_deg, not both"),
    # canopy physics (docs/models/canopy.md): apparent mass, inflation, load-elongation tables
    ("negative apparent-mass coefficient", lambda t: ["run", APPARENT, "--set", "parachute.apparent_mass.axial=-1"],
     "bodies.parachute.apparent_mass.axial = -1"),
    ("negative projected radius", lambda t: ["run", APPARENT, "--set",
                                             "parachute.apparent_mass.projected_radius=-5.3"],
     "bodies.parachute.apparent_mass.projected_radius = -5.3"),
    ("zero projected radius", lambda t: ["run", APPARENT, "--set", "parachute.apparent_mass.projected_radius=0"],
     "bodies.parachute.apparent_mass.projected_radius = 0"),
    ("line table not starting at (0, 0)", lambda t: ["run", PA1_INFLATION, "--set", RISER_TABLE
                                                     + "strain=[0.001, 0.01]", "--set", RISER_TABLE
                                                     + "tension=[0.0, 7e4]"], "load_elongation.strain = [0.001, 0.01]"),
    ("line table decreasing", lambda t: ["run", PA1_INFLATION, "--set", RISER_TABLE + "strain=[0.0, 0.01, 0.02]",
                                         "--set", RISER_TABLE + "tension=[0.0, 7e4, 6e4]"],
     "load_elongation.tension = [0.0, 70000.0, 60000.0]: must increase strictly"),
    ("line table and stiffness", lambda t: ["run", PA1_INFLATION, "--set", "main.lines.riser.stiffness=6e5"],
     "give stiffness or load_elongation, not both"),
    ("stages out of order", lambda t: ["run", PA1_INFLATION, "--set", MAIN_INFLATION + "stage_start=[0.0, 16.0, 8.0]"],
     "systems.main.inflation.stage_start = [0.0, 16.0, 8.0]: stages must start in order"),
    ("first stage after line stretch", lambda t: ["run", PA1_INFLATION, "--set",
                                                  MAIN_INFLATION + "stage_start=[1.0, 8.0, 16.0]"],
     "inflation.stage_start = [1.0, 8.0, 16.0]: the first stage starts at line stretch"),
    ("zero fill constant", lambda t: ["run", PA1_INFLATION, "--set", MAIN_INFLATION + "fill_constant=[1.13, 0, 0.52]"],
     "systems.main.inflation.fill_constant = [1.13, 0.0, 0.52]: each must be > 0"),
    ("overinflation below 1", lambda t: ["run", PA1_INFLATION, "--set", MAIN_INFLATION + "overinflation=0.9"],
     "systems.main.inflation.overinflation = 0.9: must be >= 1"),
    ("stage fraction above 1", lambda t: ["run", PA1_INFLATION, "--set", MAIN_INFLATION + "fraction=[0.08, 0.25, 1.5]"],
     "inflation.fraction = [0.08, 0.25, 1.5]: each must be within (0, 1]"),
    ("inflation and schedule", lambda t: ["run", PA1, "--set", MAIN_INFLATION + "stage_start=[0.0]", "--set",
                                          MAIN_INFLATION + "fraction=[1.0]", "--set",
                                          MAIN_INFLATION + "fill_constant=[2.0]", "--set",
                                          MAIN_INFLATION + "exponent=[2.0]"],
     "a drag_area_schedule or an inflation, not both"),
    # clusters and failures (docs/models/cluster.md)
    ("canopy without a riser", lambda t: ["run", CLUSTER, "--set", "main.lines.riser3.attach=\"main2.riser\""],
     "systems.main.canopies = ['main1', 'main2', 'main3']: canopy 'main3' has no riser"),
    ("riser to another system's confluence", lambda t: ["run", CLUSTER, "--set",
                                                         "main.lines.extra.attach=\"drogue1.riser\"", *EXTRA_LINE],
     "systems.main.lines.extra.attach = 'drogue1.riser': runs to canopy 'drogue1' of system 'drogue'"),
    ("zero contact stiffness", lambda t: ["run", CLUSTER, "--set", "main.contact.stiffness=0"],
     "systems.main.contact.stiffness = 0: must be > 0 (N/m)"),
    ("negative contact stiffness", lambda t: ["run", CLUSTER, "--set", "main.contact.stiffness=-1e4"],
     "systems.main.contact.stiffness = -10000.0: must be > 0 (N/m)"),
    ("failed canopy also cut away", lambda t: ["run", CLUSTER, "--set", "failures.not_inflated=main2", "--set",
                                               "failures.cutaway.main2=30"],
     "failures.cutaway.main2 = 30: canopy 'main2' never inflates (failures.not_inflated)"),
    ("unknown canopy that fails", lambda t: ["run", CLUSTER, "--set", "failures.not_inflated=main9"],
     "failures.not_inflated = 'main9': unknown canopy 'main9'; the canopies are: drogue1, drogue2, main1"),
    ("unknown canopy cut away", lambda t: ["run", CLUSTER, "--set", "failures.cutaway.capsule=30"],
     "failures.cutaway.capsule = 30: unknown canopy 'capsule'"),
    ("unknown canopy skipping a stage", lambda t: ["run", CLUSTER, "--set", "failures.skipped_stages.mian1=2"],
     "failures.skipped_stages.mian1 = 2: unknown canopy 'mian1'"),
    ("skipping the full stage", lambda t: ["run", CLUSTER, "--set", "failures.skipped_stages.main1=3"],
     "failures.skipped_stages.main1 = [3]: each must be a reefed stage, 1 to 2"),
    ("cutter delay out of order", lambda t: ["run", CLUSTER, "--set", "failures.disreef_delay.main1=[9.0, 0.0]"],
     "failures.disreef_delay.main1 = [9.0, 0.0]: moves the disreefs out of order"),
    ("cut away after the run", lambda t: ["run", CLUSTER, "--set", "failures.cutaway.main1=500"],
     "failures.cutaway.main1 = 500.0: must be before 200 s"),
    ("cut away before deployment", lambda t: ["run", CLUSTER, "--set", "failures.cutaway.main1=5"],
     "failures.cutaway.main1 = 5: must be > 9.5 (s)"),
    ("contact without a canopy's aerodynamics", lambda t: ["run", CLUSTER, "--set", "main1.aerodynamics.enabled=false"],
     "systems.main.contact: needs every canopy's aerodynamics, enabled"),
    ("cluster canopy without aerodynamics", lambda t: ["run", _bare_canopy(t)],
     "systems.main.canopies = ['c1', 'c2']: canopy 'c2' has no aerodynamics: every canopy of a cluster needs them"),
    ("cluster keys on one canopy", lambda t: ["run", PA1, "--set", "main.contact.stiffness=1e4"],
     "systems.main.contact: needs a cluster"),
    ("drag efficiency above 1", lambda t: ["run", CLUSTER, "--set", "main.cluster.drag_efficiency=[1.0, 1.2]"],
     "systems.main.cluster.drag_efficiency = [1.0, 1.2]: each must be within (0, 1]"),
    ("study draws an unknown canopy", lambda t: ["study", _file(t, "s.toml", STUDY.format(case=CLUSTER, extra="seed = 1")
                                                                + '[parameters."failures.not_inflated"]\n'
                                                                  'distribution = "choice"\n'
                                                                  'values = ["main1", "main4"]\n')],
     "parameters.\"failures.not_inflated\": does not apply to case cev_pa1_cluster.toml: unknown canopy 'main4'"),
    ("study configuration with step and steps", lambda t: ["study", _file(t, "s.toml", STUDY.format(
        case=CLUSTER, extra="").replace("steps = [1e-2]", "steps = [1e-2]\nstep = 0.02"))],
     "study.configurations[0].step = 0.02: give step or steps, not both (steps = [...] lists every step)"),
    ("study scales a text key", lambda t: ["study", _file(t, "s.toml", STUDY.format(case=CLUSTER, extra="")
                                                       + '[parameters."systems.drogue.canopy_model"]\n'
                                                         'values = ["reduced"]\nrelative = true\n')],
     # the third battery's: an internal error (ValueError) in the first run
     "relative = True: scales numbers: every value must be a number (a factor on the case's)"),
    ("study duration before a fixed event", lambda t: ["study", _file(t, "s.toml", STUDY.format(
        case=CLUSTER, extra="seed = 1\nruns = 2\nduration = 5.0") + '[parameters."capsule.mass"]\n'
                                                                     'distribution = "normal"\nmean = 7500.0\n'
                                                                     'std = 10.0\n')],
     # the study's own key named, not the parameter first tried with it (the battery's)
     "study.duration = 5.0: does not apply to case cev_pa1_cluster.toml: systems.drogue.cutaway_time = 9.5: must be "
     "before the end of the run (simulation.duration = 5 s)"),
    # aerodynamic databases (docs/models/aerodatabase.md)
    ("angles not increasing", lambda t: ["run", CASE1, "--set", "parachute.aerodynamics.normal_coefficient.alpha_deg="
                                                                 "[0.0, 45.0, 40.0, 90.0]"],
     "bodies.parachute.aerodynamics.normal_coefficient.alpha_deg = [0.0, 45.0, 40.0, 90.0]: must increase strictly"),
    ("Mach numbers not increasing", lambda t: ["run", CASE1, "--set", "parachute.aerodynamics.axial_coefficient="
                                                                       "{mach=[1.0, 0.5], value=[0.4, 0.5]}"],
     "bodies.parachute.aerodynamics.axial_coefficient.mach = [1.0, 0.5]: must increase strictly"),
    ("ragged coefficient table", lambda t: ["run", CASE1, "--set", "parachute.aerodynamics.axial_coefficient={mach="
                                            "[0.5, 1.0], alpha_deg=[0.0, 90.0], value=[[0.4, 0.5], [0.4]]}"],
     "bodies.parachute.aerodynamics.axial_coefficient.value = [[0.4, 0.5], [0.4]]: must be 2 rows (one per Mach"),
    ("NaN in a coefficient table", lambda t: ["run", CASE1, "--set", "parachute.aerodynamics.axial_coefficient="
                                                                      "{mach=[0.5, 1.0], value=[0.4, nan]}"],
     "bodies.parachute.aerodynamics.axial_coefficient.value = [0.4, nan]: must be finite numbers"),
    ("negative reference length", lambda t: ["run", CASE1, "--set", "parachute.aerodynamics.reference_length=-1.0"],
     "bodies.parachute.aerodynamics.reference_length = -1.0: must be > 0 (m)"),
    ("damping without a reference length", lambda t: ["run", CASE1, "--set",
                                                      "parachute.aerodynamics.pitch_damping=-1.0"],
     "bodies.parachute.aerodynamics.reference_length: required (m): the pitch_damping is per unit of it"),
    ("Mach table without a temperature", lambda t: ["run", str(ROOT / "tests" / "cases" / "canopy_bump.toml"), "--set",
                                                    "c1.aerodynamics.axial_coefficient={mach=[0.5, 1.0], "
                                                    "value=[0.4, 0.5]}"],
     "bodies.c1.aerodynamics.axial_coefficient.mach = [0.5, 1.0]: a Mach-number table needs the speed of sound"),
    ("speed of sound for a standard atmosphere", lambda t: ["run", PA1, "--set", "atmosphere.speed_of_sound=340"],
     "atmosphere.speed_of_sound"),
    # run: the case file, the command line and overrides
    ("missing case file", lambda t: ["run", str(t / "nope.toml")], "case file not found"),
    ("malformed TOML", lambda t: ["run", _file(t, "bad.toml", "[case\nname = 1")], "malformed TOML"),
    ("case not UTF-8", lambda t: ["run", _bytes(t)], "not UTF-8"),
    ("unknown method", lambda t: ["run", CASE1, "--method", "magic"], "invalid choice: 'magic'"),
    ("unknown integrator", lambda t: ["run", CASE1, "--integrator", "euler"], "invalid choice: 'euler'"),
    ("zero step", lambda t: ["run", CASE1, "--dt", "0"], "step (--dt) = 0.0: must be a number > 0"),
    ("NaN step", lambda t: ["run", CASE1, "--dt", "nan"], "step (--dt) = nan: must be a number > 0"),
    ("negative duration", lambda t: ["run", CASE1, "--t-end", "-1"], "duration (--t-end) = -1.0: must be"),
    ("infinite duration", lambda t: ["run", CASE1, "--t-end", "inf"], "duration (--t-end) = inf: must be"),
    ("step longer than the run", lambda t: ["run", CASE1, "--dt", "5", "--t-end", "1"], "must not exceed the duration"),
    ("negative mass", lambda t: ["run", CASE1, "--set", "vehicle.mass=-5"], "bodies.vehicle.mass = -5"),
    ("absurdly small mass", lambda t: ["run", CASE1, "--method", "sp", "--t-end", "1", "--set", "vehicle.mass=1e-30",
                                       "--out", str(t / "o")], "bodies.vehicle.mass = 1e-30: must be within 1e-06..1e+15 (kg)"),
    ("mistyped key", lambda t: ["run", CASE1, "--set", "vehicle.masss=800"], "did you mean 'mass'"),
    ("index out of range", lambda t: ["run", CASE1, "--set", "vehicle.inertia[5]=1"], "index out of range"),
    ("override without '='", lambda t: ["run", CASE1, "--set", "vehicle.mass"], "must look like key=value"),
    ("text for a number", lambda t: ["run", CASE1, "--set", "vehicle.mass=heavy"], "must be a number (kg)"),
    ("SP without line damping", lambda t: ["run", CASE1, "--method", "sp", "--set", "main.lines.*.damping=0"],
     "needs damping on every line"),
    ("kappa_max of 3", lambda t: ["run", CASE1, "--method", "sp", "--kappa-max", "3"], "must be > 3"),
    ("SP flag with full mass", lambda t: ["run", CASE1, "--method", "full", "--kappa-max", "7"],
     "--kappa-max is an option of the sp method, not of --method full"),
    ("SP with the implicit integrator", lambda t: ["run", CASE1, "--method", "sp", "--integrator", "implicit"],
     "runs with --integrator rk4 only"),
    ("more steps than the engine counts", lambda t: ["run", CASE1, "--method", "sp", "--t-end", "1e9"],
     "the engine counts at most 2147483647"),
    ("histories beyond memory", lambda t: ["run", CASE1, "--method", "sp", "--t-end", "1e6"],
     "more than the 4 GB a run may hold"),
    ("output folder under a file", lambda t: ["run", CASE1, "--out", _file(t, "f.txt", "x") + "/o"],
     "cannot be written"),
    ("output folder holding other files", lambda t: ["run", CASE1, "--out", _folder_with_notes(t)],
     "is not empty and holds no result"),
    ("earlier result without --overwrite", lambda t: ["run", CASE1, "--out", _result_folder(t)],
     "holds an earlier result; pass --overwrite"),
    ("unstable explicit step", lambda t: ["run", CASE1, "--dt", "1e-3", "--t-end", "1", "--out", str(t / "o")],
     "exceeds the stability limit"),
    ("ground above the start", lambda t: ["run", CASE1, "--set", "simulation.ground_altitude=9000"],
     "simulation.ground_altitude = 9000.0: must be below the vehicle's start altitude"),
    ("zero output step", lambda t: ["run", CASE1, "--set", "simulation.output_step=0"],
     "simulation.output_step = 0: must be > 0"),
    ("unknown atmosphere", lambda t: ["run", CASE1, "--set", "atmosphere.model=venus"], "must be one of: mars_grc"),
    ("SP order 2", lambda t: ["run", CASE1, "--set", "simulation.sp.order=2"], "simulation.sp.order = 2: must be 0"),
    ("unknown full-mass line law", lambda t: ["run", CASE1, "--set", "simulation.full.line_law=magic"],
     "simulation.full.line_law = 'magic': must be one of: symbolic, python"),
    ("system tied to one body", lambda t: ["run", CASE1, "--set", "main.lines.riser.attach=\"vehicle.bridle1\""],
     "every line attaches to body 'vehicle'"),
    ("unknown attach point", lambda t: ["run", CASE1, "--set", "main.lines.riser.attach=\"parachute.apex\""],
     "has no point 'apex'"),
    # compare
    ("missing result", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV), str(t / "none")], "result not found"),
    ("no time column", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV), _file(t, "b.csv", "sec,x\n0,1\n1,2\n")],
     "no 'time' column"),
    ("time going back", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV),
                                   _file(t, "b.csv", GOOD_CSV.replace("2,3,98", "0.5,3,98"))], "time goes back"),
    ("repeated time", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV),
                                 _file(t, "b.csv", GOOD_CSV.replace("2,3,98", "1,3,98"))], "time repeats"),
    ("NaN value", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV),
                             _file(t, "b.csv", GOOD_CSV.replace("1,2,99", "1,nan,99"))],
     "column tension_riser is nan at t = 1 s"),
    ("non-numeric row", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV),
                                   _file(t, "b.csv", GOOD_CSV + "3,x,97\n")], "row 5 is not numeric"),
    ("NaN map factor", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV), _file(t, "b.csv", GOOD_CSV), "--map",
                                  "tension_riser=tension_riser*nan"], "finite, non-zero number"),
    ("mistyped map target", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV), _file(t, "b.csv", GOOD_CSV),
                                       "--map", "tension_riser=tension_risr"], "A has no column 'tension_risr'"),
    ("map entry without '='", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV), _file(t, "b.csv", GOOD_CSV),
                                         "--map", "tension_riser"], "THEIRS=OURS"),
    ("negative settling time", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV), _file(t, "b.csv", GOOD_CSV),
                                          "--settle", "-1"], "--settle = -1.0: must be >= 0"),
    ("map offset not a number", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV), _file(t, "b.csv", GOOD_CSV),
                                           "--map", "vehicle_altitude=vehicle_altitude+ten"],
     "the offset 'ten' is not a number"),
    ("column mapped twice", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV), _file(t, "b.csv", GOOD_CSV),
                                       "--map", "vehicle_altitude=vehicle_altitude", "--map",
                                       "vehicle_altitude=vehicle_altitude*2"], "column 'vehicle_altitude' is already "
                                                                               "mapped"),
    ("two columns to one of ours", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV), _file(t, "b.csv", GOOD_CSV),
                                              "--map", "vehicle_altitude=tension_riser", "--map",
                                              "tension_riser=tension_riser"], "'tension_riser' is already mapped from "
                                                                              "'vehicle_altitude'"),
    ("bad --altitudes", lambda t: ["compare", _file(t, "a.csv", GOOD_CSV), _file(t, "b.csv", GOOD_CSV),
                                   "--altitudes", "99,high"], "--altitudes = '99,high': must be altitudes in m"),
    # new
    ("new: negative mass", lambda t: ["new", str(t / "n.toml"), "--mass", "-100"], "mass = -100.0: must be a number "
                                                                                   "> 0 (kg)"),
    ("new: zero drag area", lambda t: ["new", str(t / "n.toml"), "--drag-area", "0"], "drag_area = 0.0: must be a "
                                                                                      "number > 0 (m^2)"),
    ("new: unknown planet", lambda t: ["new", str(t / "n.toml"), "--planet", "venus"], "invalid choice: 'venus'"),
    ("new: both drag area and diameter", lambda t: ["new", str(t / "n.toml"), "--drag-area", "40",
                                                    "--canopy-diameter", "8"], "give one of them, not both"),
    ("new: thirteen bridles", lambda t: ["new", str(t / "n.toml"), "--bridles", "13"], "bridles = 13: must be a whole "
                                                                                       "number from 1 to 12"),
    ("new: bridle shorter than its attach radius", lambda t: ["new", str(t / "n.toml"), "--bridle-length", "0.5"],
     "must exceed the attach circle's radius"),
    ("new: existing file", lambda t: ["new", _file(t, "n.toml", "")], "exists; pass --overwrite"),
    # linearize
    ("no system at the time", lambda t: ["linearize", PA1], "no parachute system is present then"),
    ("time beyond the run", lambda t: ["linearize", PA1, "--time", "1e6"], "must be within the case's run"),
    ("unknown system", lambda t: ["linearize", PA1, "--time", "20", "--system", "reserve"],
     "unknown system 'reserve'"),
    ("system cut away by then", lambda t: ["linearize", PA1, "--time", "20", "--system", "drogue"],
     "system 'drogue' is not present then"),
    # study
    ("missing study file", lambda t: ["study", str(t / "none.toml")], "none.toml: study file not found"),
    ("unknown study key", lambda t: ["study", _study(t, "speed = 2")], "unknown key"),
    ("zero runs", lambda t: ["study", _study(t, "runs = 0")], "must be an integer >= 1"),
    ("draws without a seed", lambda t: ["study", _study(t, body="[parameters.\"vehicle.mass\"]\n"
                                                           "distribution = \"normal\"\nmean = 800.0\nstd = 5.0\n")],
     "seed: required"),
    ("option without its method", lambda t: ["study", _file(t, "s.toml", STUDY.format(case=CASE1, extra="")
                                                            .replace('method = "sp"\n', "kappa_max = 7.0\n"))],
     "needs the configuration's method"),
    ("SP option out of range", lambda t: ["study", _file(t, "s.toml", STUDY.format(case=CASE1, extra="")
                                                         + "kappa_max = 2.0\n")], "kappa_max = 2.0: must be > 3"),
    ("option of another method", lambda t: ["study", _file(t, "s.toml", STUDY.format(case=CASE1, extra="")
                                                           .replace('"sp"', '"full"') + "kappa_max = 7.0\n")],
     "kappa_max = 7.0: not an option of this method; options are: line_law"),
    ("parameter the case lacks", lambda t: ["study", _study(t, body="[parameters.\"vehicle.colour\"]\n"
                                                                   "values = [1.0]\n")], "does not apply to case"),
    ("zero workers", lambda t: ["study", _study(t), "--workers", "0"], "--workers = 0: must be >= 1"),
    ("report of a folder that is no study", lambda t: ["study-report", str(t)], "no runs.csv"),
    # a release from an aircraft (issue 33): `pchute new` and the case format
    ("negative release airspeed", lambda t: ["new", str(t / "r.toml"), "--release-airspeed", "-5"],
     "release_airspeed = -5.0: must be >= 0 (m/s)"),
    ("release flight path beyond 90 deg", lambda t: ["new", str(t / "r.toml"), "--release-airspeed", "65",
                                                     "--release-flight-path-deg", "95"],
     "release_flight_path_deg = 95.0: must be within -90..90"),
    ("negative static-line time", lambda t: ["new", str(t / "r.toml"), "--release-airspeed", "65",
                                             "--static-line-time", "-1"], "static_line_time = -1.0: must be >= 0"),
    ("release and a start speed", lambda t: ["new", str(t / "r.toml"), "--release-airspeed", "65", "--speed", "5"],
     "give one of them"),
    ("case release airspeed < 0", lambda t: ["run", _released(t), "--set", "start.release.airspeed=-1"],
     "start.release.airspeed = -1: must be >= 0 (m/s)"),
    ("case release flight path", lambda t: ["run", _released(t), "--set", "start.release.flight_path_deg=-120"],
     "start.release.flight_path_deg = -120: must be >= -90"),
    ("case static-line time < 0", lambda t: ["run", _released(t), "--set", "main.deploy_time=-0.5"],
     "systems.main.deploy_time = -0.5: must be >= 0 (s)"),
    ("release with an initial velocity", lambda t: ["run", _released(t), "--set", "vehicle.initial.velocity_east=3"],
     "bodies.vehicle.initial.velocity_east = 3: a vehicle released from an aircraft"),
    ("release with an initial rate", lambda t: ["run", _released(t), "--set", "vehicle.initial.rate_x=0.1"],
     "bodies.vehicle.initial.rate_x = 0.1: a vehicle released"),
    ("release with a system present at the start", lambda t: ["run", _released(t, 'remove = ["systems.main.deploy_'
                                                                                 'time"]\n')],
     "deploy_time: required with start.release"),
    ("velocities relative to nothing", lambda t: ["run", CASE1, "--set", "start.velocities_relative_to=water"],
     "start.velocities_relative_to = 'water': must be one of: ground, air"),
]


def _released(tmp: Path, extra: str = "") -> str:
    """A cargo release written by `pchute new`, extended by ``extra`` (TOML lines)."""
    from pchute_exudyn.authoring.write import new_case_text

    base = _file(tmp, "release_base.toml", new_case_text(planet="earth", mass=500.0, canopy_diameter=15.0,
                                                         canopy_type="flat_circular", altitude=800.0,
                                                         release_airspeed=60.0))
    return _file(tmp, "release.toml", f'extends = "{Path(base).as_posix()}"\n{extra}')


def _bare_canopy(tmp: Path) -> str:
    """The test cluster pair with its second canopy's aerodynamics removed."""
    text = (ROOT / "tests" / "cases" / "cluster_pair.toml").read_text()
    start = text.index("[bodies.c2.aerodynamics]")
    text = text[:start] + text[text.index("[systems.main]"):]
    (tmp / "constant_air.csv").write_text((ROOT / "tests" / "cases" / "constant_air.csv").read_text())
    return _file(tmp, "bare.toml", text)


def _bytes(tmp: Path) -> str:
    path = tmp / "latin1.toml"
    path.write_bytes(b"[case]\nname = \"caf\xe9\"\n")
    return str(path)


def _folder_with_notes(tmp: Path) -> str:
    folder = tmp / "notes"
    folder.mkdir()
    (folder / "todo.txt").write_text("mine")
    return str(folder)


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_bad_input_gives_one_line_and_a_nonzero_exit(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)


def test_the_battery_is_large_and_distinct():
    assert len(BATTERY) >= 40 and len({entry[0] for entry in BATTERY}) == len(BATTERY)
    assert len({entry[2] for entry in BATTERY}) >= 40


if __name__ == "__main__":   # the battery's messages as a table
    print_table(BATTERY)

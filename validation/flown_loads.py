"""Opening loads against the flight record: the supersonic disk-gap-band opening model calibrated on ASPIRE SR01,
SR02 and MSL, then predicting Mars 2020 and ASPIRE SR03 blind, each flight as a Monte Carlo of its opening.

Run:  python validation/flown_loads.py [--runs 400] [--workers 2] [--check | --compare]

1. Calibration: the model's two constants (C_ref and s_M of docs/models/supersonic_opening.md) are fitted, with the
   simulation in the loop, so that the nominal runs of the three calibration flights meet their flown first peaks in
   the least-squares sense (relative errors); their residuals give the load factor's uncertainty.
2. Predictions: every flight's case (cases/edl/) as a Monte Carlo study of its opening (the draws and their sources:
   DISPERSIONS and docs/validation/flown_loads.md); the first peak is the largest riser tension within WINDOW s of line
   stretch. Written to validation/output/flown_loads/predictions.json (median, p01, p99 in N, with the inputs).
3. Comparison: only then are the held-out flights' flown loads read (validation/flown_loads/held_out.json), and the
   page docs/validation/flown_loads.md is written.

``--check`` stops (exit 1) unless cases/edl/msl.toml holds the calibrated constants to 4 significant digits;
``--compare`` only writes the page again from the predictions.json on disk and the flown loads (no runs).
"""

from __future__ import annotations

import json
import math
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from script_arguments import OneLineParser, run_script

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "output" / "flown_loads"


def check_arguments(parser: OneLineParser, args) -> None:
    """Every argument, before anything is computed or written: one line naming the bad one (exit status 1)."""
    parser.check_counts(args)
    if args.compare:
        missing = [name for name in ("calibration.json", "predictions.json") if not (OUT / name).is_file()]
        if missing:
            parser.refuse(f"--compare: {OUT.relative_to(ROOT) / missing[0]} is missing: run without --compare first "
                          "(it calibrates and predicts)")


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--runs", type=int, default=400, help="Monte Carlo runs per flight (default 400)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    only = parser.add_mutually_exclusive_group()   # each is a whole mode of its own: both would drop one
    only.add_argument("--check", action="store_true", help="only check that msl.toml holds the calibration")
    only.add_argument("--compare", action="store_true", help="only write the page from predictions.json")
    args = parser.parse_args(argv)
    check_arguments(parser, args)
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

import numpy as np
from flown_loads_page import page

from pchute_exudyn import load_case, simulate
from pchute_exudyn.case.files import load_merged
from pchute_exudyn.errors import PchuteError
from pchute_exudyn.physics.inflation import nominal_diameter
from pchute_exudyn.physics.supersonic_opening import mass_ratio
from pchute_exudyn.results.io import atomic_write_text, atomic_writer
from pchute_exudyn.study import load as load_runs
from pchute_exudyn.study import load_study, run_study

HELD_OUT = HERE / "flown_loads" / "held_out.json"
PAGE = ROOT / "docs" / "validation" / "flown_loads.md"
WINDOW = 1.5          # s after line stretch: the first peak (fill about 0.5 s, overinflation decay 0.3 s)
KLBF = 4448.2216      # N per 1000 lbf
SEED = 2021


@dataclass(frozen=True)
class Flight:
    """One flown deployment: its case, its role and, for a calibration flight, its flown first peak (N)."""

    case: str
    label: str
    role: str                       # "calibration" or "held out"
    inputs: str                     # where the deployment conditions come from
    flown: float | None = None      # N, calibration flights only
    flown_source: str = ""
    dispersions: dict = field(default_factory=dict)   # case key -> (kind, spread): see DISPERSIONS


MARS = {"bodies.vehicle.mass": ("relative", 0.03), "bodies.vehicle.initial.mach": ("absolute", 0.02),
        "bodies.vehicle.initial.dynamic_pressure": ("relative", 0.03)}
EARTH = {"bodies.vehicle.mass": ("relative", 0.15), "bodies.vehicle.initial.mach": ("absolute", 0.02),
         "bodies.vehicle.initial.dynamic_pressure": ("relative", 0.03)}
DERIVED = {"bodies.vehicle.initial.mach": ("absolute", 0.05), "bodies.vehicle.initial.dynamic_pressure":
           ("relative", 0.10)}
DISPERSIONS = {"bodies.parachute.aerodynamics.axial_coefficient": ("relative", 0.05),
               "systems.main.inflation.supersonic.fill_constant": ("relative", 0.15)}
"""Every flight's draws (1-sigma, normal): C_D 5 % (assumed; MSL's reconstructed 0.636 against the pre-flight 0.615
is 3.4 %), the fill constant 15 % (assumed: SR03 filled in about 0.4 s, SR01 in about 0.5 s); the load factor's own
spread comes from the calibration's residuals."""

FLIGHTS = {
    "aspire_sr01": Flight("cases/edl/aspire_sr01.toml", "ASPIRE SR01 (2017, Earth)", "calibration",
                          "Mach 1.8 at about 42 km (NASA release); q from US76", 35.0 * KLBF,
                          "nearly 35 000 lbf (NASA/JPL release)", {**EARTH, **DERIVED}),
    "aspire_sr02": Flight("cases/edl/aspire_sr02.toml", "ASPIRE SR02 (2018, Earth)", "calibration",
                          "Mach 1.97, 670 Pa (O'Farrell et al., abstract)", 55.8 * KLBF,
                          "55.8 klbf (O'Farrell et al., abstract)", EARTH),
    "msl": Flight("cases/edl/msl.toml", "MSL (2012, Mars)", "calibration",
                  "11 km, 405 m/s (Nature's EDL graphic); Mach and q from our Mars atmosphere", 153.8e3,
                  "153.8 kN, the first peak's aerodynamic part (Cruz et al. 2014, abstract)", {**MARS, **DERIVED}),
    "mars2020": Flight("cases/edl/mars2020.toml", "Mars 2020 (2021, Mars)", "held out",
                       "Mach 1.82, 518 Pa (O'Farrell and Clark, abstract)", dispersions=MARS),
    "aspire_sr03": Flight("cases/edl/aspire_sr03.toml", "ASPIRE SR03 (2018, Earth)", "held out",
                          "Mach 1.85, 932 Pa (O'Farrell et al., abstract)", dispersions=EARTH),
}
CONSTANTS = ("load_factor", "mach_slope")
OPENING = "systems.main.inflation.supersonic"


def first_peak(key: str, constants: dict | None = None) -> dict:
    """The nominal run of flight ``key`` (with the model's ``constants`` when given): its first peak (N) and what
    the canopy met at line stretch."""
    path = ROOT / FLIGHTS[key].case
    overrides = {f"{OPENING}.{name}": value for name, value in (constants or {}).items()}
    case = load_case(path, overrides)
    stretch = case.systems["main"].deploy_time
    columns = simulate(case, duration=stretch + WINDOW).columns
    time, tension = columns["time"], columns["tension_riser"]
    at = int(np.searchsorted(time, stretch))
    peak = int(np.nanargmax(tension))
    parachute = case.bodies["parachute"]
    diameter = nominal_diameter(parachute.aerodynamics.reference_area)
    mach = float(columns["parachute_mach"][at])
    opening = case.systems["main"].inflation.supersonic
    drag_coefficient = float(parachute.aerodynamics.axial_coefficient(0.0, mach))
    density = case.atmosphere.density(float(columns["parachute_altitude"][at]))
    return {"peak": float(tension[peak]), "peak_time": float(time[peak] - stretch), "mach": mach,
            "dynamic_pressure": float(columns["parachute_dynamic_pressure"][at]), "drag_coefficient":
            drag_coefficient, "load_factor": opening.load_factor_at(mach, diameter),
            "reference_area": parachute.aerodynamics.reference_area, "mass": case.bodies["vehicle"].mass,
            "mass_ratio": mass_ratio(density, drag_coefficient * parachute.aerodynamics.reference_area,
                                     case.bodies["vehicle"].mass)}


def calibrate(rounds: int = 6) -> dict:
    """C_ref and s_M fitted to the calibration flights' flown peaks (relative least squares), the simulation in the
    loop; with each flight's residual and the load factor's 1-sigma spread from them."""
    keys = [key for key, flight in FLIGHTS.items() if flight.role == "calibration"]
    constants = {"load_factor": 1.5, "mach_slope": 0.0}
    reference = load_case(ROOT / FLIGHTS["msl"].case).systems["main"].inflation.supersonic.reference_mach
    for _ in range(rounds):
        runs = {key: first_peak(key, constants) for key in keys}
        needed = np.array([runs[k]["load_factor"] * FLIGHTS[k].flown / runs[k]["peak"] for k in keys])
        mach = np.array([runs[k]["mach"] for k in keys])
        rows = np.column_stack([1.0 / needed, (mach - reference) / needed])
        solution = np.linalg.lstsq(rows, np.ones(len(keys)), rcond=None)[0]
        moved = abs(solution[0] - constants["load_factor"]) + abs(solution[1] - constants["mach_slope"])
        constants = {"load_factor": float(solution[0]), "mach_slope": float(solution[1])}
        if moved < 1e-6:
            break
    runs = {key: first_peak(key, constants) for key in keys}
    residuals = {key: runs[key]["peak"] / FLIGHTS[key].flown - 1.0 for key in keys}
    spread = math.sqrt(sum(r * r for r in residuals.values()) / (len(keys) - len(CONSTANTS)))
    return {"constants": constants, "reference_mach": reference, "residuals": residuals, "spread": spread,
            "runs": runs}


def study_text(key: str, runs: int, spread: float) -> str:
    """The Monte Carlo study of flight ``key``'s opening (``pchute study`` can run it)."""
    flight = FLIGHTS[key]
    case = load_case(ROOT / flight.case)
    lines = ["[study]", f'name = "{key} opening"', f'case = "{(ROOT / flight.case).as_posix()}"', f"runs = {runs}",
             f"seed = {SEED}", f"duration = {case.systems['main'].deploy_time + WINDOW}",
             'sampling = "latin_hypercube"', ""]
    draws = {**DISPERSIONS, **flight.dispersions, f"{OPENING}.load_factor": ("relative", spread)}
    for name, (kind, sigma) in draws.items():
        lines.append(f'[parameters."{name}"]')
        if kind == "relative":
            lines += ['distribution = "normal"', "mean = 1.0", f"std = {sigma!r}", "relative = true", ""]
        else:
            mean = _value(ROOT / flight.case, name)
            lines += ['distribution = "normal"', f"mean = {mean!r}", f"std = {sigma!r}", ""]
    return "\n".join(lines)


def _value(path: Path, dotted: str) -> float:
    """The value the case file (with its ``extends`` chain) gives at ``dotted`` (the absolute draws' means)."""
    data = load_merged(path, {})
    for part in dotted.split("."):
        data = data[part]
    return float(data)


def predict(key: str, runs: int, spread: float, workers: int, kept: dict) -> dict:
    """The flight's Monte Carlo: the first peak's median, 1st and 99th percentiles (N), and the runs that failed.
    The study runs in a temporary folder; its file and table go into ``kept`` (study_files/<key>/study.toml and
    runs/<key>.csv, written by ``main`` once every flight has its prediction)."""
    text = study_text(key, runs, spread)
    with tempfile.TemporaryDirectory() as scratch:
        spec_path = Path(scratch) / "study.toml"   # the case's path in it is absolute
        spec_path.write_text(text)
        folder = Path(scratch) / key
        run_study(load_study(spec_path), folder, workers=workers, progress=sys.stderr.isatty())
        kept[Path("study_files") / key / "study.toml"] = text
        kept[Path("runs") / f"{key}.csv"] = (folder / "runs.csv").read_bytes()   # as the study wrote it
        table = load_runs(folder)
    peaks = table["peak_tension_riser"].to_numpy(float)
    peaks = peaks[np.isfinite(peaks)]
    return {"median": float(np.median(peaks)), "p01": float(np.percentile(peaks, 1.0)),
            "p99": float(np.percentile(peaks, 99.0)), "runs": int(len(peaks)), "failed": int(runs - len(peaks))}


def calibrated_in_case(calibration: dict) -> list:
    """The constants cases/edl/msl.toml should hold and does not (to 4 significant digits): (name, file's, fitted)."""
    opening = load_case(ROOT / FLIGHTS["msl"].case).systems["main"].inflation.supersonic
    return [(name, getattr(opening, name), value) for name, value in calibration["constants"].items()
            if float(f"{value:.4g}") != getattr(opening, name)]


def predictions(calibration: dict, runs: int, workers: int, kept: dict) -> dict:
    """Every flight's inputs (with their sources) and predicted first peak (N), as predictions.json holds them."""
    return {key: {**flight_inputs(key, calibration["spread"]),
                  **predict(key, runs, calibration["spread"], workers, kept)} for key in FLIGHTS}


def flight_inputs(key: str, spread: float) -> dict:
    """What flight ``key``'s prediction starts from: its case, the deployment conditions and their source, the
    Monte Carlo's draws, and its nominal run."""
    flight = FLIGHTS[key]
    path = ROOT / flight.case
    case = load_case(path)
    conditions = {name: _value(path, f"bodies.vehicle.initial.{name}") for name in ("mach", "dynamic_pressure")}
    return {"flight": flight.label, "role": flight.role, "case": flight.case,
            "inputs": {"mach_at_mortar_fire": conditions["mach"], "dynamic_pressure_at_mortar_fire":
                       conditions["dynamic_pressure"], "source": flight.inputs,
                       "vehicle_mass": case.bodies["vehicle"].mass,
                       "parachute_reference_area": case.bodies["parachute"].aerodynamics.reference_area,
                       "line_stretch_after_mortar_fire": case.systems["main"].deploy_time,
                       "dispersions": {**DISPERSIONS, **flight.dispersions,
                                       f"{OPENING}.load_factor": ("relative", spread)}},
            "nominal": first_peak(key), "unit": "N"}


def main(argv=None) -> int:
    args = arguments(argv)
    try:
        return _main(args)
    except (PchuteError, OSError, ValueError) as exc:
        raise SystemExit(f"flown_loads.py: {exc}") from None


def _main(args) -> int:
    if args.compare:
        return write_page()
    calibration = calibrate()
    stale = calibrated_in_case(calibration)
    for name, held, fitted in stale:
        print(f"cases/edl/msl.toml: {OPENING}.{name} = {held!r}, the calibration gives {fitted:.4g}", file=sys.stderr)
    if stale or args.check:
        return 1 if stale else 0
    kept: dict = {}
    flights = predictions(calibration, args.runs, args.workers, kept)
    # written only now, every flight predicted: a run that fails leaves the committed outputs as they were
    kept[Path("calibration.json")] = json.dumps(calibration, indent=2, allow_nan=False) + "\n"
    kept[Path("predictions.json")] = json.dumps(flights, indent=2, allow_nan=False) + "\n"
    for relative, content in kept.items():
        (OUT / relative).parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            with atomic_writer(OUT / relative, "wb") as handle:
                handle.write(content)
        else:
            atomic_write_text(OUT / relative, content)
    print(f"wrote {OUT / 'calibration.json'} and {OUT / 'predictions.json'}")
    return write_page()


def write_page() -> int:
    """The page from the calibration and the predictions on disk; the held-out flights' flown loads are read here,
    after them."""
    result = {"calibration": json.loads((OUT / "calibration.json").read_text()),
              "flights": json.loads((OUT / "predictions.json").read_text())}
    held_out = json.loads(HELD_OUT.read_text()) if HELD_OUT.exists() else {}
    calibration = {k: {"flown": f.flown, "source": f.flown_source} for k, f in FLIGHTS.items() if f.flown}
    atomic_write_text(PAGE, page(result, held_out, calibration))
    print(f"wrote {PAGE}")
    return 0


if __name__ == "__main__":
    run_script(main)

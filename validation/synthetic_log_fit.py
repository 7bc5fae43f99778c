"""A fit to a flight log the package made itself: does `pchute fit` recover what it was made with?

A dual-deploy rocket (`pchute new --dual-deploy`) is flown with known drag areas and a known main lag; its height above
the ground is sampled at the altimeter's rate with Gaussian noise (1 m rms) and written as a log a rocketeer would
bring (pad samples, a climb to the apogee, the descent: a generic CSV). The fit starts 30 % off on each canopy's
C_D S and on the main's lag, fits the log's descent (`log = ...` target, std 1 m) and reports each key's error
against the truth in standard errors.

    python validation/synthetic_log_fit.py [--out DIR] [--seeds 56,1,2,3,4,5] [--page docs/validation/log_fit.md]

Writes DIR/synthetic_log_fit.json (and the page) and prints one line per key and seed. tests/integration/
test_log_fit.py fits one log and asserts C_D S within 2 %, the lag within 0.2 s, each within 3 standard errors.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from script_arguments import OneLineParser, output_file, output_path, run_script


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--out", default="validation/output/synthetic_log_fit", type=output_path)
    parser.add_argument("--seeds", default="56,1,2,3,4,5", help="the logs' noise seeds, comma separated")
    parser.add_argument("--page", type=output_file, default=None, help="also write the Markdown page here")
    args = parser.parse_args(argv)
    try:
        args.seeds = [int(seed) for seed in args.seeds.split(",")]
    except ValueError:
        parser.refuse(f"--seeds {args.seeds!r}: must be whole numbers separated by commas")
    if any(not 0 <= seed < 2**32 for seed in args.seeds):
        parser.refuse(f"--seeds {','.join(map(str, args.seeds))}: each must be from 0 to 2^32 - 1 (a noise seed)")
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

import numpy as np

TRUTH = {"drogue_canopy.aerodynamics.reference_area": 0.3, "main_canopy.aerodynamics.reference_area": 4.0,
         "main.deploy_trigger.lag": 1.0}
"""The flown values: the canopies' S0 (m^2, C_D fixed by the case: C_D S follows S0) and the main's lag (s)."""
BOUNDS = {"drogue_canopy.aerodynamics.reference_area": (0.1, 0.6),
          "main_canopy.aerodynamics.reference_area": (1.5, 8.0), "main.deploy_trigger.lag": (0.0, 2.5)}
START_OFF = 0.3
"""The fit starts this far off the truth (+30 % on the areas, -30 %... on the lag: 0.7 s)."""
NOISE = 1.0
"""m rms: the altimeter's noise on every sample."""
RATE = 20.0
"""Hz: the log's sampling rate."""
CASE_OPTIONS = ["--planet", "earth", "--mass", "8.0", "--length", "1.8", "--diameter", "0.1",
                "--drogue-drag-area", "0.4", "--main-drag-area", "5.0", "--main-height", "150", "--height", "600",
                "--ground-elevation", "200", "--latitude", "41.0"]


def write_case(folder: Path) -> Path:
    """The rocket's case with the main's lag written in (the fit's free keys must be the case's own)."""
    path = folder / "rocket.toml"
    subprocess.run([sys.executable, "-m", "pchute_exudyn", "new", "--dual-deploy", str(path), "--overwrite",
                    *CASE_OPTIONS, "--main-lag", "1"], check=True, capture_output=True)
    return path


def flown(case: Path) -> tuple:
    """(time s from the apogee, height m above the ground) of the case flown at TRUTH."""
    from pchute_exudyn import load_case, simulate

    result = simulate(load_case(case, TRUTH), "sp")
    height = result["rocket_height"]
    top = int(np.argmax(height))
    return result.time[top:] - result.time[top], height[top:]


def write_log(path: Path, time, height, seed: int) -> None:
    """A log as an altimeter writes it: 5 s on the pad, a 12 s climb to the apogee (a coasting parabola), the
    descent, 5 s on the ground; every sample with NOISE; a generic CSV (time (s), height (m))."""
    rng = np.random.default_rng(seed)
    climb = 12.0
    t = np.arange(-climb - 5.0, time[-1] + 5.0, 1.0 / RATE)
    up = np.clip(t + climb, 0.0, climb)
    h = np.where(t < 0.0, height[0] * (1.0 - (1.0 - up / climb) ** 2), np.interp(t, time, height, right=0.0))
    h += rng.normal(0.0, NOISE, len(t))
    lines = ["time (s),height (m)"] + [f"{a + climb + 5.0:.3f},{b:.3f}" for a, b in zip(t, h)]
    from pchute_exudyn.results.io import atomic_write_text

    atomic_write_text(path, "\n".join(lines) + "\n")


def write_fit(folder: Path, case: Path, log: Path) -> Path:
    start = {key: value * (1.0 + START_OFF) if "area" in key else value * (1.0 - START_OFF)
             for key, value in TRUTH.items()}
    rows = ["[fit]", 'name = "synthetic log"', f'case = "{case.name}"', 'method = "sp"', ""]
    for key, (low, high) in BOUNDS.items():
        rows += [f'[free."{key}"]', f"low = {low}", f"high = {high}", f"initial = {start[key]:.6g}", ""]
    rows += ["[[targets]]", f'log = "{log.name}"', f"std = {NOISE}"]
    path = folder / "fit.toml"
    from pchute_exudyn.results.io import atomic_write_text

    atomic_write_text(path, "\n".join(rows) + "\n")
    return path


def fit_seed(out: Path, seed: int) -> list:
    """One synthetic log (``seed``) made, fitted in ``out``; per key: truth, fitted, standard error, errors."""
    out.mkdir(parents=True, exist_ok=True)
    case = write_case(out)
    write_log(out / "flight.csv", *flown(case), seed)
    fit = write_fit(out, case, out / "flight.csv")
    subprocess.run([sys.executable, "-m", "pchute_exudyn", "fit", str(fit), "--out", str(out / "fit")], check=True,
                   capture_output=True)
    outcome = json.loads((out / "fit" / "fit.json").read_text())
    rows = []
    for key, fitted, error, start in zip(outcome["keys"], outcome["fitted"], outcome["standard_error"],
                                         outcome["initial"]):
        truth = TRUTH[key]
        rows.append({"key": key, "truth": truth, "start": start, "fitted": fitted, "standard_error": error,
                     "error": fitted - truth, "relative_error": (fitted - truth) / truth,
                     "errors_in_se": (fitted - truth) / error, "runs": outcome["runs"]})
    return rows


def page(results: dict) -> str:
    lines = ["# A fit to a log the package made itself", "",
             "Written by `python validation/synthetic_log_fit.py` (its docstring says how the log is made). A "
             f"dual-deploy rocket flown with known S0 of both canopies and a known main lag, sampled at {RATE:g} Hz "
             f"with {NOISE:g} m rms Gaussian noise, fitted by `pchute fit` (a `log` target, std {NOISE:g} m) from "
             f"{START_OFF:.0%} off the truth (the areas high, the lag low). C_D is fixed by the case, so a canopy's "
             "C_D S errs as its S0.", "",
             "| seed | key | truth | start | fitted | standard error | fitted - truth | in standard errors |",
             "|---|---|---|---|---|---|---|---|"]
    for seed, rows in results.items():
        for r in rows:
            lines.append(f"| {seed} | {r['key']} | {r['truth']:g} | {r['start']:.4g} | {r['fitted']:.5g} | "
                         f"{r['standard_error']:.2g} | {r['error']:+.3g} ({r['relative_error']:+.2%}) | "
                         f"{r['errors_in_se']:+.2f} |")
    z = np.array([r["errors_in_se"] for rows in results.values() for r in rows])
    worst_area = max(abs(r["relative_error"]) for rows in results.values() for r in rows if "area" in r["key"])
    worst_lag = max(abs(r["error"]) for rows in results.values() for r in rows if "lag" in r["key"])
    lines += ["", f"Over {len(results)} logs: the largest C_D S error {worst_area:.2%} (bound 2 %), the largest lag "
                  f"error {worst_lag:.3f} s (bound 0.2 s); the errors in standard errors have RMS {np.sqrt(np.mean(z**2)):.2f} "
                  f"(1 if the standard errors are right), {np.count_nonzero(np.abs(z) <= 2.0)} of {len(z)} within 2 "
                  f"and all within {np.abs(z).max():.2f}."]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    args = arguments(argv)
    results = {}
    for seed in args.seeds:
        results[seed] = fit_seed(args.out / f"seed_{seed}", seed)
        for r in results[seed]:
            print(f"seed {seed}: {r['key']}: truth {r['truth']:g}, fitted {r['fitted']:.5g} +- "
                  f"{r['standard_error']:.2g} ({r['relative_error']:+.2%}, {r['errors_in_se']:+.2f} SE)", flush=True)
    from pchute_exudyn.results.io import atomic_write_text

    atomic_write_text(args.out / "synthetic_log_fit.json", json.dumps(results, indent=2) + "\n")
    if args.page is not None:
        atomic_write_text(args.page, page(results))
    return 0


if __name__ == "__main__":
    run_script(main)

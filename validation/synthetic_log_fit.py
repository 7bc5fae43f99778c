"""A fit to a flight log the package made itself: does `pchute fit` recover what it was made with?

A dual-deploy rocket (`pchute new --dual-deploy`) is flown with known drag areas and a known main lag; its height above
the ground is sampled at the altimeter's rate with Gaussian noise (1 m rms) and written as a log a rocketeer would
bring (pad samples, a climb to the apogee, the descent: a generic CSV). The fit starts 30 % off on each canopy's
C_D S and on the main's lag, fits the log's descent (`log = ...` target, std 1 m) and reports each key's error
against the truth in standard errors.

    python validation/synthetic_log_fit.py [--out DIR] [--seed N]

Writes DIR/synthetic_log_fit.json and prints one line per key. Checked by tests/integration/test_log_fit.py (which
asserts: C_D S within 2 %, lag within 0.2 s, each within 3 standard errors).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

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
CASE_OPTIONS = ["--planet", "earth", "--mass", "4.0", "--length", "1.2", "--diameter", "0.075",
                "--drogue-drag-area", "0.4", "--main-drag-area", "5.0", "--main-height", "150", "--height", "600",
                "--ground-elevation", "200", "--latitude", "41.0"]


def write_case(folder: Path) -> Path:
    """The rocket's case with the main's lag written in (the fit's free keys must be the case's own)."""
    path = folder / "rocket.toml"
    subprocess.run([sys.executable, "-m", "pchute_exudyn", "new", "--dual-deploy", str(path), "--overwrite",
                    *CASE_OPTIONS], check=True, capture_output=True)
    text = path.read_text().replace('reference = "ground", rate = 100 }', 'reference = "ground", rate = 100, lag = 1 }')
    path.write_text(text)
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
    path.write_text("\n".join(lines) + "\n")


def write_fit(folder: Path, case: Path, log: Path) -> Path:
    start = {key: value * (1.0 + START_OFF) if "area" in key else value * (1.0 - START_OFF)
             for key, value in TRUTH.items()}
    rows = ["[fit]", 'name = "synthetic log"', f'case = "{case.name}"', 'method = "sp"', ""]
    for key, (low, high) in BOUNDS.items():
        rows += [f'[free."{key}"]', f"low = {low}", f"high = {high}", f"initial = {start[key]:.6g}", ""]
    rows += ["[[targets]]", f'log = "{log.name}"', f"std = {NOISE}"]
    path = folder / "fit.toml"
    path.write_text("\n".join(rows) + "\n")
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="validation/output/synthetic_log_fit", type=Path)
    parser.add_argument("--seed", type=int, default=56)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    case = write_case(args.out)
    write_log(args.out / "flight.csv", *flown(case), args.seed)
    fit = write_fit(args.out, case, args.out / "flight.csv")
    subprocess.run([sys.executable, "-m", "pchute_exudyn", "fit", str(fit), "--out", str(args.out / "fit")],
                   check=True)
    outcome = json.loads((args.out / "fit" / "fit.json").read_text())
    rows = []
    for key, fitted, error in zip(outcome["keys"], outcome["fitted"], outcome["standard_error"]):
        truth = TRUTH[key]
        rows.append({"key": key, "truth": truth, "fitted": fitted, "standard_error": error,
                     "relative_error": (fitted - truth) / truth, "errors_in_se": (fitted - truth) / error})
        print(f"{key}: truth {truth:g}, fitted {fitted:.5g} +- {error:.2g} ({(fitted - truth) / truth:+.2%}, "
              f"{(fitted - truth) / error:+.2f} SE)")
    summary = {"seed": args.seed, "noise_m": NOISE, "rate_hz": RATE, "start_off": START_OFF, "runs": outcome["runs"],
               "keys": rows}
    (args.out / "synthetic_log_fit.json").write_text(json.dumps(summary, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

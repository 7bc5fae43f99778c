"""What packing the recovery gear changes on the shipped cases that deploy during the run (issue 48): each run with
its systems unpacked (``packed = false``: each system's mass enters at its deployment; the model before packing
became the default, and the one the thesis's PA1 cases keep by name) and packed (the gear rides in the vehicle until
it deploys: the default, and the EDL case as shipped), side by side.

Run:  python validation/packed_gear.py
Writes validation/output/packed/shipped.md.
"""

from __future__ import annotations

import math
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

from pchute_exudyn import load_case, simulate
from pchute_exudyn.case.carried import suspended_mass
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "validation" / "output" / "packed" / "shipped.md"
CASES = ("cev_pa1.toml", "cev_pa1_inflation.toml", "cev_pa1_winds.toml", "cev_pa1_triggers.toml",
         "cev_pa1_cluster.toml", "mer/edl.toml")


def _figures(result) -> dict:
    summary = result.summary
    touchdown = summary.touchdown
    peaks = summary.peak_tension
    return {"touchdown (s)": touchdown.time if touchdown else math.nan,
            "east (m)": summary.final.east, "north (m)": summary.final.north,
            "final rate (m/s)": summary.descent.final_rate,
            "peak line load (N)": max(peaks.values()) if peaks else math.nan}


def compare(name: str) -> list:
    path = ROOT / "cases" / name
    deploying = [name for name, s in load_case(path).systems.items() if s.deploy_time is not None]
    unpacked, packed = (load_case(path, overrides={f"systems.{s}.packed": value for s in deploying})
                        for value in (False, True))
    runs = [(label, case, simulate(case, "sp")) for label, case in (("unpacked", unpacked), ("packed", packed))]
    start_masses = [suspended_mass(case, 0.0) for _, case, _ in runs]
    figures = [_figures(result) for _, _, result in runs]
    rows = []
    for key in figures[0]:
        before, after = figures[0][key], figures[1][key]
        change = f"{after - before:+.3f}" if np.isfinite(before) and np.isfinite(after) else "-"
        rows.append(f"| {name} | {key} | {before:.3f} | {after:.3f} | {change} |")
    rows.append(f"| {name} | suspended mass at the start (kg) | {start_masses[0]:.3f} | {start_masses[1]:.3f} | "
                f"{start_masses[1] - start_masses[0]:+.3f} |")
    return rows


def main() -> None:
    lines = ["# Packed recovery gear on the shipped cases", "",
             "`python validation/packed_gear.py`: each case that deploys a system during the run, flown with SP "
             "(the case's step) with its systems unpacked (`packed = false`: the mass of each enters at its "
             "deployment; the thesis's PA1 model, which the PA1 cases keep by name) and packed (the gear rides in the "
             "vehicle until it deploys: the default, as `cases/mer/edl.toml` is shipped). "
             f"Exudyn {versions()['exudyn']}, pchute-exudyn {versions()['pchute_exudyn']}.", "",
             "| case | figure | unpacked | packed | change |", "|---|---|---|---|---|"]
    for name in CASES:
        lines += compare(name)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(OUT, "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    run_script(main)

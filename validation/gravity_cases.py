"""What normal gravity would change on the shipped cases: each run with spherical gravity (the thesis's model) and with
normal gravity (the level ellipsoid's, docs/models/gravity.md), switched by an override of ``planet.gravity_model``,
side by side: the touchdown time and the vehicle's east, north and altitude at touchdown (or at the end of a run that
stops at its duration).

Run:  python validation/gravity_cases.py      (about 2 minutes; writes validation/output/gravity/cases.md)

MER's ellipsoid (thesis Table 3.3) is not the published IAU one, so its spin cannot default: the normal runs set
``planet.spin_rate`` to Mars's sidereal rate (``physics.gravity.MARS_OMEGA``).
"""

from __future__ import annotations

from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.physics.gravity import MARS_OMEGA
from pchute_exudyn.results.io import atomic_write_text

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "output" / "gravity" / "cases.md"
CASES = [   # (label, case file, overrides of the normal-gravity run)
    ("MER case 1 (SP, ends at 60 s)", "cases/mer/case1.toml", {"planet.spin_rate": MARS_OMEGA}),
    ("MER EDL (SP)", "cases/mer/edl.toml", {"planet.spin_rate": MARS_OMEGA}),
    ("Orion PA1 (SP)", "cases/cev_pa1.toml", {}),
    ("Rocket dual deploy (SP)", "cases/rocket/dual_deploy.toml", {}),
]


def landing(case_file: str, gravity_model: str, extra: dict) -> tuple:
    """(end, time in s, east in m, north in m, altitude in m) of the vehicle at touchdown (interpolated to the event's
    time) or at the run's end."""
    overrides = {"planet.gravity_model": gravity_model, **(extra if gravity_model == "normal" else {})}
    case = pc.load_case(ROOT / case_file, overrides)
    result = pc.simulate(case)
    events = result.summary.events_of("touchdown")
    columns, vehicle = result.columns, case.vehicle
    time = events[0].time if events else float(columns["time"][-1])
    east, north, altitude = (float(np.interp(time, columns["time"], columns[f"{vehicle}_{axis}"]))
                             for axis in ("east", "north", "altitude"))
    return ("touchdown" if events else "end"), time, east, north, altitude


def main() -> int:
    rows = []
    for label, case_file, extra in CASES:
        end, *spherical = landing(case_file, "spherical", extra)
        _, *normal = landing(case_file, "normal", extra)
        change = [n - s for n, s in zip(normal, spherical)]
        rows.append(f"| {label} | {end} | " + " | ".join(
            f"{s:.3f} / {n:.3f} ({c:+.3f})" for s, n, c in zip(spherical, normal, change)) + " |")
        print(rows[-1], flush=True)
    text = "\n".join([
        "# Spherical against normal gravity on the shipped cases",
        "",
        "`python validation/gravity_cases.py`: each case run with its default method and steps, once with "
        "`planet.gravity_model = \"spherical\"` and once with `\"normal\"` (docs/models/gravity.md). Values: "
        "spherical / normal (normal - spherical). Time in s, the vehicle's east and north of the start point in m "
        "(relative to the ground) and its altitude in m, at touchdown interpolated to the event, or at the run's end. MER's normal runs set "
        f"`planet.spin_rate = {MARS_OMEGA}` rad/s (its thesis ellipsoid is not the published one).",
        "",
        "| case | at | time (s) | east (m) | north (m) | altitude (m) |",
        "|---|---|---|---|---|---|",
        *rows, ""])
    OUT.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(OUT, text)
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    run_script(main)

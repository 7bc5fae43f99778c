"""What `pchute new` prints against what its case runs: the steady rate of 1, 2, 3 and 5 canopies.

Run:  python validation/new_case_rates.py

For the cargo choices (Earth, 2000 kg, 30.5 m flat circular canopies) at each canopy count: the rate `pchute new`
states for 1500 m (the suspended mass, the cluster's drag efficiency and spread, the air where the drag acts), and the
SP run's rate as it passes 1500 m in the case written 150 m higher (the start's transient over). Writes
validation/output/new_case/cluster_rates.md.
"""

from __future__ import annotations

import math
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.authoring.choices import NewCase
from pchute_exudyn.authoring.layout import layout
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions

OUT = Path(__file__).resolve().parent / "output" / "new_case"
CARGO = dict(planet="earth", mass=2000.0, canopy_diameter=30.5, canopy_type="flat_circular")
STATED, ABOVE, TOLERANCE = 1500.0, 150.0, 2e-3


def main(argv=None) -> int:
    rows, worst = [], 0.0
    for canopies in (1, 2, 3, 5):
        plan = layout(NewCase(**CARGO, canopies=canopies, altitude=STATED))
        result = pc.simulate(pc.new_case(**CARGO, canopies=canopies, altitude=STATED + ABOVE), "sp", duration=60.0)
        when = np.interp(-STATED, -result["vehicle_altitude"], result.time)
        rate = float(np.interp(when, result.time, result["vehicle_velocity_down"]))
        stated = plan.steady_rate(STATED)
        worst = max(worst, abs(rate / stated - 1.0))
        rows.append(f"| {canopies} | {plan.total_mass:.2f} | {plan.drag_efficiency:g} | {math.degrees(plan.spread):.2f} "
                    f"| {plan.vertical_coefficient:.5f} | {stated:.4f} | {when:.1f} | {rate:.4f} | "
                    f"{(rate / stated - 1.0) * 100:+.3f} % |")
    v = versions()
    text = "\n".join([
        "# `pchute new`'s steady rate against its run",
        "",
        f"`python validation/new_case_rates.py` (pchute_exudyn {v['pchute_exudyn']}, Exudyn {v['exudyn']}): Earth, "
        "2000 kg under 30.5 m flat circular canopies (C_D0 0.77). The stated rate is sqrt(2 m g / (rho n C_V S0)) at "
        f"{STATED:g} m; the run is SP from {STATED + ABOVE:g} m, its rate read as it passes {STATED:g} m. C_V = eta "
        "C_D0 cos(theta) + C_N(theta) sin(theta), eta the cluster's drag efficiency, theta the spread its canopies "
        f"fly at (their envelopes touching). Largest difference {worst * 100:.3f} % (limit {TOLERANCE * 100:g} %).",
        "",
        "| canopies | suspended mass (kg) | eta | spread (deg) | C_V | stated rate (m/s) | passes 1500 m at (s) | run's "
        "rate (m/s) | run - stated |",
        "|---|---|---|---|---|---|---|---|---|",
        *rows, ""])
    atomic_write_text(OUT / "cluster_rates.md", text)
    print(text)
    return 0 if worst <= TOLERANCE else 1


if __name__ == "__main__":
    run_script(main)

"""The cluster closed forms through the engine (docs/models/cluster.md, section 6), measured with every method.

Run:  python validation/cluster_checks.py

The cases are the test suite's (tests/cases/cluster_pair.toml, cluster_pair_as_one.toml, cluster_trio.toml,
canopy_bump.toml; tests/integration/test_cluster.py asserts the same checks). Writes validation/output/cluster/closed_forms.md:

* two identical canopies, mirror-symmetric start: the largest riser tension difference over the peak;
* the pair against one canopy of twice the mass and drag area, and against sqrt(2 W / (rho C_A S)): the steady rate;
* two of three canopies (the third never inflates, packed in the payload) against three: the rate ratio over
  sqrt(3/2) sqrt(eta(3) / eta(2));
* two canopies pushed together (undamped contact): the largest overlap over v sqrt(mu / k) and the speeds they part at.
"""

from __future__ import annotations

import math
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.physics.cluster import DEFAULT_DRAG_EFFICIENCY
from pchute_exudyn.results.io import atomic_write_text
from pchute_exudyn.run.simulation import versions

HERE = Path(__file__).resolve().parent
CASES = HERE.parent / "tests" / "cases"
OUT = HERE / "output" / "cluster"
METHODS = [("SP", "sp", "rk4"), ("full mass implicit", "full", "implicit"), ("equilibrium point", "equilibrium", "rk4")]
RHO, G = 0.02, 9.81   # kg/m^3 (tests/cases/constant_air.csv), m/s^2


def rate(result, seconds: float = 5.0) -> float:
    window = result["time"] >= result["time"][-1] - seconds
    return float(np.mean(result["payload_velocity_down"][window]))


def main(argv=None) -> int:
    rows = []
    for label, method, integrator in METHODS:
        pair = pc.simulate(pc.load_case(CASES / "cluster_pair.toml"), method, integrator)
        one = pc.simulate(pc.load_case(CASES / "cluster_pair_as_one.toml"), method, integrator)
        tension = np.stack([pair["tension_r1"], pair["tension_r2"]])
        symmetric = np.nanmax(np.abs(tension[0] - tension[1])) / np.nanmax(tension)
        massless = method == "equilibrium"
        weight = (220.0 + (0.0 if massless else 0.5)) * G
        closed = math.sqrt(2 * weight / (RHO * 0.8 * 200.0))
        rates = {}
        for failed in ("", "c3"):
            rates[failed] = rate(pc.simulate(pc.load_case(CASES / "cluster_trio.toml",
                                                          {"failures.not_inflated": failed}), method, integrator))
        expected = math.sqrt(1.5) * math.sqrt(DEFAULT_DRAG_EFFICIENCY[2] / DEFAULT_DRAG_EFFICIENCY[1])
        bump = pc.simulate(pc.load_case(CASES / "canopy_bump.toml"), method, integrator)
        bound = 2.0 * math.sqrt(5.0 / 1000.0)
        rows.append(f"| {label} | {symmetric:.1e} | {rate(pair) / rate(one) - 1:+.1e} | {rate(pair) / closed - 1:+.1e} | "
                    f"{rates['c3'] / rates['']:.6f} ({rates['c3'] / rates[''] / expected - 1:+.1e}) | "
                    f"{np.nanmax(bump['c1_c2_overlap']) / bound - 1:+.1e} | "
                    f"{bump['c1_velocity_east'][-1]:+.5f} / {bump['c2_velocity_east'][-1]:+.5f} |")
        print(rows[-1], flush=True)
    v = versions()
    text = "\n".join([
        "# Cluster closed forms through the engine",
        "",
        "`python validation/cluster_checks.py`; cases in tests/cases/ (tests/integration/test_cluster.py asserts the same). "
        f"Exudyn {v['exudyn']}, pchute-exudyn {v['pchute_exudyn']}.",
        "",
        "| method | pair: largest riser tension difference / peak | pair against one canopy of twice the size: steady "
        "rate | pair against sqrt(2 W / (rho C_A S)) | two of three against three: rate ratio (against sqrt(3/2) "
        f"sqrt(eta3/eta2) = {expected:.6f}) | bump: largest overlap against v sqrt(mu / k) | bump: speeds they "
        "part at (m/s; met at +1 / -1) |",
        "|---|---|---|---|---|---|---|",
        *rows,
        "",
        "The pair deploys mirror-symmetrically 10 deg either side of the vertical with contact off, so the canopies "
        "swing onto the axis and must fly as one canopy of twice the mass and drag area; the trio likewise (contact "
        "off). The equilibrium point's confluence is massless (its weight left out of W). The bump: two canopies of "
        "10 kg with 5 m envelopes closing at 2 m/s, k = 1000 N/m, no damping, no gravity, no aerodynamic force.",
        ""])
    atomic_write_text(OUT / "closed_forms.md", text)
    print(text)
    return 0


if __name__ == "__main__":
    run_script(main)

"""The full-mass model (Exudyn's implicit integrator) against singular perturbation on MER case 1, 20 s.

    python examples/compare_methods.py [OUTPUT_FOLDER]

Prints the comparison table and writes compare_tensions.png: each line's tension from both runs, with the SP-minus-
full-mass difference under it (a 0.1 N difference on a 700 N tension).
"""

from _output import ROOT, output_folder

import pchute_exudyn as pc
from pchute_exudyn.results.compare import compare_results
from pchute_exudyn.views.plotting import plot_tension_overlay, save_figure

out = output_folder()
case = pc.load_case(ROOT / "cases" / "mer" / "case1.toml")
full = pc.simulate(case, "full", "implicit", 1e-2, duration=20.0)
sp = pc.simulate(case, "sp", "rk4", 1e-2, duration=20.0)
print(compare_results(full, sp, "full implicit", "SP").table())
save_figure(plot_tension_overlay({"full mass, implicit 1e-2 s": full, "SP, RK4 1e-2 s": sp},
                                 title="MER case 1: full mass against SP"), out / "compare_tensions.png")

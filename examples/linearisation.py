"""The confluence of MER case 1 linearised at 30 s: its modes and the largest stable RK4 steps.

    python examples/linearisation.py [OUTPUT_FOLDER]

Prints the report of `pchute linearize` and writes eigenvalues.png: the six eigenvalues of the full-mass confluence
(all real and negative: overdamped) and the decay rate 2.785 / h at which RK4 with step h turns unstable, at the
largest stable full-mass step.
"""

import numpy as np
from _output import ROOT, output_folder

import pchute_exudyn as pc
from pchute_exudyn.run.linear_report import format_report, linearization_report
from pchute_exudyn.views.plotting import new_figure, save_figure

out = output_folder()
report = linearization_report(pc.load_case(ROOT / "cases" / "mer" / "case1.toml"), None, 30.0)
print(format_report(report))
eigenvalues = np.array(report["eigenvalues"])
figure, axes = new_figure(1, 1, size=(7.0, 4.0))
ax = axes[0, 0]
ax.semilogx(-eigenvalues[:, 0], eigenvalues[:, 1], "o", label="confluence eigenvalues (full mass)")
step = report["max_stable_step_full"]
ax.axvline(2.785 / step, color="k", linestyle="--", linewidth=0.8,
           label=f"RK4 stability edge 2.785 / h at the largest stable step h = {step * 1e3:.3f} ms")
ax.set_xlabel("decay rate -Re(lambda) (1/s)")
ax.set_ylabel("Im(lambda) (1/s)")
ax.legend(fontsize="small")
ax.grid(True, which="both", alpha=0.3)
figure.suptitle("MER case 1 at 30 s: confluence modes")
save_figure(figure, out / "eigenvalues.png")

"""A 12-run Monte Carlo of MER case 1 (10 s, SP) on every core, and its report.

    python examples/small_study.py [OUTPUT_FOLDER]

Writes study/ (runs.csv and the report: report/report.md, histograms and scatter plots).
"""

import shutil

from _output import ROOT, output_folder

from pchute_exudyn.study import load_study, run_study
from pchute_exudyn.study.report import study_report

out = output_folder()
study_file = out / "small_study.toml"
study_file.write_text(f"""
[study]
name = "MER case 1, 12 dispersed runs"
case = "{(ROOT / 'cases' / 'mer' / 'case1.toml').as_posix()}"
runs = 12
seed = 7
duration = 10.0

[[study.configurations]]
method = "sp"
steps = [1e-2]

[parameters."vehicle.initial.velocity_east"]
distribution = "normal"
mean = 0.0
std = 0.5                      # m/s

[parameters."parachute.aerodynamics.axial_coefficient"]
distribution = "uniform"
low = 0.95
high = 1.05
relative = true                # x the case's C_A
""")
shutil.rmtree(out / "study", ignore_errors=True)
counts = run_study(load_study(study_file), out / "study", progress=False)
paths = study_report(out / "study")
print(f"{counts.executed} runs, {counts.failed} failed; report {paths['report']}")

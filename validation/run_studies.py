"""Run the built-in studies of validation/studies/ and write their reports into validation/output/studies/<name>/.

Run:  python validation/run_studies.py [--workers N] [names ...]

Each study resumes if its folder already holds some of its runs (delete the folder to start over). Wall times are
measured inside the runs, with the workers running side by side.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pchute_exudyn.study import load_study, run_study
from pchute_exudyn.study.report import study_report

HERE = Path(__file__).resolve().parent
STUDIES = ["step_method", "sp_presets", "kappa_max", "confluence_mass", "mer_monte_carlo", "pa1_footprint"]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", default=STUDIES, help=f"studies to run (default: {' '.join(STUDIES)})")
    parser.add_argument("--workers", type=int, default=None, help="worker processes (default: every core)")
    args = parser.parse_args(argv)
    for name in args.names:
        spec = load_study(HERE / "studies" / f"{name}.toml")
        out = HERE / "output" / "studies" / name
        counts = run_study(spec, out, workers=args.workers)
        paths = study_report(out)
        print(f"{name}: {counts.executed} runs ({counts.skipped} already done, {counts.failed} failed of "
              f"{counts.planned}) in {counts.wall_time:.1f} s; report {paths['report']}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

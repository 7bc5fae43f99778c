"""Run the built-in studies of validation/studies/ and write their reports into validation/output/studies/<name>/.

Run:  python validation/run_studies.py [--workers N] [names ...]

Each study resumes if its folder already holds some of its runs (delete the folder to start over). Wall times are
measured inside the runs, with the workers running side by side.
"""

from __future__ import annotations

from pathlib import Path

from script_arguments import OneLineParser, run_script, workers

HERE = Path(__file__).resolve().parent
STUDIES = ["step_method", "sp_presets", "kappa_max", "confluence_mass", "mer_monte_carlo", "pa1_footprint"]


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("names", nargs="*", default=STUDIES, help=f"studies to run (default: {' '.join(STUDIES)})")
    parser.add_argument("--workers", type=workers, default=None, help="worker processes (default: every core)")
    args = parser.parse_args(argv)
    for name in args.names:
        if not (HERE / "studies" / f"{name}.toml").is_file():
            parser.refuse(f"study {name!r}: no validation/studies/{name}.toml (studies: {', '.join(STUDIES)})")
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

from pchute_exudyn.study import load_study, run_study
from pchute_exudyn.study.report import study_report


def main(argv=None) -> int:
    args = arguments(argv)
    for name in args.names:
        spec = load_study(HERE / "studies" / f"{name}.toml")
        out = HERE / "output" / "studies" / name
        counts = run_study(spec, out, workers=args.workers)
        paths = study_report(out)
        print(f"{name}: {counts.executed} runs ({counts.skipped} already done, {counts.failed} failed of "
              f"{counts.planned}) in {counts.wall_time:.1f} s; report {paths['report']}", flush=True)
    return 0


if __name__ == "__main__":
    run_script(main)

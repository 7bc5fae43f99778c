"""What a command imports on its way to its work (issue 58, start-up): `pchute --help` needs neither Exudyn nor any
heavy library, and a run without figures none of the plotting or table stacks. Read as a set of module names from
Python's own import log (PYTHONPROFILEIMPORTTIME, as `python -X importtime`), so a loaded machine cannot fail it as
it could a timing; validation/startup_budget.py times the same commands."""

import os

from tests.helpers import MER, run_cli

HELP_NEVER = {"exudyn", "numba", "scipy", "matplotlib", "pandas", "xarray", "dask"}
RUN_WITHOUT_FIGURES_NEVER = {"matplotlib", "pandas", "xarray", "dask"}


def imported_packages(*args, cwd) -> set:
    """The top-level packages the command ``pchute ARGS`` imported (from its import log on standard error)."""
    done = run_cli(*args, env={**os.environ, "PYTHONPROFILEIMPORTTIME": "1"}, cwd=cwd, timeout=60)
    assert done.returncode == 0, done.stderr[-2000:]
    names = [line.rsplit("|", 1)[1].strip() for line in done.stderr.splitlines() if line.startswith("import time:")]
    return {name.split(".")[0] for name in names[1:]}   # the first line is the log's header


def test_help_imports_no_engine_and_no_heavy_library(tmp_path):
    packages = imported_packages("--help", cwd=tmp_path)
    assert "pchute_exudyn" in packages and not packages & HELP_NEVER, sorted(packages & HELP_NEVER)


def test_a_run_without_figures_imports_no_plotting_or_table_library(tmp_path):
    packages = imported_packages("run", MER / "case1.toml", "--method", "sp", "--t-end", "1", "--no-plot", "--quiet", "--out",
                                 tmp_path / "run", cwd=tmp_path)
    assert "exudyn" in packages and not packages & RUN_WITHOUT_FIGURES_NEVER, sorted(packages & RUN_WITHOUT_FIGURES_NEVER)

"""Parameter studies and Monte Carlo dispersions (spec: study files; runner: execution; store: results;
report: summaries and plots)."""

from .runner import StudyOutcome, dask_executor, execute, run_study, scalar_outputs
from .spec import Configuration, Parameter, RunSpec, StudySpec, load_study
from .store import RunRecord
from .table import load

__all__ = ["Configuration", "Parameter", "RunRecord", "RunSpec", "StudyOutcome", "StudySpec", "dask_executor",
           "execute", "load", "load_study", "run_study", "scalar_outputs"]

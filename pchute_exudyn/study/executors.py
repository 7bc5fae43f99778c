"""Where a study's or a fit's runs execute, as ``pchute study`` and ``pchute fit`` ask: the worker counts checked
first, then the executor (None: the local process pool; or a Dask cluster)."""

from __future__ import annotations

import os

from ..boundary import most_workers
from ..errors import InputError
from .runner import dask_executor


def check_worker_counts(workers: int | None, dask_local: int | None) -> None:
    """The worker counts of ``--workers`` and ``--dask-local``, checked before any folder, pool or cluster is made
    (``--dask-timeout`` is checked as the command line is read)."""
    for flag, value in (("--workers", workers), ("--dask-local", dask_local)):
        if value is not None and value < 1:
            raise InputError(f"{flag} = {value}: must be >= 1")
        if value is not None and value > most_workers():   # runs are CPU-bound: more only share the cores
            raise InputError(f"{flag} = {value}: must be <= {most_workers()} (4 worker processes per core of this "
                             f"machine's {os.cpu_count() or 1})")


def executor_for(dask_scheduler: str | None, dask_local: int | None, dask_timeout: float) -> tuple:
    """The executor ``--dask-scheduler`` or ``--dask-local`` ask for: (executor or None for the local pool, its
    closing function or None)."""
    if dask_scheduler is None and dask_local is None:
        return None, None
    return dask_executor(dask_scheduler, dask_local, dask_timeout)

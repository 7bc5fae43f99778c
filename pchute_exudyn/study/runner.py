"""Run a study on any ``concurrent.futures.Executor``: a local process pool by default, a Dask client's executor
when asked. Results are recorded as they come back, in whatever order; the inputs never depend on the executor."""

from __future__ import annotations

import asyncio
import gc
import math
import os
import sys
import threading
import time
from concurrent.futures import Executor, ProcessPoolExecutor, ThreadPoolExecutor, as_completed
from pathlib import Path

import numpy as np

from ..errors import InputError, PchuteError
from .spec import RunSpec, StudySpec
from .store import StudyStore


def scalar_outputs(result) -> dict:
    """The scalar outputs a study keeps of a run (m, s, N, m/s)."""
    s, f = result.summary, result.summary["final"]
    out = {"final_time": f["time"], "final_altitude": f["vehicle_altitude"], "final_east": f["vehicle_east"],
           "final_north": f["vehicle_north"], "final_lateral": math.hypot(f["vehicle_east"], f["vehicle_north"])}
    touchdown = [e for e in s.get("events", []) if e["event"] == "touchdown"]
    if touchdown:
        out["touchdown_time"] = touchdown[0]["time"]
        out["touchdown_speed"] = touchdown[0]["speed"]
    for name in result.tension_names():
        values = result[name][np.isfinite(result[name])]
        label = name.removeprefix("tension_")
        out[f"peak_tension_{label}"] = float(values.max()) if len(values) else None
        out[f"rms_tension_{label}"] = float(np.sqrt(np.mean(values ** 2))) if len(values) else None
    out.update(cluster_outputs(s))
    return out


def cluster_outputs(summary: dict) -> dict:
    """The outputs an analyst reads of clusters and of the vehicle's swing (deg, -, m/s): per cluster its peak load
    share and its canopies' largest and mean flyout once open (the largest over its canopies, and each canopy's
    largest), the vehicle's largest and RMS pendulum angle and its swing amplitude to the vertical once the last
    system flies, and its rate of descent over the run's last seconds (``analysis``)."""
    out = {}
    for system, entry in summary.get("cluster", {}).items():
        out[f"peak_load_share_{system}"] = entry["peak_load_share"]
        flyout = {canopy: value for canopy, value in entry["flyout_deg"].items() if value is not None}
        out[f"max_flyout_{system}"] = max((v["max"] for v in flyout.values()), default=None)
        out[f"mean_flyout_{system}"] = float(np.mean([v["mean"] for v in flyout.values()])) if flyout else None
        for canopy, value in entry["flyout_deg"].items():
            out[f"max_flyout_{canopy}"] = None if value is None else value["max"]
    pendulum = summary.get("pendulum", {})
    if pendulum:
        out["pendulum_max_deg"], out["pendulum_rms_deg"] = pendulum["max_vertical_deg"], pendulum["rms_vertical_deg"]
        out["pendulum_amplitude_deg"] = pendulum["amplitude_vertical_deg"]
    if summary.get("descent"):
        out["descent_rate"] = summary["descent"]["mean_rate"]
    return out


_settled = [False]   # whether this worker process has frozen what its first run left (``execute``)


def execute(run: RunSpec) -> dict:
    """Run one study run in a worker; never raises: a failure is a record with its error text.

    A worker keeps what its first run loaded (modules, the compiled kernels, the parsed case files, drawn graphics)
    and moves it out of the garbage collector's sight (``gc.freeze``), and a run pauses the cyclic collector (its
    objects are freed by reference counting; the few cycles wait for the next collection): collections cost a run
    nothing (they took 5 ms of a 0.35 s PA1 run)."""
    from ..case import load_case
    from ..simulation import simulate

    collecting = gc.isenabled()
    gc.disable()
    try:
        return _execute(run, load_case, simulate)
    finally:
        if not _settled[0]:
            gc.collect()
            gc.freeze()
            _settled[0] = True
        if collecting:
            gc.enable()


def _execute(run: RunSpec, load_case, simulate) -> dict:
    started = time.perf_counter()
    record = {"run": run.index, "status": "ok", "error": ""}
    try:
        case = load_case(run.case_file, run.overrides())
        c = run.configuration
        result = simulate(case, c.method, c.integrator, c.step, history=run.history_dir is not None,
                          **dict(c.options))
        record.update(scalar_outputs(result))
        record["wall_time"] = result.summary["wall_time"]
        record["steps"] = result.summary["steps"]
        if run.history_dir is not None:
            result.save(run.history_dir, plot=False, csv=False, overwrite=True)   # a retried run replaces its own
    except PchuteError as exc:
        record.update(status="failed", error=str(exc), wall_time=time.perf_counter() - started)
    except Exception as exc:  # a bug, not a user mistake: still recorded, the study goes on
        record.update(status="failed", error=f"internal error: {exc!r}", wall_time=time.perf_counter() - started)
    record["run_time"] = time.perf_counter() - started
    return record


def warm() -> None:
    """What a worker loads before its first run (the methods, the engine, the compiled kernels): submitted once per
    worker while the study's runs are drawn."""
    from .. import methods, simulation  # noqa: F401


def _load_table_libraries() -> None:
    """Import what writes ``runs.parquet`` (pandas, pyarrow: 0.4 s) while the runs go on, not after the last."""
    try:
        import pandas  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        pass


def _describe(exc: Exception) -> str:
    """'TypeName: first line of the message' (or the type name alone)."""
    text = str(exc).strip()
    return f"{type(exc).__name__}: {text.splitlines()[0]}" if text else type(exc).__name__


async def _scheduler_identity(address: str, timeout: float) -> dict:
    from distributed.core import rpc

    scheduler = rpc(address, timeout=timeout)
    try:
        return await asyncio.wait_for(scheduler.identity(), timeout)
    finally:
        await scheduler.close_rpc()


def dask_executor(scheduler: str | None = None, local_workers: int | None = None, timeout: float = 10.0):
    """A Dask executor and a function that closes what was opened: a scheduler at ``scheduler`` (bounded by
    ``timeout`` s) or a ``LocalCluster`` of ``local_workers`` processes."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise InputError("Dask is not installed: pip install 'pchute-exudyn[dask]'") from None
    if scheduler is not None:
        # Ask the scheduler who it is before building a Client: a Client that fails to connect blocks its own
        # clean-up for 2 x timeout at exit, and a port that answers but is not a scheduler breaks it oddly.
        try:
            with ThreadPoolExecutor(1) as thread:   # its own event loop, even when the caller runs one (Jupyter)
                identity = thread.submit(asyncio.run, _scheduler_identity(scheduler, timeout)).result()
        except (OSError, TimeoutError, asyncio.TimeoutError) as exc:   # refused, unreachable, no answer in time
            raise InputError(f"could not reach the Dask scheduler at {scheduler!r} within {timeout:g} s "
                             f"({_describe(exc)})") from None
        except Exception as exc:  # something answered, but not the Dask protocol
            raise InputError(f"{scheduler!r} did not answer as a Dask scheduler ({_describe(exc)}): check the "
                             "address and port") from None
        if not isinstance(identity, dict) or identity.get("type") != "Scheduler":
            raise InputError(f"{scheduler!r} answered but is not a Dask scheduler")
        if not identity.get("workers"):
            print(f"pchute study: the Dask scheduler at {scheduler} has no workers yet; runs start when workers join",
                  file=sys.stderr)
        client = Client(scheduler, timeout=timeout, set_as_default=False)
        return client.get_executor(pure=False), client.close
    cluster = LocalCluster(n_workers=local_workers, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(cluster, set_as_default=False)

    def close():
        client.close()
        cluster.close()
    return client.get_executor(pure=False), close


def run_study(spec: StudySpec, out, executor: Executor | None = None, workers: int | None = None,
              progress: bool = True, retry_failed: bool = False) -> dict:
    """Run (or resume) ``spec`` into folder ``out``.

    Parameters
    ----------
    spec : StudySpec
    out : path
        The study folder (see ``study.store``); rerunning into it skips finished runs.
    executor : concurrent.futures.Executor, optional
        Where runs execute; default a process pool of ``workers`` (default: every core).
    progress : bool
        Show a progress bar (runs done, failed, time left).
    retry_failed : bool
        Run again the runs recorded as failed.

    Returns
    -------
    dict
        Counts: planned, skipped (already done), executed, failed, and the wall time (s).
    """
    out = Path(out)
    owned = executor is None
    if owned:   # started first: the workers load the package while this process draws the runs
        executor = ProcessPoolExecutor(max_workers=workers or os.cpu_count())
        for _ in range(workers or os.cpu_count()):
            executor.submit(warm)
    threading.Thread(target=_load_table_libraries, daemon=True).start()   # for the table written at the end
    runs = spec.expand(out.resolve() / "histories")   # absolute: workers may run elsewhere
    store = StudyStore(out, spec, runs)
    try:
        store.open()
    except BaseException:
        if owned:
            executor.shutdown(wait=False, cancel_futures=True)
        raise
    done = store.done(retry_failed)
    pending = [r for r in runs if r.index not in done]
    failed = sum(1 for i in done if store.records[i].get("status") != "ok")
    bar = _progress(len(runs), len(done), failed) if progress else None
    started = time.perf_counter()
    try:
        executed, failed = _record_as_they_finish(executor, pending, store, bar, failed)
    finally:
        store.write_table(final=True)
        if bar is not None:
            bar.close()
        if owned:
            executor.shutdown(wait=True, cancel_futures=True)
    return {"planned": len(runs), "skipped": len(done), "executed": executed, "failed": failed,
            "wall_time": time.perf_counter() - started, "folder": str(out)}


def _record_as_they_finish(executor: Executor, pending: list, store: StudyStore, bar, failed: int) -> tuple:
    """Submit ``pending`` runs and record each as it finishes; returns (runs executed, failed so far). Ctrl-C cancels
    what has not started."""
    executed = 0
    futures = {}
    try:
        futures = {executor.submit(execute, run): run for run in pending}
        # as_completed watches each future once (``wait`` in a loop re-registers on every pending future: quadratic
        # in the runs, seconds of this process's time in a 2000-run study, taken from the workers)
        for future in as_completed(futures):
            run = futures[future]
            try:
                record = future.result()
            except Exception as exc:  # the executor itself failed (a worker died, transport error)
                record = {"run": run.index, "status": "failed", "error": f"executor error: {exc!r}"}
            store.record(record)
            executed += 1
            failed += record["status"] != "ok"
            if bar is not None:
                bar.update(1)
                bar.set_postfix(failed=failed)
    except KeyboardInterrupt:
        for future in futures:
            future.cancel()
        raise
    return executed, failed


def _progress(total: int, initial: int, failed: int):
    from tqdm import tqdm
    bar = tqdm(total=total, initial=initial, unit="run", desc="study", dynamic_ncols=True)
    bar.set_postfix(failed=failed)
    return bar

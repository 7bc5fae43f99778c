"""Run a study on any ``concurrent.futures.Executor``: a local process pool by default, a Dask client's executor
when asked. Results are recorded as they come back, in whatever order; the inputs never depend on the executor."""

from __future__ import annotations

import asyncio
import contextlib
import gc
import logging
import math
import os
import signal
import sys
import threading
import time
from concurrent.futures import Executor, InvalidStateError, ProcessPoolExecutor, ThreadPoolExecutor, as_completed
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..boundary import check_executor, check_flag, check_loaded, check_path, check_workers
from ..errors import InputError, PchuteError
from ..registries.columns import DEPLOY_CONDITIONS, column
from ..registries.quantities import QUANTITIES
from ..results.io import ensure_writable_dir
from ..results.journal import WriteFailed
from ..results.summary import RunSummary
from .spec import RunSpec, StudySpec
from .store import RunRecord, StudyStore


def scalar_outputs(result) -> dict:
    """The scalar outputs a study keeps of a run (m, s, N, m/s), by their columns (``registries.columns``)."""
    s, f = result.summary, result.summary.final
    out = {column("final_time"): f.time, column("final_altitude"): f.altitude, column("final_east"): f.east,
           column("final_north"): f.north, column("final_lateral"): f.lateral}
    if f.place is not None:   # an ellipsoidal planet: where the run ended on it
        out[column("final_latitude")], out[column("final_longitude")] = f.place
    touchdown = s.touchdown
    if touchdown is not None:
        out[column("touchdown_time")] = touchdown.time
        out[column("touchdown_speed")] = touchdown.speed
        for name, value in ((column("touchdown_descent_rate"), getattr(touchdown, "descent_rate", None)),
                            (column("touchdown_horizontal_speed"),
                             getattr(touchdown, "horizontal_speed_over_ground", None))):
            if value is not None:
                out[name] = value
    for label, name in result.tensions().items():
        values = result[name][np.isfinite(result[name])]
        out[column("peak_tension_{owner}", label)] = float(values.max()) if len(values) else None
        out[column("rms_tension_{owner}", label)] = float(np.sqrt(np.mean(values ** 2))) if len(values) else None
    out.update(cluster_outputs(s))
    out.update(sequence_outputs(s))
    out.update(load_outputs(s))
    return out


def load_outputs(summary: RunSummary) -> dict:
    """Per deployment (``summary.deployments``: a system or a tether) its snatch and opening loads (N), Knacke's
    estimate and the lowest rated breaking strength of its lines (N), when it has them."""
    out = {}
    for d in summary.deployments:
        out[column("snatch_load_{owner}", d.system)] = _finite(d.snatch_load)
        out[column("opening_load_{owner}", d.system)] = _finite(d.opening_load)
        if d.knacke_opening_load is not None:
            out[column("knacke_opening_load_{owner}", d.system)] = _finite(d.knacke_opening_load)
        strengths = [p["breaking_strength"] for p in d.lines.values() if p.get("breaking_strength")]
        if strengths:
            out[column("breaking_strength_{owner}", d.system)] = float(min(strengths))
    return out


STUDIED = tuple(q.name for q in QUANTITIES if q.studied)
"""The recorded quantities a study keeps of each triggered deployment (``registries.quantities.Quantity.studied``)."""


def sequence_outputs(summary: RunSummary) -> dict:
    """The outputs of a run's triggered sequence (-, Pa, m, s): per system whose deployment a trigger fired (its
    event carries ``trigger.conditions``), the vehicle's Mach number, dynamic pressure and altitude at the deployment
    and its time; per separated body (``summary.separations``), the separation time and the distance between the
    vehicle's and the body's centres of mass ``clearance_after`` s later. A run without triggered deployments or
    separations has none of these columns (its study table keeps exactly the columns it had)."""
    out = {}
    for event in summary.events_of("deploy"):
        trigger = getattr(event, "trigger", None)
        conditions = trigger.get("conditions") if isinstance(trigger, dict) else None
        system = getattr(event, "system", None)
        if not conditions or not system or column("deploy_time_{owner}", system) in out:
            continue
        for quantity in STUDIED:
            out[column(DEPLOY_CONDITIONS[quantity], system)] = _finite(conditions.get(quantity))
        out[column("deploy_time_{owner}", system)] = _finite(event.time)
    for body, separation in summary.separations.items():
        out[column("separation_time_{owner}", body)] = _finite(separation.time)
        out[column("separation_clearance_{owner}", body)] = _finite(separation.clearance)
    return out


def trigger_outcome(case, summary: RunSummary) -> tuple[str | None, tuple]:
    """What a run's triggers did, for the study's records: the triggered events that did not happen
    (``never_fired``: space-separated names, "" when all fired; None for a case without triggers: it explains the
    run's empty ``deploy_time_<system>`` or ``separation_time_<body>`` cells), and the run's warnings (the case's and
    each trigger's "never fired" line; kept in ``runs.jsonl``, not in the tables)."""
    never_fired = None
    if case.triggers:
        fired = {getattr(event, "name", None) for event in summary.events}
        never_fired = " ".join(event for event in case.triggers if event not in fired)
    return never_fired, tuple(summary.warnings)


def _finite(value) -> float | None:
    """``value`` as a float, or None when absent or not finite (an empty cell in the study table)."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        return None
    return value if math.isfinite(value) else None


def cluster_outputs(summary: RunSummary) -> dict:
    """The outputs an analyst reads of clusters and of the vehicle's swing (deg, -, m/s): per cluster its peak load
    share and its canopies' largest and mean flyout once open (the largest over its canopies, and each canopy's
    largest), the vehicle's largest and RMS pendulum angle and its swing amplitude to the vertical once the last
    system flies, and its rate of descent over the run's last seconds (``analysis``)."""
    out = {}
    for system, loads in summary.cluster.items():
        out[column("peak_load_share_{owner}", system)] = loads.peak_load_share
        flyout = {canopy: value for canopy, value in loads.flyout_deg.items() if value is not None}
        out[column("max_flyout_{owner}", system)] = max((v["max"] for v in flyout.values()), default=None)
        out[column("mean_flyout_{owner}", system)] = (float(np.mean([v["mean"] for v in flyout.values()])) if flyout
                                                      else None)
        for canopy, value in loads.flyout_deg.items():
            out[column("max_flyout_{owner}", canopy)] = None if value is None else value["max"]
    pendulum = summary.pendulum
    if pendulum is not None:
        out[column("pendulum_max_deg")], out[column("pendulum_rms_deg")] = (pendulum.max_vertical_deg,
                                                                            pendulum.rms_vertical_deg)
        out[column("pendulum_amplitude_deg")] = pendulum.amplitude_vertical_deg
    if summary.descent is not None:
        out[column("descent_rate")] = summary.descent.mean_rate
    return out


_settled = [False]   # whether this worker process has frozen what its first run left (``execute``)


def execute(run: RunSpec) -> RunRecord:
    """Run one study run in a worker; never raises: a failure is a record with its error text.

    A worker keeps what its first run loaded (modules, the compiled kernels, the parsed case files, drawn graphics)
    and moves it out of the garbage collector's sight (``gc.freeze``), and a run pauses the cyclic collector (its
    objects are freed by reference counting; the few cycles wait for the next collection): collections cost a run
    nothing (they took 5 ms of a 0.35 s PA1 run)."""
    from ..case import load_case
    from ..run.simulation import simulate

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


def _execute(run: RunSpec, load_case, simulate) -> RunRecord:
    started = time.perf_counter()
    outputs = {}
    try:
        case = load_case(run.case_file, run.overrides())
        c = run.configuration
        result = simulate(case, c.method, c.integrator, c.step, history=run.history_dir is not None,
                          **dict(c.options))
        outputs = scalar_outputs(result)
        never_fired, warnings = trigger_outcome(case, result.summary)
        record = RunRecord(run.index, "ok", "", outputs, never_fired, warnings, result.summary.wall_time,
                           result.summary.steps, site=result.summary.site)
    except PchuteError as exc:
        record = RunRecord(run.index, "failed", str(exc), outputs, wall_time=time.perf_counter() - started)
    except Exception as exc:  # a bug, not a user mistake: still recorded, the study goes on
        record = RunRecord(run.index, "failed", f"internal error: {exc!r}", outputs,
                           wall_time=time.perf_counter() - started)
    else:
        if run.history_dir is not None:
            record = replace(record, write_error=_save_history(result, run.history_dir))
    return replace(record, run_time=time.perf_counter() - started)


def _save_history(result, folder: str) -> str | None:
    """Save a run's histories; a folder that cannot take them (a full disk) is the study folder's fault, not the
    run's: returns why (the record's ``write_error``: the study stops with it, and its resume runs the run again),
    None when saved."""
    try:
        result.save(folder, plot=False, csv=False, overwrite=True)   # a retried run replaces its own
    except (PchuteError, OSError) as exc:
        where = exc.filename if isinstance(exc, OSError) and exc.filename else folder
        return str(exc) if isinstance(exc, PchuteError) else f"{where}: {exc.strerror}"
    return None


def warm() -> None:
    """What a worker loads before its first run (the methods, the engine, the compiled kernels): submitted once per
    worker while the study's runs are drawn."""
    from .. import methods  # noqa: F401
    from ..run import simulation as simulation  # noqa: F401


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
    # Its worker processes start with Ctrl-C ignored (a disposition a started process keeps): Ctrl-C to the whole
    # process group reaches this process alone, which stops the study and closes the cluster (no worker traceback).
    # Its log is silent: what goes wrong in a run is in that run's record, and the workers' complaints about a
    # scheduler stopped on purpose (an interrupt) are noise, tracebacks included. Its web server takes a free port
    # (the default 8787 may be another cluster's: a warning) and serves no dashboard.
    previous = {s: signal.signal(s, signal.SIG_IGN) for s in (signal.SIGINT, signal.SIGTERM)} if _main_thread() else {}
    try:
        cluster = LocalCluster(n_workers=local_workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                               scheduler_kwargs={"dashboard": False}, silence_logs=logging.CRITICAL)
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
    client = Client(cluster, set_as_default=False)

    def close():
        client.close()
        cluster.close()
    return client.get_executor(pure=False), close


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def _check_arguments(spec, out, executor, workers, progress, retry_failed) -> None:
    """The API's boundary: an argument of the wrong type gets one line naming it."""
    check_loaded(spec, StudySpec, "spec", "pchute_exudyn.study.load_study")
    check_path(out, "out", "study folder")
    check_executor(executor)
    check_workers(workers)
    check_flag(progress, "progress")
    check_flag(retry_failed, "retry_failed")


@dataclass(frozen=True)
class StudyOutcome:
    """What ``run_study`` did.

    Attributes
    ----------
    planned, skipped, executed, failed : int
        The study's runs; those skipped because already recorded; those run now; those recorded as failed (of
        every recorded run).
    wall_time : float
        The time (s) the runs took now.
    folder : str
        The study folder.
    table : Path
        Its ``runs.csv``: every run's inputs, status and outputs (units in ``registries.columns``).
    failures : dict
        The failed runs' errors, {run index: error text}.
    report : Path or None
        The report folder (``report/``, once ``study_report`` has written it).
    """

    planned: int
    skipped: int
    executed: int
    failed: int
    wall_time: float
    folder: str
    table: Path
    failures: dict
    report: Path | None


def run_study(spec: StudySpec, out, executor: Executor | None = None, workers: int | None = None,
              progress: bool = True, retry_failed: bool = False) -> StudyOutcome:
    """Run (or resume) ``spec`` into folder ``out``.

    Parameters
    ----------
    spec : StudySpec
    out : path
        The study folder (see ``study.store``); rerunning into it skips finished runs. It is locked while the study
        runs: a second study into it is refused.
    executor : concurrent.futures.Executor, optional
        Where runs execute; default a process pool of ``workers`` (default: every core).
    progress : bool
        Show progress: a bar (runs done, failed, time left) on a terminal, else a line per tenth of the runs.
    retry_failed : bool
        Run again the runs recorded as failed.

    Returns
    -------
    StudyOutcome
        The counts (planned, skipped: already done, executed, failed), the wall time (s), the table, the failed runs'
        errors and the report folder.
    """
    _check_arguments(spec, out, executor, workers, progress, retry_failed)
    for line in getattr(spec, "warnings", ()):   # a dispersed key with no effect (study.spec)
        print(f"pchute study: warning: {line}", file=sys.stderr)
    out = Path(out)
    ensure_writable_dir(out)   # before any worker starts: an unwritable folder is one line, at once
    owned = executor is None
    if owned:   # started early: the workers load the package while this process draws the runs
        executor = worker_pool(workers or os.cpu_count())
        for _ in range(workers or os.cpu_count()):
            executor.submit(warm)
    try:
        counts = _open_and_run(spec, out, executor, progress, retry_failed)
    except BaseException:   # an interrupt, a busy folder, a full disk: no worker outlives it
        if owned:
            stop_pool(executor, now=True)
        raise
    if owned:
        stop_pool(executor, now=False)
    return counts


def _open_and_run(spec: StudySpec, out: Path, executor: Executor, progress: bool,
                  retry_failed: bool) -> StudyOutcome:
    """Draw the runs, open (and lock) the study folder, run what it lacks, release it."""
    threading.Thread(target=_load_table_libraries, daemon=True).start()   # for the table written at the end
    runs = spec.expand(out.resolve() / "histories")   # absolute: workers may run elsewhere
    store = StudyStore(out, spec, runs)
    store.open()
    try:
        return _run_pending(executor, store, progress, retry_failed, out)
    finally:
        store.close()


def _run_pending(executor: Executor, store: StudyStore, progress: bool, retry_failed: bool,
                 out: Path) -> StudyOutcome:
    done = store.done(retry_failed)
    pending = [r for r in store.runs if r.index not in done]
    failed = sum(1 for i in done if not store.records[i].ok)
    bar = _progress(len(store.runs), len(done), failed) if progress else None
    started = time.perf_counter()
    try:
        executed, failed = _record_as_they_finish(executor, pending, store, bar, failed)
    except BaseException:
        try:
            store.write_table(final=True)   # the runs recorded so far, in run order
        except WriteFailed:
            pass   # the error on its way out says what failed; the journal has every finished run
        raise
    finally:
        if bar is not None:
            bar.close()
    store.write_table(final=True)
    failures = {i: str(r.error or "") for i, r in sorted(store.records.items()) if not r.ok}
    report = out / "report"
    return StudyOutcome(len(store.runs), len(done), executed, failed, time.perf_counter() - started, str(out),
                        out / "runs.csv", failures, report if report.is_dir() else None)


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
                record = RunRecord(run.index, "failed", f"executor error: {exc!r}")
            if record.write_error:   # a worker could not write the run's histories: the disk, not the run
                raise WriteFailed(f"run {run.index}: {record.write_error.removesuffix('.')}; free space and "
                                  "rerun the same command to resume")
            store.record(record)
            executed += 1
            failed += not record.ok
            if bar is not None:
                bar.update(1)
                bar.set_postfix(failed=failed)
    except BaseException:
        for future in futures:
            future.cancel()
        raise
    return executed, failed


def _worker_start() -> None:
    """A pool worker: dies with its parent (Linux), and leaves Ctrl-C and SIGTERM to it: the parent records what
    finished and stops the workers, so that a signal to the whole process group ends in one clean path."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        try:
            import ctypes
            ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)   # PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            pass
    if os.getppid() == 1:   # the parent died before the line above (the worker was handed to init)
        os._exit(1)


def worker_pool(workers: int) -> ProcessPoolExecutor:
    """A local process pool whose workers never outlive this process (``stop_pool`` ends them)."""
    return ProcessPoolExecutor(max_workers=workers, initializer=_worker_start)


def stop_pool(executor: ProcessPoolExecutor, now: bool) -> None:
    """Shut ``executor`` down: after its running work, or (``now``: an interrupt, an error) at once, its workers
    killed (they ignore SIGINT and SIGTERM) and reaped, so that no process is left."""
    if not now:
        executor.shutdown(wait=True, cancel_futures=True)
        return
    processes = list((getattr(executor, "_processes", None) or {}).values())   # the pool's own worker processes
    with _quiet_pool_manager(executor):
        for process in processes:
            try:
                process.kill()
            except (OSError, ValueError, AttributeError):
                pass
        for process in processes:
            try:
                process.join(5)
            except (OSError, ValueError, AssertionError):
                pass
        try:
            executor.shutdown(wait=True, cancel_futures=True)   # joins the pool's manager thread
        except Exception:  # a pool broken by its killed workers has nothing more to stop
            pass


@contextlib.contextmanager
def _quiet_pool_manager(executor):
    """Python's pool, finding its workers killed, marks every waiting run's future as failed, a cancelled one too,
    and its manager thread dies printing ``InvalidStateError: CANCELLED`` (Python 3.11). That thread's death is
    expected here: it is not shown; any other thread's exception still is."""
    manager = getattr(executor, "_executor_manager_thread", None)
    previous = threading.excepthook

    def hook(args):
        if not (args.thread is manager and issubclass(args.exc_type, InvalidStateError)):
            previous(args)
    threading.excepthook = hook
    try:
        yield
    finally:
        threading.excepthook = previous


def _progress(total: int, initial: int, failed: int):
    """A bar on a terminal, one line per tenth of the runs in a log (``progress.run_progress``)."""
    from ..views.progress import run_progress
    return run_progress(total, initial, failed)

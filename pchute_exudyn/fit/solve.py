"""Bounded least squares over case runs: the free keys scaled to [0, 1] by their bounds, residuals (model -
measured) / std, ``scipy.optimize.least_squares`` (trust-region reflective, which keeps every run inside the bounds)
with a forward-difference Jacobian whose runs go to an executor side by side (process pool or Dask, as studies).

Every evaluation is recorded at once in the fit folder (``evaluations.jsonl``); a rerun of the same fit reads the
recorded points back instead of running them again, and least squares, being deterministic, retraces its path
through them: a killed fit resumes where it stopped.
"""

from __future__ import annotations

import difflib
import os
import sys
from concurrent.futures import Executor
from dataclasses import dataclass, fields, replace

import numpy as np
from scipy.optimize import least_squares

from ..boundary import check_executor, check_loaded, check_path, check_workers
from ..errors import InputError
from ..results import journal as journal
from ..results.io import atomic_write_text, json_text
from ..results.journal import RecordFolder, digests, writing
from ..study.runner import stop_pool, worker_pool
from .evaluate import Evaluation, evaluate
from .spec import FitSpec

DIFFERENCE_STEP = 1e-3
"""Forward-difference step in the scaled coordinates (a thousandth of each key's bound range)."""
WIDER_STEP = 10.0
"""The factor a key's step grows by when it changed no residual (``Problem.jacobian``)."""
WIDEST_STEP = 0.1
"""The widest step (a tenth of the key's range): a key that changes nothing even then has a column of zeros."""

class FitStore(RecordFolder):
    """The fit folder: ``fit.toml`` (a copy), ``manifest.json`` (fingerprint and the digests of the files the fit
    reads), ``evaluations.jsonl`` (one checksummed line per run, flushed at once; see ``journal``) and the lock
    ``.pchute.lock`` held while the fit works in it."""

    what, journal_name = "fit", "evaluations.jsonl"

    def __init__(self, folder, spec: FitSpec):
        super().__init__(folder)
        self.spec = spec
        self.records: dict = {}

    def _open_locked(self) -> None:
        manifest = self.folder / "manifest.json"
        files, fingerprint = digests(self.spec.source_files()), self.spec.fingerprint()
        saved = self.saved_manifest(self.spec.source, fingerprint, files)
        if saved is None:
            with writing(self.folder / "fit.toml"):
                atomic_write_text(self.folder / "fit.toml", self.spec.text)
        if saved is None or "files" not in saved:   # (folders of earlier versions: the digests from now on)
            with writing(manifest):
                atomic_write_text(manifest, json_text({"name": self.spec.name, "fingerprint": fingerprint,
                                                       "files": files}, indent=2) + "\n")
        for record in journal.read(self.journal, self._check, _label, _note):
            self.records[_key(record["values"])] = Evaluation.from_dict(record)

    def _check(self, record: dict) -> str | None:
        """Why ``record`` is not an evaluation of this fit (None when it is one)."""
        values = record.get("values")
        if not isinstance(record.get("status"), str) or not isinstance(values, list):
            return "is not an evaluation record"
        if len(values) != len(self.spec.free) or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                         for v in values):
            return f"does not hold one number per free key ({len(self.spec.free)})"
        if record["status"] == "ok" and not isinstance(record.get("predictions"), list):
            return "is not an evaluation record"
        return None

    def add(self, record: Evaluation) -> None:
        # numbered after the last recorded (not counted: a line set aside on resume leaves a gap, not a repeat)
        record = replace(record, evaluation=1 + max((r.evaluation for r in self.records.values()
                                                     if isinstance(r.evaluation, int)), default=-1))
        journal.append(self.journal, record.to_dict())
        self.records[_key(record.values)] = record


def _label(record, line) -> str:
    return "that run runs again if the fit needs it"


def _note(text: str) -> None:
    print(f"pchute fit: {text}", file=sys.stderr)


def _key(values) -> tuple:
    return tuple(float(v).hex() for v in values)


class Problem:
    """The residual function and its parallel Jacobian over the scaled free keys."""

    def __init__(self, spec: FitSpec, store: FitStore, executor: Executor):
        self.spec, self.store, self.executor = spec, store, executor
        self.low = np.array([f.low for f in spec.free])
        self.span = np.array([f.high - f.low for f in spec.free])
        self.measured, self.scales = spec.measured(), spec.scales()
        self.reused = self.ran = 0
        self.budget = spec.max_runs          # None once the fit has stopped: the outcome's runs are always allowed
        self.best, self.best_cost = None, np.inf   # the point of least cost evaluated (scaled), for a stopped fit

    def values(self, u) -> list:
        return (self.low + np.asarray(u) * self.span).tolist()

    def records(self, points: list) -> list:
        """The records of free-key ``points`` (scaled), running the ones not recorded side by side."""
        wanted = [self.values(u) for u in points]
        pending = {_key(v): v for v in wanted if _key(v) not in self.store.records}
        self.reused += len(wanted) - len(pending)
        if pending and self.budget is not None and len(self.store.records) + len(pending) > self.budget:
            raise _Budget()   # before running them: the search makes at most max_runs runs
        futures = {k: self.executor.submit(evaluate, str(self.spec.case), self.spec.overrides(v),
                                           self.spec.configuration, self.spec.targets) for k, v in pending.items()}
        for k, future in futures.items():
            self.store.add(replace(future.result(), values=pending[k]))
            self.ran += 1
        return [self.store.records[_key(v)] for v in wanted]

    def residuals_of(self, record: Evaluation) -> np.ndarray:
        if not record.ok:
            raise InputError(f"the run at {self._describe(record.values)} failed: {record.error}")
        residuals = (np.asarray(record.predictions, float) - self.measured) / self.scales
        if not np.isfinite(residuals).all():
            target = self._target_of(int(np.flatnonzero(~np.isfinite(residuals))[0]))
            raise InputError(f"the run at {self._describe(record.values)} gives no finite value for {target}: "
                             "the least-squares fit needs one for every target")
        return residuals

    def _target_of(self, index: int) -> str:
        """The label of the target that residual ``index`` belongs to."""
        for i, target in enumerate(self.spec.targets):
            if index < target.size:
                return f"targets[{i}] ({target.label()})"
            index -= target.size
        return "a target"

    def _describe(self, values) -> str:
        return ", ".join(f"{f.key} = {v:.6g}" for f, v in zip(self.spec.free, values))

    def residuals(self, u) -> np.ndarray:
        residuals = self.residuals_of(self.records([u])[0])
        cost = float(residuals @ residuals)
        if cost < self.best_cost:
            self.best, self.best_cost = np.array(u, float), cost
        return residuals

    def jacobian(self, u) -> np.ndarray:
        """Forward differences, every perturbed run at once (backward at an upper bound). A key whose step changes
        no residual (a trigger's threshold moves its event by less than one of its samples) is differenced again
        with a step WIDER_STEP times larger, up to WIDEST_STEP: a column of zeros would leave its standard error
        undefined."""
        u = np.asarray(u, float)
        step = np.full(len(u), DIFFERENCE_STEP)
        columns = np.zeros((len(self.measured), len(u)))
        pending = list(range(len(u)))
        while pending:
            signed = {i: _signed_step(u[i], step[i]) for i in pending}
            points = [u] + [u + signed[i] * np.eye(len(u))[i] for i in pending]
            base, *moved = [self.residuals_of(r) for r in self.records(points)]
            for i, r in zip(pending, moved):
                columns[:, i] = (r - base) / signed[i]
            pending = [i for i in pending if not columns[:, i].any() and step[i] * WIDER_STEP <= WIDEST_STEP]
            step[pending] *= WIDER_STEP
        return columns


def _signed_step(u: float, step: float) -> float:
    """``step`` forward, backward where it would cross the upper bound, and never past the farther bound."""
    if u + step <= 1.0:
        return step
    return -step if u - step >= 0.0 else max(1.0 - u, u) * (1.0 if 1.0 - u >= u else -1.0)


class _Budget(Exception):
    """More runs than the fit's budget (``FitSpec.max_runs``)."""


def run_fit(spec: FitSpec, out, executor: Executor | None = None, workers: int | None = None) -> FitOutcome:
    """Fit ``spec`` into folder ``out`` (resuming what it holds; locked while the fit runs); returns the fit's
    ``FitOutcome`` (``fit.report`` writes it)."""
    check_loaded(spec, FitSpec, "spec", "pchute_exudyn.fit.load_fit")
    check_path(out, "out", "fit folder")
    check_executor(executor)
    check_workers(workers)
    store = FitStore(out, spec)
    store.open()   # before any worker starts: an unwritable or busy folder is one line, at once
    owned = executor is None
    try:
        if owned:
            executor = worker_pool(workers or min(os.cpu_count() or 1, len(spec.free) + 1))
        result = _solve(spec, Problem(spec, store, executor))
    except BaseException:
        if owned and executor is not None:
            stop_pool(executor, now=True)
        raise
    finally:
        store.close()
    if owned:
        stop_pool(executor, now=False)
    return result


def _solve(spec: FitSpec, problem: Problem) -> FitOutcome:
    start = (np.array([f.initial for f in spec.free]) - problem.low) / problem.span
    base = problem.records([start])[0]
    _check_base_run(spec, base)
    try:
        solution = least_squares(problem.residuals, start, jac=problem.jacobian, bounds=(0.0, 1.0),
                                 method="trf", x_scale="jac", xtol=1e-8, ftol=1e-8, gtol=1e-8,
                                 max_nfev=spec.max_runs)
        u, status, message = solution.x, int(solution.status), str(solution.message)
    except _Budget:
        u = start if problem.best is None else problem.best
        status, message = -2, f"stopped after {spec.max_runs} runs (max_runs) at the best point it reached"
    problem.budget = None
    return outcome(spec, problem, start, np.asarray(u), status, message)


def _check_base_run(spec: FitSpec, record: Evaluation) -> None:
    """Before fitting: the run at the starting values must work and show every target event and column."""
    if not record.ok:
        raise InputError(f"the run at the starting values failed: {record.error}")
    for i, target in enumerate(spec.targets):
        _check_history_span(i, target, record)
        if target.name not in record.missing_events:
            continue
        if target.kind == "event":
            raise InputError(f"targets[{i}].event = {target.name!r}: never happens in the run at the starting "
                             f"values; its events are: {', '.join(record.events)}")
        similar = difflib.get_close_matches(target.name, record.columns, n=3)
        raise InputError(f"targets[{i}].{'final' if target.kind == 'final' else 'column'} = {target.name!r}: the run "
                         f"has no such column{'; similar: ' + ', '.join(similar) if similar else ''}")


def _check_history_span(i: int, target, record: Evaluation) -> None:
    """A history measured past the end of the run at the starting values is refused: the model has no value there
    (holding its last one would compare the samples with a value the run never computed). A log's descent after the
    run's touchdown is compared with the ground, where the run ended; a run that ends in the air is refused."""
    end = record.end_time
    if target.kind not in ("history", "log") or end is None or not target.times:
        return
    touchdown = "touchdown" in (record.events or {})
    last = max(target.times)
    if target.kind == "log" and not touchdown:
        raise InputError(f"targets[{i}].log: the run at the starting values ends at {end:g} s in the air, before its "
                         "touchdown: lengthen simulation.duration so that it lands")
    if target.kind == "history" and last > end + 1e-9 * max(1.0, abs(end)):
        advice = ("it touches down then: drop the samples after the touchdown, or fit a flight log's descent with "
                  "log = \"<file>\"" if touchdown else "drop them from the file or lengthen simulation.duration")
        raise InputError(f"targets[{i}].history: samples up to {last:g} s run {last - end:g} s past the end of the run "
                         f"at the starting values ({end:g} s): {advice}")


def outcome(spec: FitSpec, problem: Problem, start, u, status: int, message: str) -> FitOutcome:
    """The fitted values with standard errors (from the Jacobian at the solution), the residuals and the runs."""
    residuals = problem.residuals(u)
    jacobian = problem.jacobian(u) / problem.span          # per unit of each key
    m, n = len(residuals), len(u)
    weighted = any(t.weighted for t in spec.targets)
    scale = float(residuals @ residuals) / (m - n) if weighted and m > n else 1.0
    try:
        covariance = np.linalg.inv(jacobian.T @ jacobian) * scale
        errors = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
    except np.linalg.LinAlgError:
        covariance, errors = np.full((n, n), np.nan), np.full(n, np.nan)
    initial, fitted = problem.records([start, u])
    return FitOutcome(
        name=spec.name, status=status, message=message, keys=[f.key for f in spec.free],
        initial=problem.values(start), fitted=problem.values(u), standard_error=errors.tolist(),
        covariance=covariance.tolist(), covariance_scaled_by_residuals=weighted and m > n,
        bounds=[[f.low, f.high] for f in spec.free], at_bound=at_bounds(u),
        cost=0.5 * float(residuals @ residuals), residuals=residuals.tolist(),
        predictions_initial=initial.predictions, predictions_fitted=fitted.predictions,
        runs=len(problem.store.records), runs_this_time=problem.ran, reused=problem.reused)


def at_bounds(u) -> list:
    """Whether each scaled value lies within the Jacobian's step (DIFFERENCE_STEP of its range) of a bound: the
    trust-region method stays strictly inside its bounds, so a value pressed against one ends a hair from it, and no
    closer than the step can the fit's own derivative tell it from the bound."""
    return [bool(v <= DIFFERENCE_STEP or v >= 1.0 - DIFFERENCE_STEP) for v in u]


@dataclass(frozen=True)
class FitOutcome:
    """What ``run_fit`` found (``fit.report`` writes it); ``to_dict`` is ``fit.json``, ``from_dict`` reads it back.

    Attributes
    ----------
    name : str
        The fit's name.
    status, message
        scipy's least-squares status (an int; -2: stopped at ``max_runs``) and its message.
    keys : list of str
        The free case keys, in the order of every list below.
    initial, fitted, standard_error : list of float
        Each key's starting value, fitted value and standard error (the case key's unit).
    covariance : list of lists
        The fitted values' covariance (from the Jacobian at the solution; the keys' units squared).
    covariance_scaled_by_residuals : bool
        Whether it is scaled by the residuals' variance (weighted targets) rather than from the targets' std.
    bounds, at_bound : list
        Each key's [low, high] and whether the fit ended on one (within a thousandth of its range: ``at_bounds``).
    cost : float
        Half the sum of the squared residuals at the fit (-).
    residuals : list of float
        (model - measured) / std per measured value (-).
    predictions_initial, predictions_fitted : list of float
        The model's value of each measured value at the start and at the fit (the targets' units).
    runs, runs_this_time, reused : int
        The runs the fit folder records, those run now, and those read back instead of run.
    """

    name: str
    status: int
    message: str
    keys: list
    initial: list
    fitted: list
    standard_error: list
    covariance: list
    covariance_scaled_by_residuals: bool
    bounds: list
    at_bound: list
    cost: float
    residuals: list
    predictions_initial: list
    predictions_fitted: list
    runs: int
    runs_this_time: int
    reused: int

    def to_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    @classmethod
    def from_dict(cls, data: dict) -> FitOutcome:
        """The outcome of a ``fit.json`` (``to_dict``'s inverse)."""
        return cls(**{f.name: data.get(f.name) for f in fields(cls)})

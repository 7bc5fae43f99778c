"""``pchute compare RUN LOG`` from its paths: which side is a flight log, the run's own air, and the comparison
(``results.log_compare``) of the two as files give them."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from .flight_log import named_log_format, read_flight_log
from .log_compare import LogComparison, compare_with_log
from .result import Result


def flight_log_side(a: str, b: str, mapped_a: bool, mapped_b: bool) -> tuple | None:
    """(run path, log path, the run's Result when it was read to tell) when one of ``a`` and ``b`` is a run folder
    and the other, given without a map, a flight log: a flight computer's own export, or a CSV that shares no column
    with the run (a generic log of time and height); None otherwise."""
    for run, log, mapped in ((a, b, mapped_b), (b, a, mapped_a)):
        if not (Path(run).is_dir() and Path(log).is_file()) or mapped:
            continue
        if named_log_format(log):
            return run, log, None
        ours = Result.load(run)
        try:
            theirs = Result.load(log, {}, ours.vehicle)
        except InputError:
            return run, log, ours   # not a result another tool wrote: read as a log (which says what is wrong with it)
        if not set(theirs.names) & set(ours.names) - {"time"}:
            return run, log, ours
    return None


def run_air(run: Result, run_path: str) -> tuple:
    """(density at z m above the ground in kg/m^3 or None, its name, the case file) of the air a run of this package
    flew in: its case's atmosphere, the case found as its summary names it (a path from where the run was made, else
    beside the run's folder); None when the case is not at hand."""
    from ..case import load_case

    named = getattr(run.summary, "case_file", None) or ""
    case_file = Path(named.split(" with ")[0])   # "<file> with <overrides>"
    if not case_file.is_file():
        case_file = Path(run_path).resolve().parent / case_file
    if not named or not case_file.is_file():
        return None, "", named
    atmosphere, ground = load_case(case_file).atmosphere, run.summary.ground_altitude or 0.0
    if atmosphere is None:
        return None, "", str(case_file)
    return (lambda z: atmosphere.states(z + ground)[0]), f"{atmosphere.name} of {case_file}", str(case_file)


def compare_files(run_path: str, log_path: str, run: Result | None = None) -> LogComparison:
    """The run in folder ``run_path`` (``run``: already read) against the flight log at ``log_path``, the log's
    barometric heights read through the run's air (``run_air``); InputError in one line when that air does not reach
    them."""
    from ..physics.atmosphere import OutsideAtmosphereError

    run, log = run or Result.load(run_path), read_flight_log(log_path)
    air, name, case_file = run_air(run, run_path)
    try:
        comparison = compare_with_log(run, log, run_path, log_path, air, name, run.summary.ground_altitude or 0.0)
    except OutsideAtmosphereError as exc:
        raise InputError(f"{log_path}: its heights are read through the run's air, which does not reach them: "
                         f"{exc}") from None
    if air is None and log.kind == "barometric":
        comparison.notes.append(f"the run's case ({case_file or 'none named'}) is not at hand: the log's heights are "
                                "as the altimeter gave them")
    return comparison

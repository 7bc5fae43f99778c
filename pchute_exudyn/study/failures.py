"""Failed runs as first-class results of a study: how many, how sure that rate is, which runs, and which inputs
separate them from the runs that succeeded (``report.study_report`` writes these first).

* The failure rate's 95 % interval is Wilson's score interval: with k failed of n finished runs, p = k / n and
  z = 1.959964, centre (p + z^2 / 2n) / (1 + z^2 / n), half-width z / (1 + z^2 / n) sqrt(p (1 - p) / n + z^2 / 4n^2).
  Unlike p +- z sqrt(p (1 - p) / n) it stays inside [0, 1] and is not empty when no run (or every run) failed.
* An input separates failures from successes when the failed runs drew other values than the ok runs: per numeric
  input, the rank-biserial correlation r = 2 U / (n_failed n_ok) - 1 of the Mann-Whitney U statistic of the failed
  runs' values against the ok runs' (+1: every failed run drew more than every ok run, -1: less, 0: no
  separation), with the two-sided Mann-Whitney p-value.
"""

from __future__ import annotations

import math

import numpy as np

Z_95 = 1.959963984540054
"""The standard normal's 97.5th percentile: a two-sided 95 % interval."""
SEPARATING = 0.5
"""|r| from which the report calls an input one that separates failures from successes."""


def wilson_interval(failed: int, finished: int, z: float = Z_95) -> tuple[float, float]:
    """Wilson's score interval (fractions 0..1) of a rate of ``failed`` of ``finished`` runs; (0, 1) for none."""
    if finished <= 0:
        return 0.0, 1.0
    p = failed / finished
    scale = 1.0 + z * z / finished
    centre = (p + z * z / (2.0 * finished)) / scale
    half = z / scale * math.sqrt(p * (1.0 - p) / finished + z * z / (4.0 * finished * finished))
    # at k = 0 (k = n) the lower (upper) end is exactly 0 (1): written so, not as centre - half's round-off
    return (0.0 if failed == 0 else max(0.0, centre - half)), (1.0 if failed == finished else min(1.0, centre + half))


def failure_counts(rows: list, planned: int | None) -> dict:
    """Runs planned, finished, ok, failed and not yet run, the failure rate (of finished runs) and its interval."""
    failed = sum(r.get("status") != "ok" for r in rows)
    finished = len(rows)
    planned = max(planned or 0, finished)
    low, high = wilson_interval(failed, finished)
    return {"planned": planned, "finished": finished, "ok": finished - failed, "failed": failed,
            "not_run": planned - finished, "rate": failed / finished if finished else math.nan,
            "interval": [low, high]}


def _numbers(rows: list, key: str) -> np.ndarray:
    return np.array([r[key] for r in rows if isinstance(r.get(key), float) and math.isfinite(r[key])])


def separation(ok: list, failed: list, keys: list) -> list:
    """Per numeric input in ``keys`` drawn by both groups: a dict of its name, the failed and ok runs' median and
    range, the rank-biserial r and the Mann-Whitney p-value; strongest |r| first."""
    from scipy.stats import mannwhitneyu

    found = []
    for key in keys:
        bad, good = _numbers(failed, key), _numbers(ok, key)
        if not len(bad) or not len(good) or np.ptp(np.concatenate([bad, good])) == 0:
            continue
        test = mannwhitneyu(bad, good, alternative="two-sided")
        found.append({"parameter": key, "failed_median": float(np.median(bad)),
                      "failed_range": [float(bad.min()), float(bad.max())], "ok_median": float(np.median(good)),
                      "ok_range": [float(good.min()), float(good.max())],
                      "rank_biserial": float(2.0 * test.statistic / (len(bad) * len(good)) - 1.0),
                      "p_value": float(test.pvalue)})
    return sorted(found, key=lambda entry: -abs(entry["rank_biserial"]))


def counts_markdown(counts: dict, references: int) -> list:
    """The report's first table: runs planned, ok, failed, the failure rate and its Wilson interval."""
    rate = counts["rate"]
    low, high = counts["interval"]
    shown = "-" if math.isnan(rate) else f"{100 * rate:.1f} % [{100 * low:.1f} %, {100 * high:.1f} %]"
    return ["| runs planned | finished | ok | failed | not run | failure rate [95 % Wilson interval] |",
            "|---|---|---|---|---|---|",
            f"| {counts['planned']} | {counts['finished']} | {counts['ok']} | {counts['failed']} | "
            f"{counts['not_run']} | {shown} |", "",
            f"({references} of the finished runs are reference runs. The interval is Wilson's score interval of "
            "the rate over the finished runs: see docs/study-format.md, \"Failed runs\".)"]


def failed_runs_markdown(failed: list, parameters: list, describe) -> list:
    """A table of the failed runs: run, case, configuration (``describe(row)``), each parameter drawn, the error."""
    if not failed:
        return []
    lines = ["", "## Failed runs", "", "| run | case | configuration | " + "".join(f"{k} | " for k in parameters)
             + "error |", "|---|---|---|" + "---|" * len(parameters) + "---|"]
    for r in failed:
        cells = "".join(f"{_cell(r.get(k))} | " for k in parameters)
        error = str(r.get("error") or "").replace("|", "\\|")
        lines.append(f"| {int(r['run'])} | {_cell(r.get('case'))} | {describe(r)} | {cells}{error} |")
    return lines


def never_fired_counts(rows: list) -> dict:
    """Per triggered event, how many ok runs ended without it (their ``never_fired`` cell names it)."""
    counts: dict = {}
    for r in rows:
        if r.get("status") == "ok" and isinstance(r.get("never_fired"), str):
            for event in r["never_fired"].split():
                counts[event] = counts.get(event, 0) + 1
    return counts


def never_fired_markdown(counts: dict, ok: int) -> list:
    """Report lines: the ok runs whose trigger never fired, per event (their outputs of it are empty cells, not in
    the percentiles)."""
    if not counts:
        return []
    lines = ["", "## Triggers that never fired", "",
             f"Warning: in some of the {ok} ok runs a trigger never fired (each such run's `never_fired` column names "
             "the event and its journal line in runs.jsonl keeps the warning); the outputs of that event are "
             "empty in those runs and left out of its percentiles.", "", "| event | ok runs without it |",
             "|---|---|"]
    return lines + [f"| {event} | {n} |" for event, n in sorted(counts.items())]


def separation_markdown(found: list) -> list:
    """Report lines: which inputs separate the failed runs from the ok runs (``separation``)."""
    if not found:
        return []
    strongest = found[0]
    named = (f"The input that separates them best: `{strongest['parameter']}` (r = "
             f"{strongest['rank_biserial']:+.2f})." if abs(strongest["rank_biserial"]) >= SEPARATING else
             f"No input separates them (every |r| < {SEPARATING:g}).")
    lines = ["", "### What separates the failed runs from the ok runs", "",
             "Per input: the failed and the ok runs' median and range, and the rank-biserial correlation r = "
             "2U / (n_failed n_ok) - 1 of the Mann-Whitney U (+1: every failed run drew more than every ok run, "
             "-1: less, 0: no separation) with its two-sided p-value. " + named, "",
             "| input | failed: median [min, max] | ok: median [min, max] | r | p |", "|---|---|---|---|---|"]
    for e in found:
        lines.append(f"| {e['parameter']} | {e['failed_median']:.6g} [{e['failed_range'][0]:.6g}, "
                     f"{e['failed_range'][1]:.6g}] | {e['ok_median']:.6g} [{e['ok_range'][0]:.6g}, "
                     f"{e['ok_range'][1]:.6g}] | {e['rank_biserial']:+.2f} | {e['p_value']:.2g} |")
    return lines


def choice_markdown(rows: list, categorical: list) -> list:
    """Report lines: per drawn choice (e.g. which canopy fails), the runs that drew each value and how many of them
    failed, so a value whose runs fail stands out."""
    lines = []
    for key in categorical:
        values = sorted({_cell(r.get(key)) for r in rows})
        lines += ["", f"Failures by `{key}`:", "", "| value | runs | failed | failure rate |", "|---|---|---|---|"]
        for value in values:
            drew = [r for r in rows if _cell(r.get(key)) == value]
            failed = sum(r.get("status") != "ok" for r in drew)
            lines.append(f"| {value or '(none)'} | {len(drew)} | {failed} | {100 * failed / len(drew):.1f} % |")
    return lines


def _cell(value) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return "" if value is None else str(value)

"""Every attitude, every wind: four descents in steady winds from eight directions and in a gust, to the ground.

Run:  python validation/wind_envelope.py [--workers 2]

The cases: a cargo airdrop written by `pchute new` (2000 kg under three 30.5 m flat circular canopies, Earth, from
1500 m: validation/output/winds/cargo.toml), the PA1 cluster (cases/cev_pa1_cluster.toml), MER case 1 (flown on to
the ground) and the 440-s descent (cases/simple/descent_440s.toml). Each with SP at its case step (1e-2 s):

* still air, and steady winds of 5, 10, 15 and 20 m/s from 8 directions (0, 45, ..., 315 deg), the run starting
  with the air (``start.velocities_relative_to = "air"``);
* a 15 m/s "1 - cosine" gust from the west, 10 s long, in still air, once the canopies are open;
* the 20 m/s winds also with full mass and the implicit integrator at its case step;
* the cargo drop also started at rest over the ground in each steady wind (the issue's run: the wind hits the
  opened cluster at once).

Checks: every run reaches the ground; the payload's drift (its landing point less the still-air run's) equals the
wind times its time aloft within 10 % (both starts); full mass and SP land within 0.5 % of each other's time. Writes
validation/output/winds/envelope.md.
"""

from __future__ import annotations

import math
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from script_arguments import OneLineParser, run_script, workers


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--workers", type=workers, default=2)
    args = parser.parse_args(argv)
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "output" / "winds"
CARGO = dict(planet="earth", mass=2000.0, canopy_diameter=30.5, canopy_type="flat_circular", canopies=3,
             altitude=1500.0, name="cargo")
CASES = {   # label -> (case file, overrides, gust start in s)
    "cargo cluster": (OUT / "cargo.toml", {}, 60.0),
    "PA1 cluster": (ROOT / "cases" / "cev_pa1_cluster.toml", {}, 40.0),
    "MER case 1": (ROOT / "cases" / "mer" / "case1.toml", {"simulation.duration": 400.0}, 40.0),
    "440-s descent": (ROOT / "cases" / "simple" / "descent_440s.toml", {}, 100.0),
}
SPEEDS = (5.0, 10.0, 15.0, 20.0)
DIRECTIONS = tuple(range(0, 360, 45))
GUST = dict(amplitude=15.0, length=10.0, from_deg=270.0)
DRIFT_TOLERANCE, TOUCHDOWN_TOLERANCE = 0.10, 0.005


def jobs() -> list:
    """(case label, condition label, start, wind speed m/s, from deg, overrides, method, integrator)."""
    out = []
    for label, (_, base, gust_start) in CASES.items():
        air = {**base, "start.velocities_relative_to": "air"}
        out.append((label, "still air", "with the air", 0.0, None, air, "sp", "rk4"))
        for speed in SPEEDS:
            for direction in DIRECTIONS:
                wind = {**air, "atmosphere.wind.speed": speed, "atmosphere.wind.from_deg": float(direction)}
                out.append((label, "steady", "with the air", speed, direction, wind, "sp", "rk4"))
                if speed == SPEEDS[-1]:
                    out.append((label, "steady", "with the air", speed, direction, wind, "full", "implicit"))
                if label == "cargo cluster":
                    ground = {**wind, "start.velocities_relative_to": "ground"}
                    out.append((label, "steady", "still over the ground", speed, direction, ground, "sp", "rk4"))
        gust = {**air, "atmosphere.gusts": [{**GUST, "start": gust_start}]}
        out.append((label, f"gust at {gust_start:g} s", "with the air", GUST["amplitude"], GUST["from_deg"], gust,
                    "sp", "rk4"))
        out.append((label, "still air", "with the air", 0.0, None, air, "full", "implicit"))
    return out


def run(job) -> dict:
    """One run's figures (or its error)."""
    import pchute_exudyn as pc

    label, condition, start, speed, direction, overrides, method, integrator = job
    started = time.perf_counter()
    try:
        result = pc.simulate(pc.load_case(CASES[label][0], overrides), method, integrator)
    except pc.PchuteError as exc:
        return dict(job=job, error=str(exc), seconds=time.perf_counter() - started)
    s = result.summary
    vehicle = s.vehicle
    angles = [np.nanmax(result[c]) for c in result.columns if c.endswith("_angle_of_attack_deg")
              and c != f"{vehicle}_angle_of_attack_deg" and np.isfinite(result[c]).any()]
    return dict(job=job, end=s.end, time=s.final.time, east=s.final.east, north=s.final.north,
                peak=max(v for v in s.peak_tension.values() if v is not None), angle=max(angles), step=s.step,
                seconds=time.perf_counter() - started)


def wind_vector(speed: float, direction) -> np.ndarray:
    """(east, north) (m/s) of a wind of ``speed`` from ``direction`` (deg clockwise from north)."""
    if direction is None:
        return np.zeros(2)
    return -speed * np.array([math.sin(math.radians(direction)), math.cos(math.radians(direction))])


def summary(results: list, drifts: dict, differences: list) -> list:
    """The summary table's rows: runs that touched down, the largest errors, the largest canopy angle."""
    def landed(method):
        runs = [r for r in results if r["job"][6] == method]
        return f"{sum(r.get('end') == 'touchdown' for r in runs)} of {len(runs)}"
    angle = max(r["angle"] for r in results if "error" not in r)
    return [f"| SP runs that touched down | {landed('sp')} |",
            f"| full mass implicit runs that touched down | {landed('full')} |",
            f"| largest drift error, started with the air (% of wind x time) | "
            f"{max(drifts['with the air'], default=0.0) * 100:.3f} |",
            f"| largest drift error, started still over the ground (% of wind x time) | "
            f"{max(drifts['still over the ground'], default=0.0) * 100:.3f} |",
            f"| largest touchdown difference, full mass implicit - SP (%) | "
            f"{max(differences, default=0.0) * 100:.3f} |",
            f"| largest canopy angle of attack flown (deg) | {angle:.1f} |"]


def table(results: list) -> tuple:
    """Markdown rows, the summary's rows and the failed checks."""
    still = {(r["job"][0], r["job"][6]): r for r in results if r["job"][1] == "still air" and "error" not in r}
    sp = {(r["job"][0], r["job"][2], r["job"][3], r["job"][4]): r for r in results
          if r["job"][6] == "sp" and r["job"][1] == "steady" and "error" not in r}
    rows, failed, drifts, differences = [], [], {"with the air": [], "still over the ground": []}, []
    for r in results:
        label, condition, start, speed, direction, _, method, integrator = r["job"]
        name = f"{label}, {condition}" + (f" {speed:g} m/s from {direction} deg" if condition == "steady" else "") \
            + f", {start}, {method} {integrator}"
        if "error" in r:
            rows.append(f"| {label} | {condition} | {start} | {speed:g} | {direction} | {method} {integrator} | - | "
                        f"failed: {r['error']} | | | | | {r['seconds']:.1f} |")
            failed.append(f"{name}: {r['error']}")
            continue
        drift_cell, versus = "", ""
        base = still.get((label, method))
        if condition == "steady" and base is not None:
            drift = np.array([r["east"] - base["east"], r["north"] - base["north"]])
            expected = wind_vector(speed, direction) * r["time"]
            error = float(np.linalg.norm(drift - expected) / np.linalg.norm(expected))
            drift_cell = f"{np.linalg.norm(drift):.1f} m ({error * 100:+.3f} %)"
            drifts[start].append(error)
            if error > DRIFT_TOLERANCE:
                failed.append(f"{name}: drift off by {error:.1%}")
        if method == "full":
            twin = sp.get((label, start, speed, direction)) if condition == "steady" else still.get((label, "sp"))
            if twin is not None:
                difference = r["time"] / twin["time"] - 1.0
                versus = f"{difference * 100:+.3f} %"
                differences.append(abs(difference))
                if abs(difference) > TOUCHDOWN_TOLERANCE:
                    failed.append(f"{name}: touchdown {difference:+.2%} from SP's")
        if r["end"] != "touchdown":
            failed.append(f"{name}: ended at {r['time']:.1f} s without touching down")
        rows.append(f"| {label} | {condition} | {start} | {speed:g} | {'-' if direction is None else direction} | "
                    f"{method} {integrator} | {r['step']:g} | {r['end']} at {r['time']:.2f} s | {drift_cell} | "
                    f"{versus} | {r['peak'] / 1e3:.2f} | {r['angle']:.1f} | {r['seconds']:.1f} |")
    return rows, summary(results, drifts, differences), failed


def write_cargo() -> None:
    import pchute_exudyn as pc
    from pchute_exudyn.results.io import atomic_write_text

    OUT.mkdir(parents=True, exist_ok=True)
    atomic_write_text(OUT / "cargo.toml", pc.new_case_text(**CARGO))


def main(argv=None) -> int:
    args = arguments(argv)
    write_cargo()
    todo = jobs()
    started = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        results = []
        for i, result in enumerate(pool.map(run, todo), start=1):
            results.append(result)
            print(f"\r{i}/{len(todo)} runs", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    rows, summary_rows, failed = table(results)
    from pchute_exudyn.results.io import atomic_write_text
    from pchute_exudyn.run.simulation import versions

    v = versions()
    text = "\n".join([
        "# Every attitude, every wind: four descents to the ground",
        "",
        f"`python validation/wind_envelope.py` ({len(todo)} runs in {time.perf_counter() - started:.0f} s on "
        f"{args.workers} workers; pchute_exudyn {v['pchute_exudyn']}, Exudyn {v['exudyn']}). "
        "The cargo cluster is `pchute new`'s (validation/output/winds/cargo.toml: 2000 kg under three 30.5 m flat "
        "circular canopies, Earth, from 1500 m). Winds are constant with altitude, from the direction given "
        "(clockwise from north); the gust is a 15 m/s 1 - cosine pulse from the west, 10 s long, in still air. "
        "'with the air': the run starts moving with the wind (`start.velocities_relative_to = \"air\"`); 'still over "
        "the ground': the cargo cluster starts at rest over the ground, so that the wind strikes the open canopies at "
        "once (the issue's run). Drift: the landing point less the still-air run's, against the wind times the time "
        "aloft (started still over the ground, the payload lags the air by the few seconds the wind takes to carry "
        "it along). Full mass against SP: the difference of their touchdown times. Largest angle: of any canopy, over "
        "the run (deg).",
        "",
        f"Checks: every run touches down; drift within {DRIFT_TOLERANCE:.0%} of wind x time; full mass within "
        f"{TOUCHDOWN_TOLERANCE:.1%} of SP on touchdown. **{'All hold.' if not failed else 'Failed: ' + '; '.join(failed)}**",
        "",
        "| summary | value |",
        "|---|---|",
        *summary_rows,
        "",
        "| case | air | start | wind (m/s) | from (deg) | method | step (s) | end | drift (error) | full - SP | "
        "peak tension (kN) | largest canopy angle (deg) | wall (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        *rows, ""])
    atomic_write_text(OUT / "envelope.md", text)
    print(f"{len(todo)} runs, {len(failed)} failed checks -> {OUT / 'envelope.md'}")
    for line in failed:
        print("  " + line)
    return 0 if not failed else 1


if __name__ == "__main__":
    run_script(main)

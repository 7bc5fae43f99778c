"""The figures of the README and the documentation, regenerated from the test suite and the committed validation
outputs (never typed by hand).

Run:  python validation/readme_figures.py            # print each line these figures belong in
      python validation/readme_figures.py --check    # exit 1 and name every line no page holds
      python validation/readme_figures.py --write    # put the lines into the pages (each replaces the line
                                                     # that starts the same way, up to its first figure)

The pages are README.md and the Markdown files under docs/ (``pages()``): most figures stand in docs/validation.md,
the test count in the README, a few beside what they measure (docs/methods.md). Each line goes to the page that holds
a line starting the same way; --write refuses a line with no single such place among all the pages.

Each figure comes from the output of the script named beside it on its page, which writes the file read here:
`validation/benchmark_sp.py` (benchmark_sp.md), `validation/benchmark_full.py` (benchmark_full.md),
`validation/cev_pa1.py` (cev_pa1/pa1.md), `validation/benchmark_study.py` (benchmark_study.md),
`validation/run_studies.py` (studies/step_method/report/errors.csv, studies/pa1_footprint/report/footprint.json),
`validation/startup_budget.py` (startup_budget.md), `validation/study_overhead.py` (study_overhead.md),
`validation/canopy_checks.py`
(canopy/closed_forms.json), `validation/canopy_effects.py` (canopy/effects.md), `validation/cluster_checks.py`
(cluster/closed_forms.md), `validation/cev_pa1_cluster.py` (cluster/pa1_cluster.md), `validation/cluster_study.py`
(cluster/study_executors.md, studies/pa1_cluster/report/percentiles.json), `validation/wind_envelope.py`
(winds/envelope.md), `validation/release.py` (release/release.md), `validation/benchmark_steps.py`
(benchmark_steps.md), `validation/benchmark_rocketpy.py` (rocketpy/benchmark.json); the test count
from `python -m pytest --collect-only`. Refresh a figure by rerunning its script, then this one. The test suite runs
the check (tests/acceptance/test_architecture.py), so a page that disagrees with the committed outputs fails CI.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from script_arguments import OneLineParser, run_script


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--check", action="store_true", help="exit 1 when no page holds one of the lines")
    parser.add_argument("--write", action="store_true", help="put the lines into README.md and the docs/ pages")
    args = parser.parse_args(argv)
    if args.check and args.write:
        parser.refuse("--check and --write: choose one (--check reads the pages, --write changes them)")
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "output"


def table(path: Path, first: str) -> dict:
    """Rows of the Markdown table in ``path`` whose first cell starts with ``first``, by first cell: cells."""
    rows = {}
    for line in path.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and cells[0].startswith(first):
            rows[cells[0]] = cells
    return rows


def test_count() -> int:
    done = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider"],
                          cwd=ROOT, capture_output=True, text=True, timeout=600)
    found = re.search(r"^(\d+)(?:/\d+)? tests? collected", done.stdout, re.MULTILINE)
    if not found:
        raise SystemExit(f"readme_figures: pytest collected nothing:\n{done.stdout[-500:]}{done.stderr[-500:]}")
    return int(found.group(1))


def sp_lines() -> list:
    """The SP speed tables (MER case 1 and PA1) and the first-run costs, from benchmark_sp.md."""
    path = OUT / "benchmark_sp.md"
    rows = table(path, "mer ") | table(path, "pa1 ")
    first = next(iter(table(path, "first run without a compiled module").values()))
    later = next(iter(table(path, "later runs").values()))
    lines = []
    names = {"full implicit 0.01": "full mass implicit, SP's step", "sp thesis 0.01": "SP, thesis's settings",
             "sp accurate 0.01": "SP, accurate preset", "sp accurate 0.02": "SP, accurate preset, twice the step"}
    for case, reference in (("mer", "full rk4 0.0001"), ("pa1", "full rk4 0.0005")):
        for label in (reference, *names):
            cells = rows[f"{case} {label}"]
            name = names.get(label, "full mass RK4, the thesis's step")
            lines.append(f"| {'MER' if case == 'mer' else 'Orion'}, {name} | " + " | ".join(cells[1:2] + cells[3:])
                         + " |")
    sp = rows["mer sp thesis 0.01"]
    lines.append(f"`pchute run cases/mer/case1.toml --method sp` integrates case 1 in {float(sp[1]):.2f} s instead of "
                 f"{float(rows['mer full rk4 0.0001'][1]):.0f} s (RK4 at 1e-2 s instead of")
    before = next(iter(table(path, "the code before").values()))
    size = re.search(r"numba and llvmlite installed: (\d+) MB", path.read_text()).group(1)
    commit = re.search(r"the code before \((\w+)\)", path.read_text()).group(1)
    lines.append(f"first run without a compiled module of its source {float(first[1]):.1f} s, later runs "
                 f"{float(later[1]):.1f} s, the code before ({commit}) {float(before[1]):.1f} s; numba and llvmlite add "
                 f"{size} MB to the environment.")
    implicit = float(rows["mer full implicit 0.01"][1])
    lines.append(f"  RK4 1e-4 s result within 1 cm in altitude and 1.2 N in tension at "
                 f"1/{float(rows['mer full rk4 0.0001'][1]) / implicit:.0f} of the cost ([full-mass model](validation.md#full-mass-model)).")
    speed = table(path, "")
    lines.append(f"Against the code before the last cut of the stage cost ({commit}), each code in its own process, "
                 "medians of the same interleaved rounds:")
    for label, key in (("MER case 1, 60 s", "MER case 1, "), ("PA1 to touchdown", "PA1 to touchdown, constant")):
        cells = next(cells for first, cells in speed.items() if first.startswith(key))
        lines.append(f"| {label} | {cells[1]} | {cells[2]} | {cells[3]} |")
    stage = next(cells for first, cells in speed.items() if first.startswith("**total per stage**"))
    lines.append(f"| MER case 1, one RK4 stage (us) | {stage[1].strip('*')} | {stage[2].strip('*')} | "
                 f"{float(stage[1].strip('*')) / float(stage[2].strip('*')):.2f}x |")
    return lines


def full_lines() -> list:
    rows = table(OUT / "benchmark_full.md", "rk4") | table(OUT / "benchmark_full.md", "implicit")
    lines = []
    for cells in rows.values():
        integrator, step, law = cells[0], f"{float(cells[1]):.0e}".replace("e-0", "e-"), cells[2]
        label = integrator if law == "symbolic" else f"{integrator}, Python line law"
        altitude = "reference (4462.193 m)" if cells[7] == "+0.00e+00" and law == "symbolic" else (
            "0" if cells[7] == "+0.00e+00" else f"{float(cells[7]):+.1e}")
        tension = "reference" if altitude.startswith("reference") else (
            "0" if cells[8] == "0" else cells[8])
        lines.append(f"| {label} | {step} | {float(cells[3]):.2f} | {float(cells[6]):.3f} | {altitude} | {tension} |")
    return lines


PA1_FLIGHT_TOUCHDOWN = ("74-76 or about 114 (95-97 s or about 135 s after ignition: the sources disagree), 7.2-7.3 "
                        "(16 mph, 24 ft/s)")
"""The PA1 table (docs/validation.md): the flown test's public touchdown figures (docs/models/cev_pa1.md quotes the sources)."""


def pa1_lines() -> list:
    text = (OUT / "cev_pa1" / "pa1.md").read_text()
    rounds = [[float(c.rstrip("x")) for c in cells[1:]] for cells in table(OUT / "cev_pa1" / "pa1.md", "").values()
              if cells[0].isdigit()]
    order1, order0 = [r[2] for r in rounds], [r[4] for r in rounds]
    medians = re.search(r"Median speed-up .*?: ([\d.]+)x \(order 1\), ([\d.]+)x \(order 0\)", text)
    agreement = table(OUT / "cev_pa1" / "pa1.md", "")
    single = {label: agreement[label][-1] for label in ("full implicit 1e-2", "equilibrium 1e-2")}
    runs = ("full rk4 5e-4", "full implicit 1e-2", "sp order 1 stretch 1e-2", "sp order 0 stretch 1e-2", "equilibrium 1e-2")
    header = next(cells for key, cells in agreement.items() if key == "event")
    columns = [header.index(run) for run in runs]
    touchdown, speed = agreement["Touchdown"], agreement["touchdown speed (m/s)"]
    attitude = [agreement[run][3] for run in runs[1:]]
    tension = [agreement[run][4].split(": ")[1].split(" (")[0] for run in runs[1:]]
    return ["| touchdown (s), speed (m/s) | " + " | ".join(f"{touchdown[c]}, {speed[c]}" for c in columns)
            + f" | 78.87 | {PA1_FLIGHT_TOUCHDOWN} |",
            "| capsule yaw / pitch / roll diff after the mains are open (deg) | reference | " + " | ".join(attitude)
            + " | | |",
            "| largest main-line tension diff after the mains are open (N) | reference | " + " | ".join(tension)
            + " | | |",
            f"| median speed-up over full RK4, 3 interleaved rounds | 1 | {single['full implicit 1e-2']} (single run) | "
            f"{medians.group(1)}x | {medians.group(2)}x | {single['equilibrium 1e-2']} (single run) | "
            "2.25x (80.57 vs 35.80 s) | |", f"full-mass RK4 run is {min(order1):.1f}-{max(order1):.1f}x for order 1 and {min(order0):.1f}-"
            f"{max(order0):.1f}x for order 0 over the committed run's three rounds",
            f"(medians {medians.group(1)}x and {medians.group(2)}x): " + _against_step_ratio(order1 + order0)]


def _against_step_ratio(ratios: list) -> str:
    """How PA1's measured speed-ups stand against the ratio of the steps (5e-4 s against 1e-2 s)."""
    clear = sum(r >= 20.0 for r in ratios)
    if clear == len(ratios):
        return "every round clears the step ratio of 20 (5e-4 s against 1e-2 s)."
    if clear == 0:
        return "short of the step ratio of 20 (5e-4 s against 1e-2 s) in every round; the SP section says why."
    return (f"{clear} of {len(ratios)} round results clear the step ratio of 20 (5e-4 s against 1e-2 s), the rest "
            "fall short by the machine's noise.")


def study_lines() -> list:
    rows = table(OUT / "benchmark_study.md", "")
    one, two = rows["1 worker (process pool)"], rows["2 workers (process pool)"]
    dask = rows["Dask LocalCluster, 2 workers"]
    return [f"side on this 2-core machine): 1 worker {float(one[1]):.1f} s, 2 workers {float(two[1]):.1f} s "
            f"({two[3]}), Dask `LocalCluster` of 2 workers {float(dask[1]):.1f} s"]


STEP_METHOD = {"full implicit 2e-3 s": "full implicit 0.002", "full implicit 1e-2 s": "full implicit 0.01",
               "full implicit 2e-2 s": "full implicit 0.02",
               "SP thesis 2e-3 s": "sp 0.002 thesis stretch order 0", "SP thesis 1e-2 s": "sp 0.01 thesis stretch order 0",
               "SP accurate 1e-2 s": "sp 0.01 accurate kappa_max 10 stretch order 1",
               "SP accurate 2e-2 s": "sp 0.02 accurate kappa_max 10 stretch order 1",
               "SP thesis, force rule 1e-2 s": "sp 0.01 thesis force order 0", "equilibrium 1e-2 s": "equilibrium 0.01"}
STEP_CASES = ("case1", "case3", "case5", "cev_pa1")


def _study_rows(name: str) -> list:
    import csv

    with open(OUT / "studies" / name / "report" / "errors.csv", newline="") as handle:
        return list(csv.DictReader(handle))


def step_method_lines() -> list:
    """Wall time (s) and largest tension error after 2 s (N) per case of the step and method study
    (`validation/run_studies.py`)."""
    rows = {(r["case"], r["configuration"]): r for r in _study_rows("step_method")}

    def cells(configuration):
        return " | ".join(f"{float(rows[(c, configuration)]['wall_time']):.3g} / "
                          f"{float(rows[(c, configuration)]['max_tension_error']):.3g}" for c in STEP_CASES)
    lines = [f"    | full RK4 3e-4 s | {cells('full rk4 0.0003')} |"]   # a table inside a list item: 4 spaces
    return lines + [f"    | {label} | {cells(configuration)} |" for label, configuration in STEP_METHOD.items()]


PRESET_ROWS = {r"thesis's settings (massless, $\kappa_\text{max}$ 5)": "sp 0.01 thesis",
               r"with the confluence mass to first order only ($\kappa_\text{max}$ 5)": "sp 0.01 thesis order 1",
               r"with $\kappa_\text{max}$ 10 only (massless)": "sp 0.01 thesis kappa_max 10",
               r"**accurate** (first order, $\kappa_\text{max}$ 10)": "sp 0.01 accurate",
               r"first order, $\kappa_\text{max}$ 20": "sp 0.01 accurate kappa_max 20"}


def preset_lines() -> list:
    """The SP presets study (`validation/run_studies.py sp_presets`): largest tension error after 2 s (N) per MER
    case at 1e-2 s, and the 2e-2 s figures of cases 3-4 quoted beside it."""
    rows = {(r["case"], r["configuration"]): float(r["max_tension_error"]) for r in _study_rows("sp_presets")}
    cases = [f"case{i}" for i in range(1, 7)]
    lines = []
    for label, configuration in PRESET_ROWS.items():
        bold = "**" if label.startswith("**accurate") else ""
        lines.append(f"| {label} | " + " | ".join(f"{bold}{rows[(c, configuration)]:.3g}{bold}" for c in cases) + " |")
    wide = [rows[(c, "sp 0.02 accurate kappa_max 20")] for c in ("case3", "case4")]
    ten = [rows[(c, "sp 0.02 accurate")] for c in ("case3", "case4")]
    worst = max(rows[(c, "sp 0.01 accurate")] for c in cases)
    lines.append(f"2e-2 s (cases 3-4: {wide[0]:.0f} and {wide[1]:.0f} N, against {ten[0]:.0f} and {ten[1]:.0f} N with "
                 "10). On PA1 the accurate preset keeps the capsule's")
    lines.append(r"  (the confluence's weight and inertia kept to first order, our addition, and $\kappa_\text{max}$ = 10: "
                 f"within {worst:.2g} N of")
    return lines


def canopy_lines() -> list:
    """The canopy physics: worst closed-form error per check, PA1 inflation SP against full mass, feature costs."""
    import json

    worst = {}
    for row in json.loads((OUT / "canopy" / "closed_forms.json").read_text()):
        old = worst.get(row["check"], (0.0, row["tolerance"]))
        worst[row["check"]] = (max(old[0], row["relative_error"]), row["tolerance"])
    lines = [f"| {check} | {error:.1e} | {tolerance:g} |" for check, (error, tolerance) in worst.items()]
    effects = OUT / "canopy" / "effects.md"
    text = effects.read_text()
    ratio = re.search(r"full/SP median \*\*([\d.]+)x\*\*", text).group(1)
    rows = table(effects, "")
    touchdown = rows["touchdown time (s)"][3].split()[0]
    peaks = " / ".join(rows[f"main riser peak, stage {i} (N, at s)"][3].split()[0] for i in (1, 2, 3))
    lines += [f"| touchdown time, SP - full mass (s) | {touchdown} |",
              f"| main riser peak of each stage, SP against full mass (%) | {peaks} |",
              f"| engine solve time, full mass RK4 / SP, median of 3 rounds | {ratio}x |"]
    lines += [f"| {label} | {rows[label][3]} |" for label in rows if label.startswith(("apparent mass, MER",
                                                                                      "inflation + riser table"))]
    return lines


def footprint_lines() -> list:
    """The PA1 landing footprint study's figures (`validation/run_studies.py pa1_footprint`)."""
    import json

    stats = json.loads((OUT / "studies" / "pa1_footprint" / "report" / "footprint.json").read_text())
    speed, riser = stats["percentiles"]["touchdown_speed"], stats["percentiles"]["peak_tension_main_riser"]
    return [f"  report `validation/output/studies/pa1_footprint/report/report.md`): mean touchdown point "
            f"{stats['mean_east']:.0f} m east and {stats['mean_north']:.0f} m north of the start, principal standard "
            f"deviations {stats['sigma_major']:.0f} m and {stats['sigma_minor']:.0f} m, CEP "
            f"{stats['miss_distance']['p50']:.0f} m; touchdown speed {speed['p50']:.1f} / {speed['p99']:.1f} m/s "
            f"(50 / 99 %); peak main-riser load {riser['p50'] / 1e3:.1f} / {riser['p99'] / 1e3:.1f} kN (50 / 99 %)."]


CLOSED_FORMS = {1: "two identical canopies, mirror-symmetric start: riser tension difference / peak",
                2: "the pair against one canopy of twice the mass and drag area: steady rate",
                3: r"the pair against $\sqrt{2 W / (\rho C_A S)}$: steady rate",
                4: r"two of three canopies against three: rate ratio against $\sqrt{3/2}\, \sqrt{\eta_3/\eta_2}$",
                5: r"two canopies pushed together: largest overlap against $v \sqrt{\mu / k}$"}


def cluster_lines() -> list:
    """The cluster section: closed forms (cluster_checks.py), PA1 (cev_pa1_cluster.py), the study
    (cluster_study.py)."""
    import json

    methods = table(OUT / "cluster" / "closed_forms.md", "")
    cells = {m: methods[m] for m in ("SP", "full mass implicit", "equilibrium point")}
    lines = [f"| {label} | " + " | ".join(c[column].split(" (")[-1].rstrip(")") for c in cells.values()) + " |"
             for column, label in CLOSED_FORMS.items()]
    path = OUT / "cluster" / "pa1_cluster.md"
    text = path.read_text()
    rows = [[c.strip() for c in line.strip().strip("|").split("|")] for line in text.splitlines()
            if line.startswith("|")]
    runs = {cells[0]: cells for cells in rows if len(cells) == 9}      # the runs' table
    agreement = {cells[0]: cells for cells in rows if len(cells) == 4}  # against full mass RK4
    sp, implicit = agreement["sp 1e-2"], agreement["full implicit 1e-2"]
    speedup = re.search(r"Median speed-up of SP over full mass RK4: ([\d.]+)x", text).group(1)
    rates = re.search(r"([\d.]+) m/s under two mains against ([\d.]+) m/s under three, ([\d.]+) times; .*? = "
                      r"([\d.]+) \(", text)
    nominal, out = runs["sp 1e-2"], runs["main out: sp 1e-2"]
    peaks = [(float(a), float(b)) for a, b in zip(nominal[4].split(" / ")[:2], out[4].split(" / ")[:2])]
    lines += [f"| touchdown time, SP 1e-2 s - full mass RK4 5e-4 s (s) | {sp[1]} |",
              f"| each main riser's peak, SP against full mass RK4 (%) | {sp[2]} |",
              f"| touchdown, full mass implicit 1e-2 s - RK4 (s); riser peaks (%) | {implicit[1]}; {implicit[2]} |",
              f"| median speed-up of SP 1e-2 s over full mass RK4 5e-4 s, 3 rounds side by side | {speedup}x |",
              f"| rate of descent over the last 5 s, three / two mains (m/s) | {rates.group(2)} / {rates.group(1)} "
              f"({rates.group(3)} times; " r"$\sqrt{3/2}\, \sqrt{\eta_3/\eta_2}$" f" = {rates.group(4)}) |",
              "| main1 / main2 riser peak, three mains -> two (kN) | "
              + " / ".join(f"{a:.1f} -> {b:.1f}" for a, b in peaks) + " |",
              f"| mean flyout once open, three / two mains (deg) | {nominal[6].split(' / ')[0]} / "
              f"{out[6].split(' / ')[0]} |"]
    stats = json.loads((OUT / "studies" / "pa1_cluster" / "report" / "percentiles.json").read_text())
    executors = table(OUT / "cluster" / "study_executors.md", "")
    same = "identical" if "identical (every input and output column but the wall time): yes" in \
        (OUT / "cluster" / "study_executors.md").read_text() else "DIFFERENT"

    def median(name, unit="", digits=3):
        s = stats[name]
        return (f"{s['p50']:.{digits}g} ({s['p50_ci'][0]:.{digits}g}-{s['p50_ci'][1]:.{digits}g}) / "
                f"{s['p99']:.{digits}g}{unit}")
    lines.append(f"median (its 95 % bootstrap interval) / 99th percentile (two runs beyond it: indicative): peak main "
                 f"load share {median('peak_load_share_main')}; largest main flyout {median('max_flyout_main', ' deg')};"
                 f" capsule pendulum angle {median('pendulum_max_deg', ' deg', 2)}; rate of descent over the last 5 s "
                 f"{median('descent_rate', ' m/s')}; touchdown speed {median('touchdown_speed', ' m/s')}. 2 worker "
                 f"processes {float(executors['2 worker processes'][3]):.0f} s, a Dask LocalCluster of 2 workers "
                 f"{float(executors['Dask LocalCluster, 2 workers'][3]):.0f} s, {same} run tables.")
    return lines


def aero_lines() -> list:
    """The aerodynamic-database section: closed forms (aero_checks.py), PA1 and MER (cev_pa1_aero.py), the speed
    with and without the databases and the per-stage aerodynamics (benchmark_sp.py)."""
    closed = [line for line in (OUT / "aero" / "closed_forms.md").read_text().splitlines()
              if line.startswith("| ") and not line.startswith("| check")]
    lines = ["| " + " | ".join([c.strip() for c in line.strip().strip("|").split("|")][:4]) + " |" for line in closed]
    rows = [[c.strip() for c in line.strip().strip("|").split("|")]
            for line in (OUT / "aero" / "pa1_aero.md").read_text().splitlines() if line.startswith("| ")]
    runs = {(cells[0], cells[1]): cells for cells in rows if len(cells) == 7 and not cells[0].startswith("case5")}
    agreement = {cells[0]: cells for cells in rows if len(cells) == 4}
    mer = {(cells[0], cells[1]): cells for cells in rows if cells[0].startswith("case5")}
    sp, without, constants = (runs[("databases", "sp 1e-2")], runs[("no capsule database", "sp 1e-2")],
                              runs[("cev_pa1.toml (constants, no damping)", "sp 1e-2")])

    def amplitude(cells, column):
        return cells[column].split(" / ")[0]
    speed = table(OUT / "benchmark_sp.md", "")
    pa1_speed = speed["PA1 to touchdown, constant coefficients (cev_pa1.toml)"]
    aero_speed = next(cells for key, cells in speed.items() if key.startswith("PA1 with the aerodynamic databases"))
    budget = next(cells for key, cells in speed.items() if key.startswith("**aerodynamics in all**"))
    lines += [f"| touchdown, SP 1e-2 s - full mass RK4 5e-4 s (s) | {agreement['sp 1e-2'][1]} |",
              f"| capsule swing amplitude under the open mains, SP - full mass RK4, to the vertical / to the airspeed "
              f"(deg) | {agreement['sp 1e-2'][2]} / {agreement['sp 1e-2'][3]} |",
              f"| capsule swing amplitude under the drogues, to the vertical, with / without the capsule database / "
              f"constants without damping (deg) | {amplitude(sp, 5)} / {amplitude(without, 5)} / "
              f"{amplitude(constants, 5)} |",
              f"| the same under the open mains, to the airspeed (deg) | {amplitude(sp, 4)} / {amplitude(without, 4)} / "
              f"{amplitude(constants, 4)} |",
              f"| vehicle swing amplitude of MER case 5 over 30 s without / with the parachute's C_m and damping, SP "
              f"(deg) | {mer[('case5.toml', 'sp')][2]} / {mer[('case5_aero.toml', 'sp')][2]} |",
              f"| MER case 5's disk-gap-band stable about 0 / trimming at 5 deg: its angle of attack once settled, SP / full "
              f"mass RK4 (deg) | {mer[('case5_aero.toml', 'sp')][4]} / {mer[('case5_aero.toml', 'full rk4 1e-4')][4]}, "
              f"{mer[('case5_aero_trim.toml', 'sp')][4]} / {mer[('case5_aero_trim.toml', 'full rk4 1e-4')][4]} |",
              f"| the same: the vehicle's drift east in 30 s, SP / full mass RK4 (m) | {mer[('case5_aero.toml', 'sp')][5]} / "
              f"{mer[('case5_aero.toml', 'full rk4 1e-4')][5]}, {mer[('case5_aero_trim.toml', 'sp')][5]} / "
              f"{mer[('case5_aero_trim.toml', 'full rk4 1e-4')][5]} |",
              f"| PA1 SP at 1e-2 s, with the databases / with constants (s) | {aero_speed[2]} / {pa1_speed[2]} |",
              f"| aerodynamics per RK4 stage (MER case 1), inside the stage kernel (us) | {budget[2].strip('*')} |"]
    return lines


def new_case_lines() -> list:
    """The cross-check line: the new case's closed-form rates and RocketPy (new_case_checks.py)."""
    rows = [line.split("|")[1:-1] for line in (OUT / "new_case" / "checks.md").read_text().splitlines()
            if line.startswith("| ")]
    closed = [cells[5].strip() for cells in rows if cells[0].strip() == "sp rk4" and len(cells) == 6
              and cells[1].strip() in ("2500", "1500", "500")]
    rocketpy = [cells for cells in rows if cells[0].strip().startswith(("non-rotating", "rotating"))]

    def ground(cells):
        return cells[2].strip().split("(")[1].rstrip(")")
    return [f"The tutorial's new case descends at its closed-form steady rate to {' / '.join(closed)} at 2500 / 1500 / "
            f"500 m (SP); against RocketPy's export of the same descent its rate differs by {rocketpy[0][1].strip()} "
            f"and its time to ground by {ground(rocketpy[0])} s as written, by {rocketpy[1][1].strip()} and "
            f"{ground(rocketpy[1])} s on a rotating Earth (`python validation/new_case_checks.py`, "
            "table `validation/output/new_case/checks.md`)."]


def study_overhead_lines() -> list:
    """A study's time around its solves, and the 2000-draw study at adaptive and fixed steps (study_overhead.py)."""
    text = (OUT / "study_overhead.md").read_text()
    rows = [[c.strip() for c in line.split("|")[1:-1]] for line in text.splitlines()
            if line.startswith("| before") or line.startswith("| now")]
    before, now, large, fixed = rows
    inside = re.search(r"Every percentile inside its interval: (\w+)", text).group(1)
    return [f"Around the solves (`python validation/study_overhead.py --before DIR --runs 200 --large 2000 "
            f"--compare-fixed`, table `validation/output/study_overhead.md`): the 200-run PA1 footprint study on 2 "
            f"workers takes {now[3]} s against {before[3]} s before (wall time x workers / sum of solve times "
            f"{now[5]}, was {before[5]}); {large[1]} runs take {large[3]} s at adaptive steps ({large[5]}), "
            f"{fixed[3]} s at a fixed 1e-2 s, every footprint percentile (1 to 99 %) of the one inside the other's "
            f"95 % bootstrap interval: {inside}."]


def steps_lines() -> list:
    """Adaptive steps on the 440-s descent against the code before (benchmark_steps.py)."""
    path = OUT / "benchmark_steps.md"
    before, now = next(iter(table(path, "before").values())), next(iter(table(path, "now").values()))
    text = path.read_text()
    change = re.search(r"touchdown [\d.]+ s against [\d.]+ s \(([-+][\d.]+) %\)", text).group(1)
    rounds = re.search(r"--repeat (\d+)", text).group(1)
    return [f"  cases set theirs. The 440-s descent takes {now[1]} steps instead of {before[1]} and solves "
            f"{now[4].rstrip('x')} times faster side by side (median of {rounds}), touchdown {change} % "
            "(table `validation/output/benchmark_steps.md`, `python validation/benchmark_steps.py --before DIR`)."]


def rocketpy_lines() -> list:
    """The rocket's dual deploy against RocketPy (benchmark_rocketpy.py)."""
    import json

    data = json.loads((OUT / "rocketpy" / "benchmark.json").read_text())
    rates = [abs(r["percent"]) for r in data["descent_rates"]]
    touchdown = next(r for r in data["touchdown"] if r["quantity"] == "time")
    medians = data["medians"]
    return [f"table `validation/output/rocketpy/benchmark.md`): descent rates under each canopy within "
            f"{max(rates):.2f} %, touchdown within {abs(touchdown['percent']):.2f} %, the differences explained "
            "(our canopies' drag in the air 7-10 m above the rocket; both sides fly WGS-84 normal gravity); solve "
            f"{medians['ours_solve']:.3f} s against RocketPy's {medians['rocketpy_flight']:.3f} s "
            f"(medians of {data['rounds']} rounds in one process)."]


README_RUN = "the README's first run (MER case 1, full mass, RK4 1e-4 s, with the figure)"
"""The fresh-install table's row of the README's quick-start run (startup_budget.py)."""


def startup_lines() -> list:
    """A warm run around its solve and a fresh install's first runs (startup_budget.py)."""
    text = (OUT / "startup_budget.md").read_text()
    rows = [[c.strip() for c in line.strip().strip("|").split("|")] for line in text.splitlines()
            if line.startswith(("| now", "| before"))]
    fresh = ("440", "MER", "the README")   # the fresh-install table's runs; the warm table's first cell is a number
    warm = {cells[0].split(" ")[0]: cells for cells in rows if not cells[1].startswith(fresh)}
    runs = {(cells[0].split(" ")[0], cells[1]): cells for cells in rows if cells[1].startswith(fresh)}
    now, before = warm["now"], warm["before"]

    def first(side, label):
        cells = runs[(side, label)]
        return f"{cells[2]} s against {cells[3]} s later ({cells[4]})"
    long, mer = "440-s descent (descent_440s.toml), with the figure", "MER case 1 SP, with the figure"
    commit = re.search(r"\| before \((\w+)", text).group(1)
    installed = {side: re.search(rf"\| {side} \((\w+)[^|]*\| (?:440|MER|the README)", text).group(1)
                 for side in ("now", "before")}
    return [f"Around the solve (`python validation/startup_budget.py --repeat 5 --before DIR`, "
            f"table `validation/output/startup_budget.md`, DIR a checkout of {commit}): a warm `pchute run "
            f"cases/mer/case1.toml --method sp --no-plot` takes {now[1]} s for its {now[2]} s solve ({now[3]}; "
            f"before: {before[1]} s, {before[3]}), the overview figure adds {now[5]} s (before: {before[5]} s) and "
            f"`pchute --help` takes {now[6]} s (before: {before[6]} s); "
            f"after a fresh install (code {installed['now']}, before {installed['before']}) the first run of the "
            f"440-s descent takes {first('now', long)}, before "
            f"{first('before', long)}; of MER case 1 {first('now', mer)}, before {first('before', mer)}; the "
            f"README's first run (full mass, RK4 1e-4 s) {first('now', README_RUN)}."]


def attitude_lines() -> list:
    """Every attitude in real winds (wind_envelope.py: its summary table) and the release (release.py: opening loads
    and the swing), as table rows of docs/validation.md."""
    lines = [f"| {cells[0]} | {cells[1]} |" for cells in table(OUT / "winds" / "envelope.md", "").values()
             if len(cells) == 2 and cells[0] not in ("summary", "---")]
    release = OUT / "release" / "release.md"
    for name, cells in table(release, "canopy").items():
        if name == "canopy":   # the header
            continue
        loads = [re.match(r"([\d.]+) kN at ([\d.]+) s \(([-+][\d.]+)%\)", cell).groups() for cell in cells[1:]]
        lines.append(f"| release: {name}'s opening load, SP / full mass RK4 / full mass implicit (kN) | "
                     + " / ".join(load[0] for load in loads) + f" (SP {loads[0][2]} %) |")
    sp = table(release, "SP")["SP"]
    lines.append(f"| release: swing below 2 deg after (s); rate at 500 m and settled, SP, against the stated rate | "
                 f"{sp[3]}; {sp[4].split('(')[1].rstrip(')')} and {sp[5].split('(')[1].rstrip(')')} |")
    return lines


def figures() -> list:
    """Every line of the pages these figures belong in."""
    count = f"3. runs the test suite ({test_count()} tests, about"
    return [count, *sp_lines(), *preset_lines(), *full_lines(), *pa1_lines(), *study_lines(), *step_method_lines(),
            *canopy_lines(), *footprint_lines(), *cluster_lines(), *aero_lines(), *new_case_lines(), *startup_lines(),
            *study_overhead_lines(), *attitude_lines(), *steps_lines(), *rocketpy_lines()]


def _key(line: str) -> str:
    """The start of a line up to its first figure (a digit after the label): how --write finds its place."""
    found = re.search(r"(?<=[\s(|])[-+]?\d+(?:\.\d+)?(?:x|\b)(?![e-]\d)", line[3:] if line.startswith("3. ") else line)
    return line[:found.start() + (3 if line.startswith("3. ") else 0)] if found else line


_NUMBER = r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?x?"


def _pattern(line: str) -> str:
    """A regular expression for ``line`` with every figure after its key free to differ."""
    key = _key(line)
    parts = re.split(r"([-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?x?)", line[len(key):])
    return re.escape(key) + "".join(re.escape(part) if i % 2 == 0 else _NUMBER for i, part in enumerate(parts))


def pages() -> list:
    """The files that hold figures: README.md, then every Markdown page under docs/."""
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def write(lines: list) -> int:
    """Put each line into the page where the same text with other figures stands; exit 1 when one has no single
    place among all the pages."""
    texts = {path: path.read_text() for path in pages()}
    homeless = []
    for line in lines:
        pattern = _pattern(line)
        places = [(path, found) for path, text in texts.items() for found in re.finditer(pattern, text)]
        if len(places) != 1:
            homeless.append(line)
            continue
        path, found = places[0]
        texts[path] = texts[path][:found.start()] + line + texts[path][found.end():]
    from pchute_exudyn.results.io import atomic_write_text

    for path, text in texts.items():
        if text != path.read_text():
            atomic_write_text(path, text)
    for line in homeless:
        print(f"no single place in README.md or docs/ for: {line}", file=sys.stderr)
    return 1 if homeless else 0


def main(argv=None) -> int:
    args = arguments(argv)
    lines = figures()
    if args.write:
        return write(lines)
    if not args.check:
        print("\n".join(lines))
        return 0
    texts = [path.read_text() for path in pages()]
    missing = [line for line in lines if not any(line in text for text in texts)]
    for line in missing:
        print(f"neither README.md nor a page under docs/ holds: {line}", file=sys.stderr)
    return 1 if missing else 0


if __name__ == "__main__":
    run_script(main)

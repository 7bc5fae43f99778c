"""Study files: a base case (or several), method and step configurations, and varied parameters; expanded into runs.

A study file is TOML::

    [study]
    name = "MER Monte Carlo"
    case = "../../cases/mer/case1.toml"   # a path relative to this file, or a list of them (a grid dimension)
    runs = 200                            # Monte Carlo samples per grid point (default 1)
    seed = 2026                           # master seed: required when a parameter has a distribution
    duration = 60.0                       # optional: overrides the cases' simulation.duration (s)
    histories = false                     # also save each run's time histories

    [[study.configurations]]              # method, integrator, steps (a list: one run each) and the
    method = "sp"                         # method's options by name (SP: kappa_max, slack_rule, order)
    steps = [1e-2]

    [study.reference]                     # optional: every sample is also run like this; the report measures
    method = "full"                       # each run's error against it
    integrator = "rk4"
    step = 1e-4
    per = "sample"                        # or "case": one reference per case file, run as written (without the
                                          # parameter values), for keys it does not depend on (kappa_max for full)

    [parameters."vehicle.initial.velocity_east"]      # dotted case keys, as for --set
    distribution = "normal"                           # normal (mean, std), uniform (low, high),
    mean = 0.0                                        # truncated_normal (mean, std, low, high), seed (none)
    std = 0.5

    [parameters."main.lines.*.stiffness"]
    distribution = "uniform"
    low = 0.9
    high = 1.1
    relative = true                                   # multiplies the case's value(s)

    [parameters."main.confluence.mass"]               # a grid: values = [...], or
    values = [0.1539, 0.01539]                        # range = {start, stop, step}, linspace = {start, stop, num}

    [parameters."failures.not_inflated"]              # a discrete draw: one of the values per sample
    distribution = "choice"
    values = ["main1", "main2", "main3"]
    weights = [1, 1, 1]                               # optional: relative probabilities (default equal)

Runs are the product of cases, grid values and Monte Carlo samples (the *samples*), times the configurations (and
the reference). Random draws come from ``numpy.random.SeedSequence(seed).spawn`` by sample index, in the file's
parameter order, so they do not depend on how many workers run the study, and every configuration of a sample (and
its reference) sees the same draws (common random numbers).
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from ..boundary import check_path
from ..case.fields import Context, Table
from ..case.files import read_toml
from ..case.loader import load_case, override_leaves
from ..case.overrides import Scale
from ..case.trigger_reach import SENSOR_ERRORS, idle_sensor_key
from ..errors import CaseError
from ..registries.methods import ADAPTIVE_STEP, INTEGRATORS, METHODS, OptionError, make_options

DISTRIBUTIONS = {"normal": ("mean", "std"), "uniform": ("low", "high"),
                 "truncated_normal": ("mean", "std", "low", "high"), "seed": (), "choice": ()}
"""Each distribution and the numbers it needs (``choice`` takes ``values`` and optional ``weights`` instead)."""
SAMPLINGS = ("random", "latin_hypercube", "sobol")
"""``[study] sampling``: independent random draws, a Latin hypercube or a scrambled Sobol sequence (scipy.stats.qmc)
over the drawn parameters, mapped through each distribution's inverse CDF."""
MAX_RUNS = 1_000_000
"""The most runs a study may expand into (docs/study-format.md, "Limits"): its run list is built, and its journal
read, in memory; split a larger study into several."""
SEED_LIMIT = 2 ** 31
"""A ``seed`` draw is an integer in [0, SEED_LIMIT) (a fresh seed per sample, e.g. for turbulence)."""


@dataclass(frozen=True)
class Parameter:
    """A varied case key: a grid of values, or a distribution to draw from.

    Attributes
    ----------
    key : str
        Dotted case key (``--set`` syntax).
    values : tuple
        Grid values; empty for a distribution.
    distribution : str or None
        One of DISTRIBUTIONS.
    arguments : dict
        The distribution's parameters (same unit as the key, or multipliers when relative).
    relative : bool
        The value multiplies the case's value(s) instead of replacing it.
    """

    key: str
    values: tuple = ()
    distribution: str | None = None
    arguments: dict = field(default_factory=dict)
    relative: bool = False

    def draw(self, rng: np.random.Generator) -> float | int | str:
        """A random draw (``sampling = "random"``)."""
        a = self.arguments
        if self.distribution == "choice":
            return self.quantile(float(rng.random()))
        if self.distribution == "seed":
            return int(rng.integers(0, SEED_LIMIT))
        if self.distribution == "normal":
            return float(rng.normal(a["mean"], a["std"]))
        if self.distribution == "uniform":
            return float(rng.uniform(a["low"], a["high"]))
        return self.quantile(float(rng.random()))   # truncated normal: by its inverse CDF, never a redraw loop

    def quantile(self, u: float) -> float | int | str:
        """The value at cumulative probability ``u`` in [0, 1) (inverse CDF): how a design's points become draws."""
        a = self.arguments
        if self.distribution == "choice":   # the first value whose cumulative weight exceeds u
            cumulative = np.cumsum(a["weights"]) / np.sum(a["weights"])
            return a["values"][min(int(np.searchsorted(cumulative, u, side="right")), len(a["values"]) - 1)]
        if self.distribution == "seed":
            return int(u * SEED_LIMIT)
        if self.distribution == "uniform":
            return float(a["low"] + u * (a["high"] - a["low"]))
        from scipy.stats import norm, truncnorm
        if self.distribution == "normal":
            return float(norm.ppf(u, a["mean"], a["std"]))
        lower, upper = (a["low"] - a["mean"]) / a["std"], (a["high"] - a["mean"]) / a["std"]
        return float(np.clip(truncnorm.ppf(u, lower, upper, a["mean"], a["std"]), a["low"], a["high"]))


@dataclass(frozen=True)
class Configuration:
    """How a run integrates: method, integrator, step (s) (None: the case's) and the method options it sets, as
    (name, value) pairs in the method's declaration order (the others: the case's)."""

    method: str | None = None
    integrator: str | None = None
    step: float | None = None
    options: tuple = ()

    @property
    def label(self) -> str:
        parts = [self.method or "case method", self.integrator or "", _step_label(self.step)]
        parts += [f"{name} {value:g}" if isinstance(value, float) else f"{name} {value}"
                  for name, value in self.options]
        return " ".join(p for p in parts if p)


@dataclass(frozen=True)
class RunSpec:
    """One run of a study; everything a worker needs, picklable."""

    index: int
    sample: int
    case_file: str
    configuration: Configuration
    values: dict
    relative: dict
    duration: float | None
    reference: bool
    history_dir: str | None = None
    reference_run: int | None = None   # the reference run this run's errors are measured against

    def overrides(self) -> dict:
        """The case overrides of this run (relative values as Scale)."""
        over = {key: (Scale(value) if self.relative.get(key) else value) for key, value in self.values.items()}
        if self.duration is not None:
            over["simulation.duration"] = self.duration
        return over

    def row(self, case_label: str) -> dict:
        """The run's inputs as a table row."""
        c = self.configuration
        return {"run": self.index, "sample": self.sample, "case": case_label, "reference": self.reference,
                "reference_run": self.reference_run, "method": c.method or "", "integrator": c.integrator or "",
                "step": c.step, **dict(c.options), **self.values}


@dataclass(frozen=True)
class StudySpec:
    """A validated study file."""

    name: str
    source: Path
    cases: tuple
    configurations: tuple
    reference: Configuration | None
    reference_per: str
    parameters: tuple
    runs: int
    seed: int | None
    duration: float | None
    histories: bool
    text: str
    parameter_units: dict = field(default_factory=dict)   # key -> unit ("" for none), for reports
    sampling: str = "random"                              # random, latin_hypercube or sobol (SAMPLINGS)
    warnings: list = field(default_factory=list)          # one line each (a key with no effect): run_study prints

    def design(self) -> np.ndarray | None:
        """(runs, drawn parameters) points in [0, 1) of a Latin hypercube or a scrambled Sobol sequence, seeded
        from the study seed (None for random sampling): Monte Carlo sample k of every grid point takes row k."""
        drawn = [p for p in self.parameters if p.distribution is not None]
        if self.sampling == "random" or not drawn:
            return None
        import warnings

        from scipy.stats import qmc
        rng = np.random.default_rng(np.random.SeedSequence(self.seed))
        engine = (qmc.LatinHypercube(len(drawn), rng=rng) if self.sampling == "latin_hypercube"
                  else qmc.Sobol(len(drawn), scramble=True, rng=rng))
        with warnings.catch_warnings():   # Sobol's balance wants a power of 2 of points: documented, not an error
            warnings.simplefilter("ignore", UserWarning)
            return engine.random(self.runs)

    def samples(self) -> list:
        """(case file, grid values) of every sample, with its Monte Carlo index: the study's sample order."""
        grid = [p for p in self.parameters if p.distribution is None]
        combos = list(itertools.product(*[p.values for p in grid])) if grid else [()]
        return [(case, dict(zip([p.key for p in grid], combo)), mc)
                for case in self.cases for combo in combos for mc in range(self.runs)]

    def expand(self, history_root: Path | None = None) -> list:
        """Every run of the study, in order: per sample its reference (if any), then each configuration; with a
        per-case reference, that reference comes before the case's first sample and runs the case file as written (no
        parameter values: the varied keys may not even apply to the reference's method, e.g. kappa_max to full mass)."""
        samples = self.samples()
        # one child seed per sample, by index: the draws never depend on the number of workers or their order
        seeds = [None] * len(samples) if self.seed is None else np.random.SeedSequence(self.seed).spawn(len(samples))
        drawn = [p for p in self.parameters if p.distribution is not None]
        design = self.design()
        relative = {p.key: p.relative for p in self.parameters}
        keep = history_root is not None and (self.histories or self.reference is not None)
        runs, case_reference = [], {}

        def add(sample, case, configuration, values, is_reference, reference_run):
            index = len(runs)
            history = str(history_root / f"run_{index:05d}") if keep else None
            runs.append(RunSpec(index, sample, str(case), configuration, values, relative, self.duration,
                                is_reference, history, reference_run))
            return index

        for sample, ((case, grid_values, mc), seed) in enumerate(zip(samples, seeds)):
            values = dict(grid_values)
            if design is not None:
                for j, parameter in enumerate(drawn):
                    values[parameter.key] = parameter.quantile(float(design[mc, j]))
            elif drawn:
                rng = np.random.default_rng(seed)
                for parameter in drawn:
                    values[parameter.key] = parameter.draw(rng)
            ordered = {p.key: values[p.key] for p in self.parameters}
            reference_run = None
            if self.reference is not None and self.reference_per == "case":
                if case not in case_reference:
                    case_reference[case] = add(sample, case, self.reference, {}, True, None)
                reference_run = case_reference[case]
            elif self.reference is not None:
                reference_run = add(sample, case, self.reference, ordered, True, None)
            for configuration in self.configurations:
                add(sample, case, configuration, ordered, False, reference_run)
        return runs

    def fingerprint(self) -> str:
        """A hash of the study file, the case files and the expanded inputs: a resumed study must match it."""
        digest = hashlib.sha256(self.text.encode())
        for case in self.cases:
            digest.update(Path(case).read_bytes())
        digest.update(json.dumps([r.row("") for r in self.expand()], sort_keys=True, default=str).encode())
        return digest.hexdigest()

    def source_files(self) -> list:
        """Every file the study reads: the study file, its cases, their ``extends`` chains and data tables (their
        contents' digests are kept in the study folder: a resume after one changed is refused)."""
        from ..results.journal import case_files

        files = [Path(self.source).resolve()]
        for case in self.cases:
            files += [f for f in case_files(case) if f not in files]
        return files


def _read_options(t: Table, method: str | None) -> tuple:
    """The configuration's remaining keys as options of its method, validated by the method's Options type."""
    given = {key: value for key, value in t.data.items() if key not in t.allowed}
    if not given:
        return ()
    if method is None:
        raise t.error(next(iter(given)), "a method option needs the configuration's method (method = \"...\")")
    options_type = METHODS[method].Options
    try:
        make_options(options_type, given)
    except OptionError as exc:
        raise t.error(exc.field, exc.allowed, exc.value) from None
    t.allowed.extend(given)
    return tuple((f.name, given[f.name]) for f in fields(options_type) if f.name in given)


def _step_label(step) -> str:
    """A configuration's step as its label shows it: '0.01', 'auto' or nothing (the case's)."""
    return "" if not step else step if isinstance(step, str) else f"{step:g}"


def _step(t: Table, key: str):
    """A configuration's ``step``: a number > 0 (s), ``"auto"`` (adaptive steps) or absent (None: the case's)."""
    if t.data.get(key) == ADAPTIVE_STEP:
        t.raw(key, None, "s")
        return ADAPTIVE_STEP
    return t.number(key, "s", None, above=0.0)


def _steps(t: Table) -> list:
    """A configuration's ``steps``: a list of steps > 0 (s) and ``"auto"`` (adaptive steps)."""
    value = t.raw("steps", None, "s")
    numbers = [item for item in value if item != ADAPTIVE_STEP] if isinstance(value, list) else value
    if not isinstance(value, list) or not value or \
            (numbers and any(isinstance(x, bool) or not isinstance(x, (int, float)) or not x > 0.0 for x in numbers)):
        raise t.error("steps", f"must be a list of steps > 0 (s) or {ADAPTIVE_STEP!r} (adaptive steps)", value)
    return [item if item == ADAPTIVE_STEP else float(item) for item in value]


def read_configuration(t: Table, single_step: bool) -> list:
    if single_step:
        t.allowed.append("per")
    method = t.string("method", None, tuple(METHODS))
    integrator = t.string("integrator", None, INTEGRATORS)
    if single_step:
        steps = [_step(t, "step")]
    else:
        if "steps" in t.data and "step" in t.data:   # one would be dropped without a word
            raise t.error("step", "give step or steps, not both (steps = [...] lists every step)", t.data["step"])
        steps = _steps(t) if "steps" in t.data else [_step(t, "step")]
        t.allowed.extend(["step", "steps"])
    options = _read_options(t, method)
    t.finish()
    if integrator is not None:
        _check_adaptive(t, steps, integrator, "")
    return [Configuration(method, integrator, step, options) for step in steps]


def _check_adaptive(t: Table, steps: list, integrator: str, whose: str) -> None:
    """Refuse adaptive steps ("auto") for an implicit ``integrator`` (``whose``: where it comes from, or "")."""
    if ADAPTIVE_STEP in steps and not INTEGRATORS[integrator].explicit:
        key = "steps" if "steps" in t.data else "step"
        raise t.error(key, f"adaptive steps ({ADAPTIVE_STEP!r}) are RK4's; the {integrator} integrator{whose} needs "
                           "a step > 0 (s)", t.data[key])


def _read_parameter(key: str, t: Table, source: str) -> Parameter:
    relative = t.boolean("relative", False)
    if "distribution" in t.data:
        name = t.string("distribution", choices=tuple(DISTRIBUTIONS))
        if name == "choice":
            return _read_choice(key, t, relative)
        arguments = {}
        for argument in DISTRIBUTIONS[name]:
            if argument not in t.data:
                raise t.error(argument, f"required by distribution '{name}' (it needs "
                                        f"{', '.join(DISTRIBUTIONS[name])})")
            arguments[argument] = t.number(argument, "")
        if "std" in arguments and not arguments["std"] > 0.0:
            raise t.error("std", "must be > 0", arguments["std"])
        if "low" in arguments and not arguments["low"] < arguments["high"]:
            raise t.error("high", f"must be > low ({arguments['low']:g})", arguments["high"])
        if name == "seed" and relative:
            raise t.error("relative", "a seed cannot be relative", True)
        if name == "truncated_normal":
            mass = _normal_mass(arguments["low"], arguments["high"], arguments["mean"], arguments["std"])
            if mass < 1e-6:
                raise t.error("low", "the bounds leave almost none of the normal distribution's probability")
        t.finish()
        return Parameter(key, (), name, arguments, relative)
    given = [k for k in ("values", "range", "linspace") if k in t.data]
    if len(given) != 1:
        raise t.error(None, "give exactly one of: distribution (with its parameters), values = [...], "
                            "range = {start, stop, step} or linspace = {start, stop, num}")
    if given[0] == "values":
        raw = t.raw("values", None, "")
        if not isinstance(raw, list) or not raw:
            raise t.error("values", "must be a non-empty list", raw)
        if any(isinstance(v, float) and not math.isfinite(v) for v in raw):   # no case key takes NaN or inf
            raise t.error("values", "must be finite numbers (or strings, booleans, lists)", raw)
        _check_relative_numbers(t, raw, relative)
        values = tuple(raw)
    elif given[0] == "range":
        r = t.table("range")
        start, stop, step = r.number("start", ""), r.number("stop", ""), r.number("step", "")
        r.finish()
        if step == 0.0 or (stop - start) / step < 0:
            raise r.error("step", "must be non-zero and point from start to stop", step)
        count = int(math.floor((stop - start) / step + 1e-9)) + 1
        if count > MAX_RUNS:
            raise r.error("step", f"gives {count:.3g} values; a study runs at most {MAX_RUNS} (MAX_RUNS)", step)
        values = tuple(float(start + i * step) for i in range(count))
    else:
        r = t.table("linspace")
        start, stop = r.number("start", ""), r.number("stop", "")
        num = r.raw("num", None, "")
        r.allowed.append("num")
        if isinstance(num, bool) or not isinstance(num, int) or num < 2:
            raise r.error("num", "must be an integer >= 2", num)
        if num > MAX_RUNS:
            raise r.error("num", f"must be <= {MAX_RUNS}: a study runs at most {MAX_RUNS} runs (MAX_RUNS)", num)
        r.finish()
        values = tuple(float(v) for v in np.linspace(start, stop, num))
    t.finish()
    return Parameter(key, values, None, {}, relative)


def _normal_mass(low: float, high: float, mean: float, std: float) -> float:
    """The probability (-) of a normal distribution between ``low`` and ``high`` (a check of a truncated normal's
    bounds when the study file is read: without scipy.stats, whose import takes 0.6 s)."""
    def cdf(x):
        return 0.5 * math.erfc(-(x - mean) / (std * math.sqrt(2.0)))
    return cdf(high) - cdf(low)


def _check_relative_numbers(t: Table, values: list, relative: bool) -> None:
    """A relative grid scales the case's value: every value a number (a canopy model's name scales nothing)."""
    if relative and not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        raise t.error("relative", "scales numbers: every value must be a number (a factor on the case's)", True)


def _read_choice(key: str, t: Table, relative: bool) -> Parameter:
    """A discrete draw: ``values`` (any TOML values, e.g. canopy names) with optional ``weights`` (>= 0, not all 0)."""
    values = t.raw("values", None, "")
    if not isinstance(values, list) or not values:
        raise t.error("values", "required by distribution 'choice': a non-empty list of the values to draw from",
                      values)
    weights = t.vector("weights", "", len(values), tuple(1.0 for _ in values))
    if any(w < 0.0 for w in weights) or not sum(weights) > 0.0:
        raise t.error("weights", "must be >= 0 and not all 0 (relative probabilities of the values)", list(weights))
    if relative:
        raise t.error("relative", "a choice cannot be relative", True)
    t.finish()
    return Parameter(key, (), "choice", {"values": tuple(values), "weights": tuple(weights)}, relative)


def load_study(path) -> StudySpec:
    """Read and validate a study file; every parameter key is checked against the base case(s)."""
    path = check_path(path, "path", "study file (TOML)")
    data = read_toml(path, "study")
    source = str(path)
    ctx = Context(source, {})
    top = Table(data, (), ctx)
    s = top.table("study")
    name = s.string("name", path.stem)
    raw_cases = s.raw("case", None, "")
    if isinstance(raw_cases, str):
        raw_cases = [raw_cases]
    if not isinstance(raw_cases, list) or not raw_cases or not all(isinstance(c, str) for c in raw_cases):
        raise s.error("case", "must be a case file path or a non-empty list of them", raw_cases)
    cases = tuple((path.parent / c).resolve() for c in raw_cases)
    for case in cases:
        if not case.is_file():
            raise s.error("case", f"case file not found: {case}", str(case))
    runs = s.raw("runs", 1, "")
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
        raise s.error("runs", "must be an integer >= 1 (Monte Carlo samples per grid point)", runs)
    if runs > MAX_RUNS:
        raise s.error("runs", f"must be <= {MAX_RUNS}: a study runs at most {MAX_RUNS} runs (MAX_RUNS)", runs)
    seed = s.raw("seed", None, "")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
        raise s.error("seed", "must be an integer >= 0", seed)
    duration = s.number("duration", "s", None, above=0.0)
    histories = s.boolean("histories", False)
    sampling = s.string("sampling", "random", SAMPLINGS)
    configurations = []
    outer = s.raw("configurations", [{}], "")
    if not isinstance(outer, list) or not outer:
        raise s.error("configurations", "must be a non-empty array of tables ([[study.configurations]])", outer)
    read = [(table, read_configuration(table, False))
            for table in (Table(entry, ("study", "configurations", i), ctx) for i, entry in enumerate(outer))]
    configurations.extend(entry for _, entries in read for entry in entries)
    reference_table = s.table("reference", None)
    reference, reference_per = None, "sample"
    if reference_table is not None:
        reference_per = reference_table.string("per", "sample", ("sample", "case"))
        reference = read_configuration(reference_table, True)[0]
        read.append((reference_table, [reference]))
    s.finish()
    _check_case_integrators(read, cases)
    parameters = []
    for key, table in top.named_tables("parameters", {}).items():
        parameters.append(_read_parameter(key, table, source))
    top.finish()
    if any(p.distribution for p in parameters) and seed is None:
        raise s.error("seed", "required: the study draws random values")
    if runs > 1 and not any(p.distribution for p in parameters):
        raise s.error("runs", "more than one run per grid point needs a parameter with a distribution", runs)
    if sampling != "random" and not any(p.distribution for p in parameters):
        raise s.error("sampling", f"{sampling} needs a parameter with a distribution to spread", sampling)
    spec = StudySpec(name, path, cases, tuple(configurations), reference, reference_per, tuple(parameters), runs, seed,
                     duration, histories, path.read_text(), sampling=sampling)
    return _checked(spec, s, source)


def _checked(spec: StudySpec, s: Table, source: str) -> StudySpec:
    """``spec`` with its run count and parameters checked (refusals), and the settings another overrides warned."""
    _check_run_count(spec, s)
    _check_parameters(spec, source)
    spec.warnings.extend(_idle_study_settings(spec))
    return spec


def _idle_study_settings(spec: StudySpec) -> list:
    """Warnings for a study setting another one overrides: a parameter on ``simulation.duration`` beside the study's
    own ``duration`` (which every run takes), and Sobol sampling of a run count that is not a power of 2 (its
    balance needs one)."""
    lines = [f'parameters."{p.key}": has no effect: the study\'s duration ({spec.duration:g} s) is every run\'s'
             for p in spec.parameters if spec.duration and p.key == "simulation.duration"]
    if spec.sampling == "sobol" and spec.runs & (spec.runs - 1):
        lines.append(f"sampling = 'sobol' with runs = {spec.runs}: a Sobol sequence keeps its balance only at a "
                     "power of 2 runs (e.g. 4 or 8)")
    return lines


def _check_case_integrators(read: list, cases: tuple) -> None:
    """Refuse adaptive steps in a configuration that names no integrator when a case's own is implicit (``read``:
    each configuration table with what it gave; a case is loaded only for such a configuration)."""
    auto = [t for t, entries in read if any(c.integrator is None and c.step == ADAPTIVE_STEP for c in entries)]
    for case in cases if auto else ():
        integrator = load_case(case).simulation.integrator
        for t in auto:
            _check_adaptive(t, [ADAPTIVE_STEP], integrator, f" of case {case.name} (its simulation.integrator)")


def _check_run_count(spec: StudySpec, s: Table) -> None:
    """Refuse, before the run list is built, a study of more than MAX_RUNS runs (cases x grid x runs x
    configurations, with the references)."""
    grid = math.prod(len(p.values) for p in spec.parameters if p.distribution is None)
    per_sample = len(spec.configurations) + (spec.reference is not None)
    total = len(spec.cases) * grid * spec.runs * per_sample
    if total > MAX_RUNS:
        raise s.error("runs", f"the study expands into {total:.3g} runs ({len(spec.cases)} case(s) x {grid} grid "
                              f"point(s) x {spec.runs} sample(s) x {per_sample} configuration(s)); a study runs at "
                              f"most {MAX_RUNS} (MAX_RUNS): split it", spec.runs)


def _check_parameters(spec: StudySpec, source: str) -> None:
    """Apply each parameter to every case now, so a key that does not exist fails before any run. A grid passes
    when one of its values applies: a value the case refuses (a step study's unstable step, a kappa_max of 3) is
    recorded as that run's failure instead. Every value of a choice must apply (a misspelt canopy fails here)."""
    extra = {"simulation.duration": spec.duration} if spec.duration else {}
    for case in spec.cases:
        _check_duration(case, extra, source)
        for p in spec.parameters:
            every = p.distribution == "choice"
            candidates = p.values or ((0,) if p.distribution == "seed" else p.arguments["values"] if every else
                                      (p.arguments.get("mean", p.arguments.get("low")),))
            first, applied = None, False
            for value in candidates:
                try:
                    loaded = load_case(case, {p.key: Scale(value) if p.relative else value, **extra})
                except CaseError as exc:
                    first = first or exc
                    if every:
                        break
                    continue
                applied = True
                _note_idle_key(spec, case, p.key, loaded)
                unit = loaded.unit_of(p.key)
                if unit is not None:
                    spec.parameter_units[p.key] = unit
                if p.distribution == "seed" and unit:   # integers up to 2^31: 2e9 m/s on a velocity key
                    raise CaseError(source, f'parameters."{p.key}".distribution', f"'seed' draws integers from 0 to "
                                    f"2^31 - 1, for a seed key (atmosphere.turbulence.seed); this key is in {unit}: "
                                    "draw it from normal, uniform or truncated_normal", "seed")
                if not every:
                    break
            if first is not None and (every or not applied):
                raise CaseError(source, f'parameters."{p.key}"',
                                f"does not apply to case {case.name}: {first.detail}") from None


def _check_duration(case: Path, extra: dict, source: str) -> None:
    """The study's own ``duration`` (``extra``) on ``case`` alone, so that a case it cannot apply to (a deployment
    after the end) names the study's key, not the first parameter tried with it."""
    if not extra:
        return
    try:
        load_case(case, extra)
    except CaseError as exc:
        theirs = str(exc).removeprefix(f"{exc.source}: ")   # "key = value: what is allowed"
        raise CaseError(source, "study.duration", f"does not apply to case {case.name}: {theirs}",
                        extra["simulation.duration"]) from None


def _note_idle_key(spec: StudySpec, case: Path, key: str, loaded) -> None:
    """A warning in ``spec.warnings`` when parameter ``key`` is a trigger's sensor error its condition never reads
    (pressure_bias on a Mach trigger): every run would be the same whatever the draw."""
    if key.rpartition(".")[2] not in SENSOR_ERRORS or not loaded.triggers:
        return
    for full in override_leaves(case, {key: 987654321.125}):
        why = idle_sensor_key(loaded.triggers, full)
        line = f'parameters."{key}": has no effect in case {case.name}: {why}; every run draws it in vain'
        if why is not None and line not in spec.warnings:
            spec.warnings.append(line)

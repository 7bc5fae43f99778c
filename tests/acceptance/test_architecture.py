"""The architecture is checked, not promised: import-linter's layer contracts, ruff, short functions, and no method
name compared outside the method table."""

import ast
import functools
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers import ROOT

PACKAGE = ROOT / "pchute_exudyn"
MAX_FUNCTION_LINES = 60


def _tool(name: str) -> str:
    """A console script of this environment (next to the running Python), else from PATH."""
    beside = Path(sys.executable).parent / name
    found = str(beside) if beside.exists() else shutil.which(name)
    if found is None:
        pytest.fail(f"{name} is not installed: install the test extra (pip install -e '.[test]')")
    return found


def _lint_imports(root: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(root)}
    return subprocess.run([_tool("lint-imports"), "--config", str(root / "pyproject.toml"), "--no-cache"],
                          cwd=root, env=env, capture_output=True, text=True, timeout=300)


def test_the_import_contracts_hold():
    run = _lint_imports(ROOT)
    assert run.returncode == 0, run.stdout + run.stderr


def test_ruff_finds_nothing():
    run = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache", str(ROOT)], cwd=ROOT,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr


@pytest.mark.parametrize("module, violation", [
    ("physics/lines.py", "from ..engine import model  # noqa\n"),          # physics reaching up to the engine
    ("engine/phase_model.py", "from ..run import simulation  # noqa\n"),        # the engine reaching up
    ("run/simulation.py", "import exudyn  # noqa\n"),                      # Exudyn outside the engine
    ("physics/air.py", "import threading  # noqa\n"),                      # a thread in the pure layer
    ("triggers/watch.py", "from ..case import model  # noqa\n"),          # triggers reaching up to the case reader
    ("case/loader.py", "from ..authoring import write  # noqa\n"),        # the case reader reaching up to authoring
])
def test_a_crossed_layer_breaks_the_contracts(tmp_path, module, violation):
    shutil.copytree(PACKAGE, tmp_path / "pchute_exudyn", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    target = tmp_path / "pchute_exudyn" / module
    target.write_text(target.read_text() + "\n" + violation)
    run = _lint_imports(tmp_path)
    assert run.returncode != 0 and "BROKEN" in run.stdout.upper(), run.stdout + run.stderr


# -- no import cycle (issue 54) --------------------------------------------------------------------------------


def _modules(root: Path) -> dict:
    """Dotted name -> (path, whether it is a package's __init__) of every module of the package under ``root``."""
    found = {}
    for path in sorted((root / "pchute_exudyn").rglob("*.py")):
        parts = path.relative_to(root).with_suffix("").parts
        package = parts[-1] == "__init__"
        found[".".join(parts[:-1] if package else parts)] = (path, package)
    return found


@functools.cache
def _import_statements(text: str) -> tuple:
    """(level, module, names) of every import statement anywhere in a module's ``text``: ``import a.b`` is
    (None, None, ("a.b",)); ``from ..a import b, c`` (2, "a", ("b", "c")). Kept by text, so that a copy of the
    package is parsed again only where it differs."""
    statements = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Import):
            statements.append((None, None, tuple(alias.name for alias in node.names)))
        elif isinstance(node, ast.ImportFrom):
            statements.append((node.level, node.module, tuple(alias.name for alias in node.names)))
    return tuple(statements)


def import_graph(root: Path) -> dict:
    """Module -> the package's modules it imports anywhere in its text: at module level, inside functions, classes,
    ``if`` and ``try`` alike, relative or absolute; ``from a import b`` imports a.b when b is a submodule, else a.
    (An import by name at run time, ``importlib.import_module``, is not seen.)"""
    modules = _modules(root)
    graph = {}
    for name, (path, package) in modules.items():
        here = name.split(".") if package else name.split(".")[:-1]   # what ``from .`` means in this module
        targets = set()
        for level, module, names in _import_statements(path.read_text()):
            if level is None:
                targets.update(names)
                continue
            base = ".".join(here[:len(here) - level + 1] + ([module] if module else [])) if level else module
            targets.update(f"{base}.{alias}" if f"{base}.{alias}" in modules else base for alias in names)
        graph[name] = {target for target in targets if target in modules and target != name}
    return graph


def import_cycles(graph: dict) -> list:
    """The modules that import each other in a circle, as sorted lists: each strongly connected component of more
    than one module (Tarjan's algorithm); ``circle`` traces one circle through it."""
    index, low, stack, components = {}, {}, [], []

    def visit(module):
        index[module] = low[module] = len(index)
        stack.append(module)
        for target in sorted(graph[module]):
            if target not in index:
                visit(target)
                low[module] = min(low[module], low[target])
            elif target in stack:
                low[module] = min(low[module], index[target])
        if low[module] == index[module]:
            component = set()
            while module not in component:
                component.add(stack.pop())
            if len(component) > 1:
                components.append(component)

    for module in sorted(graph):
        if module not in index:
            visit(module)
    return sorted(sorted(component) for component in components)


def circle(graph: dict, component) -> list:
    """A shortest circle of imports through the first module (by name) of a strongly connected ``component``, the
    first module repeated at the end."""
    component = set(component)
    start = min(component)
    paths = {start: [start]}
    queue = [start]
    for module in queue:   # breadth first, inside the component
        for target in sorted(graph[module] & component):
            if target == start:
                return paths[module] + [start]
            if target not in paths:
                paths[target] = paths[module] + [target]
                queue.append(target)
    raise AssertionError(f"no circle through {start}")   # a strongly connected component always has one


def test_no_module_imports_itself_through_others():
    """No circle of imports in the package, counting those inside functions: each layer's modules import in one
    order (a circle is a misfiled name; issue 54 found `pchute new`'s six modules in one)."""
    graph = import_graph(ROOT)
    cycles = import_cycles(graph)
    assert not cycles, "modules that import each other in a circle:\n" + "\n".join(
        f"{', '.join(cycle)} (e.g. {' -> '.join(circle(graph, cycle))})" for cycle in cycles)


@pytest.mark.parametrize("planted", ["from .cli import main", "from . import cli", "import pchute_exudyn.cli"])
def test_a_planted_import_cycle_is_caught(tmp_path, planted):
    """errors.py importing the command inside a function (the command imports errors at its top) closes a circle
    the check names, in each form an import can take."""
    shutil.copytree(PACKAGE, tmp_path / "pchute_exudyn", ignore=shutil.ignore_patterns("__pycache__", "_compiled"))
    target = tmp_path / "pchute_exudyn" / "errors.py"
    target.write_text(target.read_text() + f"\n\ndef _planted():\n    {planted}  # noqa\n")
    graph = import_graph(tmp_path)
    cycles = import_cycles(graph)
    assert len(cycles) == 1, cycles   # the package had none: every circle now runs through the planted import
    assert {"pchute_exudyn.errors", "pchute_exudyn.cli"} <= set(cycles[0])
    traced = circle(graph, cycles[0])
    assert ("pchute_exudyn.errors", "pchute_exudyn.cli") in zip(traced, traced[1:]), traced


def _functions():
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield path.relative_to(ROOT), node.name, node.end_lineno - node.lineno + 1


def test_every_function_reads_at_once():
    long = sorted(((n, f"{p}:{name}") for p, name, n in _functions() if n >= MAX_FUNCTION_LINES), reverse=True)
    assert not long, f"functions of {MAX_FUNCTION_LINES} lines or more: {long}"


METHOD_COMPARISON = re.compile(r"""(==|!=|\bin\b|\bis\b)\s*\(?\s*["'](full|sp|equilibrium)["']"""
                               r"""|["'](full|sp|equilibrium)["']\s*(==|!=)""")


def test_no_method_name_is_compared_outside_the_method_table():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for number, line in enumerate(path.read_text().splitlines(), start=1):
            if METHOD_COMPARISON.search(line):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not found, "method names compared outside the table:\n" + "\n".join(found)


def test_default_output_folders_are_ignored_by_git():
    if not (ROOT / ".git").exists() or shutil.which("git") is None:
        pytest.skip("not a git checkout")
    paths = ["results/case1_full_rk4/summary.json", "studies/mer/runs.csv"]
    run = subprocess.run(["git", "check-ignore", *paths], cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert run.stdout.split() == paths


@pytest.mark.parametrize("outcome", [0, 3])
def test_ci_script_removes_its_environment_whether_it_passes_or_fails(tmp_path, outcome):
    """.ci/run with stand-ins for python3 and the environment's python (no install, no test run): the temporary
    folder it makes is gone when it ends, passed or failed (before, each run left its 0.4 GB environment)."""
    if shutil.which("bash") is None:
        pytest.skip("no bash")
    stubs, scratch = tmp_path / "bin", tmp_path / "tmp"
    stubs.mkdir()
    scratch.mkdir()
    (stubs / "python3").write_text(   # `python3 -m venv DIR` makes DIR/bin/activate put a stand-in python first
        '#!/bin/sh\nmkdir -p "$3/bin"\nprintf \'#!/bin/sh\\nexit %s\\n\' "$STUB_EXIT" > "$3/bin/python"\n'
        'chmod +x "$3/bin/python"\nprintf \'PATH="%s/bin:$PATH"\\n\' "$3" > "$3/bin/activate"\n')
    (stubs / "python3").chmod(0o755)
    env = {**os.environ, "PATH": f"{stubs}:{os.environ['PATH']}", "TMPDIR": str(scratch), "STUB_EXIT": str(outcome)}
    run = subprocess.run(["bash", str(ROOT / ".ci" / "run")], cwd=ROOT, env=env, capture_output=True, text=True,
                         timeout=60)
    assert run.returncode == outcome, run.stdout + run.stderr
    assert list(scratch.iterdir()) == []


def test_readme_figures_match_the_committed_outputs():
    """The README's test count, wall times and speed-ups are those `validation/readme_figures.py` derives from the
    test suite and the committed validation outputs (rerun the validation script, then fix the README)."""
    run = subprocess.run([sys.executable, str(ROOT / "validation" / "readme_figures.py"), "--check"], cwd=ROOT,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr


# -- the house a newcomer reads (issue 35) ---------------------------------------------------------------------

ROOT_MODULES_MAX = 8
MAX_MODULE_LINES = 700


def test_the_package_root_holds_only_the_public_api_shared_types_and_errors():
    root = sorted(path.name for path in PACKAGE.glob("*.py"))
    assert len(root) <= ROOT_MODULES_MAX, root


def test_no_module_exceeds_its_limit():
    long = sorted((len(path.read_text().splitlines()), str(path.relative_to(ROOT))) for path in PACKAGE.rglob("*.py"))
    assert not [entry for entry in long if entry[0] > MAX_MODULE_LINES], long[-3:]


PACKED_READ = re.compile(r"\b(parameters|params|memory|record|records|row|layout)\[[0-9]+\]")
"""A packed layout's position written as a number (issue 54's check): every layout names its positions where it is
defined (``physics.atmosphere.KIND_AT``, ``physics.air.AIR_RATE``, ``methods.sp.memory``, ...) and is read by name."""
INTEGRATOR_COMPARISON = re.compile(r"""(==|!=)\s*["'](rk4|implicit)["']|["'](rk4|implicit)["']\s*(==|!=)""")


def _lines_matching(pattern, package=PACKAGE):
    for path in sorted(package.rglob("*.py")):
        for number, line in enumerate(path.read_text().splitlines(), start=1):
            if pattern.search(line):
                yield str(path.relative_to(package.parent)), f"{path.relative_to(package.parent)}:{number}: {line.strip()}"


def test_packed_layouts_are_read_by_name():
    found = [text for _, text in _lines_matching(PACKED_READ)]
    assert not found, "positions of a packed layout written as numbers:\n" + "\n".join(found)


def test_a_planted_packed_read_by_number_is_caught(tmp_path):
    shutil.copytree(PACKAGE, tmp_path / "pchute_exudyn", ignore=shutil.ignore_patterns("__pycache__", "_compiled"))
    target = tmp_path / "pchute_exudyn" / "physics" / "air.py"
    target.write_text(target.read_text() + "\n\ndef planted(parameters):\n    return parameters[12]\n")
    found = [text for _, text in _lines_matching(PACKED_READ, tmp_path / "pchute_exudyn")]
    assert found == ["pchute_exudyn/physics/air.py:" + str(len(target.read_text().splitlines()))
                     + ": return parameters[12]"], found


def _names_used(path: Path) -> set:
    """Every name a module reads, imports or defines (identifiers and attribute names)."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Name):
            names.add(node.id)
        elif isinstance(node, ast.Attribute):
            names.add(node.attr)
        elif isinstance(node, ast.alias):
            names.add(node.name.rsplit(".", 1)[-1])
    return names


def _memory_offsets() -> set:
    """The positions SP's named memory defines (``methods/sp/memory.py``: the integer constants it assigns)."""
    tree = ast.parse((PACKAGE / "methods" / "sp" / "memory.py").read_text())
    names = {target.id for node in tree.body if isinstance(node, ast.Assign) for target in ast.walk(node)
             if isinstance(target, ast.Name) and isinstance(target.ctx, ast.Store) and target.id.isupper()}
    from pchute_exudyn.methods.sp import memory

    return {name for name in names if type(getattr(memory, name)) is int}


def test_no_module_outside_sps_package_names_its_memory_offsets():
    offsets = _memory_offsets()
    assert {"MEMORY_POSITION", "WORK_TENSION", "RECORD_TENSIONS", "LAYOUT_DAMPING"} <= offsets
    sp = PACKAGE / "methods" / "sp"
    found = sorted(f"{path.relative_to(ROOT)}: {', '.join(sorted(_names_used(path) & offsets))}"
                   for path in PACKAGE.rglob("*.py") if sp not in path.parents and _names_used(path) & offsets)
    assert not found, "SP's memory offsets named outside its package:\n" + "\n".join(found)


def test_inside_sps_package_only_the_kernels_and_memory_index_it():
    """The runtime half of SP's package (the confluence, the reduced canopy, the method) reads the memory by name
    (``memory.Memory``, ``Work``, ``Record``), never by an offset constant."""
    offsets = _memory_offsets() - {"BRIDLE_ROW", "RISER_ROW"}   # a reduced canopy's two lines, by name
    kernels = {"memory.py", "balance.py", "stepping.py", "canopy_kernels.py"}
    found = sorted(f"{path.name}: {', '.join(sorted(_names_used(path) & offsets))}"
                   for path in (PACKAGE / "methods" / "sp").glob("*.py")
                   if path.name not in kernels and _names_used(path) & offsets)
    assert not found, found


def test_integrators_are_compared_only_in_their_table():
    found = [text for path, text in _lines_matching(INTEGRATOR_COMPARISON)
             if path != "pchute_exudyn/registries/methods.py"]
    assert not found, "integrator names compared outside the table:\n" + "\n".join(found)


def test_study_and_fit_import_no_private_name_of_the_case_layer():
    found = []
    for folder in ("study", "fit"):
        for path in sorted((PACKAGE / folder).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text())):
                if not isinstance(node, ast.ImportFrom):
                    continue
                module = node.module or ""
                if (node.level, module.split(".")[0]) in ((2, "case"), (0, "pchute_exudyn")) and ".case" in f".{module}":
                    found += [f"{path.name}: {alias.name}" for alias in node.names if alias.name.startswith("_")]
    assert not found, found


# -- the unit tier's budget (issue 54) -------------------------------------------------------------------------

BUDGETED_TESTS = '''
import time


def test_quick():
    pass


def test_computes():
    end = time.process_time() + 0.3
    while time.process_time() < end:
        pass


def test_waits():
    time.sleep(0.3)


def test_fails_on_its_own():
    time.sleep(0.3)
    assert False, "its own failure"
'''


def test_the_unit_tier_fails_a_test_over_its_budget(tmp_path):
    """tests/unit/conftest.py, its budgets scaled down to 0.1 s, in a pytest run of its own: a test that computes or
    waits past them fails naming the budget; a quick one passes; one that fails keeps its own failure."""
    conftest = (ROOT / "tests" / "unit" / "conftest.py").read_text()
    for name in ("CPU_BUDGET", "WALL_BUDGET"):
        conftest, found = re.subn(rf"^{name} = .*$", f"{name} = 0.1", conftest, flags=re.MULTILINE)
        assert found == 1, name
    (tmp_path / "conftest.py").write_text(conftest)
    (tmp_path / "test_budgeted.py").write_text(BUDGETED_TESTS)
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-rA", "-p", "no:cacheprovider", str(tmp_path)],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    outcomes = {name: outcome for outcome, name in re.findall(r"^(PASSED|FAILED) \S+::(\w+)", run.stdout,
                                                              re.MULTILINE)}
    assert outcomes == {"test_quick": "PASSED", "test_computes": "FAILED", "test_waits": "FAILED",
                        "test_fails_on_its_own": "FAILED"}, run.stdout
    budget = "a unit test's budget is 0.1 s and 0.1 s (tests/unit/conftest.py)"
    for name in ("test_computes", "test_waits"):
        assert re.search(rf"::{name} took [0-9.]+ s of processor time and [0-9.]+ s on the clock: {re.escape(budget)}",
                         run.stdout), run.stdout
    assert "its own failure" in run.stdout


# -- docs/architecture.md names the modules as they are (issue 54) ----------------------------------------------------

DOC_MODULE = re.compile(r"`([A-Za-z0-9_./-]+\.py)`")
"""A module named on the page: a path in backticks, relative to the package (or to the repository)."""


def _package_modules() -> set:
    """Every module of the package by its path from the package folder (a subpackage by its modules)."""
    return {str(path.relative_to(PACKAGE)) for path in PACKAGE.rglob("*.py") if "_compiled" not in path.parts
            and not (path.name == "__init__.py" and path.parent != PACKAGE)}


def test_docs_architecture_names_every_module_and_only_modules_that_exist():
    named = set(DOC_MODULE.findall((ROOT / "docs" / "architecture.md").read_text()))
    missing = sorted(name for name in named if not (PACKAGE / name).is_file() and not (ROOT / name).is_file())
    unnamed = sorted(_package_modules() - named)
    assert not missing, f"docs/architecture.md names modules that do not exist: {missing}"
    assert not unnamed, f"modules docs/architecture.md does not name: {unnamed}"


PARALLEL = {"spec.py": {"study", "fit"}, "report.py": {"study", "fit"}}
"""The names two parallel packages share on purpose: a study's and a fit's input file and report."""


def test_each_module_name_once():
    """No two modules of the package share a name (issue 54: triggers, aerodynamics, reduced_canopy, step_control and
    model were each written in two or three layers), but for the parallel packages study/ and fit/."""
    by_name: dict = {}
    for module in _package_modules():
        path = Path(module)
        if path.name != "__init__.py":
            by_name.setdefault(path.name, set()).add(str(path.parent))
    shared = {name: folders for name, folders in by_name.items() if len(folders) > 1 and PARALLEL.get(name) != folders}
    assert not shared, shared

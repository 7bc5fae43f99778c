"""The compiled kernel module: built from the current source, loaded without numba, serving every kernel call the
package makes from Python with compiled code, and naming argument types as numba does."""

from __future__ import annotations

import inspect
import json
import os
import subprocess
import sys
from array import array
from importlib import import_module
from pathlib import Path

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.kernels import lock, selection
from pchute_exudyn.physics import compiled
from tests.helpers import ROOT, run_cli


def test_the_suite_runs_the_compiled_module_of_the_current_source():
    assert compiled.MODE == "compiled"
    assert selection.table_path().is_file()
    table = json.loads(selection.table_path().read_text())
    assert table["key"] == selection.source_key()


def test_a_process_that_runs_the_compiled_module_never_imports_numba():
    done = subprocess.run([sys.executable, "-c", "import sys, pchute_exudyn as pc; "
                           "pc.simulate(pc.load_case(sys.argv[1]), 'sp', duration=1.0); "
                           "print(sorted(m for m in sys.modules if m.split('.')[0] in ('numba', 'llvmlite')))",
                           str(ROOT / "cases" / "mer" / "case1.toml")], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


def test_a_kernel_form_that_does_not_exist_is_one_line_naming_it_and_exit_2(tmp_path):
    environment = {**os.environ, "PCHUTE_KERNELS": "fast"}
    done = run_cli("run", ROOT / "cases" / "mer" / "case1.toml", "--no-plot", "--out", tmp_path / "r", env=environment)
    assert done.returncode == 2 and not (tmp_path / "r").exists()
    assert done.stderr.splitlines() == [
        "pchute: error: PCHUTE_KERNELS='fast' in the environment: allowed compiled, jit, python, or unset (automatic)"]
    done = subprocess.run([sys.executable, "-c", "import sys, pchute_exudyn as pc\ntry:\n"
                           " pc.simulate(pc.load_case(sys.argv[1]), 'sp', duration=0.1)\n"
                           "except pc.InputError as error:\n print(error)", str(ROOT / "cases" / "mer" / "case1.toml")],
                          capture_output=True, text=True, env=environment, check=True)
    assert "PCHUTE_KERNELS='fast'" in done.stdout and done.stderr == ""


@pytest.mark.parametrize("value", [
    1.5, 3, True, np.float64(2.0), np.int64(4), np.bool_(False), np.zeros(3), np.zeros((2, 3)), np.zeros((2, 3, 4)),
    np.zeros((3, 2), order="F"), np.zeros((4, 4))[:, 1], np.zeros(3, np.int64), np.zeros(2, bool),
    np.frombuffer(b"\0" * 24), array("d", [1.0, 2.0]), (1.0, 2), (np.zeros(2), 1.0)])
def test_argument_types_are_named_as_numba_types_them(value):
    """``describe`` (no numba at run time) and the builder's ``describe_type`` of numba's own type agree."""
    numba = pytest.importorskip("numba")
    from pchute_exudyn.kernels.build import describe_type, numba_type

    assert compiled.describe(value) == describe_type(numba.typeof(value))
    assert describe_type(numba_type(compiled.describe(value))) == compiled.describe(value)


def test_every_recorded_signature_names_an_existing_kernel_with_its_argument_count():
    signatures = json.loads(selection.SIGNATURES.read_text())
    assert signatures
    for name, entries in signatures.items():
        module, function = name.rsplit(".", 1)
        kernel = getattr(import_module(module), function)
        if not isinstance(kernel, compiled.CompiledKernel):   # a name Python callers get another function for
            kernel = getattr(import_module(module), f"{function}_port")
        parameters = inspect.signature(compiled.python_form(kernel)).parameters
        for arguments, _ in entries:
            assert len(arguments) == len(parameters), name


def test_every_kernel_call_of_every_method_runs_compiled_code():
    """Small models of every method, a cluster, a load-elongation line, winds and turbulence, the rocket's reduced
    canopies at adaptive steps, with outputs and summaries: no call fell back to the Python form (the signatures cover what the package calls)."""
    from pchute_exudyn.tools.record_signatures import BRIDLE, CASE, CLUSTER

    compiled.FALLBACKS.clear()
    base = CASE.replace("{bridles}", "".join(BRIDLE.format(name=n) for n in "abc"))
    runs = [(base, method, integrator, step) for method, integrator, step in
            (("sp", "rk4", 1e-2), ("equilibrium", "rk4", 1e-2), ("full", "rk4", 1e-4), ("full", "implicit", 1e-2))]
    runs.append((base + CLUSTER, "sp", "rk4", 1e-2))
    for text, method, integrator, step in runs:
        pc.simulate(_load(text), method, integrator, step, 0.05)
    winds = pc.load_case(ROOT / "cases" / "cev_pa1_winds.toml")
    pc.simulate(winds, "sp", duration=3.0)
    pc.simulate(pc.load_case(ROOT / "cases" / "cev_pa1_aero.toml"), "sp", duration=3.0)
    pc.simulate(pc.load_case(ROOT / "cases" / "rocket" / "dual_deploy.toml"), "sp")   # reduced canopies, own steps
    assert compiled.FALLBACKS == {}


def _load(text: str):
    import tempfile
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "case.toml"
        path.write_text(text)
        return pc.load_case(path)


def test_a_call_with_other_argument_types_runs_the_python_form_and_is_counted():
    """Compiled code converts its arguments without checking them: a call whose types differ from the ones compiled
    (here a strided array) must run the Python form, with the same result."""
    from pchute_exudyn.physics.atmosphere import atmosphere_state

    parameters = pc.load_case(ROOT / "cases" / "mer" / "case1.toml").atmosphere.kernel_parameters()
    compiled.FALLBACKS.clear()
    as_compiled = atmosphere_state(parameters, 5000.0)
    assert compiled.FALLBACKS == {}
    strided = np.repeat(parameters, 2)[::2]
    assert atmosphere_state(strided, 5000.0) == as_compiled
    assert list(compiled.FALLBACKS) == [("pchute_exudyn.physics.atmosphere.atmosphere_state", ("<f8:1:A", "f8"))]
    compiled.FALLBACKS.clear()


def test_a_module_of_other_source_is_not_loaded(tmp_path):
    """A kernel folder holding only a module built from other source (its table under another key) gives no
    compiled module: the run would use the Python form and build one."""
    current = selection.table_path()
    table = json.loads(current.read_text())
    (tmp_path / "kernels_0000000000000000.json").write_text(json.dumps({**table, "key": "0000000000000000"}))
    (tmp_path / table["file"]).write_bytes((current.parent / table["file"]).read_bytes())
    assert selection.load_compiled(tmp_path) is None
    assert selection.load_compiled(current.parent) is not None


def test_a_build_that_failed_is_not_started_again_by_every_run(tmp_path, monkeypatch):
    """Where no module can be built (no C compiler, say) the builder leaves a mark: runs stop starting builds in the
    background or first, and keep the Python form; without the mark a long run builds first."""
    monkeypatch.setenv("PCHUTE_KERNEL_DIR", str(tmp_path))
    monkeypatch.setenv(selection.VARIABLE, "python")
    monkeypatch.setenv(selection.VARIABLE + "_AUTO", "1")
    assert lock.worth_building_first(100_000) and not lock.worth_building_first(1_000)
    lock.failed().write_text("CompileError: no C compiler\n")
    assert not lock.worth_building_first(100_000)
    assert not lock.start_background_build() and not lock.lock().exists()


def test_a_build_lock_counts_only_while_its_builder_lives(tmp_path, monkeypatch):
    """A run waits for a build in progress, never for the lock of a builder that was killed outright (it would wait
    LOCK_AGE, ten minutes, without progress)."""
    monkeypatch.setenv("PCHUTE_KERNEL_DIR", str(tmp_path))
    builder = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        lock.lock().write_text(str(builder.pid))
        assert lock.building()
    finally:
        builder.kill()
        builder.wait()
    assert not lock.building()
    lock.lock().write_text("")   # being written by a starting build
    assert lock.building()
    old = lock.lock().stat().st_mtime - lock.LOCK_AGE - 1
    os.utime(lock.lock(), (old, old))
    assert not lock.building()


def test_the_jit_form_keeps_numbas_cache_per_kernel_source(tmp_path):
    """numba keys a cached kernel by its own file only: the jit form's cache is a folder of the kernels' source key
    (under the user's NUMBA_CACHE_DIR), so a kernel calling one in an edited file is compiled anew; child processes
    (the module builder) agree on it."""
    code = ("import os, pchute_exudyn; from pchute_exudyn.kernels import selection as k; "
            "print(os.environ['NUMBA_CACHE_DIR']); print(k.source_key())")
    env = {**os.environ, "PCHUTE_KERNELS": "jit", "NUMBA_CACHE_DIR": str(tmp_path)}
    env.pop(selection.JIT_CACHE_BASE, None)
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    folder, key = done.stdout.split()
    assert Path(folder) == tmp_path / f"jit_{key}"
    child = {**env, "NUMBA_CACHE_DIR": folder, selection.JIT_CACHE_BASE: str(tmp_path)}
    again = subprocess.run([sys.executable, "-c", code], env=child, capture_output=True, text=True, timeout=120)
    assert again.stdout.split()[0] == folder   # not nested a second time

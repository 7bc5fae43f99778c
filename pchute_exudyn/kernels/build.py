"""Build the compiled kernel module (``_kernel_mode`` says why and when it is used).

``python -m pchute_exudyn.kernels.build`` compiles every kernel for the argument types the package calls it with from
Python (``kernel_signatures.json``) into one extension module, with numba's ahead-of-time compiler, into the
kernel folder (``_kernel_mode.cache_directory``; ``--out DIR`` elsewhere). The package's install runs it
(``setup.py``); a run that finds no module of the current source starts it in the background. The module's table,
written last, says which export serves which kernel.

``--record`` runs small models of every method (two bodies, a load-elongation line, SP of either order and slack
rule, equilibrium point, full mass RK4 and implicit, a cluster) and formats a table (``number_text``) with numba
compiling each kernel on first call, and
writes the argument types each kernel was called with from Python to ``kernel_signatures.json``: rerun it when a
kernel's arguments change (``tests/test_kernels.py`` fails until then).
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import shutil
import subprocess
import sys
import tempfile
import warnings
from importlib import import_module
from pathlib import Path

from . import selection as _kernel_mode

CASE = """
[case]
vehicle = "probe"
[planet]
name = "Mars"
gravitational_parameter = 4.282828685e13
equatorial_radius = 3393940.0
polar_radius = 3376780.0
[start]
latitude_deg = 0.0
longitude_deg = 0.0
[atmosphere]
model = "mars_grc"
[bodies.probe]
mass = 700.0
inertia = [200.0, 180.0, 210.0]
[bodies.probe.points]
a = [-0.8, 0.3, 0.5]
b = [-0.8, 0.3, -0.5]
c = [-0.8, -0.6, 0.0]
[bodies.probe.initial]
altitude = 8000.0
[bodies.canopy]
mass = 16.0
inertia = [250.0, 1100.0, 1100.0]
[bodies.canopy.points]
riser = [31.3, 0.0, 0.0]
[bodies.canopy.initial]
altitude = 8034.4
[bodies.canopy.aerodynamics]
reference_area = 178.0
axial_coefficient = 0.46
center = [-1.5, 0.0, 0.0]
[bodies.canopy.aerodynamics.normal_coefficient]
alpha_deg = [0.0, 45.0, 90.0]
value = [0.0, 0.14, 0.0]
[systems.main.confluence]
mass = 0.15
[systems.main.confluence.initial]
altitude = 8001.2
{bridles}[systems.main.lines.riser]
attach = "canopy.riser"
free_length = 1.83
damping = 600.0
load_elongation = { strain = [0.0, 0.01, 0.05], tension = [0.0, 1100.0, 9000.0] }
[simulation]
duration = 0.05
output_step = 0.01
"""
CLUSTER = """
[systems.main]
canopies = ["canopy", "twin"]
[bodies.twin]
mass = 16.0
inertia = [250.0, 1100.0, 1100.0]
points.riser = [31.3, 0.0, 0.0]
initial = { altitude = 8034.4, east = 3.0 }
[bodies.twin.aerodynamics]
reference_area = 178.0
axial_coefficient = 0.46
center = [-1.5, 0.0, 0.0]
normal_coefficient = { alpha_deg = [0.0, 90.0], value = [0.0, 0.0] }
[systems.main.lines.twin]
attach = "twin.riser"
free_length = 1.83
stiffness = 4000.0
damping = 600.0
"""
"""A second canopy on the same confluence: a cluster, for the canopy-contact kernel."""
BRIDLE = """[systems.main.lines.{name}]
attach = "probe.{name}"
free_length = 0.7
stiffness = 47000.0
damping = 470.0
"""


# -- the types, as the compiled module's table names them (``physics.compiled.describe``) -------------------------

def describe_type(numba_type) -> str:
    """A numba type as ``physics.compiled.describe`` names the values numba gives it."""
    from numba import types

    if isinstance(numba_type, types.PyArray):
        return f"array.{'d' if str(numba_type.dtype) == 'float64' else numba_type.dtype}"
    if isinstance(numba_type, types.Array):
        import numpy as np

        dtype = np.dtype(str(numba_type.dtype)).str
        return f"{dtype}:{numba_type.ndim}:{numba_type.layout}" + ("" if numba_type.mutable else ":r")
    if isinstance(numba_type, types.BaseTuple):
        return "(" + ",".join(describe_type(item) for item in numba_type) + ")"
    if numba_type == types.none:
        return "none"
    return {types.float64: "f8", types.int64: "i8", types.boolean: "b1"}.get(numba_type, str(numba_type))


def numba_type(text: str):
    """The numba type ``describe_type`` named ``text``."""
    import numpy as np
    from numba import types
    from numba.np.numpy_support import from_dtype

    if text.startswith("("):
        return types.Tuple([numba_type(item) for item in _split_top(text[1:-1])])
    if text.startswith("array."):
        return types.PyArray(types.float64, 1, "C")
    if ":" in text:
        dtype, ndim, layout, *flags = text.split(":")
        return types.Array(from_dtype(np.dtype(dtype)), int(ndim), layout, readonly=flags == ["r"])
    return {"f8": types.float64, "i8": types.int64, "b1": types.boolean, "none": types.none}[text]


def _split_top(text: str) -> list:
    """The comma-separated items of a tuple's text, nested tuples kept whole."""
    items, depth, start = [], 0, 0
    for i, char in enumerate(text):
        depth += {"(": 1, ")": -1}.get(char, 0)
        if char == "," and depth == 0:
            items.append(text[start:i])
            start = i + 1
    return items + [text[start:]] if text else items


# -- recording the signatures ----------------------------------------------------------------------------------

def record(cases=()) -> dict:
    """Run small models of every method, then each case file of ``cases`` with each method, with numba compiling
    the kernels; the argument and return types of every kernel called from Python, by kernel name."""
    import numpy as np

    import pchute_exudyn as pc
    from pchute_exudyn.physics.singular_perturbation import confluence_velocity
    from pchute_exudyn.results.number_text import table_text

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "warm.toml"
        base = CASE.replace("{bridles}", "".join(BRIDLE.format(name=n) for n in "abc"))
        path.write_text(base)
        case = pc.load_case(path)
        for options in ({"order": 0}, {"order": 1}, {"slack_rule": "force"}):
            pc.simulate(case, "sp", "rk4", 1e-2, 0.05, **options)
        pc.simulate(case, "equilibrium", "rk4", 1e-2, 0.05)
        pc.simulate(case, "full", "rk4", 1e-4, 0.002)
        pc.simulate(case, "full", "implicit", 1e-2, 0.05)
        path.write_text(base + CLUSTER)
        pc.simulate(pc.load_case(path), "sp", "rk4", 1e-2, 0.05)
    confluence_velocity([(0.0, 0.0, 1.1)], [(0.0, 0.0, 0.0)], (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), [1.0], [1e4],
                        [1e2])
    table_text(["a", "b"], [np.zeros(2), np.ones(2)])
    for path in cases:
        case = pc.load_case(path)
        pc.simulate(case, "sp", "rk4", 1e-2)
        pc.simulate(case, "equilibrium", "rk4", 1e-2)
        pc.simulate(case, "full", "implicit", 1e-2)
    return signatures_in_use()


def merged(old: dict, new: dict) -> dict:
    """The signatures of ``old`` and ``new`` together (a recording adds to what earlier ones found)."""
    table = {name: list(entries) for name, entries in old.items()}
    for name, entries in new.items():
        table.setdefault(name, []).extend(entry for entry in entries if entry not in table[name])
    return dict(sorted(table.items()))


def signatures_in_use() -> dict:
    """Every kernel's compiled signatures in this (jit-form) process: {name: [[argument types], return type]}."""
    from numba.core.registry import CPUDispatcher

    found = {}
    for name in sorted(sys.modules):
        if not name.startswith(_kernel_mode.KERNEL_MODULES):
            continue
        for value in vars(sys.modules[name]).values():
            if isinstance(value, CPUDispatcher) and value.py_func.__module__ == name:
                kernel = f"{name}.{value.py_func.__qualname__}"
                for arguments, result in value.overloads.items():
                    entry = [[describe_type(t) for t in arguments], describe_type(result.signature.return_type)]
                    if _exportable(entry) and entry not in found.setdefault(kernel, []):
                        found[kernel].append(entry)
    return {name: entries for name, entries in found.items() if entries}


def _exportable(entry) -> bool:
    """Whether a signature's types can cross from Python (a kernel called by another kernel may have been compiled
    for constants, 'Literal[int](0)': that is not a call from Python)."""
    try:
        [numba_type(text) for text in [*entry[0], entry[1]]]
    except (KeyError, ValueError):
        return False
    return True


# -- building the module ---------------------------------------------------------------------------------------

def _forwarder(target, count: int):
    """A function of ``count`` arguments that calls kernel ``target``: what is exported, so that the kernel itself
    is compiled with its own options (numpy's error model) wherever it is called."""
    names = ", ".join(f"a{i}" for i in range(count))
    scope = {"target": target}
    exec(f"def forward({names}):\n    return target({names})\n", scope)   # noqa: S102 - fixed text, our names
    return scope["forward"]


def build(folder: Path | None = None, verbose: bool = False) -> Path:
    """Compile every kernel in ``kernel_signatures.json`` into the module of the current source in ``folder``
    (default: the kernel folder); returns the module's table. Needs the jit form (numba) in this process."""
    import numba
    from numba.pycc import CC

    folder = Path(folder) if folder is not None else _kernel_mode.cache_directory()
    folder.mkdir(parents=True, exist_ok=True)
    key = _kernel_mode.source_key()
    wanted = json.loads(_kernel_mode.SIGNATURES.read_text())
    name = _kernel_mode.module_name(key)
    table = {"key": key, "numba": numba.__version__, "kernels": {}}
    with tempfile.TemporaryDirectory(dir=folder, prefix=".build-") as scratch:
        cc = CC(name, source_module=__name__)
        cc.output_dir = scratch
        cc.verbose = verbose
        exports = (f"k{number}" for number in itertools.count())
        for kernel, entries in wanted.items():
            module_path, function_name = kernel.rsplit(".", 1)
            target = getattr(import_module(module_path), function_name)
            for arguments, result in entries:
                export = next(exports)
                signature = numba_type(result)(*(numba_type(a) for a in arguments))
                cc.export(export, signature)(_forwarder(target, len(arguments)))
                table["kernels"].setdefault(kernel, []).append({"export": export, "arguments": arguments})
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")   # pycc's deprecation notice: the module is what we ship
            cc.compile()
        built = Path(cc._output_file)
        table["file"] = built.name
        os.replace(Path(scratch) / built.name, folder / built.name)
    path = _kernel_mode.table_path(key, folder)
    partial = path.with_suffix(".json.tmp")
    partial.write_text(json.dumps(table, indent=1) + "\n")
    os.replace(partial, path)   # the table last: its presence says the module is complete
    for old in folder.glob("kernels_*"):   # modules of other source are never loaded again
        if not old.name.startswith(name):
            old.unlink(missing_ok=True)
    for old in folder.glob("jit_*"):   # nor numba's caches of other source (_kernel_mode.use_jit_cache_of_this_source)
        if old.name != f"jit_{key}":
            shutil.rmtree(old, ignore_errors=True)
    return path


STOP_SECONDS = 5.0
"""How long a Ctrl-C'd build is given to stop by itself before it is killed."""


def _build_in_jit_process(arguments: list, lock: Path | None) -> int:
    """This command again in a process that imports the kernels in the jit form (compiling needs them as numba
    dispatchers). It holds the build lock meanwhile; on Ctrl-C (which reaches both) it gives that process
    STOP_SECONDS to stop and remove its scratch folder before killing it."""
    if lock is not None:
        lock.write_text(str(os.getpid()))   # the builder holds the lock now, not the run that started it
    builder = subprocess.Popen([sys.executable, "-m", "pchute_exudyn.kernels.build", *arguments],
                               env={**os.environ, _kernel_mode.VARIABLE: "jit"})
    try:
        return builder.wait()
    except KeyboardInterrupt:
        try:
            builder.wait(timeout=STOP_SECONDS)
        except (subprocess.TimeoutExpired, KeyboardInterrupt):
            builder.kill()
        raise
    finally:
        if lock is not None:
            lock.unlink(missing_ok=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pchute_exudyn.kernels.build", description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None, help="folder for the module (default: the kernel folder)")
    parser.add_argument("--record", nargs="*", metavar="CASE", default=None,
                        help="add to kernel_signatures.json the signatures that small models of every method (and "
                             "each CASE file, run with each method) call the kernels with")
    parser.add_argument("--if-missing", action="store_true",
                        help="build only when the folder has no module of the current source")
    parser.add_argument("--lock", type=Path, default=None, help=argparse.SUPPRESS)   # removed when done
    parser.add_argument("--verbose", action="store_true")
    args = parser.parse_args(argv)
    if args.if_missing and _kernel_mode.table_path(folder=args.out).is_file():
        return 0
    if os.environ.get(_kernel_mode.VARIABLE) != "jit":
        return _build_in_jit_process(argv or sys.argv[1:], args.lock)
    failed = _kernel_mode.failed() if args.out is None else None
    try:
        if args.record is not None:
            old = json.loads(_kernel_mode.SIGNATURES.read_text()) if _kernel_mode.SIGNATURES.is_file() else {}
            _kernel_mode.SIGNATURES.write_text(json.dumps(merged(old, record(args.record)), indent=1) + "\n")
            print(f"wrote {_kernel_mode.SIGNATURES}")
            return 0
        try:
            table = build(args.out, args.verbose)
        except Exception as exc:   # recorded, so that runs stop starting builds that fail the same way
            if failed is not None:
                failed.parent.mkdir(parents=True, exist_ok=True)
                failed.write_text(f"{type(exc).__name__}: {exc}\n")
            raise
        if failed is not None:
            failed.unlink(missing_ok=True)
        print(f"compiled kernels: {table.parent / json.loads(table.read_text())['file']}")
    finally:
        if args.lock is not None:
            args.lock.unlink(missing_ok=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

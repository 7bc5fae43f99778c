"""Build the compiled kernel module (``kernels.selection`` says why and when it is used).

``python -m pchute_exudyn.kernels.build`` compiles every kernel for the argument types the package calls it with from
Python (``kernels/signatures.json``, written by ``python -m pchute_exudyn.tools.record_signatures``) into one extension
module, with numba's ahead-of-time compiler, into the kernel folder (``selection.cache_directory``; ``--out DIR``
elsewhere). The package's install runs it (``setup.py``); a command that finds no module of the current source
starts it in the background (``kernels.lock``). The module's table, written last, says which export serves which
kernel.
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

from . import dataclass_code, lock, selection

COMMAND = "pchute_exudyn.kernels.build"
"""This module as a command (``python -m``), run again in the jit form."""


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


# -- building the module ---------------------------------------------------------------------------------------

def _forwarder(target, count: int):
    """A function of ``count`` arguments that calls kernel ``target``: what is exported, so that the kernel itself
    is compiled with its own options (numpy's error model) wherever it is called."""
    names = ", ".join(f"a{i}" for i in range(count))
    scope = {"target": target}
    exec(f"def forward({names}):\n    return target({names})\n", scope)   # noqa: S102 - fixed text, our names
    return scope["forward"]


def build(folder: Path | None = None, verbose: bool = False) -> Path:
    """Compile every kernel in ``kernels/signatures.json`` into the module of the current source in ``folder``
    (default: the kernel folder); returns the module's table. Needs the jit form (numba) in this process."""
    import numba
    from numba.pycc import CC

    folder = Path(folder) if folder is not None else selection.cache_directory()
    folder.mkdir(parents=True, exist_ok=True)
    key = selection.source_key()
    wanted = json.loads(selection.SIGNATURES.read_text())
    name = selection.module_name(key)
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
    path = selection.table_path(key, folder)
    partial = path.with_suffix(".json.tmp")
    partial.write_text(json.dumps(table, indent=1) + "\n")
    os.replace(partial, path)   # the table last: its presence says the module is complete
    for old in folder.glob("kernels_*"):   # modules of other source are never loaded again
        if not old.name.startswith(name):
            old.unlink(missing_ok=True)
    for old in folder.glob("jit_*"):   # nor numba's caches of other source (selection.use_jit_cache_of_this_source)
        if old.name != f"jit_{key}":
            shutil.rmtree(old, ignore_errors=True)
    return path


STOP_SECONDS = 5.0
"""How long a Ctrl-C'd build is given to stop by itself before it is killed."""


def in_jit_process(module: str, arguments: list, held: Path | None = None) -> int:
    """The command ``python -m module arguments`` again in a process that imports the kernels in the jit form
    (compiling and recording need them as numba dispatchers). It holds the build lock ``held`` meanwhile; on Ctrl-C
    (which reaches both) it gives that process STOP_SECONDS to stop and remove its scratch folder before killing
    it."""
    if held is not None:
        held.write_text(str(os.getpid()))   # the builder holds the lock now, not the run that started it
    builder = subprocess.Popen([sys.executable, "-m", module, *arguments],
                               env={**os.environ, selection.VARIABLE: "jit"})
    try:
        return builder.wait()
    except KeyboardInterrupt:
        try:
            builder.wait(timeout=STOP_SECONDS)
        except (subprocess.TimeoutExpired, KeyboardInterrupt):
            builder.kill()
        raise
    finally:
        if held is not None:
            held.unlink(missing_ok=True)


def check(folder: Path | None) -> int:
    """0 when ``folder`` (default: the package's ``_compiled`` folder, where the install puts it) holds the module of
    the current source, else 1 with one line saying so: what CI asserts right after the install."""
    folder = folder if folder is not None else selection.PACKAGE / "_compiled"
    table = selection.table_path(folder=folder)
    if table.is_file() and (folder / json.loads(table.read_text())["file"]).is_file():
        print(f"compiled kernels in place: {table.with_suffix('').name}")
        return 0
    print(f"no compiled kernel module of the current source in {folder} (the install did not build it)",
          file=sys.stderr)
    return 1


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog=f"python -m {COMMAND}", description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None, help="folder for the module (default: the kernel folder)")
    parser.add_argument("--if-missing", action="store_true",
                        help="build only when the folder has no module of the current source")
    parser.add_argument("--lock", type=Path, default=None, help=argparse.SUPPRESS)   # removed when done
    parser.add_argument("--verbose", action="store_true")
    parser.add_argument("--check", action="store_true",
                        help="only say whether the folder holds the module of the current source (exit 1 if not)")
    args = parser.parse_args(argv)
    if args.check:
        return check(args.out)
    if args.if_missing and selection.table_path(folder=args.out).is_file():
        return 0
    if os.environ.get(selection.VARIABLE) != "jit":
        return in_jit_process(COMMAND, argv or sys.argv[1:], args.lock)
    failed = lock.failed() if args.out is None else None
    try:
        table = build(args.out, args.verbose)
    except Exception as exc:   # recorded, so that runs stop starting builds that fail the same way
        if failed is not None:
            failed.parent.mkdir(parents=True, exist_ok=True)
            failed.write_text(f"{type(exc).__name__}: {exc}\n")
        raise
    else:
        if failed is not None:
            failed.unlink(missing_ok=True)
        print(f"compiled kernels: {table.parent / json.loads(table.read_text())['file']}")
        if args.out is None:
            dataclass_code.warm_and_save()   # the classes' code too (``dataclass_code``): a fast first run
    finally:
        if args.lock is not None:
            args.lock.unlink(missing_ok=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

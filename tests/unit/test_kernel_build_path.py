"""The install's kernel build needs only the build requirements (issue 58: a scipy import on its path made every
fresh install skip the build, unnoticed, and the first run paid 82 s for it)."""

from __future__ import annotations

import json
import subprocess
import sys

from pchute_exudyn.case.files import tomllib
from tests.helpers import ROOT, cli_environment

# a finder that refuses every module outside the standard library, the build requirements (numba brings llvmlite)
# and the package, then imports what `python -m pchute_exudyn.kernels.build` imports: the builder and each kernel's
# module, in the jit form
PROBE = """
import importlib, json, sys
allowed = set(sys.argv[1].split(",")) | set(sys.stdlib_module_names) | {"pchute_exudyn", "llvmlite", "_distutils_hack"}
class Refuse:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] not in allowed:
            raise ModuleNotFoundError(f"not a build requirement: {name}")
sys.meta_path.insert(0, Refuse())
importlib.import_module("pchute_exudyn.kernels.build")
for kernel in json.load(open(sys.argv[2])):
    importlib.import_module(kernel.rsplit(".", 1)[0])
print("ok")
"""


def build_requirements() -> list:
    requires = tomllib.loads((ROOT / "pyproject.toml").read_text())["build-system"]["requires"]
    names = [entry.split(";")[0].split(">")[0].split("<")[0].split("=")[0].strip() for entry in requires]
    return [name.replace("-", "_") for name in names]


def probe(requirements: list) -> subprocess.CompletedProcess:
    environment = cli_environment({**cli_environment(), "PCHUTE_KERNELS": "jit"})
    signatures = ROOT / "pchute_exudyn" / "kernels" / "signatures.json"
    return subprocess.run([sys.executable, "-c", PROBE, ",".join(requirements), str(signatures)], env=environment,
                          capture_output=True, text=True, timeout=120)


def test_the_kernel_build_imports_nothing_beyond_its_build_requirements():
    requirements = build_requirements()
    assert {"numpy", "numba"} <= set(requirements)
    done = probe(requirements)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr[-2000:]


def test_the_probe_catches_a_requirement_the_build_does_not_declare():
    """Without numpy among the allowed names the same probe fails: it would see a scipy import the same way."""
    done = probe([name for name in build_requirements() if name != "numpy"])
    assert done.returncode != 0 and "not a build requirement: numpy" in done.stderr
    assert json.loads((ROOT / "pchute_exudyn" / "kernels" / "signatures.json").read_text())

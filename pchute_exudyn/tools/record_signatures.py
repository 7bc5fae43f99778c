"""Record the argument types the package calls each kernel with from Python: a developer tool.

``python -m pchute_exudyn.tools.record_signatures [CASE ...]`` runs small models of every method (two bodies, a
load-elongation line, SP of either order and slack rule, equilibrium point, full mass RK4 and implicit, a cluster),
the rocket case (reduced canopies at adaptive steps), then each CASE file with each method, and formats a table
(``number_text``), with numba compiling each kernel on first call, and adds the argument types each kernel was called
with from Python to ``kernels/signatures.json`` (what ``python -m pchute_exudyn.kernels.build`` compiles). Rerun it
when a kernel's arguments change (``tests/integration/test_kernels.py`` fails until then). It runs the whole package: a
top-layer module.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

from ..kernels.build import describe_type, in_jit_process, numba_type
from ..kernels.selection import KERNEL_MODULES, SIGNATURES, VARIABLE

ROCKET = Path(__file__).resolve().parents[2] / "cases" / "rocket" / "dual_deploy.toml"
"""A shipped case with reduced canopies, run whole with its own step control (its kernels are recorded too)."""

COMMAND = "pchute_exudyn.tools.record_signatures"
"""This module as a command (``python -m``), run again in the jit form."""

CASE = """
[case]
vehicle = "probe"
[planet]
name = "Mars"
gravitational_parameter = 4.282828685e13
equatorial_radius = 3393940.0
polar_radius = 3376780.0
gravity_model = "spherical"
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
TRIO = (CLUSTER.replace('"twin"]', '"twin", "third"]')
        + CLUSTER.split('"twin"]\n', 1)[1].replace("twin", "third").replace("east = 3.0", "east = -3.0"))
"""A third canopy: a cluster of three, whose four bodies' coordinates cross into SP's fused stage kernels as tuples of
24 floats (without it such a cluster runs those kernels' Python form)."""
BRIDLE = """[systems.main.lines.{name}]
attach = "probe.{name}"
free_length = 0.7
stiffness = 47000.0
damping = 470.0
"""


def record(cases=()) -> dict:
    """Run small models of every method, then each case file of ``cases`` with each method, with numba compiling
    the kernels; the argument and return types of every kernel called from Python, by kernel name."""
    import numpy as np

    import pchute_exudyn as pc
    from pchute_exudyn.methods.sp.balance import confluence_velocity
    from pchute_exudyn.physics.lines import LineLaw
    from pchute_exudyn.results.number_text import table_text

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "warm.toml"
        base = CASE.replace("{bridles}", "".join(BRIDLE.format(name=n) for n in "abc"))
        path.write_text(base)
        every_method(pc.load_case(path))
        path.write_text(base + CLUSTER)
        every_method(pc.load_case(path), variants=False)
        path.write_text(base + TRIO)
        every_method(pc.load_case(path), variants=False)
    pc.simulate(pc.load_case(ROCKET), "sp")   # reduced canopies (methods.sp.canopy_kernels), adaptive steps, triggers
    confluence_velocity([(0.0, 0.0, 1.1)], [(0.0, 0.0, 0.0)], (0.0, 0.0, 0.0), (0.0, 0.0, 0.0),
                        [LineLaw(1.0, 1e4, 1e2)])
    table_text(["a", "b"], [np.zeros(2), np.ones(2)])
    for path in cases:
        case = pc.load_case(path)
        every_method(case, duration=None, variants=False)
    return signatures_in_use()


def every_method(case, duration: float | None = 0.05, variants: bool = True) -> None:
    """Run ``case`` with every method of the method table, each of its integrators and (``variants``) each of its
    option sets (``Method.record_variants``): at a fixed step from the stability limit and with the step the run
    chooses itself (adaptive for RK4), for ``duration`` (s) or, None, for the case's duration up to STEPS steps of
    that fixed step (full mass RK4 at its limit would take hours on a whole descent)."""
    import pchute_exudyn as pc
    from pchute_exudyn.registries.methods import METHODS
    from pchute_exudyn.run.step_control import stability_step

    for name, method_class in METHODS.items():
        for options in method_class.record_variants if variants else ({},):
            for integrator in method_class.integrators:
                step, _ = stability_step(case, method_class.configure(case, options), integrator)
                span = duration if duration is not None else min(case.simulation.duration, STEPS * step)
                for chosen in (step, None):
                    pc.simulate(case, name, integrator, chosen, span, **options)


STEPS = 2000
"""Steps of its stability step a case file runs for with each method (``every_method``)."""


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
        if not name.startswith(KERNEL_MODULES):
            continue
        for value in vars(sys.modules[name]).values():
            if isinstance(value, CPUDispatcher) and value.py_func.__module__ == name:
                kernel = f"{name}.{value.py_func.__qualname__}"
                for arguments, result in value.overloads.items():
                    entry = [[describe_type(t) for t in arguments], describe_type(result.signature.return_type)]
                    if _exportable(entry) and entry not in found.setdefault(kernel, []):
                        found[kernel].append(entry)
    return {name: entries for name, entries in found.items() if entries}


def _fits(name: str, entry) -> bool:
    """Whether a recorded signature still fits the kernel ``name`` ('package.module.function'): the kernel is still
    defined where its name says, with as many parameters (a kernel moved, gone or changed loses its old ones)."""
    module, _, function = name.rpartition(".")
    kernel = getattr(sys.modules.get(module), function, None)
    code = getattr(getattr(kernel, "py_func", kernel), "__code__", None)
    return code is not None and code.co_argcount == len(entry[0])


def _exportable(entry) -> bool:
    """Whether a signature's types can cross from Python (a kernel called by another kernel may have been compiled
    for constants, 'Literal[int](0)': that is not a call from Python)."""
    try:
        [numba_type(text) for text in [*entry[0], entry[1]]]
    except (KeyError, ValueError):
        return False
    return True


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog=f"python -m {COMMAND}", description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", metavar="CASE",
                        help="a case file to run with each method too, after the small models of every method")
    args = parser.parse_args(argv)
    if os.environ.get(VARIABLE) != "jit":
        return in_jit_process(COMMAND, argv or sys.argv[1:])
    old = json.loads(SIGNATURES.read_text()) if SIGNATURES.is_file() else {}
    new = record(args.cases)
    old = {name: [entry for entry in entries if _fits(name, entry)] for name, entries in old.items()}
    SIGNATURES.write_text(json.dumps(merged(old, new), indent=1) + "\n")
    print(f"wrote {SIGNATURES}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Compile the per-stage kernels into numba's disk cache (``_kernel_mode`` says why and when).

``python -m pchute_exudyn.kernel_cache`` compiles every kernel the methods call by running small models of each
method (two bodies, a load-elongation line, SP of either order and slack rule, equilibrium point, full mass RK4 and
implicit, a deployment) and then writes the marker that makes later processes import the kernels compiled.
``_kernel_mode.start_background_compile`` spawns that command, detached, once per machine.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from . import _kernel_mode

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


def compile_all() -> None:
    """Compile every kernel the methods call (in this process, which must import them compiled), then write the
    marker."""
    if os.environ.get(_kernel_mode.VARIABLE) != "compiled":
        raise RuntimeError(f"compile_all needs {_kernel_mode.VARIABLE}=compiled before pchute_exudyn is imported")
    import pchute_exudyn as pc
    from pchute_exudyn.physics.singular_perturbation import confluence_velocity

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "warm.toml"
        path.write_text(CASE.replace("{bridles}", "".join(BRIDLE.format(name=n) for n in "abc")))
        case = pc.load_case(path)
        for options in ({"order": 0}, {"order": 1}, {"slack_rule": "force"}):
            pc.simulate(case, "sp", "rk4", 1e-2, 0.05, **options)
        pc.simulate(case, "equilibrium", "rk4", 1e-2, 0.05)
        pc.simulate(case, "full", "rk4", 1e-4, 0.002)
        pc.simulate(case, "full", "implicit", 1e-2, 0.05)
        path.write_text(CASE.replace("{bridles}", "".join(BRIDLE.format(name=n) for n in "abc")) + CLUSTER)
        pc.simulate(pc.load_case(path), "sp", "rk4", 1e-2, 0.05)
    confluence_velocity([(0.0, 0.0, 1.1)], [(0.0, 0.0, 0.0)], (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), [1.0], [1e4],
                        [1e2])
    target = _kernel_mode.marker()
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(f"compiled {time.strftime('%Y-%m-%dT%H:%M:%S')}\n")


def main() -> int:
    if os.environ.get(_kernel_mode.VARIABLE) != "compiled":
        # this process imported the kernels' Python form (no cache yet): compile in one that imports them compiled
        return subprocess.run([sys.executable, "-m", "pchute_exudyn.kernel_cache"],
                              env={**os.environ, _kernel_mode.VARIABLE: "compiled"}).returncode
    try:
        compile_all()
    finally:
        _kernel_mode.lock().unlink(missing_ok=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The package's build step beyond pyproject.toml: compile the kernel module and the bytecode at install.

``pip install`` (editable or not) runs ``build_py``; after copying the sources it builds the compiled kernel module
(``python -m pchute_exudyn.kernels.build``, numba's ahead-of-time compiler, about 10 s) into the package's
``_compiled`` folder, so that the first run after an install is as fast as any later one, and compiles the
package's bytecode (Python does not write it where PYTHONDONTWRITEBYTECODE is set).

A failed kernel build fails the install, with the builder's last lines: pip shows a build's warnings only with
``-v``, so a warning would go unseen and every first run would pay for the build (issue 58: a scipy import on the
build's path did exactly that, unnoticed). Where no C compiler can be had, ``PCHUTE_SKIP_KERNEL_BUILD=1`` installs
without the module: runs then use the kernels' Python form and the commands build the module in the background
(``pchute_exudyn.kernels.lock``).
"""

import compileall
import os
import subprocess
import sys
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent
SKIP = "PCHUTE_SKIP_KERNEL_BUILD"
"""Set to 1 to install without building the kernel module (pchute_exudyn/environment.py names it too)."""


class BuildWithKernels(build_py):
    def run(self):
        super().run()
        package = ROOT / "pchute_exudyn" if self.editable_mode else Path(self.build_lib) / "pchute_exudyn"
        # the sources first, then whatever the build environment put on the path (pip's isolated build finds its
        # packages, numba and numpy among them, through PYTHONPATH)
        path = os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))
        environment = {**os.environ, "PCHUTE_KERNELS": "jit", "PYTHONPATH": path}
        if os.environ.get(SKIP) != "1":
            built = subprocess.run([sys.executable, "-m", "pchute_exudyn.kernels.build", "--out",
                                    str(package / "_compiled")], env=environment, cwd=ROOT, capture_output=True,
                                   text=True)
            if built.returncode != 0:
                tail = "\n".join((built.stdout + built.stderr).strip().splitlines()[-12:])
                raise SystemExit(f"pchute-exudyn: the compiled kernel module could not be built:\n{tail}\n"
                                 f"Fix the cause above, or install without it ({SKIP}=1): runs then use the "
                                 "kernels' Python form and build the module in the background.")
        compileall.compile_dir(str(package), quiet=1)


setup(cmdclass={"build_py": BuildWithKernels})

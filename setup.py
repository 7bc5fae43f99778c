"""The package's build step beyond pyproject.toml: compile the kernel module and the bytecode at install.

``pip install`` (editable or not) runs ``build_py``; after copying the sources it builds the compiled kernel module
(``python -m pchute_exudyn.kernels.build``, numba's ahead-of-time compiler, about 10 s) into the package's
``_compiled`` folder, so that the first run after an install is as fast as any later one, and compiles the
package's bytecode (Python does not write it where PYTHONDONTWRITEBYTECODE is set). A failed kernel build does not
fail the install: runs then use the kernels' Python form, and the commands build the module in the background
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


class BuildWithKernels(build_py):
    def run(self):
        super().run()
        package = ROOT / "pchute_exudyn" if self.editable_mode else Path(self.build_lib) / "pchute_exudyn"
        # the sources first, then whatever the build environment put on the path (pip's isolated build finds its
        # packages, numba and numpy among them, through PYTHONPATH)
        path = os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))
        environment = {**os.environ, "PCHUTE_KERNELS": "jit", "PYTHONPATH": path}
        built = subprocess.run([sys.executable, "-m", "pchute_exudyn.kernels.build", "--out",
                                str(package / "_compiled")], env=environment, cwd=ROOT)
        if built.returncode != 0:
            self.warn("the compiled kernel module could not be built: runs will build it in the background")
        compileall.compile_dir(str(package), quiet=1)


setup(cmdclass={"build_py": BuildWithKernels})

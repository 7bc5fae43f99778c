"""pchute-exudyn: multibody parachute descent simulation on the Exudyn engine.

Quick use::

    import pchute_exudyn as pc
    case = pc.load_case("cases/mer/case1.toml")
    result = pc.simulate(case, method="full", integrator="rk4", step=1e-4)
    result.save("out/case1")

The confluence methods are classes in one table, ``pc.METHODS`` (name -> class), filled by
:mod:`pchute_exudyn.methods`; ``simulate`` takes a name or a class.
"""

__version__ = "0.1.0"

from . import _kernel_mode  # noqa: E402

_kernel_mode.select()   # compiled or Python kernels, before physics is imported (see _kernel_mode)

from . import methods  # noqa: E402,F401  (registers the built-in methods in METHODS)
from .case import Case, load_case  # noqa: E402
from .case.method_table import METHODS  # noqa: E402
from .case.new import NewCase, new_case, new_case_text  # noqa: E402
from .errors import CaseError, InputError, PchuteError, SimulationError  # noqa: E402
from .results import Result  # noqa: E402
from .simulation import simulate  # noqa: E402

__all__ = ["METHODS", "Case", "CaseError", "InputError", "NewCase", "PchuteError", "Result", "SimulationError",
           "__version__", "load_case", "new_case", "new_case_text", "simulate"]

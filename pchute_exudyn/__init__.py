"""pchute-exudyn: multibody parachute descent simulation on the Exudyn engine.

Quick use::

    import pchute_exudyn as pc
    case = pc.load_case("cases/mer/case1.toml")
    result = pc.simulate(case, method="full", integrator="rk4", step=1e-4)
    result.save("out/case1")
"""

__version__ = "0.1.0"

from .case import Case, load_case  # noqa: E402
from .errors import CaseError, InputError, PchuteError, SimulationError  # noqa: E402
from .results import Result  # noqa: E402
from .simulation import simulate  # noqa: E402

__all__ = ["Case", "CaseError", "InputError", "PchuteError", "Result", "SimulationError", "__version__",
           "load_case", "simulate"]

"""pchute-exudyn: multibody parachute descent simulation on the Exudyn engine.

Quick use::

    import pchute_exudyn as pc
    case = pc.load_case("cases/mer/case1.toml")
    result = pc.simulate(case, method="full", integrator="rk4", step=1e-4)
    result.save("out/case1")

The confluence methods are classes in one table, ``pc.METHODS`` (name -> class), filled by
``pchute_exudyn.methods``; ``simulate`` takes a name or a class.

The names below are imported when first used (PEP 562), so that a command imports what it needs and no more
(``import pchute_exudyn.physics.atmosphere`` needs neither Exudyn nor the method table).
"""

__version__ = "0.1.0"

from importlib import import_module

from . import _interrupt, environment

if _interrupt.launched_as_command():   # Ctrl-C while the command starts: an interrupt, not a broken import
    _interrupt.install()
    environment.single_thread_blas()   # before numpy's import starts its BLAS threads

from .kernels.selection import cache_directory as _cache_directory  # noqa: E402
from .kernels.selection import select as _select_kernel_form  # noqa: E402

if not (_interrupt.launched_as_command() and _interrupt.asks_only_about_the_command()):   # pchute --help: none
    _select_kernel_form()   # compiled, jit or Python kernels, before physics is imported (see kernels.selection)

from .kernels import dataclass_code as _dataclass_code  # noqa: E402

_dataclass_code.install(_cache_directory())   # before the first of the package's dataclasses is defined

from .registries.lazy_names import lazy_names  # noqa: E402
from .registries.methods import METHODS  # noqa: E402

METHODS.fill_with(lambda: import_module(".methods", __name__).register_builtin())   # when the table is first read

_HOMES = {"Case": "case", "load_case": "boundary", "NewCase": "authoring.choices",
          "new_case": "boundary", "new_case_text": "boundary", "CaseError": "errors", "InputError": "errors",
          "PchuteError": "errors", "SimulationError": "errors", "Result": "results.result",
          "simulate": "run.simulation", "compare_results": "results.compare"}
"""Where each public name lives."""

__all__ = ["METHODS", "Case", "CaseError", "InputError", "NewCase", "PchuteError", "Result", "SimulationError",
           "__version__", "compare_results", "load_case", "new_case", "new_case_text", "simulate"]


__getattr__, __dir__ = lazy_names(__name__, _HOMES, __all__)

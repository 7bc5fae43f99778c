"""The singular-perturbation method (thesis chapter 3) as one package.

* ``method``: ``SingularPerturbation``, what the method table sees (checks, model, step limits, relaxation);
* ``options``: ``SPOptions`` and the ``PRESETS``;
* ``confluence``: ``SPConfluence``, the confluence at run time; ``reduced_canopy``: a reduced canopy at run time;
* ``builder``: ``build_sp_model``;
* ``memory``: the named memory of the compiled kernels (the only module that names a position in it);
* ``balance``, ``stepping``, ``canopy_kernels``: the compiled kernels (pure: no Exudyn, no engine).

The names below are imported when first used (PEP 562), so that the kernels' build imports the kernel modules alone.
"""

from importlib import import_module

_HOMES = {"SingularPerturbation": "method", "SPOptions": "options", "PRESETS": "options", "SPConfluence": "confluence",
          "StageSolution": "confluence", "build_sp_model": "builder"}

__all__ = sorted(_HOMES)


def __getattr__(name: str):
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(f".{home}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))

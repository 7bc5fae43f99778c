"""The singular-perturbation method (thesis chapter 3) as one package.

* ``method``: ``SingularPerturbation``, what the method table sees (checks, model, step limits, relaxation);
* ``options``: ``SPOptions`` and the ``PRESETS``;
* ``confluence``: ``SPConfluence``, the confluence at run time; ``reduced_canopy``: a reduced canopy at run time;
* ``builder``: ``build_sp_model``;
* ``memory``: the named memory of the compiled kernels (the only module that names a position in it);
* ``balance``, ``stepping``, ``canopy_kernels``: the compiled kernels (pure: no Exudyn, no engine).

The names below are imported when first used (PEP 562), so that the kernels' build imports the kernel modules alone.
"""

from ...registries.lazy_names import lazy_names

_HOMES = {"SingularPerturbation": "method", "SPOptions": "options", "PRESETS": "options", "SPConfluence": "confluence",
          "StageSolution": "confluence", "build_sp_model": "builder"}

__all__ = sorted(_HOMES)


__getattr__, __dir__ = lazy_names(__name__, _HOMES, __all__)

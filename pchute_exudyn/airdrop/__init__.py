"""The computed air release point (CARP) of an airdrop: where an aircraft must release a load for it to land on a
target (``release_point``: an inverse solve over full runs), the landing footprint of a Monte Carlo dispersion
around it (``dispersion``: a study) and the folder that records both (``release_files``).

The names below are imported when first used (PEP 562): the command line imports ``airdrop.command`` to build its
parser, and the study stack behind a dispersion (matplotlib's among it) only when a release point is solved."""

from ..registries.lazy_names import lazy_names

_HOMES = {"Dispersion": "dispersion", "Footprint": "dispersion", "release_footprint": "dispersion",
          "ReleasePoint": "release_point", "solve_release_point": "release_point"}

__all__ = sorted(_HOMES)


__getattr__, __dir__ = lazy_names(__name__, _HOMES, __all__)

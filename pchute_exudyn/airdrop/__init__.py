"""The computed air release point (CARP) of an airdrop: where an aircraft must release a load for it to land on a
target (``release_point``: an inverse solve over full runs), the landing footprint of a Monte Carlo dispersion
around it (``dispersion``: a study) and the folder that records both (``release_files``).

The names below are imported when first used (PEP 562): the command line imports ``airdrop.command`` to build its
parser, and the study stack behind a dispersion (matplotlib's among it) only when a release point is solved."""

from importlib import import_module

_HOMES = {"Dispersion": "dispersion", "Footprint": "dispersion", "release_footprint": "dispersion",
          "ReleasePoint": "release_point", "solve_release_point": "release_point"}

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

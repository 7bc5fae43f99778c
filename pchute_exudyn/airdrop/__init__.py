"""The computed air release point (CARP) of an airdrop: where an aircraft must release a load for it to land on a
target (``release_point``: an inverse solve over full runs), the landing footprint of a Monte Carlo dispersion
around it (``dispersion``: a study) and the folder that records both (``release_files``)."""

from .dispersion import Dispersion, Footprint, release_footprint
from .release_point import ReleasePoint, solve_release_point

__all__ = ["Dispersion", "Footprint", "ReleasePoint", "release_footprint", "solve_release_point"]

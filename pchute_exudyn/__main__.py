"""``python -m pchute_exudyn`` runs the command line."""

from .cli import command

command()

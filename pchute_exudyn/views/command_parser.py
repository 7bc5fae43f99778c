"""The ``pchute`` command's argument parser class: errors in one line, and each command's options added only when
that command is chosen, so that `pchute --help` and every other command skip what building them imports (``run``'s
read the method table, Exudyn behind it; ``new``'s the authoring layer). What a user sees of the command line, as
``views.progress`` is what they see of a run."""

from __future__ import annotations

import argparse

EXIT_USAGE = 2
"""The exit status of a command line argparse rejects."""


class CommandParser(argparse.ArgumentParser):
    """An argument parser whose errors are one line (no usage block); ``arguments(parser)``, if given, adds its
    options the first time it parses (for a command's parser: when the command is chosen)."""

    def __init__(self, *args, arguments=None, **kwargs):
        super().__init__(*args, **kwargs)
        self._arguments = arguments

    def parse_known_args(self, args=None, namespace=None):
        arguments, self._arguments = self._arguments, None
        if arguments is not None:
            arguments(self)
        return super().parse_known_args(args, namespace)

    def error(self, message):
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")

"""The validation scripts' command lines: errors in one line naming the script, exit status 1, before anything
runs or is written (the package's own rule for bad input)."""

from __future__ import annotations

import argparse
from pathlib import Path


class OneLineParser(argparse.ArgumentParser):
    """argparse with its errors as one line '<script>: <message>' and exit status 1 (not the usage and status 2)."""

    def __init__(self, script: str, description: str):
        super().__init__(prog=Path(script).name, description=description)

    def error(self, message):
        raise SystemExit(f"{self.prog}: {message}")

    def refuse(self, message: str):
        """Stop with one line about an argument argparse accepted but the script cannot use."""
        raise SystemExit(f"{self.prog}: {message}")

    def check_counts(self, args) -> None:
        """``--runs`` at least 1 and ``--workers`` from 1 to the machine's limit."""
        from pchute_exudyn.boundary import most_workers  # here: a script may choose the kernels before the import

        if args.runs < 1:
            self.refuse(f"--runs = {args.runs}: must be >= 1")
        if not 1 <= args.workers <= most_workers():
            self.refuse(f"--workers = {args.workers}: must be from 1 to {most_workers()}")

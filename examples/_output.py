"""Where the gallery's scripts write their pictures: the folder given as the first argument, else
examples/output/ (created)."""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def output_folder() -> Path:
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent / "output"
    folder.mkdir(parents=True, exist_ok=True)
    return folder

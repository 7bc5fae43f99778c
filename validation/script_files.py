"""Folders a validation script writes whole (a study, a fit): built beside their place and moved in only when
complete, so that a script that fails or is interrupted leaves the committed folder with every byte it had.

Single files go through the package's ``atomic_write_text`` and ``atomic_writer`` (pchute_exudyn/results/io.py)."""

from __future__ import annotations

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

from pchute_exudyn.results.journal import LOCK_NAME


@contextmanager
def staged_folder(folder, copy: bool = False):
    """A hidden folder beside ``folder`` (the same parent: the relative paths a study or fit writes into its files
    stay right) to build ``folder``'s new contents in; with ``copy`` it starts as a copy of ``folder`` (a fit resumes
    from its records). On success it replaces ``folder``, without the lock file a study or fit leaves behind; on any
    error, Ctrl-C too, it is removed and ``folder`` is untouched."""
    folder = Path(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.", suffix=".tmp"))
    try:
        os.chmod(staging, 0o777 & ~_umask())
        if copy and folder.is_dir():
            shutil.copytree(folder, staging, dirs_exist_ok=True)
        yield staging
        (staging / LOCK_NAME).unlink(missing_ok=True)
        _replace(staging, folder)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


def _replace(staging: Path, folder: Path) -> None:
    """``staging`` renamed to ``folder``; an earlier ``folder`` is moved aside first and put back if the rename
    fails."""
    if not folder.exists():
        os.replace(staging, folder)
        return
    aside = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.", suffix=".old"))
    os.replace(folder, aside / folder.name)
    try:
        os.replace(staging, folder)
    except OSError:
        os.replace(aside / folder.name, folder)
        raise
    finally:
        shutil.rmtree(aside, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask

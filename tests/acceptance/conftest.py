"""The documentation site, built once per session (`mkdocs build --strict`, about 10 s) for the tests that check the
build (test_docs_site.py) and the pages in a browser (test_docs_pages.py); once in all when pytest-xdist runs the
suite on several workers (pyproject's addopts): the first worker to ask builds it into the run's shared temporary
folder under a lock, the others read that build."""

import fcntl
import json
import os
import subprocess
import sys

import pytest

from tests.helpers import ROOT


@pytest.fixture(scope="session")
def docs_site(tmp_path_factory):
    """(the site's folder, the build's CompletedProcess): the test that needs a clean build asserts its exit code."""
    shared = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):   # each worker's base folder sits in the run's own
        shared = shared.parent
    site, outcome = shared / "docs" / "site", shared / "docs" / "build.json"
    outcome.parent.mkdir(exist_ok=True)
    with open(shared / "docs.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)   # released when the file closes: the other workers wait for the build
        if not outcome.is_file():
            run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)],
                                 cwd=ROOT, capture_output=True, text=True, timeout=300)
            outcome.write_text(json.dumps({"returncode": run.returncode, "stdout": run.stdout, "stderr": run.stderr}))
    return site, subprocess.CompletedProcess(["mkdocs", "build"], **json.loads(outcome.read_text()))

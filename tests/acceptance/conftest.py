"""The documentation site, built once per session (`mkdocs build --strict`, about 10 s) for the tests that check the
build (test_docs_site.py) and the pages in a browser (test_docs_pages.py)."""

import subprocess
import sys

import pytest

from tests.helpers import ROOT


@pytest.fixture(scope="session")
def docs_site(tmp_path_factory):
    """(the site's folder, the build's CompletedProcess): the test that needs a clean build asserts its exit code."""
    site = tmp_path_factory.mktemp("docs") / "site"
    run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)], cwd=ROOT,
                         capture_output=True, text=True, timeout=300)
    return site, run

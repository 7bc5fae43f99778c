"""The documentation site (mkdocs.yml) builds in strict mode: every page in the navigation, every link, anchor and
figure found, and the API reference rendered from the docstrings without a warning."""

import subprocess
import sys

from tests.helpers import ROOT


def test_the_documentation_site_builds_without_a_warning(tmp_path):
    site = tmp_path / "site"
    run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)], cwd=ROOT,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, f"mkdocs build --strict failed:\n{run.stdout}\n{run.stderr}"
    # the API reference is rendered from the source, and the validation figures the pages show are published
    assert "pchute_exudyn.run.simulation.simulate" in (site / "api" / "index.html").read_text()
    assert (site / "repository" / "validation" / "output" / "cluster" / "mains.png").is_file()

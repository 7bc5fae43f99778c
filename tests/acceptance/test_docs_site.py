"""The documentation site (mkdocs.yml) builds in strict mode: every page in the navigation, every link, anchor and
figure found, and the API reference rendered from the docstrings without a warning."""


def test_the_documentation_site_builds_without_a_warning(docs_site):
    site, run = docs_site
    assert run.returncode == 0, f"mkdocs build --strict failed:\n{run.stdout}\n{run.stderr}"
    # the API reference is rendered from the source, and the validation figures the pages show are published
    assert "pchute_exudyn.run.simulation.simulate" in (site / "api" / "index.html").read_text()
    assert (site / "repository" / "validation" / "output" / "cluster" / "mains.png").is_file()
    # the formula renderer is in the site itself: a local build reads offline
    assert (site / "assets" / "katex" / "katex.min.js").is_file()

"""Headless Chromium for the page tests (the map page, the documentation site).

Chromium and ChromeDriver come from the system packages (`.ci/run` installs them, which also sets
``PCHUTE_BROWSER_TESTS=required``): where they are missing the browser tests are skipped with the reason, unless that
variable asks for them, when they fail instead, so that CI cannot pass by skipping them.

The flags are the ones a closed network needs: no background networking, component updates, sync or QUIC, so that
Chromium does not spend its start on refused connections; a new empty profile each time.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

import pytest

CHROMIUM = ("/usr/bin/chromium", "/usr/bin/chromium-browser")
CHROMEDRIVER = ("/usr/bin/chromedriver",)
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync", "--hide-scrollbars")


def _first(paths) -> str | None:
    return next((p for p in paths if Path(p).is_file()), None)


def browser_or_skip():
    """The paths of Chromium and ChromeDriver, or skip (fail where ``PCHUTE_BROWSER_TESTS=required``)."""
    chromium, driver = _first(CHROMIUM), _first(CHROMEDRIVER)
    missing = [name for name, path in (("chromium", chromium), ("chromium-driver", driver)) if path is None]
    try:
        import selenium  # noqa: F401
    except ImportError:
        missing.append("selenium (the test extra)")
    if missing:
        reason = "headless browser tests need " + ", ".join(missing) + " (Debian: apt-get install chromium chromium-driver)"
        if os.environ.get("PCHUTE_BROWSER_TESTS") == "required":
            pytest.fail(reason)
        pytest.skip(reason)
    return chromium, driver


@contextmanager
def chromium_page(width: int = 1400, height: int = 900):
    """A headless Chromium window ``width`` x ``height`` px, driven by Selenium; closed and its profile removed after."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    chromium, driver = browser_or_skip()
    profile = tempfile.mkdtemp(prefix="pchute-chromium-")
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for flag in FLAGS:
        options.add_argument(flag)
    options.add_argument(f"--window-size={width},{height}")
    options.add_argument(f"--user-data-dir={profile}")
    browser = webdriver.Chrome(service=Service(driver), options=options)
    try:
        yield browser
    finally:
        browser.quit()
        shutil.rmtree(profile, ignore_errors=True)


def screenshot_is_blank(png: bytes) -> bool:
    """True when a screenshot is one colour (a page that drew nothing)."""
    import io

    import matplotlib.image as mpimg

    pixels = mpimg.imread(io.BytesIO(png), format="png")
    return float(pixels[..., :3].std()) < 1e-3

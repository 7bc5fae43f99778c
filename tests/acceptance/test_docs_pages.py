"""The documentation site reads well in a browser: headless Chromium at 1400 px opens the built pages over file:// (the
site is self-contained: KaTeX is vendored, nothing is fetched) and measures what a reader sees. The text column is
wide; a table fits its column or scrolls in a wrapper that shows it does; no key name in a table breaks over two
lines; every formula is typeset (no TeX source left in the text) and the formula pages have some; the page draws."""

import pytest

from tests.browser import chromium_page, screenshot_is_blank

WINDOW = 1400       # px, a laptop's browser window
MIN_COLUMN = 900    # px of text column at that window (Material's default grid gave 690)
PAGES = ["index", "tutorial", "case-format", "models/gravity", "validation", "validation/flown_loads",
         "validation/rescue_drops", "validation/flight_logs", "validation/log_fit"]
FORMULA_PAGES = {"tutorial", "case-format", "models/gravity", "validation", "validation/flown_loads",
                 "validation/rescue_drops"}

# what the page shows, measured in it: one object per page
MEASURE = r"""
const column = document.querySelector("article.md-content__inner");
const wide = [], unmarked = [], broken = [], tex = [];
for (const table of column.querySelectorAll("table")) {
  const wrap = table.closest(".md-typeset__scrollwrap");
  const box = (wrap || column).getBoundingClientRect(), edge = table.getBoundingClientRect();
  if (edge.right <= box.right + 1) continue;                  // fits
  const style = wrap && getComputedStyle(wrap);
  const scrolls = wrap && wrap.scrollWidth > wrap.clientWidth && ["auto", "scroll"].includes(style.overflowX);
  const shown = scrolls && style.backgroundImage.includes("radial-gradient");   // the scroll shadow
  (shown ? wide : unmarked).push(table.rows[0].innerText.slice(0, 60));
}
for (const code of column.querySelectorAll("table code, p > code, li > code")) {
  if (!code.textContent.includes(" ") && code.getClientRects().length !== 1) broken.push(code.textContent);
}
const walker = document.createTreeWalker(column, NodeFilter.SHOW_TEXT);
const source = /\\(frac|sqrt|sin|cos|left|right|mathrm|text|cdot|times|Delta|omega)\b|\$\$|\\\(|\\\[/;
for (let node = walker.nextNode(); node; node = walker.nextNode()) {
  if (!node.parentElement.closest("pre, code, script, style, .katex-mathml") && source.test(node.data))
    tex.push(node.data.trim().slice(0, 80));
}
return {column: column.getBoundingClientRect().width, wide, unmarked, broken, tex,
        math: column.querySelectorAll(".arithmatex .katex").length,
        pending: column.querySelectorAll(".arithmatex:not(:has(.katex))").length,
        errors: column.querySelectorAll(".katex-error").length,
        tables: column.querySelectorAll("table").length,
        wrapped: column.querySelectorAll(".md-typeset__scrollwrap table").length};
"""


@pytest.fixture(scope="module")
def pages(docs_site):
    """What each page shows at 1400 px, and whether its screenshot is blank: one browser for all of them."""
    site, run = docs_site
    assert run.returncode == 0, run.stderr
    from selenium.webdriver.support.ui import WebDriverWait

    seen = {}
    with chromium_page(WINDOW, 900) as browser:
        for page in PAGES:
            browser.get((site / page / "index.html" if page != "index" else site / "index.html").as_uri())
            # Material wraps the tables and KaTeX typesets the formulas once the scripts have run
            WebDriverWait(browser, 10).until(lambda b: b.execute_script(
                "return document.querySelectorAll('article .arithmatex:not(:has(.katex))').length === 0 && "
                "document.querySelectorAll('article table').length === "
                "document.querySelectorAll('article .md-typeset__scrollwrap table').length"))
            seen[page] = browser.execute_script(MEASURE)
            seen[page]["blank"] = screenshot_is_blank(browser.get_screenshot_as_png())
    return seen


@pytest.mark.parametrize("page", PAGES)
def test_a_page_reads_well_at_1400_px(pages, page):
    shown = pages[page]
    assert shown["column"] >= MIN_COLUMN, shown["column"]
    assert shown["unmarked"] == [], "tables wider than their column that do not scroll visibly"
    assert shown["broken"] == [], "key names broken over two lines"
    assert shown["tex"] == [] and shown["errors"] == 0, "TeX left unrendered"
    assert (shown["math"] > 0) == (page in FORMULA_PAGES), shown["math"]
    assert not shown["blank"]

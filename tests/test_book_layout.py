"""The built book fits its column at 1280 x 900 and at 768 x 1000 in headless Chromium.

Nothing but a code block may scroll sideways: display maths, tables, cell outputs (printed
results and error messages), figures and widget areas must fit the text column, and a
widget readout takes at most two lines. A failure names the page, the width and the
element. Screenshots of the elements a review found clipped (six equations, two tables,
the log-axis figure of the recursive filter and the lab's error messages) go to
test-artifacts/layout/ for a person to look at.

Uses the Chromium and local-server fixtures of test_book_browser (same rules: Debian's
/usr/bin/chromium, no other host reachable; skipped without it unless
DSTOOLKIT_REQUIRE_BROWSER=1).
"""

from __future__ import annotations

import pytest
from conftest import ARTIFACTS
from test_book_browser import _MATHJAX_READY_JS, _WIDGETS_RENDERED_JS, TIMEOUT_MS, site  # noqa: F401

pytestmark = [pytest.mark.browser, pytest.mark.slow]

VIEWPORTS = {"1280": (1280, 900), "768": (768, 1000)}
SHOTS = ARTIFACTS / "layout"

#: Elements that must fit the column (everything a reader sees except code blocks).
_CHECKED = ", ".join(
    [
        'mjx-container[display="true"]',
        "table",
        "div.pst-scrollable-table-container",
        "div.cell_output",
        "div.cell_output div.output",
        "div.cell_output pre",
        "div.dstoolkit-explorer",
        "div.dstoolkit-control",
        "figure",
        "img",
        "div.admonition",
        "p",
    ]
)

_OVERFLOW_JS = """
(selector) => {
  const column = document.querySelector('article.bd-article') || document.querySelector('main');
  const right = column.getBoundingClientRect().right;
  // code blocks: cell inputs and code fences; a cell's printed output is not code
  const isCode = el => el.closest('div.cell_input, script, style')
    || (el.closest('div.highlight') && !el.closest('div.cell_output'));
  const describe = el => {
    const id = el.id || (el.closest('[id]') ? el.closest('[id]').id : '');
    const cls = (el.getAttribute('class') || '').split(/\\s+/).slice(0, 3).join('.');
    const text = (el.innerText || el.getAttribute('alt') || '').replace(/\\s+/g, ' ').trim();
    const short = Array.from(text).slice(0, 60).join('');
    return `<${el.tagName.toLowerCase()}${cls ? '.' + cls : ''}> near #${id}: "${short}"`;
  };
  const found = [];
  const seen = new Set();
  for (const el of column.querySelectorAll(selector)) {
    if (isCode(el)) continue;
    const box = el.getBoundingClientRect();
    if (box.width === 0 || box.height === 0) continue;  // hidden (a folded dropdown)
    let why = null;
    if (el.scrollWidth > el.clientWidth + 1 && getComputedStyle(el).display !== 'inline') {
      why = `scrolls sideways: scrollWidth ${el.scrollWidth} > clientWidth ${el.clientWidth}`;
    } else if (box.right > right + 1) {
      why = `sticks out of the column by ${Math.round(box.right - right)} px`;
    }
    if (why) {
      // report the outermost offender only
      let parentFlagged = false;
      for (const other of seen) { if (other.contains(el)) { parentFlagged = true; break; } }
      if (!parentFlagged) { seen.add(el); found.push(`${describe(el)} ${why}`); }
    }
  }
  const doc = document.scrollingElement;
  if (doc.scrollWidth > doc.clientWidth + 1) {
    found.push(`the page scrolls sideways: ${doc.scrollWidth} > ${doc.clientWidth}`);
  }
  return found;
}
"""

#: Explorer readouts (one header row, one value row) taller than two lines of text.
_READOUT_JS = """
() => Array.from(document.querySelectorAll('.widget-html-content table'))
  .filter(t => t.querySelector('th'))
  .map(t => {
    const line = parseFloat(getComputedStyle(t.querySelector('td') || t).lineHeight) || 20;
    const text = Array.from(t.innerText.replace(/\\s+/g, ' ')).slice(0, 80).join('');
    return {height: t.getBoundingClientRect().height, line, text};
  })
  .filter(r => r.height > 2.5 * r.line)
"""

#: (page, element id or CSS selector, file name) of the screenshots kept for review.
SCREENSHOTS = [
    ("book/why_bounded_noise", "#equation-wb-kalman", "eq-kalman-update"),
    ("book/dependent_evidence", "#equation-de-enf", "eq-enf"),
    ("book/random_sets", "#equation-rs-product", "eq-product"),
    ("book/random_sets", "#equation-rs-image", "eq-image"),
    ("book/random_sets", "#equation-rs-monotone", "eq-monotone"),
    ("book/level_gauge", "#equation-lg-beat-phase", "eq-beat-phase"),
    (
        "book/estimating_level",
        "div.cell_output table:has-text('particle') >> nth=0",
        "table-true-orders",
    ),
    ("book/notation", "table >> nth=0", "table-notation"),
    ("book/recursive_filter", "#rf-fig-start", "fig-log-axis"),
    ("book/lab", "div.cell_output:has-text('DetectionError') >> nth=0", "lab-error-1"),
    ("book/lab", "div.cell_output:has-text('DetectionError') >> nth=1", "lab-error-2"),
]


def _open(
    chromium: object,
    site: str,  # noqa: F811
    page_name: str,
    width: int,
    height: int,
) -> object:
    context = chromium.new_context(viewport={"width": width, "height": height})
    page = context.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    page.route(
        "**/*",
        lambda route: route.continue_() if "127.0.0.1" in route.request.url else route.abort(),
    )
    page.goto(site + page_name + ".html", wait_until="load")
    page.evaluate(_MATHJAX_READY_JS)
    if page.locator(".dstoolkit-explorer").count():
        page.wait_for_function(_WIDGETS_RENDERED_JS, timeout=TIMEOUT_MS)
    page.wait_for_load_state("networkidle")
    return page


@pytest.mark.parametrize("viewport", list(VIEWPORTS))
def test_page_fits_its_column(
    chromium: object,
    site: str,  # noqa: F811
    toc_page: str,
    viewport: str,
) -> None:
    width, height = VIEWPORTS[viewport]
    page = _open(chromium, site, toc_page, width, height)
    try:
        overflow = page.evaluate(_OVERFLOW_JS, _CHECKED)
        assert not overflow, f"{toc_page} at {width} px: wider than the column:\n  " + "\n  ".join(
            overflow
        )
    finally:
        page.context.close()


@pytest.mark.parametrize("viewport", list(VIEWPORTS))
def test_widget_readouts_take_two_lines(
    chromium: object,
    site: str,  # noqa: F811
    toc_page: str,
    viewport: str,
) -> None:
    width, height = VIEWPORTS[viewport]
    page = _open(chromium, site, toc_page, width, height)
    try:
        tall = page.evaluate(_READOUT_JS)
        assert not tall, f"{toc_page} at {width} px: widget readouts over two lines: {tall}"
    finally:
        page.context.close()


@pytest.mark.parametrize("viewport", list(VIEWPORTS))
def test_screenshots_of_the_elements_once_found_clipped(
    chromium: object,
    site: str,  # noqa: F811
    viewport: str,
) -> None:
    width, height = VIEWPORTS[viewport]
    SHOTS.mkdir(parents=True, exist_ok=True)
    missing = []
    for page_name, selector, name in SCREENSHOTS:
        page = _open(chromium, site, page_name, width, height)
        try:
            element = page.locator(selector).first
            if not element.count():
                missing.append(f"{page_name}: {selector}")
                continue
            element.scroll_into_view_if_needed()
            element.screenshot(path=str(SHOTS / f"{name}-{viewport}.png"))
        finally:
            page.context.close()
    assert not missing, f"elements to photograph not found: {missing}"

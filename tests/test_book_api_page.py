"""The API reference on a phone and by keyboard (browser, the built site).

The reference holds some 250 examples from the docstrings. They wrap their long lines
(book/_static/dstoolkit.css) instead of each scrolling in its own box: a box that scrolls
takes a Tab stop (scroll-boxes.js), and a keyboard user would otherwise press Tab past
hundreds of them to reach the next link. At 320 and 1280 CSS px no example scrolls, the
page does not scroll sideways, and the boxes that do scroll (other code) have names of
their own.
"""

from __future__ import annotations

import pytest
from test_book_browser import TIMEOUT_MS, site

pytestmark = [pytest.mark.browser, pytest.mark.slow]
__all__ = ["site"]  # fixture used by the tests below

_EXAMPLES_JS = """() => {
  const examples = Array.from(document.querySelectorAll('.bd-article div.doctest'));
  const scrolling = examples.filter(box => Array.from(box.querySelectorAll('*'))
      .concat([box]).some(el => el.scrollWidth > el.clientWidth + 1
        && ['auto', 'scroll'].includes(getComputedStyle(el).overflowX)));
  const stops = Array.from(document.querySelectorAll(
      '.bd-article [tabindex="0"][role="region"]')).map(el => el.getAttribute('aria-label'));
  return {examples: examples.length, scrolling: scrolling.length, stops: stops,
          page: document.documentElement.scrollWidth, view: window.innerWidth};
}"""


@pytest.mark.parametrize("width", [320, 1280])
def test_api_examples_wrap_and_take_no_tab_stop(chromium: object, site: str, width: int) -> None:
    context = chromium.new_context(viewport={"width": width, "height": 900})
    try:
        page = context.new_page()
        page.goto(site + "book/api.html", timeout=TIMEOUT_MS)
        # scroll-boxes.js looks 150 ms after the first paint, and again on load
        page.wait_for_load_state("load")
        page.wait_for_timeout(800)
        report = page.evaluate(_EXAMPLES_JS)
    finally:
        context.close()
    # the reference's examples are there (a renamed class would make this test vacuous)
    assert report["examples"] >= 100, report["examples"]
    assert report["scrolling"] == 0, f"{report['scrolling']} examples scroll at {width} px"
    assert report["page"] <= report["view"], f"the API page scrolls sideways at {width} px"
    # what still scrolls is a handful of other code boxes, each named apart
    assert len(report["stops"]) <= 5, report["stops"]
    assert len(set(report["stops"])) == len(report["stops"]), report["stops"]


_SIDEBAR_JS = """() => {
  // every entry of the page's contents sidebar, and whether a word of it breaks across
  // lines; a name may break after "_" or ".", or before the capital of a CamelCase word
  // (between its words), nowhere else
  const links = Array.from(document.querySelectorAll('#pst-page-toc-nav a.nav-link'));
  const broken = [];
  for (const link of links) {
    const words = link.textContent.trim()
      .split(/\\s+|(?<=[_.])|(?<=[a-z])(?=[A-Z])/).filter(w => w);
    const range = document.createRange();
    for (const word of words) {
      const node = Array.from(link.querySelectorAll('*')).concat([link])
        .flatMap(el => Array.from(el.childNodes))
        .find(n => n.nodeType === 3 && n.textContent.includes(word));
      if (!node) continue;
      const start = node.textContent.indexOf(word);
      range.setStart(node, start);
      range.setEnd(node, start + word.length);
      const tops = new Set(Array.from(range.getClientRects()).map(r => Math.round(r.top)));
      if (tops.size > 1) broken.push(link.textContent.trim());
    }
  }
  return {entries: links.length, broken: broken};
}"""


def test_api_contents_sidebar_breaks_no_name(chromium: object, site: str) -> None:
    """The contents sidebar (1280 px) breaks a long name only between its words.

    Fails on a long qualified name ("MassFunction.commonality()" broke after "commonal").
    """
    context = chromium.new_context(viewport={"width": 1280, "height": 900})
    try:
        page = context.new_page()
        page.goto(site + "book/api.html#dstoolkit.evidence.MassFunction", timeout=TIMEOUT_MS)
        page.wait_for_load_state("load")
        # the theme unfolds only the entries of the section in view; unfold them all (the
        # sidebar's width does not change) so that every class's methods are measured
        page.add_style_tag(content="#pst-page-toc-nav ul { display: block !important; }")
        report = page.evaluate(_SIDEBAR_JS)
    finally:
        context.close()
    # the sidebar lists the reference's classes and methods (else this test is vacuous)
    assert report["entries"] >= 100, report["entries"]
    assert report["broken"] == [], report["broken"][:10]

"""The built book in headless Chromium, served from 127.0.0.1 with no other host reachable.

Every page of _toc.yml must load, have its maths typeset (at build time), show every
image and every embedded widget, log no console error and make no request that fails or
leaves 127.0.0.1. Screenshots of three chapters go to test-artifacts/.

Needs Debian's chromium at /usr/bin/chromium (Playwright drives it; no `playwright install`).
Without it the tests skip, except when DSTOOLKIT_REQUIRE_BROWSER=1 (CI), where they fail.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from urllib.parse import urlsplit

import pytest
from conftest import ARTIFACTS, BookBuild, served

pytestmark = [pytest.mark.browser, pytest.mark.slow]

#: Chapters whose full-page screenshots are saved in test-artifacts/.
SCREENSHOT_PAGES = ("book/intro", "book/mass_functions", "book/dependent_evidence")
LOCAL_SCHEMES = ("data:", "blob:", "about:")
TIMEOUT_MS = 30_000


@pytest.fixture(scope="module")
def site(chromium: object, built_book: BookBuild) -> Iterator[str]:
    """Serve _build/html by a local http.server thread on 127.0.0.1; yield its base URL.

    A build that only warned (--keep-going still writes every page) is checked anyway, so
    that one run reports both; test_book_build fails on the warnings themselves.
    """
    if not (built_book.html_dir / "index.html").is_file():
        pytest.fail(f"the book was not built, see test_book_build:\n{built_book.tail(20)}")
    with served(built_book.html_dir) as base:
        yield base


@dataclass
class _PageProblems:
    console_errors: list[str] = field(default_factory=list)
    failed_requests: list[str] = field(default_factory=list)
    external_requests: list[str] = field(default_factory=list)


# Visible text that MathJax should have replaced, outside code and MathJax's own output.
_RAW_MATH_JS = """
() => {
  const skip = 'pre, code, script, style, textarea, mjx-container, .highlight';
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  const found = [];
  for (let node = walker.nextNode(); node; node = walker.nextNode()) {
    const parent = node.parentElement;
    if (!parent || parent.closest(skip)) continue;
    const text = node.textContent;
    for (const token of ['\\\\(', '\\\\[', '$$']) {
      if (text.includes(token)) found.push(text.trim().slice(0, 80));
    }
  }
  return found;
}
"""

# The maths is typeset when the book is built (scripts/typeset-maths.js, the page is marked)
# or, on a page without the mark, by MathJax in the browser.
_MATHJAX_READY_JS = """
async () => {
  const mathNodes = document.querySelectorAll('.math').length;
  const built = document.querySelector('meta[name="dstoolkit-maths"]') !== null;
  if (!built) {
    if (!window.MathJax || !window.MathJax.startup || !window.MathJax.startup.promise) {
      return {mathNodes, loaded: false};
    }
    await window.MathJax.startup.promise;
  }
  return {
    mathNodes,
    loaded: true,
    typeset: document.querySelectorAll('.math mjx-container').length,
    errors: Array.from(document.querySelectorAll('mjx-merror, g[data-mml-node="merror"]'))
      .map(e => e.getAttribute('data-mjx-error') || e.textContent),
  };
}
"""

# scripts/site_postbuild.py writes every widget view as plain HTML (div.dstoolkit-explorer)
# and leaves no widget view or widget state in the page; explorers.js (deferred) wires the
# controls and adds the skip link once it has run.
_WIDGETS_RENDERED_JS = """
() => {
  const views = document.querySelectorAll(
    'script[type="application/vnd.jupyter.widget-view+json"],'
    + ' script[type="application/vnd.jupyter.widget-state+json"]');
  const explorers = Array.from(document.querySelectorAll('.dstoolkit-explorer'));
  return views.length === 0 && explorers.every(e => e.firstElementChild !== null)
    && (explorers.length === 0 || document.querySelector('.dstoolkit-skip') !== null);
}
"""

_WIDGET_REPORT_JS = """
() => Array.from(document.querySelectorAll(
  'script[type="application/vnd.jupyter.widget-view+json"], .dstoolkit-explorer'
)).map((area, id) => {
  if (area.tagName === 'SCRIPT') return {id, rendered: false, visible: false};
  const box = area.getBoundingClientRect();
  const style = getComputedStyle(area);
  return {
    id, rendered: area.firstElementChild !== null,
    visible: box.width > 0 && box.height > 0 && style.visibility !== 'hidden'
      && style.display !== 'none',
  };
})
"""

_IMAGES_JS = """
async () => {
  const images = Array.from(document.images);
  images.forEach(img => { img.loading = 'eager'; });  // the lazy ones load now
  // the pictures of the explorers' states not shown (fetched when shown) load now too
  images.filter(img => img.dataset.src && !img.getAttribute('src'))
    .forEach(img => { img.src = img.dataset.src; });
  await Promise.all(images.map(img => img.complete ? null : new Promise(resolve => {
    img.addEventListener('load', resolve); img.addEventListener('error', resolve);
  })));
  return images.filter(img => !(img.complete && img.naturalWidth > 0))
    .map(img => img.currentSrc || img.src || img.outerHTML.slice(0, 120));
}
"""


def _is_local(url: str) -> bool:
    return url.startswith(LOCAL_SCHEMES) or urlsplit(url).hostname == "127.0.0.1"


def _watch(context: object, page: object) -> _PageProblems:
    """Record console errors, failed requests, and block (and record) any other host."""
    problems = _PageProblems()

    def handle_route(route: object) -> None:
        if _is_local(route.request.url):
            route.continue_()
        else:
            problems.external_requests.append(route.request.url)
            route.abort()

    def on_console(message: object) -> None:
        if message.type == "error":
            problems.console_errors.append(message.text)

    def on_request_failed(request: object) -> None:
        if _is_local(request.url):  # blocked external requests are reported separately
            problems.failed_requests.append(f"{request.url} ({request.failure})")

    def on_response(response: object) -> None:
        if response.status >= 400:
            problems.failed_requests.append(f"{response.url} (HTTP {response.status})")

    context.route("**/*", handle_route)
    page.on("console", on_console)
    page.on("pageerror", lambda error: problems.console_errors.append(f"uncaught: {error}"))
    page.on("requestfailed", on_request_failed)
    page.on("response", on_response)
    return problems


def test_page_in_browser(chromium: object, site: str, toc_page: str) -> None:
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    context = chromium.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    problems = _watch(context, page)
    try:
        response = page.goto(site + toc_page + ".html", wait_until="load")
        assert response is not None and response.status == 200, (
            f"{toc_page}.html answered {response and response.status}"
        )

        maths = page.evaluate(_MATHJAX_READY_JS)
        if maths["mathNodes"]:
            assert maths["loaded"], f"{toc_page}: {maths['mathNodes']} formulas, no MathJax"
            assert maths["typeset"] >= maths["mathNodes"], f"{toc_page}: maths untypeset {maths}"
            assert not maths["errors"], f"{toc_page}: TeX errors {maths['errors']}"
        raw = page.evaluate(_RAW_MATH_JS)
        assert not raw, f"{toc_page}: raw TeX left in the page: {raw[:5]}"

        if page.locator('.dstoolkit-explorer, script[type*="jupyter.widget"]').count():
            try:
                page.wait_for_function(_WIDGETS_RENDERED_JS, timeout=TIMEOUT_MS)
            except PlaywrightTimeout:
                pass  # the report below says which widget is missing
            report = page.evaluate(_WIDGET_REPORT_JS)
            bad = [w for w in report if not (w["rendered"] and w["visible"])]
            assert not bad, f"{toc_page}: widgets not shown: {bad}"

        page.evaluate("window.scrollTo(0, document.body.scrollHeight)")
        broken = page.evaluate(_IMAGES_JS)
        assert not broken, f"{toc_page}: images that did not load: {broken}"

        page.wait_for_load_state("networkidle")
        if toc_page in SCREENSHOT_PAGES:
            ARTIFACTS.mkdir(exist_ok=True)
            page.evaluate("window.scrollTo(0, 0)")
            name = toc_page.replace("/", "-") + ".png"
            page.screenshot(path=str(ARTIFACTS / name), full_page=True)

        assert not problems.external_requests, (
            f"{toc_page}: requests leaving 127.0.0.1: {problems.external_requests}"
        )
        assert not problems.failed_requests, f"{toc_page}: failed {problems.failed_requests}"
        assert not problems.console_errors, f"{toc_page}: console {problems.console_errors}"
    finally:
        context.close()


#: A chapter with folded solutions (every chapter's exercises have them).
SOLUTION_PAGE = "book/recursive_filter"

_FOLDED_JS = """() => {
  const solution = document.querySelector('.bd-article .solution.toggle');
  const body = [...solution.children].filter(e => !e.matches('.admonition-title'));
  const inside = body.flatMap(e => [e, ...e.querySelectorAll('*')]);
  return {
    folded: solution.classList.contains('toggle-hidden'),
    expanded: solution.querySelector('button.toggle-button').getAttribute('aria-expanded'),
    elements: inside.length,
    laidOut: inside.filter(e => e.getClientRects().length > 0).length,
    height: solution.getBoundingClientRect().height,
    text: body.map(e => e.innerText).join(' ').trim().length,
  };
}"""


def test_a_folded_solution_is_out_of_the_layout_and_unfolds(chromium: object, site: str) -> None:
    """A folded solution lays out none of its body (dstoolkit.css) and shows it when unfolded.

    sphinx-togglebutton folds a solution with zero height and ``visibility: hidden``, which
    still lays out every element of it on each load; the book's stylesheet takes the folded
    body out of the layout. The button still unfolds it, and folds it again.
    """
    context = chromium.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    try:
        page.goto(site + SOLUTION_PAGE + ".html", wait_until="load")
        folded = page.evaluate(_FOLDED_JS)
        assert folded["folded"] and folded["expanded"] == "false", folded
        assert folded["elements"] > 0, f"{SOLUTION_PAGE}: an empty solution? {folded}"
        assert folded["laidOut"] == 0, f"{SOLUTION_PAGE}: a folded solution is laid out {folded}"
        button = page.locator(".bd-article .solution.toggle button.toggle-button").first
        button.click()
        page.wait_for_function(
            "() => !document.querySelector('.bd-article .solution.toggle')"
            ".classList.contains('toggle-hidden')"
        )
        shown = page.evaluate(_FOLDED_JS)
        assert shown["expanded"] == "true", shown
        assert shown["laidOut"] > 0 and shown["text"] > 20, f"nothing shown unfolded: {shown}"
        assert shown["height"] > folded["height"] + 20, (folded, shown)
        button.click()
        page.wait_for_function(
            "() => document.querySelector('.bd-article .solution.toggle')"
            ".classList.contains('toggle-hidden')"
        )
        again = page.evaluate(_FOLDED_JS)
        assert again["laidOut"] == 0 and again["expanded"] == "false", again
    finally:
        context.close()


#: A chapter with formulas of every kind: fractions, scripts, matrices, text.
MATHS_PAGE = "book/random_sets"
#: The accessibility roles of MathML elements in Chromium's tree (the tags they come from).
_MATHML_ROLES = {
    "math": "MathMLMath",
    "mi": "MathMLIdentifier",
    "mn": "MathMLNumber",
    "mo": "MathMLOperator",
    "msub": "MathMLSub",
    "msup": "MathMLSup",
    "msubsup": "MathMLSubSup",
    "mfrac": "MathMLFraction",
    "mtable": "MathMLTable",
}
#: The roles of MathML's token elements (mi, mn, mo, mtext, ms), the ones that hold text.
_MATHML_TOKENS = {
    "MathMLIdentifier",
    "MathMLNumber",
    "MathMLOperator",
    "MathMLText",
    "MathMLStringLiteral",
}
_MATHML_TAGS_JS = """(tags) => {
  const count = {};
  for (const tag of tags) {
    // not those of a folded solution, which is out of the page and of its tree until opened
    count[tag] = [...document.querySelectorAll(`mjx-assistive-mml ${tag}`)]
      .filter((element) => element.checkVisibility()).length;
  }
  return count;
}"""


def test_the_maths_reads_as_mathml(chromium: object, site: str) -> None:
    """A screen reader finds every formula's MathML, element by element, and no blank words.

    The MathML beside each drawn formula is laid out as plain inline text, since nobody sees
    it (scripts/typeset-maths.js); its accessibility tree must still be MathML's: one node
    with the element's role for each element, and no text node made of the indentation
    between elements.
    """
    context = chromium.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    try:
        page.goto(site + MATHS_PAGE + ".html", wait_until="load")
        elements = page.evaluate(_MATHML_TAGS_JS, list(_MATHML_ROLES))
        cdp = context.new_cdp_session(page)
        nodes = [n for n in cdp.send("Accessibility.getFullAXTree")["nodes"] if not n["ignored"]]
        roles = Counter(n.get("role", {}).get("value") for n in nodes)
        assert elements["math"] > 50 and elements["mfrac"] > 0, f"{MATHS_PAGE}: {elements}"
        for tag, role in _MATHML_ROLES.items():
            assert roles[role] == elements[tag], (
                f"{MATHS_PAGE}: {elements[tag]} <{tag}> elements but {roles[role]} {role} nodes"
            )
        by_id = {n["nodeId"]: n for n in nodes}
        blank = []
        for node in nodes:
            if node.get("role", {}).get("value") != "StaticText":
                continue
            if node.get("name", {}).get("value", "x").strip():
                continue
            parent = by_id.get(node.get("parentId"))
            role = parent.get("role", {}).get("value", "") if parent else ""
            # a token may hold a space of TeX's own (an mtext of "\ "); a layout element
            # (math, mrow, msub, ...) holds only elements
            if role.startswith("MathML") and role not in _MATHML_TOKENS:
                blank.append(role)
        assert not blank, f"{MATHS_PAGE}: blank text read inside formulas: {Counter(blank)}"
    finally:
        context.close()

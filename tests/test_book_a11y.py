"""The built book against WCAG 2.1 AA in headless Chromium, on every page of _toc.yml.

* axe-core (installed from npm into node_modules, injected into the page from there: no CDN)
  with the rule sets wcag2a, wcag2aa, wcag21a and wcag21aa, in light and in dark mode, with
  the explorers rendered and the maths typeset: no violation. Each result is saved in
  test-artifacts/axe/.
* every slider is named by its label and its ``aria-valuetext`` is the value it shows (with
  the unit of its label); a disabled slider is out of the Tab order, exposed as disabled and
  described by the note that says where it works; every explorer has a polite live region;
* every image has a written ``alt`` (not a file name), the explorer figures included;
* at 320 CSS px no page scrolls sideways;
* every page's first load (everything fetched until ``load``), gzipped, stays within the
  budget: 1.5 MB, and 1 MB for a page without an explorer;
* on one explorer page the first slider is reached in fewer than 15 Tab presses from the
  top of the article with the skip link, and without it the Tab order is the text's links
  and controls in order, nothing else (no formula);
* at 320 CSS px every box that scrolls sideways (code, tables, outputs, formulas) takes the
  keyboard focus and has a name (axe's scrollable-region-focusable).

The browser is conftest's ``chromium`` fixture and the site is test_book_browser's ``site``
(the book built by scripts/build-book.sh, served on 127.0.0.1). Without Chromium the tests
skip, except under DSTOOLKIT_REQUIRE_BROWSER=1 (CI), where they fail.
"""

from __future__ import annotations

import importlib.util
import json
import re
import sys

import pytest
from conftest import ARTIFACTS, ROOT, browser_unavailable, toc_pages
from test_book_browser import _WIDGETS_RENDERED_JS, TIMEOUT_MS, site

pytestmark = [pytest.mark.browser, pytest.mark.slow]
__all__ = ["site"]  # fixture used by the tests below

AXE = ROOT / "node_modules" / "axe-core" / "axe.min.js"
AXE_TAGS = ["wcag2a", "wcag2aa", "wcag21a", "wcag21aa"]
AXE_RESULTS = ARTIFACTS / "axe"
#: First-load budgets, gzipped bytes.
BUDGET = 1_500_000
BUDGET_NO_EXPLORER = 1_000_000
#: The page whose Tab order is checked, and the most presses its first slider may take.
TAB_PAGE = "book/mass_functions"
TAB_PRESSES = 15

_EXPLORER = ".dstoolkit-explorer"


def _open(
    chromium: object, site: str, toc_page: str, *, dark: bool = False, width: int = 1280
) -> tuple[object, object]:
    """Open a new context and page showing ``toc_page``, its maths typeset, its widgets rendered.

    The page is in dark mode if ``dark``.
    """
    context = chromium.new_context(
        viewport={"width": width, "height": 900}, color_scheme="dark" if dark else "light"
    )
    mode = "dark" if dark else "light"
    context.add_init_script(
        f"try {{ localStorage.setItem('mode', '{mode}'); localStorage.setItem('theme', "
        f"'{mode}'); }} catch (e) {{}}"
    )
    page = context.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    page.goto(site + toc_page + ".html", wait_until="load")
    _settle(page)
    if dark:
        assert page.evaluate("document.documentElement.dataset.theme") == "dark"
    return context, page


def _settle(page: object) -> None:
    """Wait for MathJax and for every embedded widget to be drawn."""
    page.evaluate("""async () => {
      if (window.MathJax && MathJax.startup && MathJax.startup.promise)
        await MathJax.startup.promise;
    }""")
    if page.locator(_EXPLORER).count():
        page.wait_for_function(_WIDGETS_RENDERED_JS, timeout=TIMEOUT_MS)
    page.wait_for_timeout(300)


def _axe(page: object, *, rules: list[str] | None = None) -> list[dict]:
    """Axe's violations on ``page``: of the rule sets AXE_TAGS, or of ``rules`` only."""
    if not AXE.is_file():
        browser_unavailable(f"{AXE} missing: run `npm ci` (scripts/build-book.sh does)")
    if not page.evaluate("typeof window.axe !== 'undefined'"):
        page.add_script_tag(path=str(AXE))
    run_only = {"type": "rule", "values": rules} if rules else {"type": "tag", "values": AXE_TAGS}
    return page.evaluate(
        """async (runOnly) => {
          const result = await axe.run(document, {runOnly, resultTypes: ['violations']});
          return result.violations.map(v => ({
            id: v.id, impact: v.impact, help: v.help,
            nodes: v.nodes.map(n => ({target: n.target.join(' '),
                                      summary: n.failureSummary,
                                      html: n.html.slice(0, 200)}))}));
        }""",
        run_only,
    )


#: What one visit of a page found, by (page, mode): each page is opened once per colour
#: mode, and every check of this module reads what that visit recorded.
_REPORTS: dict[tuple[str, str], dict] = {}

_LIVE_JS = """() => Array.from(document.querySelectorAll('.dstoolkit-explorer')).map(area =>
    area.querySelector('.dstoolkit-slider') === null
    || area.querySelector('[aria-live="polite"]') !== null)"""

_IMAGES_JS = """() => Array.from(document.images).map(img => ({
    src: (img.getAttribute('src') || img.getAttribute('data-src') || '').slice(0, 80),
    alt: img.getAttribute('alt'),
    decorative: img.getAttribute('role') === 'presentation'
      || img.closest('[aria-hidden="true"]') !== null}))"""

_WIDTHS_JS = """() => ({
    page: document.documentElement.scrollWidth,
    view: document.documentElement.clientWidth,
    wide: Array.from(document.querySelectorAll('.bd-article *')).filter(el => {
      const box = el.getBoundingClientRect();
      return box.width > 0 && box.right > document.documentElement.clientWidth + 1;
    }).slice(0, 5).map(el => el.tagName + '.' + el.className)})"""


#: Boxes of the article that scroll sideways, and whether each takes the focus with a name.
_SCROLLING_JS = """() => Array.from(document.querySelectorAll('.bd-article *')).filter(el =>
    el.scrollWidth > el.clientWidth + 1
    && ['auto', 'scroll'].includes(getComputedStyle(el).overflowX)).map(el => ({
      tag: el.tagName + '.' + el.className, tabindex: el.getAttribute('tabindex'),
      name: el.getAttribute('aria-label') || '',
      nested: el.getAttribute('tabindex') === '0' && el.parentElement !== null
        && el.parentElement.closest('.bd-article [tabindex="0"][role="region"]') !== null}))"""


def _report(chromium: object, site: str, toc_page: str, mode: str) -> dict:
    """Open ``toc_page`` once in ``mode`` and record what the checks read.

    That is axe's violations; in light mode also the sliders, the live regions, the images,
    and the widths after the viewport narrows to 320 CSS px (the page reflows as on a
    phone).
    """
    key = (toc_page, mode)
    if key not in _REPORTS:
        context, page = _open(chromium, site, toc_page, dark=mode == "dark")
        try:
            report: dict = {"axe": _axe(page)}
            if mode == "light":
                report.update(
                    sliders=page.evaluate(_SLIDERS_JS),
                    live=page.evaluate(_LIVE_JS),
                    images=page.evaluate(_IMAGES_JS),
                )
                page.set_viewport_size({"width": 320, "height": 900})
                page.wait_for_timeout(500)
                report["widths"] = page.evaluate(_WIDTHS_JS)
                # what scrolls inside its own box now takes the keyboard focus (the
                # page's scroll-boxes.js looks again 150 ms after a resize)
                report["scroll_boxes"] = _axe(page, rules=["scrollable-region-focusable"])
                report["scrolling"] = page.evaluate(_SCROLLING_JS)
                if toc_page in {"book/recursive_filter", "book/run"}:
                    ARTIFACTS.mkdir(exist_ok=True)
                    page.screenshot(path=str(ARTIFACTS / f"{toc_page.replace('/', '-')}-320.png"))
        finally:
            context.close()
        _REPORTS[key] = report
    return _REPORTS[key]


@pytest.mark.parametrize("mode", ["light", "dark"])
def test_axe_finds_no_violation(chromium: object, site: str, toc_page: str, mode: str) -> None:
    violations = _report(chromium, site, toc_page, mode)["axe"]
    AXE_RESULTS.mkdir(parents=True, exist_ok=True)
    stem = f"{toc_page.replace('/', '-')}-{mode}"
    (AXE_RESULTS / f"{stem}.json").write_text(json.dumps(violations, indent=1), encoding="utf-8")
    summary = [
        f"{v['id']} ({len(v['nodes'])}): {v['nodes'][0]['target']} {v['nodes'][0]['summary']}"
        for v in violations
    ]
    assert not violations, f"{toc_page} ({mode}): " + "\n".join(summary)


# What every slider says to assistive technology, beside what it shows.
_SLIDERS_JS = """
() => Array.from(document.querySelectorAll('.dstoolkit-explorer .dstoolkit-slider')).map(box => {
  const handle = box.querySelector('input[type="range"]');
  const label = box.querySelector('.dstoolkit-label');
  const readout = box.querySelector('output.dstoolkit-readout');
  const named = id => id ? id.split(' ').map(i => document.getElementById(i))
    .filter(Boolean).map(e => e.textContent.trim()).join(' ') : '';
  return {
    label: label ? label.textContent.trim() : '',
    shown: readout ? (readout.value !== undefined && readout.tagName === 'INPUT'
                      ? readout.value : readout.textContent).trim() : '',
    name: handle ? (handle.getAttribute('aria-label') ||
                    named(handle.getAttribute('aria-labelledby')) ||
                    Array.from(handle.labels || []).map(l => l.textContent.trim()).join(' '))
                 : '',
    valuetext: handle ? handle.getAttribute('aria-valuetext') : null,
    disabled: handle ? handle.disabled : false,
    ariaDisabled: handle ? handle.getAttribute('aria-disabled') : null,
    // where the control stands in the Tab order (a disabled control takes no Tab stop)
    tabindex: handle ? String(handle.disabled ? -1 : handle.tabIndex) : null,
    described: handle ? named(handle.getAttribute('aria-describedby')) : '',
  };
})
"""

_UNIT = re.compile(r"\s\(([^()]+)\)\s*$")


def _unit(label: str) -> str:
    """Return the unit a slider's label ends with after a space, in parentheses.

    "level L (m)" gives "m"; none gives ""; "m({low})" names a set, not a unit.
    """
    found = _UNIT.search(label)
    return found.group(1) if found else ""


@pytest.mark.parametrize("page_name", [p for p in toc_pages() if (ROOT / f"{p}.md").is_file()])
def test_sliders_say_what_they_show(chromium: object, site: str, page_name: str) -> None:
    report = _report(chromium, site, page_name, "light")
    sliders, live = report["sliders"], report["live"]
    for s in sliders:
        assert s["label"], f"{page_name}: a slider without a label {s}"
        assert s["name"] == s["label"], f"{page_name}: slider named {s['name']!r}: {s}"
        unit = _unit(s["label"])
        want = f"{s['shown']} {unit}".strip()
        assert s["valuetext"] == want, f"{page_name}: {s['label']!r} says {s['valuetext']!r}"
        if s["disabled"]:
            assert s["ariaDisabled"] == "true" and s["tabindex"] == "-1", (
                f"{page_name}: disabled {s['label']!r} stays in the Tab order: {s}"
            )
            assert "notebook" in s["described"], (
                f"{page_name}: disabled {s['label']!r} is not described by the note: {s}"
            )
        else:
            assert s["ariaDisabled"] != "true" and s["tabindex"] == "0", s
    assert all(live), f"{page_name}: an explorer readout is not in a live region"


@pytest.mark.parametrize("page_name", [p for p in toc_pages() if (ROOT / f"{p}.md").is_file()])
def test_every_image_has_a_written_alt(chromium: object, site: str, page_name: str) -> None:
    images = _report(chromium, site, page_name, "light")["images"]
    for image in images:
        if image["decorative"]:
            continue
        alt = image["alt"] or ""
        assert len(alt.split()) >= 3, f"{page_name}: image without a written alt {image}"
        assert not re.search(r"\.(png|svg|jpe?g|gif)\b|_images/|_states/", alt), (
            f"{page_name}: alt is a file name {image}"
        )


@pytest.mark.parametrize("page_name", [p for p in toc_pages() if (ROOT / f"{p}.md").is_file()])
def test_boxes_that_scroll_take_the_keyboard_focus_at_320_px(
    chromium: object, site: str, page_name: str
) -> None:
    """At 320 CSS px, every box that scrolls on its own can be scrolled with the keyboard.

    Code, tables, outputs and formulas that scroll inside their own box are each a named
    Tab stop (axe's scrollable-region-focusable finds nothing).
    """
    report = _report(chromium, site, page_name, "light")
    assert not report["scroll_boxes"], f"{page_name}: {report['scroll_boxes']}"
    unnamed = [
        box
        for box in report["scrolling"]
        if box["tabindex"] == "0"
        and not box["name"]
        and not box["tag"].startswith(("INPUT", "SELECT", "TEXTAREA"))
    ]
    assert not unnamed, f"{page_name}: boxes that scroll without a name: {unnamed[:5]}"
    # one Tab stop per region (none inside another), each with a name of its own
    nested = [box for box in report["scrolling"] if box["nested"]]
    assert not nested, f"{page_name}: Tab stops inside a scrolling region: {nested[:5]}"
    names = [box["name"] for box in report["scrolling"] if box["tabindex"] == "0" and box["name"]]
    twice = sorted({name for name in names if names.count(name) > 1})
    assert not twice, f"{page_name}: scroll boxes with the same name: {twice[:5]}"


@pytest.mark.parametrize("page_name", [p for p in toc_pages() if (ROOT / f"{p}.md").is_file()])
def test_no_sideways_scroll_at_320_px(chromium: object, site: str, page_name: str) -> None:
    widths = _report(chromium, site, page_name, "light")["widths"]
    assert widths["page"] <= widths["view"], f"{page_name} scrolls sideways at 320 px: {widths}"


def _book_weight() -> object:
    """benchmarks/book_weight.py as a module (it measures what the budget test checks)."""
    spec = importlib.util.spec_from_file_location(
        "benchmark_book_weight", ROOT / "benchmarks" / "book_weight.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("page_name", toc_pages())
def test_first_load_within_budget(
    chromium: object, site: str, built_book: object, page_name: str
) -> None:
    weight = _book_weight().weigh(chromium, site, page_name, built_book.html_dir)
    assert weight.files > 3, f"{page_name}: only {weight.files} files fetched"
    assert weight.budget == (BUDGET if weight.explorer else BUDGET_NO_EXPLORER)
    assert weight.gzipped <= weight.budget, (
        f"{page_name}: {weight.gzipped / 1e6:.2f} MB gzipped first load "
        f"({weight.raw / 1e6:.2f} MB raw) over {weight.budget / 1e6:.1f} MB; "
        f"largest: {weight.largest}"
    )


_FOCUSED_JS = """() => { const el = document.activeElement;
    const style = getComputedStyle(el);
    return {slider: el.matches('.dstoolkit-explorer input[type="range"]'),
            skip: el.classList.contains('dstoolkit-skip'),
            math: el.closest('mjx-container') !== null,
            tag: el.tagName, text: (el.textContent || '').trim().slice(0, 40),
            outline: style.outlineStyle, width: parseFloat(style.outlineWidth) || 0,
            shadow: style.boxShadow}; }"""


def _start_at_the_top_of_the_article(page: object) -> None:
    page.evaluate("""() => {
        const start = document.createElement('span');
        start.id = 'tab-start'; start.tabIndex = -1;
        document.querySelector('article.bd-article').prepend(start);
        start.focus(); }""")


def _visibly_focused(focused: dict) -> bool:
    return (focused["outline"] != "none" and focused["width"] >= 2) or (
        focused["shadow"] not in ("none", "")
    )


def test_tab_reaches_a_slider_quickly(chromium: object, site: str) -> None:
    """From the top of the article, Tab to the skip link and Enter focus the first live slider.

    The slider has the focus in fewer than TAB_PRESSES key presses, every stop visibly
    focused.
    """
    context, page = _open(chromium, site, TAB_PAGE)
    try:
        _start_at_the_top_of_the_article(page)
        presses, stops = 0, []
        while presses < TAB_PRESSES:
            focused = page.evaluate(_FOCUSED_JS)
            if presses and focused["slider"]:
                break
            key = "Enter" if focused["skip"] else "Tab"
            page.keyboard.press(key)
            presses += 1
            focused = page.evaluate(_FOCUSED_JS)
            stops.append(focused)
            assert not focused["math"], f"{TAB_PAGE}: press {presses} lands on a formula"
            assert _visibly_focused(focused), f"{TAB_PAGE}: no visible focus on {focused}"
        assert page.evaluate(_FOCUSED_JS)["slider"], (
            f"{TAB_PAGE}: no slider within {TAB_PRESSES - 1} key presses: {stops}"
        )
        assert stops[0]["skip"], stops[0]
    finally:
        context.close()


#: Marks, in document order, what may take the focus in the article before its first live
#: slider (links, buttons, summaries, form controls, named scroll boxes) and returns how
#: many; the slider itself is marked last.
_MARK_TAB_STOPS_JS = """() => {
    const slider = document.querySelector(
      '.dstoolkit-explorer input[type="range"]:not([disabled])');
    const article = document.querySelector('article.bd-article');
    const all = Array.from(article.querySelectorAll(
      'a[href], button, summary, input, select, textarea, [tabindex="0"]'));
    const stops = all.filter(el => !el.disabled && el.getAttribute('tabindex') !== '-1'
      && el.getClientRects().length > 0 && getComputedStyle(el).visibility !== 'hidden'
      && (slider.compareDocumentPosition(el) & Node.DOCUMENT_POSITION_PRECEDING));
    stops.concat([slider]).forEach((el, i) => el.setAttribute('data-tab-stop', String(i)));
    return stops.length; }"""


def test_without_the_skip_link_tab_follows_the_text(chromium: object, site: str) -> None:
    """Tab through TAB_PAGE's article up to its first slider, without the skip link.

    The stops are its links and controls in the order of the text, each once (no formula,
    nothing that is not a control), every one visibly focused; the number of presses is
    what the text before the first explorer holds.
    """
    context, page = _open(chromium, site, TAB_PAGE)
    try:
        maths = page.locator("mjx-container").count()
        assert maths > 20, f"{TAB_PAGE}: {maths} formulas"
        _start_at_the_top_of_the_article(page)
        page.evaluate("() => document.querySelector('.dstoolkit-skip')?.remove()")
        expected = page.evaluate(_MARK_TAB_STOPS_JS)
        order = []
        for presses in range(1, expected + 2):
            page.keyboard.press("Tab")
            focused = page.evaluate(_FOCUSED_JS)
            stop = page.evaluate("() => document.activeElement.getAttribute('data-tab-stop')")
            order.append(stop)
            assert not focused["math"], f"{TAB_PAGE}: Tab {presses} lands on a formula"
            assert _visibly_focused(focused), f"{TAB_PAGE}: no visible focus on {focused}"
            assert stop == str(presses - 1), (
                f"{TAB_PAGE}: Tab {presses} lands on {focused}, stop {stop}, not on the "
                f"next link or control of the text ({presses - 1}); order so far {order}"
            )
        assert page.evaluate(_FOCUSED_JS)["slider"], f"{TAB_PAGE}: {order}"
        print(f"{TAB_PAGE}: first slider at Tab {expected + 1} without the skip link")
    finally:
        context.close()


#: The theme's own controls at the top of a page: the header's buttons and links (and the
#: site title's link), each visibly focused when it has the keyboard focus.
_THEME_CONTROLS_JS = """() => Array.from(document.querySelectorAll(
    '.bd-header-article button, .bd-header-article a[href], .bd-header-article .btn,'
    + ' a.navbar-brand')).filter(el => el.getClientRects().length > 0
      && getComputedStyle(el).visibility !== 'hidden').map((el, i) => {
    el.setAttribute('data-theme-control', String(i));
    return i; })"""

_FOCUS_ON_JS = """(i) => { const el = document.querySelector(`[data-theme-control="${i}"]`);
    el.focus(); const style = getComputedStyle(el);
    return {name: el.getAttribute('title') || el.getAttribute('data-bs-original-title')
                  || el.getAttribute('aria-label') || (el.textContent || '').trim().slice(0, 40)
                  || el.className,
            focusVisible: el.matches(':focus-visible'), focused: document.activeElement === el,
            outline: style.outlineStyle, width: parseFloat(style.outlineWidth) || 0,
            shadow: style.boxShadow}; }"""


def test_the_themes_controls_show_their_focus(chromium: object, site: str) -> None:
    """Every button and link of the theme's header shows a visible focus ring (WCAG 2.4.7).

    axe does not test focus visibility: the outline (or shadow) of each control is read
    while it has the keyboard focus.
    """
    context, page = _open(chromium, site, TAB_PAGE)
    try:
        controls = page.evaluate(_THEME_CONTROLS_JS)
        assert len(controls) >= 2, f"{TAB_PAGE}: the header's buttons were not found"
        page.keyboard.press("Tab")  # keyboard use: focus() then shows :focus-visible
        for i in controls:
            focused = page.evaluate(_FOCUS_ON_JS, i)
            if not focused["focused"]:
                continue  # not focusable (a disabled item)
            assert focused["focusVisible"] and _visibly_focused(focused), (
                f"{TAB_PAGE}: no visible focus on the theme's {focused['name']!r}: {focused}"
            )
        names = [page.evaluate(_FOCUS_ON_JS, i)["name"] for i in controls]
        assert any("sidebar" in n.lower() for n in names), names
    finally:
        context.close()


def test_the_site_title_is_in_a_landmark(chromium: object, site: str) -> None:
    """The site title (its link home) is inside a landmark, as is all content of a page."""
    context, page = _open(chromium, site, TAB_PAGE)
    try:
        outside = page.evaluate("""() => Array.from(document.querySelectorAll(
            'a.navbar-brand')).filter(el => el.closest(
            'nav, header, main, aside, footer, [role="navigation"], [role="banner"],'
            + ' [role="main"], [role="complementary"], [role="contentinfo"]') === null)
            .map(el => el.outerHTML.slice(0, 120))""")
        assert not outside, f"{TAB_PAGE}: the site title outside any landmark: {outside}"
    finally:
        context.close()

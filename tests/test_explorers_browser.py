"""The explorers on the built static site (no kernel), in headless Chromium.

On every page with an explorer (written as HTML with native controls by
scripts/site_postbuild.py), every enabled slider moved with the keyboard (arrow keys on its
range) and every enabled dropdown changed switches the figure or the readout; a disabled slider
does not move; no console error. Screenshots of every explorer before and after its first slider
moves go to test-artifacts/explorers/.

The browser is conftest's ``chromium`` fixture, the pages come from tests/test_book_browser.py (its
``site`` fixture: the book built by scripts/build-book.sh, served on 127.0.0.1). Without Chromium
the tests skip, except under DSTOOLKIT_REQUIRE_BROWSER=1 (CI), where they fail.
"""

from __future__ import annotations

import re

import pytest
from conftest import ARTIFACTS, ROOT, toc_pages
from test_book_browser import _WIDGETS_RENDERED_JS, TIMEOUT_MS, _watch, site

pytestmark = [pytest.mark.browser, pytest.mark.slow]
__all__ = ["site"]  # fixture used by the tests below

SHOTS = ARTIFACTS / "explorers"
#: An explorer cell calls one of these (dstoolkit.teaching) in a chapter, or links a
#: control to precomputed states itself (the intro's discount slider).
_EXPLORER_CALL = re.compile(
    r"^\s*((\w+_explorer|filter_widget|lab_widget)\(|widgets\.jslink\()", re.M
)


def explorer_pages() -> list[str]:
    """Return the pages of _toc.yml whose source has an explorer cell."""
    return [
        page
        for page in toc_pages()
        if (ROOT / f"{page}.md").is_file()
        and _EXPLORER_CALL.search((ROOT / f"{page}.md").read_text(encoding="utf-8"))
    ]


# Marks every explorer (a widget view written as HTML by site_postbuild.py) data-explorer="i".
_MARK_JS = """
() => Array.from(document.querySelectorAll('.dstoolkit-explorer')).map((area, i) => {
  area.setAttribute('data-explorer', String(i));
  return i;
})
"""

# What an explorer shows now: its visible images and visible HTML (readouts, warnings).
_SHOWN_JS = """
(area) => {
  const shown = el => el.offsetParent !== null && el.getClientRects().length > 0;
  const images = Array.from(area.querySelectorAll('img')).filter(shown)
    .map(img => img.src.length + ':' + img.src.slice(-60));
  const texts = Array.from(area.querySelectorAll('.widget-html-content')).filter(shown)
    .map(el => el.innerText);
  return JSON.stringify({images, texts});
}
"""


def _shown(area: object) -> str:
    return area.evaluate(_SHOWN_JS)


def _wait_for_change(page: object, area: object, before: str, timeout_ms: int = 5000) -> bool:
    deadline = timeout_ms / 100
    for _ in range(int(deadline)):
        if _shown(area) != before:
            return True
        page.wait_for_timeout(100)
    return False


#: At most this many words are announced per change (tests/test_explorer_sentences.py).
MAX_WORDS = 25


def _announced(page: object, area: object, before: str) -> str:
    """Return what the explorer's live region says after a change (once it changed)."""
    region = area.locator(".dstoolkit-announce")
    for _ in range(30):  # the page's script writes it 50 ms after the state changed
        said = region.inner_text().strip()
        if said != before:
            return said
        page.wait_for_timeout(100)
    return region.inner_text().strip()


def _slider_moves(page: object, area: object, slider: object) -> tuple[bool, bool]:
    """Press → (then ← if the slider sat at its end) on the slider's handle.

    Return (the slider's readout changed, the explorer's figure or readout changed).
    """
    readout = slider.locator("output.dstoolkit-readout")
    before_value, before = readout.inner_text(), _shown(area)
    handle = slider.locator('input[type="range"]')
    for key in ("ArrowRight", "ArrowLeft"):
        handle.focus()
        page.keyboard.press(key)
        page.wait_for_timeout(150)
        if readout.inner_text() != before_value:
            return True, _wait_for_change(page, area, before)
    return False, _shown(area) != before


@pytest.mark.parametrize("page_name", explorer_pages())
def test_explorers_answer_on_the_static_site(chromium: object, site: str, page_name: str) -> None:
    context = chromium.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    problems = _watch(context, page)
    SHOTS.mkdir(parents=True, exist_ok=True)
    stem = page_name.replace("/", "-")
    try:
        page.goto(site + page_name + ".html", wait_until="load")
        page.wait_for_function(_WIDGETS_RENDERED_JS, timeout=TIMEOUT_MS)
        explorers = page.evaluate(_MARK_JS)
        assert explorers, f"{page_name}: no explorer on the page"
        live_sliders = 0
        for i in explorers:
            area = page.locator(f'[data-explorer="{i}"]')
            sliders = area.locator(".dstoolkit-slider")
            enabled = [
                sliders.nth(j)
                for j in range(sliders.count())
                if not sliders.nth(j).locator("input[disabled]").count()
            ]
            disabled = [
                sliders.nth(j)
                for j in range(sliders.count())
                if sliders.nth(j).locator("input[disabled]").count()
            ]
            assert enabled, f"{page_name}: explorer {i} has no live slider"
            area.scroll_into_view_if_needed()
            area.screenshot(path=str(SHOTS / f"{stem}-{i}-before.png"))
            states = area.locator(".dstoolkit-states").count() > 0
            for k, slider in enumerate(enabled):
                name = slider.locator(".dstoolkit-label").inner_text()
                region = area.locator(".dstoolkit-announce")
                said_before = region.inner_text().strip() if states else ""
                moved, changed = _slider_moves(page, area, slider)
                assert moved, f"{page_name}: live slider {name!r} did not move"
                assert changed, f"{page_name}: moving {name!r} changed no figure or readout"
                if states:  # an Explorer: one short sentence in its live region
                    assert region.get_attribute("aria-live") == "polite", page_name
                    said = _announced(page, area, said_before)
                    assert said and said != said_before, f"{page_name}: {name!r} said nothing"
                    assert len(said.split()) <= MAX_WORDS, f"{page_name}: {said!r}"
                live_sliders += 1
                if k == 0:
                    area.screenshot(path=str(SHOTS / f"{stem}-{i}-after.png"))
            for slider in disabled:
                name = slider.locator(".dstoolkit-label").inner_text()
                # nothing keeps the focus: keys pressed on the disabled slider reach no
                # other control (a disabled range cannot take the focus)
                page.evaluate("() => document.activeElement && document.activeElement.blur()")
                moved, changed = _slider_moves(page, area, slider)
                assert not moved and not changed, f"{page_name}: disabled {name!r} moved"
                focused = slider.locator('input[type="range"]').evaluate(
                    "e => e === document.activeElement"
                )
                assert not focused, f"{page_name}: disabled {name!r} takes the focus"
            selects = area.locator("select")
            for j in range(selects.count()):
                select = selects.nth(j)
                if select.is_disabled():
                    continue
                options = select.locator("option").all_inner_texts()
                before = _shown(area)
                other = next(
                    o
                    for o in options
                    if o != select.evaluate("s => s.options[s.selectedIndex].text")
                )
                select.select_option(label=other)
                assert _wait_for_change(page, area, before), (
                    f"{page_name}: choosing {other!r} changed no figure or readout"
                )
        assert live_sliders, f"{page_name}: no live slider"
        assert not problems.console_errors, f"{page_name}: console {problems.console_errors}"
        assert not problems.failed_requests, f"{page_name}: failed {problems.failed_requests}"
        assert not problems.external_requests, (
            f"{page_name}: requests leaving 127.0.0.1: {problems.external_requests}"
        )
    finally:
        context.close()


# Every slider of the page's explorers: whether its readout can be edited, what it shows
# and what its range says.
_READOUTS_JS = """
() => Array.from(document.querySelectorAll('.dstoolkit-explorer .dstoolkit-slider')).map(box => {
  const readout = box.querySelector('output.dstoolkit-readout');
  const handle = box.querySelector('input[type="range"]');
  return {
    output: readout ? readout.tagName === 'OUTPUT' : null,
    editable: readout ? readout.isContentEditable : null,
    shown: readout ? readout.textContent.trim() : null,
    valuetext: handle ? handle.getAttribute('aria-valuetext') : null,
  };
})
"""


@pytest.mark.parametrize("page_name", explorer_pages())
def test_typing_into_a_readout_changes_nothing(chromium: object, site: str, page_name: str) -> None:
    """Type a value (or nonsense) into every slider's readout on the site: nothing changes.

    The readout is text: neither it, the slider's aria-valuetext nor the explorer's figure
    and readout change.
    """
    context = chromium.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    problems = _watch(context, page)
    try:
        page.goto(site + page_name + ".html", wait_until="load")
        page.wait_for_function(_WIDGETS_RENDERED_JS, timeout=TIMEOUT_MS)
        before = page.evaluate(_READOUTS_JS)
        assert before, f"{page_name}: no slider"
        editable = [s["shown"] for s in before if s["editable"] or not s["output"]]
        assert not editable, f"{page_name}: readouts that can be edited: {editable}"
        explorers = page.evaluate(_MARK_JS)
        for i in explorers:
            area = page.locator(f'[data-explorer="{i}"]')
            readouts = area.locator(".dstoolkit-slider output.dstoolkit-readout")
            for j in range(readouts.count()):
                readout = readouts.nth(j)
                readout.scroll_into_view_if_needed()
                shown = _shown(area)
                for typed in ("7.6", "0.70", "abc"):
                    readout.click(force=True)  # as a reader would, to type into it
                    page.keyboard.type(typed)
                    page.keyboard.press("Enter")
                page.keyboard.press("Tab")
                page.wait_for_timeout(300)  # what a typed value would have changed by now
                assert _shown(area) == shown, f"{page_name}: typing into readout {j} changed it"
        after = page.evaluate(_READOUTS_JS)
        assert after == before, f"{page_name}: typing changed a readout or a value text"
        assert not problems.console_errors, f"{page_name}: console {problems.console_errors}"
    finally:
        context.close()


_CONTROL_LOOKS_JS = """
() => Array.from(document.querySelectorAll(
    '.dstoolkit-explorer input[type="range"], .dstoolkit-explorer select')).map(el => ({
  name: (el.labels && el.labels[0] ? el.labels[0].textContent : el.id).trim(),
  disabled: el.disabled,
  border: getComputedStyle(el).borderTopStyle,
}))
"""


@pytest.mark.parametrize("page_name", explorer_pages())
def test_a_disabled_control_looks_disabled_beyond_its_colour(
    chromium: object, site: str, page_name: str
) -> None:
    """A control that works only in a notebook has a dashed frame; a live one a solid frame.

    Its grey alone would tell it apart by colour only.
    """
    context = chromium.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()
    try:
        page.goto(site + page_name + ".html", wait_until="load", timeout=TIMEOUT_MS)
        controls = page.evaluate(_CONTROL_LOOKS_JS)
    finally:
        context.close()
    assert controls, f"{page_name}: no slider or drop-down"
    wrong = [c for c in controls if (c["border"] == "dashed") != c["disabled"]]
    assert not wrong, f"{page_name}: controls whose frame does not say whether they work: {wrong}"

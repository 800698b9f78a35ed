"""The built book on a phone: what its pages make the browser wait for, weigh and show.

* **Nothing render-blocking in the head**: every script a page loads from its head is
  deferred (small inline scripts, such as the theme's colour mode, stay). No page
  loads MathJax (the maths is typeset at build time, scripts/typeset-maths.js, and no
  formula is left as TeX), and no page loads the widget manager (the explorers are HTML).
* **Maths without fonts**: every formula is SVG whose glyphs are drawn from one cache of
  outlines a page; no page loads a maths font (which would lay the page out again).
* **Explorers drawn before any script**: every widget view is written as plain HTML with
  native controls in its cell's output (scripts/site_postbuild.py); no widget state is left
  in the page, and the pictures of the states not shown wait in ``data-src`` (fetched by
  book/_static/explorers.js when their state is shown).
* **Every figure opens full size**: each picture of the article and of every explorer state
  is inside a link to its own file, and has a written text alternative (the link's name).
* **Figures readable at 320 CSS px** (browser): the smallest text of every explorer picture
  (``SMALL_PT`` points at ``FIGURE_DPI`` dots per inch, scaled by the picture's displayed
  width over its natural width) is at least as large as the page's small print (the
  smallest font size of the article's text: paragraphs, list items, table cells, readouts);
  its full-size link takes the keyboard focus.
* **Page weight** (browser): an explorer page scrolled to its end, its explorers drawn, has
  fetched at most 1.5 MB gzipped (each file gzipped on its own at level 6, as a server
  sends it), and no picture of a state it does not show.
"""

from __future__ import annotations

import gzip
import re
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urljoin, urlsplit

import pytest
from conftest import ROOT, BookBuild
from test_book_browser import _WIDGETS_RENDERED_JS, TIMEOUT_MS, site
from test_explorers_browser import explorer_pages
from test_site_postbuild import postbuild

from dstoolkit.plots._style import SMALL_PT
from dstoolkit.teaching._explorer import FIGURE_DPI

__all__ = ["site"]  # fixture used by the browser tests below

#: Gzipped bytes a page may have fetched once scrolled to its end.
BUDGET = 1_500_000
_WIDGET_SCRIPT = re.compile(r'<script type="application/vnd\.jupyter\.widget-(state|view)\+json">')
_EXPLORER = re.compile(r'<div class="dstoolkit-explorer[ "]')


def _figure_explorer_pages() -> list[str]:
    """Return the pages whose explorer draws figures (the intro's widget shows tables)."""
    call = re.compile(r"^\s*(\w+_explorer|filter_widget)\(", re.M)
    return [p for p in explorer_pages() if call.search((ROOT / f"{p}.md").read_text())]


class _Head(HTMLParser):
    """The scripts of a page's ``<head>`` and every script's ``src``."""

    def __init__(self) -> None:
        super().__init__()
        self.in_head = False
        self.head_scripts: list[dict[str, str | None]] = []
        self.sources: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        found = dict(attrs)
        if tag == "head":
            self.in_head = True
        elif tag == "body":
            self.in_head = False
        elif tag == "script":
            if found.get("src"):
                self.sources.append(found["src"] or "")
            if self.in_head:
                self.head_scripts.append(found)

    def handle_endtag(self, tag: str) -> None:
        if tag == "head":
            self.in_head = False


class _Images(HTMLParser):
    """Every ``<img>`` of a piece of HTML with the ``href`` of the link around it (or None)."""

    def __init__(self) -> None:
        super().__init__()
        self.links: list[str | None] = []
        self.images: list[tuple[dict[str, str | None], str | None]] = []
        self.article = 0

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        found = dict(attrs)
        if tag == "a":
            self.links.append(found.get("href"))
        elif tag == "img":
            self.images.append((found, next((h for h in reversed(self.links) if h), None)))

    def handle_endtag(self, tag: str) -> None:
        if tag == "a" and self.links:
            self.links.pop()


class _HiddenStateImages(HTMLParser):
    """The ``<img>`` with a ``src`` inside an explorer state written hidden."""

    _VOID = frozenset({"img", "input", "br", "hr", "meta", "link", "source", "wbr", "col"})

    def __init__(self) -> None:
        super().__init__()
        self.open: list[bool] = []  # per open element: inside a hidden state
        self.fetched: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        found = dict(attrs)
        inside = bool(self.open and self.open[-1])
        if tag == "img" and inside and found.get("src"):
            self.fetched.append(str(found.get("src")))
        if tag in self._VOID:
            return
        hidden_state = "dstoolkit-state" in (found.get("class") or "").split() and (
            "hidden" in found
        )
        self.open.append(inside or hidden_state)

    def handle_endtag(self, tag: str) -> None:
        if tag not in self._VOID and self.open:
            self.open.pop()


def _html(built_book: BookBuild, page: str) -> str:
    path = built_book.html_dir / f"{page}.html"
    if not path.is_file():
        pytest.fail(f"{path} is missing: the book was not built (see test_book_build)")
    return path.read_text(encoding="utf-8")


def test_no_render_blocking_script_in_the_head(built_book: BookBuild, toc_page: str) -> None:
    parser = _Head()
    parser.feed(_html(built_book, toc_page))
    blocking = [
        s["src"]
        for s in parser.head_scripts
        if s.get("src") and "defer" not in s and "async" not in s and s.get("type") != "module"
    ]
    assert not blocking, f"{toc_page}.html: scripts that block rendering: {blocking}"
    mathjax = [src for src in parser.sources if "mathjax" in src.lower()]
    assert not mathjax, f"{toc_page}.html loads MathJax ({mathjax}); maths is typeset at build"
    embed = [src for src in parser.sources if re.search(r"embed|lazy-explorers", src)]
    assert not embed, f"{toc_page}.html loads the widget manager: {embed}"


#: Font Awesome's solid font as the theme ships it (WOFF 2), the size an icon font is cut from.
_SOLID_WOFF2 = (
    Path(str(__import__("pydata_sphinx_theme").__file__)).parent
    / "theme/pydata_sphinx_theme/static/vendor/fontawesome/webfonts/fa-solid-900.woff2"
)


def test_one_purged_stylesheet_whose_icon_fonts_are_cut(
    built_book: BookBuild, toc_page: str
) -> None:
    text = _html(built_book, toc_page)
    links = re.findall(r'<link rel="stylesheet"[^>]*href="([^"]+)"', text)
    assert len(links) == 1, f"{toc_page}.html links {len(links)} stylesheets: {links}"
    page = built_book.html_dir / f"{toc_page}.html"
    sheet = (page.parent / unquote(links[0].split("?")[0])).resolve()
    css = sheet.read_text(encoding="utf-8")
    assert css.startswith(postbuild.SLIM), f"{sheet.name}: not purged (scripts/purge-styles.js)"
    faces = [f for f in re.findall(r"@font-face\s*\{[^}]*\}", css) if "Awesome" in f]
    assert faces, f"{sheet.name}: no Font Awesome font face (the theme's icons)"
    for face in faces:
        urls = re.findall(r"url\(([^)]+)\)", face)
        assert len(urls) == 1 and urls[0].endswith(".woff"), face
        font = sheet.parent / urls[0]
        # a dozen icons of ~1400: a tenth of the whole font is far more than they need
        assert font.stat().st_size < _SOLID_WOFF2.stat().st_size / 10, (
            f"{font.name} ({font.stat().st_size} bytes) is not cut to the icons the site draws"
        )


def test_maths_is_typeset_at_build_time(built_book: BookBuild, toc_page: str) -> None:
    text = _html(built_book, toc_page)
    inline = len(re.findall(r'<span class="math notranslate nohighlight">', text))
    display = len(re.findall(r'<div class="math notranslate nohighlight"', text))
    typeset = len(re.findall(r"<mjx-container ", text))
    assert typeset >= inline + display, (
        f"{toc_page}.html: {inline + display} formulas, {typeset} typeset"
    )
    left = re.findall(r'class="math notranslate nohighlight"[^>]*>[^<]*\\[(\[]', text)
    assert not left, f"{toc_page}.html: maths left as TeX: {left[:3]}"
    if typeset:
        assert "<mjx-assistive-mml" in text, f"{toc_page}.html: maths without MathML for readers"


def test_maths_draws_its_glyphs_once_and_loads_no_font(
    built_book: BookBuild, toc_page: str
) -> None:
    """Every formula is SVG drawn from one glyph cache a page: no CHTML, no maths font.

    CHTML writes an element and a generated box per character and lays the page out again
    when each of MathJax's fonts arrives; SVG refers to each glyph's outline, written once in
    the page's cache (scripts/typeset-maths.js).
    """
    text = _html(built_book, toc_page)
    formulas = re.findall(r"<mjx-container [^>]*>", text)
    if not formulas:
        assert "MJX-SVG-global-cache" not in text, f"{toc_page}.html: a cache with no formula"
        return
    chtml = [f for f in formulas if 'jax="SVG"' not in f]
    assert not chtml, f"{toc_page}.html: formulas not drawn as SVG: {chtml[:3]}"
    assert "<mjx-c " not in text and "<mjx-c>" not in text, f"{toc_page}.html: CHTML left"
    assert text.count('id="MJX-SVG-global-cache"') == 1, f"{toc_page}.html: not one glyph cache"
    cache = text[text.index('id="MJX-SVG-global-cache"') :]
    cache = cache[: cache.index("</svg>")]
    defined = set(re.findall(r'<path id="([^"]+)"', cache))
    used = set(re.findall(r'<use [^>]*xlink:href="#([^"]+)"', text))
    assert used, f"{toc_page}.html: {len(formulas)} formulas that draw no glyph"
    missing = sorted(used - defined)
    assert not missing, f"{toc_page}.html: glyphs not in the cache: {missing[:5]}"
    faces = re.findall(r"@font-face\s*\{[^}]*\}", text)
    assert not faces, f"{toc_page}.html: the page loads fonts for its maths: {faces[:1]}"


def test_the_mathml_for_readers_holds_no_indentation(built_book: BookBuild, toc_page: str) -> None:
    """The MathML beside each formula is written without indentation between its elements.

    It is laid out as inline text (scripts/typeset-maths.js), where each run of indentation
    would be a blank word in the accessibility tree and bytes the page loads for nothing.
    """
    text = _html(built_book, toc_page)
    readers = re.findall(r"<mjx-assistive-mml[^>]*>(.*?)</mjx-assistive-mml>", text, re.S)
    indented = [mml[:80] for mml in readers if re.search(r">\s+<", mml)]
    assert not indented, f"{toc_page}.html: {len(indented)} indented MathML: {indented[:2]}"


def test_explorers_are_drawn_before_any_script(built_book: BookBuild, toc_page: str) -> None:
    text = _html(built_book, toc_page)
    left = _WIDGET_SCRIPT.findall(text)
    assert not left, f"{toc_page}.html: widget {left} scripts left in the page"
    for found in _EXPLORER.finditer(text):
        before = text[: found.start()]
        assert before.rfind('class="cell_output') > before.rfind("</article>"), (
            f"{toc_page}.html: an explorer outside a cell's output"
        )
    parser = _HiddenStateImages()
    parser.feed(text)
    assert not parser.fetched, (
        f"{toc_page}.html: pictures of hidden states fetched at once: {parser.fetched[:3]}"
    )


def _linked(image: dict[str, str | None], href: str | None) -> bool:
    src = image.get("src") or image.get("data-src") or ""
    return href is not None and href.split("#")[0] == src


def test_every_figure_opens_full_size(built_book: BookBuild, toc_page: str) -> None:
    text = _html(built_book, toc_page)
    article = re.search(r'<article class="bd-article".*?</article>', text, re.S)
    assert article, f"{toc_page}.html has no article"
    pieces = [article.group(0)]  # the explorers' states are in the article
    for piece in pieces:
        parser = _Images()
        parser.feed(piece)
        for image, href in parser.images:
            src = image.get("src") or image.get("data-src") or ""
            if src.startswith("data:") or "://" in src:
                continue
            assert _linked(image, href), (
                f"{toc_page}.html: the figure {src} is not a link to its full-size file"
            )
            assert len((image.get("alt") or "").split()) >= 3, (
                f"{toc_page}.html: the full-size link of {src} has no name (no written alt)"
            )
            file = (built_book.html_dir / toc_page).parent / unquote(src.split("?")[0])
            assert file.is_file(), f"{toc_page}.html: {src} links a missing file"


_FIGURE_TEXT_JS = """
async (figurePx) => {
  const skip = 'mjx-container, pre, code, .highlight';
  const texts = Array.from(document.querySelectorAll(
    '.bd-article p, .bd-article li, .bd-article td, .bd-article th,'
    + ' .bd-article .dstoolkit-readout, .bd-article .dstoolkit-label'))
    .filter(el => el.offsetParent !== null && el.textContent.trim() && !el.closest(skip));
  const small = Math.min(...texts.map(el => parseFloat(getComputedStyle(el).fontSize)));
  const figures = [];
  for (const img of document.querySelectorAll('img.dstoolkit-figure')) {
    if (img.offsetParent === null) continue;
    img.scrollIntoView();
    if (!img.complete || !img.naturalWidth) {
      await new Promise(done => { img.onload = done; img.onerror = done;
                                  setTimeout(done, 5000); });
    }
    const link = img.closest('a.dstoolkit-fullsize');
    if (link) link.focus();
    figures.push({
      src: img.getAttribute('src'),
      text: figurePx * img.getBoundingClientRect().width / img.naturalWidth,
      natural: img.naturalWidth,
      link: link ? link.getAttribute('href') : null,
      focused: link !== null && document.activeElement === link,
      name: img.getAttribute('alt') || '',
    });
  }
  return {small, figures};
}
"""


@pytest.mark.browser
@pytest.mark.slow
@pytest.mark.parametrize("page_name", _figure_explorer_pages())
def test_explorer_figures_are_readable_at_320_px(
    chromium: object, site: str, page_name: str
) -> None:
    context = chromium.new_context(viewport={"width": 320, "height": 800})
    page = context.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    try:
        page.goto(site + page_name + ".html", wait_until="load")
        page.wait_for_function(_WIDGETS_RENDERED_JS, timeout=TIMEOUT_MS)
        # the smallest text of a figure in CSS px when the picture is shown at its own size
        figure_px = SMALL_PT * FIGURE_DPI / 72
        report = page.evaluate(_FIGURE_TEXT_JS, figure_px)
    finally:
        context.close()
    assert report["figures"], f"{page_name}: no explorer figure shown at 320 px"
    for figure in report["figures"]:
        assert figure["natural"] > 0, f"{page_name}: {figure['src']} did not load"
        # 0.05 px: the layout rounds the displayed width to a fraction of a pixel
        assert figure["text"] >= report["small"] - 0.05, (
            f"{page_name} at 320 px: the smallest text of {figure['src']} is "
            f"{figure['text']:.1f} px, the page's small print {report['small']:.1f} px"
        )
        assert figure["link"] == figure["src"] and figure["focused"], (
            f"{page_name}: {figure['src']} has no full-size link that takes the focus: {figure}"
        )
        assert len(figure["name"].split()) >= 3, f"{page_name}: a full-size link without name"


# The pictures of the explorers' states shown now (full URLs).
_SHOWN_STATE_PICTURES_JS = """
() => Array.from(document.querySelectorAll('.dstoolkit-explorer img[src]'))
  .filter(img => img.closest('.dstoolkit-state[hidden]') === null).map(img => img.src)
"""


def _gzipped_size(html_dir: Path, url: str, base: str) -> int:
    path = html_dir / unquote(urlsplit(url).path.lstrip("/"))
    if not url.startswith(base) or not path.is_file():
        return 0
    return len(gzip.compress(path.read_bytes(), compresslevel=6))


@pytest.mark.browser
@pytest.mark.slow
@pytest.mark.parametrize("page_name", explorer_pages())
def test_page_scrolled_to_its_end_weighs_at_most_the_budget(
    chromium: object, site: str, built_book: BookBuild, page_name: str
) -> None:
    context = chromium.new_context(viewport={"width": 412, "height": 823})
    page = context.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    fetched: set[str] = set()
    page.on("requestfinished", lambda request: fetched.add(request.url))
    try:
        page.goto(site + page_name + ".html", wait_until="load")
        page.wait_for_function(_WIDGETS_RENDERED_JS, timeout=TIMEOUT_MS)
        height = page.evaluate("document.documentElement.scrollHeight")
        for y in range(0, height + 800, 700):
            page.evaluate(f"window.scrollTo(0, {y})")
            page.wait_for_timeout(30)
        page.wait_for_load_state("networkidle")
        shown = set(page.evaluate(_SHOWN_STATE_PICTURES_JS))
    finally:
        context.close()
    pictures = {url for url in fetched if "/_states/" in url}
    assert pictures <= shown, (
        f"{page_name}: pictures of states not shown were fetched: {sorted(pictures - shown)[:3]}"
    )
    sizes = {url: _gzipped_size(built_book.html_dir, url, site) for url in fetched}
    total = sum(sizes.values())
    largest = sorted(sizes.items(), key=lambda item: -item[1])[:3]
    assert total <= BUDGET, (
        f"{page_name} scrolled to its end fetched {total / 1e6:.2f} MB gzipped "
        f"(budget {BUDGET / 1e6:.1f} MB); largest: {largest}"
    )
    assert urljoin(site, page_name + ".html") in fetched

"""The book builds with `bash scripts/build-book.sh` without a warning, and is self-contained.

The build runs jupyter-book build . -W -n --keep-going. Every page of the site is
self-contained: no script, style, font or image from another site, and the state of every
widget written into the page as HTML.
"""

from __future__ import annotations

import re
from html.parser import HTMLParser
from pathlib import Path

import pytest
from conftest import BookBuild, toc_pages

pytestmark = pytest.mark.slow

WIDGET_STATE = "application/vnd.jupyter.widget-state+json"
WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"
#: Hosts the default Jupyter Book / myst-nb / sphinx-thebe configuration loads code from.
CDN_HOSTS = (
    "unpkg.com",
    "cdn.jsdelivr.net",
    "cdnjs.cloudflare.com",
    "googleapis.com",
    "gstatic.com",
    "fontawesome.com",
    "mathjax.org",
    "plausible.io",
    "googletagmanager.com",
    "hypothes.is",
    "utteranc.es",
)
#: (tag, attribute) pairs whose URL the browser fetches when it renders the page.
FETCHED = {
    ("script", "src"),
    ("link", "href"),
    ("img", "src"),
    ("iframe", "src"),
    ("source", "src"),
    ("video", "src"),
    ("audio", "src"),
    ("embed", "src"),
    ("object", "data"),
    ("input", "src"),
}


class _PageParser(HTMLParser):
    """Collects the fetched URLs and the JSON of the widget <script> tags of a page."""

    def __init__(self) -> None:
        super().__init__()
        self.fetched: list[str] = []
        self.scripts: list[tuple[str, str]] = []  # (type, body) of inline typed scripts
        self._script_type: str | None = None
        self._body: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        attributes = dict(attrs)
        for name, value in attributes.items():
            if (tag, name) in FETCHED and value:
                if tag == "link" and attributes.get("rel") in {"canonical", "next", "prev"}:
                    continue  # navigation links, not fetched
                self.fetched.append(value)
        if tag == "script" and attributes.get("type") in {WIDGET_STATE, WIDGET_VIEW}:
            self._script_type = attributes["type"]
            self._body = []

    def handle_data(self, data: str) -> None:
        if self._script_type is not None:
            self._body.append(data)

    def handle_endtag(self, tag: str) -> None:
        if tag == "script" and self._script_type is not None:
            self.scripts.append((self._script_type, "".join(self._body)))
            self._script_type = None


def _page(built_book: BookBuild, page: str) -> tuple[str, _PageParser]:
    path = built_book.html_dir / f"{page}.html"
    assert path.is_file(), f"{path} was not built (build exit code {built_book.returncode})"
    text = path.read_text(encoding="utf-8")
    parser = _PageParser()
    parser.feed(text)
    return text, parser


def test_build_succeeds(built_book: BookBuild) -> None:
    assert built_book.returncode == 0, (
        f"scripts/build-book.sh exited with {built_book.returncode}; end of its log "
        f"(whole log in test-artifacts/book-build.log):\n{built_book.tail()}"
    )


def test_build_has_no_warning(built_book: BookBuild) -> None:
    log = built_book.jupyter_book_log
    assert log, f"jupyter-book never ran; end of the log:\n{built_book.tail()}"
    warnings = [line for line in log.splitlines() if "WARNING" in line]
    assert not warnings, "jupyter-book warned (fatal under -W):\n" + "\n".join(warnings)


def test_every_toc_page_has_an_html_file(built_book: BookBuild) -> None:
    pages = toc_pages()
    missing = [page for page in pages if not (built_book.html_dir / f"{page}.html").is_file()]
    assert not missing, f"pages of _toc.yml without an html file: {missing}"
    assert (built_book.html_dir / "index.html").is_file(), "no index.html at the site root"


def test_offline_assets_are_part_of_the_site(built_book: BookBuild) -> None:
    static = built_book.html_dir / "_static"
    assert (static / "mathjax" / "tex-chtml.js").is_file(), "MathJax is not in _static/mathjax"
    fonts = list((static / "mathjax" / "output" / "chtml" / "fonts").rglob("*.woff"))
    assert fonts, "MathJax's CHTML fonts are missing from _static/mathjax/output/chtml/fonts"
    # the explorers' one script (no widget manager: site_postbuild.py writes them as HTML)
    assert (static / "explorers.js").is_file(), "book/_static/explorers.js is not in _static"


def test_page_fetches_nothing_from_other_sites(built_book: BookBuild, toc_page: str) -> None:
    text, parser = _page(built_book, toc_page)
    external = [url for url in parser.fetched if url.startswith(("http:", "https:", "//"))]
    assert not external, f"{toc_page}.html fetches from other sites: {external}"
    cdn = [host for host in CDN_HOSTS if host in text]
    assert not cdn, f"{toc_page}.html mentions CDN hosts {cdn} (thebe, analytics, fonts?)"
    amd = [url for url in parser.fetched if "require" in Path(url).name or "amd" in url]
    assert not amd, f"{toc_page}.html loads require.js or an AMD bundle: {amd}"


def test_explorers_are_html_with_no_widget_state(built_book: BookBuild, toc_page: str) -> None:
    """Every widget view is written as HTML (site_postbuild.py): no widget state, no manager."""
    text, parser = _page(built_book, toc_page)
    assert not parser.scripts, (
        f"{toc_page}.html still carries {len(parser.scripts)} widget state or view scripts"
    )
    widget_code = [u for u in parser.fetched if re.search(r"embed|widgets-mathjax3|lazy-expl", u)]
    assert not widget_code, f"{toc_page}.html loads widget-manager code: {widget_code}"
    if 'class="dstoolkit-explorer' in text:
        loads = r'<script (?:defer|async)(?:="(?:defer|async)")? src="[^"]*_static/explorers\.js'
        assert re.search(loads, text), (
            f"{toc_page}.html has an explorer but does not load _static/explorers.js"
        )


def test_intro_writes_its_widget(built_book: BookBuild) -> None:
    """The intro's discount slider is the canary: its widget state reached the page as HTML."""
    text, _ = _page(built_book, "book/intro")
    switches = re.search(r'<input type="range"[^>]*data-switches="([^"]+)"', text)
    assert switches, (
        "book/intro.html has no live slider; myst-nb stores the widget state only when the "
        "executed notebook carries metadata.widgets, and site_postbuild.py writes it as HTML"
    )
    assert f'data-stack="{switches.group(1).split()[0]}"' in text, "the slider switches no stack"


def test_teaching_page_has_plans_map_and_text_version(built_book: BookBuild) -> None:
    page = (built_book.html_dir / "book" / "teaching.html").read_text(encoding="utf-8")
    for needed in (
        "6-week graduate module",
        "12-week course",
        "Text version of the map",
        "tb-fig-prerequisites",
        "How the lab fits",
        "homework or class",
    ):
        assert needed in page, needed
    parser = _PageParser()
    parser.feed(page)
    assert any(url.endswith(".png") for url in parser.fetched), "the map is not an image"
    assert page.count("Chapter 12, <em>The lab</em>") == 1  # the text version lists all


def test_chapter_one_draws_the_loop(built_book: BookBuild) -> None:
    page = (built_book.html_dir / "book" / "why_bounded_noise.html").read_text(encoding="utf-8")
    assert "wb-fig-loop" in page and "dependent combination" in page


def test_the_markup_that_fails_wcag_is_written_right(built_book: BookBuild) -> None:
    """The templates and visitors of book/ give the markup axe accepts, on every page.

    The search button is named by its visible text, the colour-mode icons are decoration,
    myst-nb's toggles and the bibliography's entries carry no wrong name or role, figures
    load lazily and the copy and toggle buttons' scripts are deferred.
    """
    pages = [p for p in built_book.html_dir.rglob("*.html") if "_static" not in p.parts]
    text = "\n".join(p.read_text(encoding="utf-8") for p in pages)
    assert "search-button-field" in text and 'data-mode="light" aria-hidden="true"' in text
    assert '<button class="btn search-button-field search-button__button pst-js-only" ' in text
    assert not re.search(r'search-button-field[^>]*aria-label="Search"', text)
    assert 'title="Light"' not in text
    assert 'aria-label="Toggle hidden content"' not in text and "<summary>" in text
    assert 'role="doc-biblioentry"' not in text and 'class="citation" id=' in text
    assert 'role="listitem"' in text
    assert re.search(r'<img [^>]*loading="lazy"', text)
    assert not re.search(r'<img (?![^>]*loading="lazy")[^>]*src="[^"]*_images/', text)
    assert re.search(r'<script defer src="[^"]*copybutton\.js', text)
    search = (built_book.html_dir / "search.html").read_text(encoding="utf-8")
    assert re.search(r'<script defer src="[^"]*searchtools\.js', search)

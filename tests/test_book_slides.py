"""The lecture decks of the built book (scripts/slides.py), read as files and in Chromium.

* every numbered chapter of _toc.yml has a deck, ``slides/<stem>.html``, and its Markdown
  source beside it; each deck has a language, a title, a heading on every slide, speaker
  notes with the slide's time on every slide, and an alt text on every image;
* the deck shows the equation numbers of the chapter's labelled display formulas outside
  its exercises, every figure of the chapter page with the page's alt text, and every key
  point of the chapter;
* the slides' times add up to the chapter's class hours of the teaching page;
* a lecturer's ``slides/<stem>.md`` replaces the generated source, and ``--edit`` does not
  overwrite it;
* in headless Chromium every deck loads with nothing fetched from another host and no
  failed request, typesets its maths with the site's MathJax (no TeX left in the text),
  shows each slide's images, moves to the next slide on the right arrow key and back on the left
  one, keeps every slide's content inside the slide, and has no axe-core violation of
  WCAG 2.1 A/AA.
"""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path
from urllib.parse import urlsplit

import pytest
from bs4 import BeautifulSoup
from conftest import ROOT, BookBuild
from test_book_browser import TIMEOUT_MS, site

pytestmark = [pytest.mark.slow]
__all__ = ["site"]  # fixture used by the browser tests below


def _slides_module() -> object:
    spec = importlib.util.spec_from_file_location("slides", ROOT / "scripts" / "slides.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


slides = _slides_module()
CHAPTERS = slides.chapters(ROOT)
AXE = ROOT / "node_modules" / "axe-core" / "axe.min.js"
AXE_TAGS = ["wcag2a", "wcag2aa", "wcag21a", "wcag21aa"]


def _deck(built_book: BookBuild, stem: str) -> BeautifulSoup:
    path = built_book.html_dir / "slides" / f"{stem}.html"
    assert path.is_file(), f"no deck for chapter {stem}: {path} (see scripts/slides.py)"
    return BeautifulSoup(path.read_text(encoding="utf-8"), "html.parser")


def _page(built_book: BookBuild, stem: str) -> BeautifulSoup:
    path = built_book.html_dir / "book" / f"{stem}.html"
    return BeautifulSoup(path.read_text(encoding="utf-8"), "html.parser")


def _outside_exercises(element: object) -> bool:
    return not any(
        p.name == "details" or {"exercise", "solution", "dropdown"} & set(p.get("class") or [])
        for p in element.parents
    )


def _words(text: str) -> str:
    """Text without maths, links' markup or spacing differences, for comparisons."""
    text = re.sub(r"\\\(.*?\\\)|\$[^$]*\$", " ", text)
    return " ".join(re.findall(r"[A-Za-z]{3,}", text))


def test_chapters_are_found() -> None:
    # the deck list follows _toc.yml; the book has had twelve numbered chapters and grows
    assert len(CHAPTERS) >= 12, CHAPTERS
    assert list(CHAPTERS.values()) == list(range(1, len(CHAPTERS) + 1))


@pytest.mark.parametrize("stem", list(CHAPTERS))
def test_deck_structure(built_book: BookBuild, stem: str) -> None:
    deck = _deck(built_book, stem)
    assert deck.html.get("lang") == "en"
    assert deck.title and f"{CHAPTERS[stem]}." in deck.title.get_text()
    assert (built_book.html_dir / "slides" / f"{stem}.md").is_file()
    sections = deck.select(".reveal .slides > section")
    assert len(sections) >= 3, f"{stem}: {len(sections)} slides"
    for i, section in enumerate(sections, start=1):
        assert section.find(["h1", "h2"]), f"{stem}, slide {i} has no heading"
        notes = section.find("aside", class_="notes")
        assert notes and re.search(r"Time: \d+ min", notes.get_text()), (
            f"{stem}, slide {i} has no speaker notes with its time"
        )
    for img in deck.find_all("img"):
        alt = (img.get("alt") or "").strip()
        assert len(alt) > 20 and not re.search(r"\.(png|svg|jpe?g)$", alt), (stem, img)
        src = urlsplit(img["src"])
        assert not src.scheme and not src.netloc, f"{stem}: image from elsewhere: {img['src']}"
        assert (built_book.html_dir / "slides" / src.path).resolve().is_file(), img["src"]
    for tag, attr in (("script", "src"), ("link", "href")):
        for element in deck.find_all(tag, attrs={attr: True}):
            assert not urlsplit(element[attr]).netloc, f"{stem} loads {element[attr]}"


@pytest.mark.parametrize("stem", list(CHAPTERS))
def test_deck_content_follows_the_chapter(built_book: BookBuild, stem: str) -> None:
    deck, page = _deck(built_book, stem), _page(built_book, stem)
    article = page.find("article")
    tags = re.findall(r"\\tag\{([^}]*)\}", deck.get_text())
    numbers = [
        div.find(class_="eqno").get_text().strip("()# \n")
        for div in article.select("div.math[id^=equation-]")
        if _outside_exercises(div) and div.find(class_="eqno")
    ]
    assert tags == numbers, f"{stem}: equations {tags} on the slides, {numbers} in the chapter"
    figures = [
        f.find("img")["alt"]
        for f in article.find_all("figure")
        if f.find("img") and _outside_exercises(f)
    ]
    assert [img["alt"] for img in deck.find_all("img")] == figures, stem
    key_points = article.find(id="key-points")
    last = deck.select(".reveal .slides > section")[-1]
    assert last.find("h2").get_text() == "Key points"
    shown = _words(last.get_text())
    for li in key_points.find_all("li") if key_points else []:
        assert _words(li.get_text()) in shown, f"{stem}: key point missing: {li.get_text()}"


@pytest.mark.parametrize("stem", list(CHAPTERS))
def test_times_add_up_to_the_class_hours(built_book: BookBuild, stem: str) -> None:
    deck = _deck(built_book, stem)
    seconds = [int(s["data-timing"]) for s in deck.select(".reveal .slides > section")]
    hours = slides.class_minutes(ROOT)
    # the teaching page's table, or one session for a chapter it does not list yet
    assert sum(seconds) == 60 * hours.get(stem, slides.SESSION_MIN), (stem, seconds)
    assert min(seconds) >= 60, f"{stem}: a slide with less than a minute: {seconds}"


def test_class_hours_come_from_the_teaching_page() -> None:
    hours = slides.class_minutes(ROOT)
    assert hours, "book/teaching.md has no CHAPTERS table with class hours"
    assert set(hours) <= set(CHAPTERS)
    assert all(m > 0 and m % 30 == 0 for m in hours.values()), hours


def test_share_gives_whole_minutes_that_add_up() -> None:
    assert slides.share(10, [1, 1, 1]) == [4, 3, 3]
    assert slides.share(7, [1.0, 2.0, 4.0]) == [1, 2, 4]
    assert sum(slides.share(173, [1.0] * 12)) == 173
    assert slides.share(5, []) == []


def test_markdown_round_trip_keeps_maths_and_notes() -> None:
    source = (
        "## A slide\n\nwith $a_1 * b_2$ inline and\n\n$$\n\\frac{1}{2}\n\\tag{1.1}\n$$\n\n"
        "Note:\nTime: 3 min (minutes 0–3 of 3).\n\n---\n\n## Two\n\n- x\n\nNote:\nTime: 1 min"
    )
    page = BeautifulSoup(slides.deck_html(source, "T"), "html.parser")
    first, second = page.select(".slides > section")
    assert first["data-timing"] == "180" and second["data-timing"] == "60"
    assert "\\(a_1 * b_2\\)" in first.get_text()  # not turned into emphasis
    assert first.find(class_="display-math").get_text() == "\\[\\frac{1}{2}\n\\tag{1.1}\\]"
    assert "Time: 3 min" in first.find("aside", class_="notes").get_text()


def test_an_edited_source_replaces_the_generated_one(built_book: BookBuild, tmp_path: Path) -> None:
    stem = next(iter(CHAPTERS))
    root = tmp_path / "repo"
    (root / "slides").mkdir(parents=True)
    for name in ("_toc.yml", "_config.yml"):
        (root / name).write_text((ROOT / name).read_text(encoding="utf-8"), encoding="utf-8")
    (root / "book").symlink_to(ROOT / "book")
    site_dir = tmp_path / "site"
    site_dir.mkdir()
    (site_dir / "book").symlink_to(built_book.html_dir / "book")
    edited = "## My own slide\n\nNote:\nTime: 90 min\n"
    (root / "slides" / f"{stem}.md").write_text(edited, encoding="utf-8")
    slides.write_decks(site_dir, root)
    deck = BeautifulSoup((site_dir / "slides" / f"{stem}.html").read_text(), "html.parser")
    assert [h.get_text() for h in deck.find_all("h2")] == ["My own slide"]
    assert (site_dir / "slides" / f"{stem}.md").read_text() == edited
    with pytest.raises(slides.OutputExistsError, match="--force"):
        slides.edit(stem, site_dir, root)
    assert (root / "slides" / f"{stem}.md").read_text() == edited
    slides.edit(stem, site_dir, root, force=True)
    assert "Key points" in (root / "slides" / f"{stem}.md").read_text()


# --------------------------------------------------------------------------------------
# In the browser
# --------------------------------------------------------------------------------------

_SLIDE_FITS = """() => {
  const s = Reveal.getCurrentSlide(), c = Reveal.getConfig();
  return {height: s.scrollHeight, width: s.scrollWidth, maxHeight: c.height, maxWidth: c.width};
}"""


@pytest.mark.browser
@pytest.mark.parametrize("stem", list(CHAPTERS))
def test_deck_in_the_browser(chromium: object, site: str, stem: str) -> None:
    context = chromium.new_context(viewport={"width": 1280, "height": 800})
    page = context.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    host = urlsplit(site).netloc
    elsewhere, failed = [], []
    page.on(
        "request", lambda r: None if urlsplit(r.url).netloc == host else elsewhere.append(r.url)
    )
    page.on("response", lambda r: failed.append(f"{r.status} {r.url}") if r.status >= 400 else None)
    try:
        page.goto(f"{site}slides/{stem}.html", wait_until="load")
        page.wait_for_function("window.MathJax && MathJax.startup && MathJax.startup.promise")
        page.evaluate("MathJax.startup.promise")
        total = page.evaluate("Reveal.getTotalSlides()")
        assert total >= 3
        # maths typeset: one MathJax container per formula, no TeX left in the slides' text
        counts = page.evaluate("""() => ({
          display: document.querySelectorAll('.slides .display-math').length,
          typeset: document.querySelectorAll('.slides .display-math mjx-container').length,
          text: [...document.querySelectorAll('.slides > section')].map(s => {
            const c = s.cloneNode(true); c.querySelectorAll('aside, mjx-container')
              .forEach(e => e.remove()); return c.textContent; }).join(' ')
        })""")
        assert counts["display"] == counts["typeset"], counts
        assert not re.search(r"\\\(|\\\[|\\frac|\\tag|\$\$", counts["text"]), counts["text"]
        # the keyboard moves through the deck; every slide's content stays inside it
        page.locator("body").focus()
        for index in range(total):
            assert page.evaluate("Reveal.getIndices().h") == index
            page.evaluate("MathJax.startup.promise")
            # the slide's images (loaded lazily) come from the site
            page.wait_for_function(
                "[...Reveal.getCurrentSlide().querySelectorAll('img')].every(i => i.complete)"
            )
            images = page.evaluate(
                "[...Reveal.getCurrentSlide().querySelectorAll('img')]"
                ".map(i => [i.getAttribute('src'), i.naturalWidth])"
            )
            assert all(width for _, width in images), f"{stem}: images not loaded: {images}"
            fits = page.evaluate(_SLIDE_FITS)
            assert fits["height"] <= fits["maxHeight"] and fits["width"] <= fits["maxWidth"], (
                f"{stem}, slide {index + 1} does not fit: {fits}"
            )
            if index < total - 1:
                page.keyboard.press("ArrowRight")
        page.keyboard.press("ArrowLeft")
        assert page.evaluate("Reveal.getIndices().h") == total - 2
        page.keyboard.press("Home")
        assert page.evaluate("Reveal.getIndices().h") == 0
        page.add_script_tag(path=str(AXE))
        result = page.evaluate(
            "tags => axe.run(document, {runOnly: {type: 'tag', values: tags}})", AXE_TAGS
        )
        violations = [
            (v["id"], [n["target"] for n in v["nodes"]][:3]) for v in result["violations"]
        ]
        assert not violations, f"{stem}: axe violations {violations}"
        assert not elsewhere, f"{stem} fetched from another host: {elsewhere}"
        assert not failed, f"{stem}: failed requests {failed}"
    finally:
        context.close()


def test_a_chapter_with_no_formula_figure_or_key_points_still_gets_a_timed_deck(
    tmp_path: Path,
) -> None:
    # a chapter being written: a title, text, nothing else the deck takes
    (tmp_path / "book").mkdir()
    (tmp_path / "book" / "draft.md").write_text("# Draft\n\nText.\n", encoding="utf-8")
    (tmp_path / "_config.yml").write_text("title: A book\n", encoding="utf-8")
    site_dir = tmp_path / "site"
    (site_dir / "book").mkdir(parents=True)
    (site_dir / "book" / "draft.html").write_text(
        '<html><body><article><section id="draft"><h1><span class="section-number">13. '
        "</span>Draft</h1><p>Text.</p></section></article></body></html>",
        encoding="utf-8",
    )
    chapter = slides.read_chapter(site_dir, "draft", 13, slides.SESSION_MIN, tmp_path)
    assert chapter.title == "Draft"
    deck = BeautifulSoup(slides.deck_html(slides.deck_markdown(chapter), "T"), "html.parser")
    sections = deck.select(".slides > section")
    assert [s.find(["h1", "h2"]).get_text() for s in sections] == [
        "13. Draft",
        "In class",
        "Key points",
    ]
    assert sum(int(s["data-timing"]) for s in sections) == 60 * slides.SESSION_MIN

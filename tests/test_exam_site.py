"""The built site: no exam solution anywhere, and every chapter's learning outcomes shown.

* No file of _build/html (pages, the chapters' notebooks, sources, search data) holds a
  clause of an exam problem's worked solution, while the problems' statements are there.
* Every chapter with an outcomes file opens with "After this chapter you can…" under its
  title, each outcome linking the exercises that assess it ("Exercise N.k"); the teaching
  page lists the course's outcomes, linking the chapter outcomes, and the table of every
  chapter's outcomes.

Reads the built book (BOOK_MODULES in conftest.py).
"""

from __future__ import annotations

import html
import re
import sys

import pytest
from conftest import ROOT, BookBuild

sys.path.insert(0, str(ROOT / "scripts"))
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import dstoolkit_outcomes as outcomes  # noqa: E402
import exams  # noqa: E402
import sheets  # noqa: E402

pytestmark = pytest.mark.slow
TEXT_FILES = (".html", ".ipynb", ".md", ".txt", ".js", ".json", ".tex")
CHAPTERS = outcomes.toc_chapters(ROOT)
ROLE_OR_MATHS = re.compile(r"\{[\w:-]+\}`[^`]*`|" + exams.MATHS.pattern, re.S)


def _plain(text: str) -> str:
    return html.unescape(re.sub(r"<[^>]+>", " ", text))


@pytest.fixture(scope="module")
def site(built_book: BookBuild) -> dict[str, str]:
    assert built_book.returncode == 0, built_book.tail()
    files = {
        str(p.relative_to(built_book.html_dir)): exams.words(
            _plain(p.read_text(encoding="utf-8", errors="replace"))
        )
        for p in built_book.html_dir.rglob("*")
        if p.is_file() and p.suffix in TEXT_FILES
    }
    assert any(name.endswith(".ipynb") for name in files), "the site offers no notebook"
    return files


def test_no_exam_solution_anywhere_in_the_site(site: dict[str, str]) -> None:
    telltales = exams.telltales(ROOT)
    found = {
        name: sorted(label for label, runs in telltales.items() if any(r in text for r in runs))
        for name, text in site.items()
    }
    assert {name: labels for name, labels in found.items() if labels} == {}


@pytest.mark.parametrize("docname", CHAPTERS)
def test_the_exam_problems_themselves_are_on_the_site(site: dict[str, str], docname: str) -> None:
    page = site[f"{docname}.html"]
    chapter = (ROOT / f"{docname}.md").read_text(encoding="utf-8")
    for label in exams.exam_labels(docname.rsplit("/", 1)[-1], ROOT):
        block = re.search(rf"^:label: {label}\n(.*?)^```", chapter, re.M | re.S)
        assert block, label
        # the first four words of prose with no maths and no role in between
        stretches = (exams.words(s).split() for s in ROLE_OR_MATHS.split(block.group(1)))
        first = " ".join(next(s for s in stretches if len(s) >= 4)[:4])
        assert first in page, (label, first)


@pytest.mark.parametrize("docname", CHAPTERS)
def test_every_chapter_opens_with_its_outcomes(built_book: BookBuild, docname: str) -> None:
    page = (built_book.html_dir / f"{docname}.html").read_text(encoding="utf-8")
    found = outcomes.load(outcomes.outcomes_path(ROOT / f"{docname}.md"))
    box = re.search(r'<div class="[^"]*\bdstoolkit-outcomes\b[^"]*">(.*?)</div>', page, re.S)
    assert box, f"{docname}: no outcomes box"
    above = page[page.rindex("<h1", 0, box.start()) : box.start()]  # from the chapter's title
    assert "<h2" not in above, "a section comes between the title and the box"
    assert outcomes.CHAPTER_LEAD in box.group(1)
    number = sheets.chapter_numbers(ROOT / "_toc.yml")[docname.rsplit("/", 1)[-1]]
    for outcome in found:
        item = re.search(rf'<li id="{outcome["id"]}">(.*?)</li>', box.group(1), re.S)
        assert item, outcome["id"]
        links = re.findall(r'href="#([\w-]+)"[^>]*>.*?Exercise ([\d.]+)', item.group(1), re.S)
        assert [label for label, _ in links] == outcome["exercises"]
        assert all(n.startswith(f"{number}.") for _, n in links), links


def test_the_teaching_page_lists_the_course_outcomes_and_the_table(built_book: BookBuild) -> None:
    page = (built_book.html_dir / "book" / "teaching.html").read_text(encoding="utf-8")
    text = _plain(page)
    course = outcomes.load(ROOT / "book" / "outcomes" / "course.yml")
    for outcome in course:
        assert f'id="{outcome["id"]}"' in page
        assert exams.words(outcome["text"]) in exams.words(text), outcome["id"]
        for oid in outcome["exercises"]:
            assert re.search(rf'href="[\w.]*#{oid}"', page), (outcome["id"], oid)
    assert "dstoolkit-outcomes-table" in page
    for docname in CHAPTERS:
        for outcome in outcomes.load(outcomes.outcomes_path(ROOT / f"{docname}.md")):
            assert f"{outcome['id']}: " in text, outcome["id"]
            assert exams.words(outcome["text"]) in exams.words(text), outcome["id"]

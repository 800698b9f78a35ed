"""Editorial rules of the book that a script can check.

- no chapter has more than about 4,000 words of prose (code cells and maths not counted);
- no internal working document is named anywhere a reader or user looks (the book, the
  package, the notebooks, the tests): cite the paper instead;
- every work cited with {cite} is in book/references.bib with author, title and year;
- the lab's widget starts at the volume the lab's safety advice gives.
"""

from __future__ import annotations

import re

import jupytext
import pytest
from conftest import ROOT, toc_pages

MAX_PROSE_WORDS = 4000
INTERNAL = re.compile(r"\b(SPEC|DESIGN)(\.md)?\b")
CITE = re.compile(r"\{cite(?::[a-z]+)?\}`([^`]+)`")
FENCED_CODE = re.compile(r"```(?:python|bash|text|console)?\n.*?```", flags=re.S)
DISPLAY_MATHS = re.compile(r"\$\$.*?\$\$", flags=re.S)


def prose_words(page: str) -> int:
    notebook = jupytext.read(ROOT / f"{page}.md")
    words = 0
    for cell in notebook.cells:
        if cell.cell_type == "markdown":
            text = DISPLAY_MATHS.sub(" ", FENCED_CODE.sub(" ", cell.source))
            words += len(re.findall(r"[A-Za-z][A-Za-z'’-]+", text))
    return words


@pytest.mark.parametrize("page", toc_pages())
def test_no_chapter_is_a_wall_of_prose(page: str) -> None:
    words = prose_words(page)
    assert words <= MAX_PROSE_WORDS, f"{page}: {words} words of prose"


def test_the_counter_counts_prose() -> None:
    assert 600 < prose_words("book/intro") < 2000


def test_no_internal_document_is_named() -> None:
    found = []
    for folder, pattern in (
        ("book", "*.md"),
        ("dstoolkit", "*.py"),
        ("tests", "*.py"),
        ("notebooks", "*.ipynb"),
        ("scripts", "*.sh"),
    ):
        for path in sorted((ROOT / folder).rglob(pattern)):
            if path.name == "test_book_text.py":
                continue
            for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if INTERNAL.search(line):
                    found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()[:80]}")
    assert not found, "internal documents named:\n  " + "\n  ".join(found)


def test_every_cited_work_is_in_the_bibliography() -> None:
    bib = (ROOT / "book" / "references.bib").read_text(encoding="utf-8")
    entries = dict(re.findall(r"@\w+\{(\w+),(.*?)\n\}", bib, flags=re.S))
    cited = set()
    for path in (ROOT / "book").glob("*.md"):
        for keys in CITE.findall(path.read_text(encoding="utf-8")):
            cited.update(key.strip() for key in keys.split(","))
    assert {"wu1996", "cramer1993", "xu2017"} <= cited
    missing = sorted(cited - set(entries))
    assert not missing, f"cited but not in references.bib: {missing}"
    incomplete = [
        key
        for key in cited
        if not all(
            re.search(rf"\b{field}\s*=", entries[key]) for field in ("author", "title", "year")
        )
    ]
    assert not incomplete, f"entries without author, title or year: {incomplete}"


def test_the_lab_widget_starts_at_the_safe_volume() -> None:
    from dstoolkit.teaching import LabSettings

    lab = (ROOT / "book" / "lab.md").read_text(encoding="utf-8")
    advice = re.search(r"volume low \((\d\.\d+) in the widget\)", lab)
    assert advice, "the lab's safety advice on the volume is gone"
    assert LabSettings().volume == pytest.approx(float(advice.group(1)))

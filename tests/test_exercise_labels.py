"""Every exercise shows its kind and difficulty, and the book has the exercises a course needs.

* The kind (Compute, Code, Predict, Proof, Explain, Exam) and the difficulty (1 to 3) are
  written once, as the title of the chapter's ``{exercise}``; the site and the PDF show it
  after the exercise's number, and the exercise sheets repeat it in their headings.
* Each theory chapter (2 to 5) has a proof; every numbered chapter has an exam problem.
* The shown kind agrees with how the sheet grades the exercise: a Code exercise is a coding
  exercise of the sheet, and a written kind (Proof, Explain, Exam) is never one.
* Every proof and exam problem has a worked solution that ends with words, not a formula
  (the exam problems' in the teacher-only bank, instructor/exams/).
"""

from __future__ import annotations

import re
import sys

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
import exams  # noqa: E402
import sheets  # noqa: E402

NUMBERS = sheets.chapter_numbers(ROOT / "_toc.yml")
THEORY = ("mass_functions", "combining_evidence", "dependent_evidence", "random_sets")
SOLUTION = re.compile(
    r"^(`{3,})\{solution\} ([\w-]+)\n(?::class: dropdown\n)?(.*?)^\1$", re.MULTILINE | re.DOTALL
)
MATHS = re.compile(r"\$\$.*?\$\$|\$[^$]*\$", re.DOTALL)


def captions(stem: str) -> dict[str, str]:
    return sheets.chapter_captions(ROOT / "book" / f"{stem}.md")


def kinds(stem: str) -> dict[str, str]:
    return {label: sheets.CAPTION.match(c).group(1) for label, c in captions(stem).items()}


@pytest.mark.parametrize("stem", sorted(NUMBERS))
def test_every_exercise_has_a_kind_and_a_difficulty(stem: str) -> None:
    text = (ROOT / "book" / f"{stem}.md").read_text(encoding="utf-8")
    found = captions(stem)  # raises on a title that is not a caption
    assert len(found) == len(re.findall(r"^`{3,}\{exercise\}", text, re.MULTILINE)), stem
    assert found, f"chapter {NUMBERS[stem]} ({stem}) has no exercise"


def test_a_missing_caption_is_an_error(tmp_path) -> None:
    page = tmp_path / "page.md"
    page.write_text("```{exercise}\n:label: x-ex-a\n\nDo it.\n```\n", encoding="utf-8")
    with pytest.raises(ValueError, match="x-ex-a"):
        sheets.chapter_captions(page)
    page.write_text(
        "```{exercise} Proof, difficulty 4 of 3\n:label: x-ex-a\n\nDo.\n```\n", encoding="utf-8"
    )
    with pytest.raises(ValueError, match="difficulty"):
        sheets.chapter_captions(page)


@pytest.mark.parametrize("stem", THEORY)
def test_each_theory_chapter_has_a_proof(stem: str) -> None:
    assert "Proof" in kinds(stem).values(), f"chapter {NUMBERS[stem]} ({stem}) has no proof"


@pytest.mark.parametrize("stem", sorted(NUMBERS))
def test_every_chapter_has_an_exam_problem(stem: str) -> None:
    assert "Exam" in kinds(stem).values(), f"chapter {NUMBERS[stem]} ({stem}) has no exam"


@pytest.mark.parametrize("stem", sorted(NUMBERS))
def test_the_shown_kind_agrees_with_the_sheet(stem: str) -> None:
    graded = dict(sheets.parse(ROOT / "notebooks" / "source" / f"{stem}.md").exercises())
    for label, kind in kinds(stem).items():
        assert (kind == "Code") == (graded[label] == "coding"), (label, kind, graded[label])
        if kind in ("Proof", "Explain", "Exam"):
            assert graded[label] in ("proof", "explanation"), (label, kind, graded[label])


@pytest.mark.parametrize("stem", sorted(NUMBERS))
def test_the_sheet_headings_show_the_caption(stem: str) -> None:
    number, title, src, labels = sheets.sheets(ROOT)[stem]
    nb = sheets.build(src, number, title, labels, False)
    heads = [
        c["source"] if isinstance(c["source"], str) else "".join(c["source"])
        for c in nb["cells"]
        if c["metadata"].get("dstoolkit", {}).get("exercise")
    ]
    shown = captions(stem)
    assert [h.splitlines()[0] for h in heads] == [
        f"## Exercise {number}.{k} ({shown[label]})" for k, label in enumerate(labels, 1)
    ]


@pytest.mark.parametrize("stem", sorted(NUMBERS))
def test_written_solutions_end_with_their_reasoning(stem: str) -> None:
    text = (ROOT / "book" / f"{stem}.md").read_text(encoding="utf-8")
    solutions = {m.group(2): m.group(3) for m in SOLUTION.finditer(text)}
    solutions.update({label: e["solution"] for label, e in exams.bank(stem, ROOT).items()})
    for label, kind in kinds(stem).items():
        if kind not in ("Proof", "Exam"):
            continue
        assert label in solutions, f"{label} has no worked solution"
        last = MATHS.sub(" ", solutions[label].strip()).rstrip()
        last_sentence = re.split(r"(?<=[.:;])\s+", last.rstrip("."))[-1]
        assert len(re.findall(r"[A-Za-z]{2,}", last_sentence)) >= 5, (label, last_sentence)

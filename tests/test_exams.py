"""The private exam bank: exam solutions only in the teacher's edition, and two sample exams.

* Every exam problem of every chapter has its worked solution and a marking scheme in the
  teacher-only bank (instructor/exams/), whose parts match the problem's parts and add up to
  the problem's points; the book's chapters and the sheets' sources hold no exam solution.
* No exam solution is in the students' sheets (as stored, and as built now); the teacher's
  edition has every one, with its marking scheme.
* The sample exams (mid-term: chapters 1–6; final: all) are built from the exam problems of
  the chapters they cover, and their time allows the longest choice a candidate can make.
* The PDFs (slow): both editions build, hold every problem (pdftotext), and only the
  teacher's holds the worked solutions and the marking schemes.

The built site is checked by tests/test_exam_site.py (it reads the built book).
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
import exams  # noqa: E402
import sheets  # noqa: E402

NUMBERS = sheets.chapter_numbers(ROOT / "_toc.yml")
TELLTALES = exams.telltales(ROOT)
SOLUTION_BLOCK = re.compile(r"^(`{3,}|:{3,})\{solution\} ([\w-]+)$", re.MULTILINE)


def leaks(text: str) -> list[str]:
    """Return the exam problems whose solution shows in ``text``."""
    haystack = exams.words(text)
    return sorted(label for label, runs in TELLTALES.items() if any(r in haystack for r in runs))


def test_every_solution_has_telltales_and_the_finder_finds_them() -> None:
    assert set(TELLTALES) == {
        label for stem in NUMBERS for label in exams.exam_labels(stem, ROOT)
    }, "an exam problem has no entry in the bank"
    for label, runs in TELLTALES.items():
        assert len(runs) >= 2, f"{label}: too few clauses to recognise its solution by"
    label, runs = next(iter(TELLTALES.items()))
    page = f"<p>Some text, then <b>{runs[0]}</b> and $x = 1$ more.</p>"
    assert leaks(page) == [label]
    assert leaks("<p>Nothing to see.</p>") == []


@pytest.mark.parametrize("stem", sorted(NUMBERS))
def test_the_bank_holds_each_exam_problem_with_a_marking_scheme(stem: str) -> None:
    found = exams.bank(stem, ROOT)  # raises when a problem is missing or the points do not add up
    statements = {
        b.arg.split()[0]: b.text
        for b in sheets.parse(ROOT / "notebooks" / "source" / f"{stem}.md").blocks
        if b.kind == "exercise"
    }
    for label, entry in found.items():
        asked = exams.PART.findall(statements[label])
        marked = [m["part"] for m in entry["marking"]]
        assert marked == (asked or ["all"]), (label, asked, marked)
        assert sum(m["points"] for m in entry["marking"]) == exams.POINTS
        assert all(len(m["earns"].split()) >= 6 for m in entry["marking"]), label
        assert "{{" not in entry["solution"], f"{label}: a number is not filled in"


def test_a_marking_that_does_not_add_up_is_refused(tmp_path: Path) -> None:
    for part in ("_toc.yml", "book/mass_functions.md"):
        (tmp_path / part).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / part, tmp_path / part)
    (tmp_path / exams.BANK).mkdir(parents=True)
    text = (ROOT / exams.BANK / "mass_functions.yml").read_text(encoding="utf-8")
    (tmp_path / exams.BANK / "mass_functions.yml").write_text(
        text.replace("points: 9,", "points: 10,"), encoding="utf-8"
    )
    with pytest.raises(ValueError, match="adds up to 26"):
        exams.bank("mass_functions", tmp_path)
    (tmp_path / exams.BANK / "mass_functions.yml").unlink()
    with pytest.raises(ValueError, match="no instructor/exams/mass_functions.yml"):
        exams.bank("mass_functions", tmp_path)


@pytest.mark.parametrize("stem", sorted(NUMBERS))
def test_no_exam_solution_in_the_chapter_or_the_sheet_source(stem: str) -> None:
    chapter = (ROOT / "book" / f"{stem}.md").read_text(encoding="utf-8")
    labels = exams.exam_labels(stem, ROOT)
    solved = {label for _, label in SOLUTION_BLOCK.findall(chapter)}
    assert not solved & set(labels), sorted(solved & set(labels))
    assert leaks(chapter) == []
    source = (ROOT / "notebooks" / "source" / f"{stem}.md").read_text(encoding="utf-8")
    assert leaks(source) == []


def _cells(notebook: dict) -> str:
    return "\n".join(
        "".join(c["source"]) + json.dumps(c.get("metadata", {})) for c in notebook["cells"]
    )


@pytest.mark.parametrize("stem", sorted(NUMBERS))
def test_the_students_sheets_hold_no_exam_solution_and_the_teachers_every_one(stem: str) -> None:
    number, title, src, labels = sheets.sheets(ROOT)[stem]
    stored = json.loads(sheets.sheet_path(stem, number, ROOT / "notebooks").read_text("utf-8"))
    assert leaks(json.dumps(stored)) == []
    assert leaks(_cells(sheets.build(src, number, title, labels, False))) == []
    teacher = _cells(sheets.build(src, number, title, labels, True))
    mine = exams.exam_labels(stem, ROOT)
    assert leaks(teacher) == sorted(mine)
    assert teacher.count("**Marking scheme**") == len(mine)


def test_the_sample_exams_cover_their_chapters_and_fit_their_time() -> None:
    found = exams.exams(ROOT)
    assert set(found) == {"midterm", "final"}
    order = list(NUMBERS)
    covered = {
        key: [s for section in e["sections"] for s in section["chapters"]]
        for key, e in found.items()
    }
    assert covered["midterm"] == order[:6]
    assert covered["final"] == order
    for exam in found.values():
        labels = [p.label for s in exam["sections"] for p in s["problems"]]
        chapters = [c for s in exam["sections"] for c in s["chapters"]]
        assert labels == [x for stem in chapters for x in exams.exam_labels(stem, ROOT)]
        longest = sum(
            sum(sorted((p.minutes for p in s["problems"]), reverse=True)[: s["answer"]])
            for s in exam["sections"]
        )
        assert exam["minutes"] == longest


def test_the_latex_keeps_maths_and_escapes_prose() -> None:
    out = exams.latex("**(a)** Take $x_1 \\le 50\\%$ of 50% & *one* `f(x)`:\n- a\n- b\n")
    assert r"\textbf{(a)}" in out and r"$x_1 \le 50\%$" in out
    assert r"50\% \&" in out and r"\emph{one}" in out and r"\texttt{f(x)}" in out
    assert "\\begin{itemize}\n\\item a\n\\item b\n\\end{itemize}" in out


def _prose_start(markdown: str, n: int = 4) -> str:
    """Return the first ``n`` words of the first stretch of prose without maths in ``markdown``.

    (In a PDF's text the maths come out as glyphs, so a run across maths would not match.)
    """
    for prose in exams.MATHS.split(markdown):
        found = exams.words(prose).split()
        if len(found) >= n:
            return " ".join(found[:n])
    raise AssertionError(f"no {n} words of prose in {markdown[:60]!r}")


def _pdf_text(path: Path) -> str:
    return subprocess.run(
        ["pdftotext", "-layout", str(path), "-"], check=True, capture_output=True, text=True
    ).stdout


@pytest.fixture(scope="module")
def built_exams(tmp_path_factory) -> dict[str, str]:
    missing = [t for t in ("xelatex", "latexmk", "pdftotext") if shutil.which(t) is None]
    if missing:
        pytest.fail(f"the sample exams need {missing} (TeX Live, poppler-utils)")
    folder = tmp_path_factory.mktemp("exams")
    return {path.stem: _pdf_text(path) for path in exams.build(folder, ROOT)}


@pytest.mark.slow
@pytest.mark.parametrize("key", ["midterm", "final"])
def test_the_exam_pdfs_hold_every_problem_and_only_the_teachers_the_answers(
    built_exams: dict[str, str], key: str
) -> None:
    student, teacher = built_exams[key], built_exams[f"{key}-teacher"]
    exam = exams.exams(ROOT)[key]
    problems = [p for s in exam["sections"] for p in s["problems"]]
    for k, problem in enumerate(problems, 1):
        head = f"Problem {k} (from Exercise {problem.number}.{problem.order} of the book)"
        first = _prose_start(problem.statement)
        for text in (student, teacher):
            assert head in text, (key, head)
            assert first in exams.words(text), (key, problem.label, first)
    assert "Marking scheme" in teacher and "what earns them" in teacher
    assert "Marking scheme" not in student and "Worked solution" not in student
    assert leaks(student) == []
    assert leaks(teacher) == sorted(p.label for p in problems)
    for problem in problems:
        for mark in problem.marking:
            words = " ".join(exams.words(mark["earns"]).split()[:5])
            assert words in exams.words(teacher) and words not in exams.words(student)

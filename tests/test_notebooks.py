"""The exercise sheets (notebooks/NN_<chapter>.ipynb) follow the book and teach.

* The sheets follow the book: chapter N of _toc.yml (numbered across parts) has the sheet
  ``NN_<stem>.ipynb``, whose k-th exercise is "Exercise N.k", the k-th ``{exercise}`` of
  the chapter; no other sheet exists.
* They are written from one source each (notebooks/source/<stem>.md) by scripts/sheets.py,
  stored without outputs, and hold no solution in any form; the teacher's edition holds
  every solution.
* Every sheet is executed three times: as shipped (every check says "not answered yet"),
  as the teacher's edition (every check says right), and with a plausible wrong answer or
  implementation in every check (every check says wrong, and names the mistake where one
  is registered). Explorer cells run in the first execution only.
"""

from __future__ import annotations

import copy
import json
import re
import sys

import nbformat
import pytest
from conftest import ROOT, execute_notebook

from dstoolkit.teaching import REGISTRY, CodingExercise

sys.path.insert(0, str(ROOT / "scripts"))
import sheets  # noqa: E402

NOTEBOOKS = ROOT / "notebooks"
SOURCES = sheets.sheets(ROOT)
NUMBERS = sheets.chapter_numbers(ROOT / "_toc.yml")
STEMS = sorted(SOURCES)
CHECK_ID = re.compile(r'check\("([a-z]+\.[a-z0-9-]+)"')
WIDGET = "application/vnd.jupyter.widget-view+json"
#: How many exercises in all, and how many coding ones, the book has at least.
MIN_EXERCISES, MIN_CODING = 70, 15


def _student(stem: str) -> nbformat.NotebookNode:
    return nbformat.read(sheets.sheet_path(stem, NUMBERS[stem], NOTEBOOKS), as_version=4)


def _teacher(stem: str) -> nbformat.NotebookNode:
    number, title, src, labels = SOURCES[stem]
    return nbformat.reads(json.dumps(sheets.build(src, number, title, labels, True)), as_version=4)


def _tags(cell: nbformat.NotebookNode) -> list[str]:
    return cell.metadata.get("tags", [])


def _check_id(cell: nbformat.NotebookNode) -> str:
    (found,) = CHECK_ID.findall(cell.source)
    return found


# -- the sheets follow the book ---------------------------------------------------------------


def test_every_chapter_with_exercises_has_its_sheet_and_no_other_sheet_exists():
    expected = set()
    for stem, number in NUMBERS.items():
        if sheets.chapter_exercises(ROOT / "book" / f"{stem}.md"):
            assert stem in SOURCES, f"chapter {number} ({stem}) has exercises but no sheet"
            expected.add(sheets.sheet_path(stem, number, NOTEBOOKS).name)
    assert {p.name for p in NOTEBOOKS.glob("*.ipynb")} == expected


@pytest.mark.parametrize("stem", STEMS)
def test_sheet_numbers_follow_the_chapter(stem: str):
    """Exercise N.k of the sheet is the k-th exercise of chapter N (labels in order)."""
    number, labels = NUMBERS[stem], sheets.chapter_exercises(ROOT / "book" / f"{stem}.md")
    nb = _student(stem)
    assert nb.cells[0].source.startswith(f"# Exercises of Chapter {number}:")
    heads = [c for c in nb.cells if c.metadata.get("dstoolkit", {}).get("exercise")]
    assert [c.metadata["dstoolkit"]["exercise"] for c in heads] == labels
    assert [c.source.splitlines()[0].partition(" (")[0] for c in heads] == [
        f"## Exercise {number}.{k}" for k in range(1, len(labels) + 1)
    ]


def test_the_chapters_link_to_the_sheets_that_exist():
    for chapter in sorted((ROOT / "book").glob("*.md")):
        for name in re.findall(r"notebooks/(\d\d_\w+\.ipynb)", chapter.read_text("utf-8")):
            assert (NOTEBOOKS / name).exists(), f"{chapter.name} links to {name}"


def test_sheets_drift_is_caught(tmp_path):
    """A chapter that gains an exercise its sheet lacks makes the sheet fail to build."""
    stem = STEMS[0]
    number, title, src, labels = SOURCES[stem]
    with pytest.raises(ValueError, match="exercises"):
        sheets.build(src, number, title, [*labels, "new-exercise"], False)
    with pytest.raises(ValueError, match="number 1"):
        sheets.build(src, number, title, labels[::-1], False)


# -- one source, two editions ----------------------------------------------------------------


@pytest.mark.parametrize("stem", STEMS)
def test_student_sheet_is_the_one_written_from_its_source(stem: str):
    number, title, src, labels = SOURCES[stem]
    stored = sheets.sheet_path(stem, number, NOTEBOOKS).read_text(encoding="utf-8")
    assert stored == sheets.dump(sheets.build(src, number, title, labels, False)), (
        "run: .venv/bin/python scripts/sheets.py"
    )


@pytest.mark.parametrize("stem", STEMS)
def test_no_solution_text_reaches_a_student_sheet(stem: str):
    """No line of a teacher-only cell is in the student's file (not even in metadata).

    The exception is the signature and docstring a coding stub shares with its solution.
    """
    raw = sheets.sheet_path(stem, NUMBERS[stem], NOTEBOOKS).read_text(encoding="utf-8")
    student = _student(stem)
    stub_lines = {
        line.strip()
        for c in student.cells
        if "answer" in _tags(c)
        for line in c.source.splitlines()
    }
    hidden = [c for c in _teacher(stem).cells if "solution" in _tags(c)]
    assert hidden, "the teacher's edition has no solution"
    text = json.dumps(json.loads(raw), ensure_ascii=False)  # every string of the file
    for cell in hidden:
        for line in cell.source.replace("**Solution.**", "").splitlines():
            line = line.strip()
            if len(line) > 12 and line not in stub_lines:
                assert json.dumps(line, ensure_ascii=False)[1:-1] not in text, line
    assert '"solution"' not in raw and "Solution." not in raw


@pytest.mark.parametrize("stem", STEMS)
def test_sheet_is_stored_without_outputs_and_short_cells(stem: str):
    nb = _student(stem)
    checks = [c for c in nb.cells if "check" in _tags(c)]
    assert checks, "a sheet without check cells"
    for cell in nb.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, cell.source[:60]
            assert len(cell.source.splitlines()) <= 25, cell.source[:60]
    for cell in checks:
        assert len(sheets.CHECK.findall(cell.source)) == 1, "one check per check cell"
        assert _check_id(cell) in REGISTRY, cell.source
    assert nb.metadata["kernelspec"]["name"] == "python3"


def test_every_registered_exercise_is_on_a_sheet():
    used = {_check_id(c) for stem in STEMS for c in _student(stem).cells if "check" in _tags(c)}
    assert set(REGISTRY) - used == set()


def test_the_exercises_are_many_and_varied():
    """At least 70 exercises, 15 of them coding, and varied kinds in every chapter.

    Per chapter at least 2 that are coding, proof, prediction or explanation, and a
    prediction wherever the sheet has an explorer.
    """
    kinds = {stem: [kind for _, kind in SOURCES[stem][2].exercises()] for stem in STEMS}
    assert sum(map(len, kinds.values())) >= MIN_EXERCISES
    assert sum(k.count("coding") for k in kinds.values()) >= MIN_CODING
    for stem, found in kinds.items():
        assert sum(k != "substitution" for k in found) >= 2, stem
        chapter = (ROOT / "book" / f"{stem}.md").read_text(encoding="utf-8")
        if any("explorer" in _tags(c) for c in _student(stem).cells) or re.search(
            r"_explorer\(|lab_widget\(|filter_widget\(", chapter
        ):
            assert "prediction" in found, f"{stem}: an explorer but no prediction exercise"
    coding_ids = {k for k, v in REGISTRY.items() if isinstance(v, CodingExercise)}
    assert len(coding_ids) >= MIN_CODING


# -- three executions -----------------------------------------------------------------------


def _results(nb: nbformat.NotebookNode) -> dict[str, str]:
    """{exercise id: what its check cell showed}."""
    out = {}
    for cell in nb.cells:
        if "check" in _tags(cell):
            shown = [
                o.get("data", {}).get("text/plain", "")
                for o in cell.outputs
                if o.get("output_type") == "execute_result"
            ]
            out[_check_id(cell)] = "".join(shown)
    return out


def _without_explorers(nb: nbformat.NotebookNode) -> nbformat.NotebookNode:
    nb = copy.deepcopy(nb)
    nb.cells = [c for c in nb.cells if "explorer" not in _tags(c)]
    return nb


@pytest.mark.slow
@pytest.mark.parametrize("stem", STEMS)
def test_sheet_as_shipped_says_not_answered_yet(stem: str):
    nb = execute_notebook(_student(stem), NOTEBOOKS)
    results = _results(nb)
    assert results
    for eid, shown in results.items():
        assert f"{eid}: not answered yet" in shown, (eid, shown)
    if any("explorer" in _tags(c) for c in nb.cells):
        widgets = [o for c in nb.cells for o in c.get("outputs", []) if WIDGET in o.get("data", {})]
        assert widgets, "the sheet's explorer displayed no widget"


@pytest.mark.slow
@pytest.mark.parametrize("stem", STEMS)
def test_teachers_edition_says_right_everywhere(stem: str):
    nb = execute_notebook(_without_explorers(_teacher(stem)), NOTEBOOKS)
    results = _results(nb)
    assert results
    for eid, shown in results.items():
        assert shown.startswith(f"✔ {eid}: right"), (eid, shown)


@pytest.mark.slow
@pytest.mark.parametrize("stem", STEMS)
def test_wrong_answers_are_caught_and_named(stem: str):
    nb = _without_explorers(_teacher(stem))
    for cell in nb.cells:
        if "check" in _tags(cell):
            eid, var = sheets.CHECK.findall(cell.source)[0]
            cell.source = "from dstoolkit.teaching import mistake\n" + cell.source.replace(
                f'check("{eid}", {var})', f'check("{eid}", mistake("{eid}"))'
            )
    results = _results(execute_notebook(nb, NOTEBOOKS))
    assert results
    for eid, shown in results.items():
        assert shown.startswith(f"✘ {eid}: wrong"), (eid, shown)
        if REGISTRY[eid].mistakes:
            assert REGISTRY[eid].mistakes[0][1] in re.sub(r"\s+", " ", shown), (eid, shown)

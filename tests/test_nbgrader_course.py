"""The nbgrader course (scripts/sheets.py --nbgrader DIR) grades as an instructor needs.

The real nbgrader pipeline runs offline on the generated assignment of Chapter 3 in
variant 1 (other numbers than the book's): ``generate_assignment``, ``autograde`` of eight
made-up submissions, a written part graded
by hand through the gradebook, ``generate_feedback`` and ``export``. The exported CSV must
hold the exact score of each submission:

* blank: 0;
* all right (the teacher's answers): every autograded point, plus the written points the
  test grades by hand;
* partly right, a crash (SyntaxError and ZeroDivisionError in two answer cells), an endless
  loop (one at the top of an answer cell, stopped by the per-cell time limit, one in a
  function, stopped by the check's time limit): the points of the cells that are right;
* one that redefines ``check`` and ``must_pass`` and edits a test cell: 0;
* one whose coding answers only call dstoolkit's own implementation: the value answers'
  points only (the hidden tests run where dstoolkit cannot be reached);
* one that copies the book's printed answers and switches the notebook back to the book's
  numbers (``set_variant(0)``), so that the visible tests pass: the coding points and the
  one value answer that is the same in every variant only (the hidden tests compute the
  answers from the variant's data).

The feedback pages write the formulas in Unicode (nbgrader's pages load no MathJax) and show
a failing check's verdict once.
"""

from __future__ import annotations

import csv
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
import course  # noqa: E402
import sheets  # noqa: E402

from dstoolkit.teaching._variants import data  # noqa: E402

pytestmark = pytest.mark.slow

STEM = "combining_evidence"
NAME = "03_combining_evidence"
NBGRADER = Path(sys.executable).with_name("nbgrader")
#: The per-cell limit of this test's autograde run (the course's own is longer).
CELL_TIMEOUT = 20

VARIANT = 1
BOOK_VALUES = {  # answer cell → the answer printed in the book (variant 0)
    "ce-ex-conflict-answer": "K = 0.54",
    "ce-ex-low-answer": "m12_low = 0.1304347826",
    "ce-ex-zadeh-answer": "K_zadeh = 0.9999",
    "ce-ex-zadeh-answer-2": "tumour = 1.0",
    "ce-ex-twice-answer": "twice = 0.75",
}


def _variant_values(d: dict) -> dict[str, str]:
    """Compute the right answers of the variant by the chapter's formulas.

    The test does not trust the generator's answers.
    """
    k = d["m1_low"] * (d["m2_high"] + d["m2_mid_high"])
    return {
        "ce-ex-conflict-answer": f"K = {k!r}",
        "ce-ex-low-answer": f"m12_low = {d['m1_low'] * d['m2_theta'] / (1 - k)!r}",
        "ce-ex-zadeh-answer": f"K_zadeh = {1 - d['zadeh_x_rest'] * d['zadeh_y_rest']!r}",
        "ce-ex-zadeh-answer-2": "tumour = 1.0",
        "ce-ex-twice-answer": f"twice = {1 - d['once_theta'] ** 2!r}",
    }


VALUES = _variant_values(data("combine", VARIANT))
BACK_TO_THE_BOOK = "from dstoolkit.teaching import set_variant\nset_variant(0)\n"
WRAP_DEMPSTER = """def dempster_rule(m1, m2):
    from dstoolkit import MassFunction, dempster
    frame = frozenset().union(*m1, *m2)
    both = dempster(MassFunction(m1, frame=frame), MassFunction(m2, frame=frame))
    return {frozenset(k): v for k, v in both.as_dict().items()}
"""
WRAP_DISCOUNT = """def discount_rule(m, rate, frame):
    return {frozenset(k): v for k, v in
            discount(MassFunction(m, frame=frame), rate).as_dict().items()}
"""
LOOPING_DEMPSTER = """def dempster_rule(m1, m2):
    while True:
        pass
"""
WRONG_DISCOUNT = """def discount_rule(m, rate, frame):
    return {**m, frozenset(frame): m.get(frozenset(frame), 0.0) + rate}
"""


def _nbgrader(course_dir: Path, *args: str) -> subprocess.CompletedProcess:
    done = subprocess.run(
        [str(NBGRADER), *args], cwd=course_dir, capture_output=True, text=True, timeout=1800
    )
    assert done.returncode == 0, f"nbgrader {' '.join(args)}:\n{done.stdout}\n{done.stderr}"
    return done


def _cells(nb: dict) -> dict[str, dict]:
    return {
        c["metadata"]["nbgrader"]["grade_id"]: c for c in nb["cells"] if "nbgrader" in c["metadata"]
    }


def _submission(
    release: dict, teacher: dict, answers: dict[str, str], edits: dict[str, str] | None = None
) -> dict:
    """Return the released notebook with ``answers`` in answer cells.

    ``"teacher"`` stands for the source's own answer; ``edits`` are written over any other
    cell.
    """
    nb = json.loads(json.dumps(release))
    cells, source = _cells(nb), _cells(teacher)
    for grade_id, text in {**answers, **(edits or {})}.items():
        cells[grade_id]["source"] = source[grade_id]["source"] if text == "teacher" else text
    return nb


@pytest.fixture(scope="module")
def graded(tmp_path_factory: pytest.TempPathFactory) -> dict[str, dict[str, str]]:
    """{student: their row of the exported CSV} after the whole pipeline."""
    if not NBGRADER.exists():
        pytest.fail(
            f"nbgrader is not installed in {NBGRADER.parent}: install the teach "
            "extra (bash scripts/ensure-env.sh does)"
        )
    home = tmp_path_factory.mktemp("course")
    written = course.write_course(home, ROOT, [STEM], VARIANT)
    assert [p.name for p in written] == ["nbgrader_config.py", "mathjax.html.j2", f"{NAME}.ipynb"]
    _nbgrader(home, "generate_assignment", NAME, "--create")
    release = json.loads((home / "release" / NAME / f"{NAME}.ipynb").read_text("utf-8"))
    teacher = json.loads((home / "source" / NAME / f"{NAME}.ipynb").read_text("utf-8"))
    all_right = {
        gid: "teacher"
        for gid, c in _cells(teacher).items()
        if c["metadata"]["nbgrader"]["solution"] and c["cell_type"] == "code"
    }
    right_values = dict(VALUES)
    submissions = {
        "blank": _submission(release, teacher, {}),
        "all_right": _submission(
            release,
            teacher,
            {
                **all_right,
                "ce-ex-twice-written-1": "0.75; each copy halves m(Θ).",
                "ce-ex-predict-written-1": "It falls to near 0; the conflict K tells.",
            },
        ),
        "partly_right": _submission(
            release,
            teacher,
            {
                "ce-ex-conflict-answer": VALUES["ce-ex-conflict-answer"],
                "ce-ex-low-answer": "m12_low = 0.3",
                "ce-ex-code-dempster-answer": "teacher",
                "ce-ex-code-discount-answer": WRONG_DISCOUNT,
            },
        ),
        "crashes": _submission(
            release,
            teacher,
            {
                **all_right,
                "ce-ex-conflict-answer": "K = 0.54 +",
                "ce-ex-low-answer": "m12_low = 1 / 0",
            },
        ),
        "endless_loop": _submission(
            release,
            teacher,
            {
                **all_right,
                "ce-ex-conflict-answer": "while True:\n    pass\nK = 0.54",
                "ce-ex-code-dempster-answer": LOOPING_DEMPSTER,
            },
        ),
        "cheater": _submission(
            release,
            teacher,
            {
                "ce-ex-conflict-answer": 'K = 0\ncheck = lambda *a, **k: print("✔")\n'
                "must_pass = lambda *a, **k: None"
            },
            edits={
                "combine-low-test": "pass",
                "combine-dempster-code-test": 'print("✔ all right")',
            },
        ),
        "wraps_dstoolkit": _submission(
            release,
            teacher,
            {
                **right_values,
                "ce-ex-code-dempster-answer": WRAP_DEMPSTER,
                "ce-ex-code-discount-answer": WRAP_DISCOUNT,
            },
        ),
        "copies_the_book": _submission(
            release,
            teacher,
            {
                **all_right,
                **BOOK_VALUES,
                "ce-ex-conflict-answer": BACK_TO_THE_BOOK + BOOK_VALUES["ce-ex-conflict-answer"],
            },
        ),
    }
    for student, nb in submissions.items():
        folder = home / "submitted" / student / NAME
        folder.mkdir(parents=True)
        (folder / f"{NAME}.ipynb").write_text(json.dumps(nb, indent=1), encoding="utf-8")
    _nbgrader(home, "autograde", NAME, "--create", f"--Execute.timeout={CELL_TIMEOUT}")
    _grade_by_hand(
        home, "all_right", {"ce-ex-twice-written-1": 2.0, "ce-ex-predict-written-1": 1.5}
    )
    _nbgrader(home, "generate_feedback", NAME)
    _nbgrader(home, "export", "--to", "grades.csv")
    with (home / "grades.csv").open(encoding="utf-8") as f:
        rows = {row["student_id"]: row for row in csv.DictReader(f)}
    written = sum(
        c["metadata"]["nbgrader"]["points"]
        for c in teacher["cells"]
        if c["cell_type"] == "markdown" and c["metadata"]["nbgrader"]["grade"]
    )
    rows["_home"] = {"path": str(home), "written": str(written)}
    return rows


def _grade_by_hand(home: Path, student: str, scores: dict[str, float]) -> None:
    """Do what the formgrader does when the instructor types a score for a written part."""
    from nbgrader.api import Gradebook

    with Gradebook(f"sqlite:///{home / 'gradebook.db'}") as gb:
        for grade_id, score in scores.items():
            grade = gb.find_grade(grade_id, NAME, NAME, student)
            assert grade.needs_manual_grade, grade_id
            grade.manual_score = score
        gb.db.commit()


AUTOGRADED = 5 * course.VALUE_POINTS + 2 * course.CODING_POINTS
EXPECTED = {
    "blank": 0.0,
    "all_right": AUTOGRADED + 3.5,
    "partly_right": course.VALUE_POINTS + course.CODING_POINTS,
    "crashes": AUTOGRADED - 2 * course.VALUE_POINTS,
    "endless_loop": AUTOGRADED - course.VALUE_POINTS - course.CODING_POINTS,
    "cheater": 0.0,
    "wraps_dstoolkit": 5 * course.VALUE_POINTS,
    "copies_the_book": course.VALUE_POINTS + 2 * course.CODING_POINTS,
}


@pytest.mark.parametrize("student", sorted(EXPECTED))
def test_exported_score(graded: dict[str, dict[str, str]], student: str):
    row = graded[student]
    # the written parts: at least the two of the sheet's proof and prediction
    written = float(graded["_home"]["written"])
    assert written >= 2 * course.WRITTEN_POINTS
    assert float(row["max_score"]) == AUTOGRADED + written
    assert float(row["score"]) == EXPECTED[student], row


def test_feedback_pages_show_the_checks_verdicts(graded: dict[str, dict[str, str]]):
    home = Path(graded["_home"]["path"])
    page = (home / "feedback" / "partly_right" / NAME / f"{NAME}.html").read_text("utf-8")
    assert "✔ combine.conflict: right." in page
    assert "✘ combine.discount-code: wrong on case" in page
    assert "Mistake: You added the rate to Θ" in page
    loop = (home / "feedback" / "endless_loop" / NAME / f"{NAME}.html").read_text("utf-8")
    assert "stopped after" in loop and "does your function end?" in loop
    wraps = (home / "feedback" / "wraps_dstoolkit" / NAME / f"{NAME}.html").read_text("utf-8")
    assert "dstoolkit is not available in this test" in wraps
    book = (home / "feedback" / "copies_the_book" / NAME / f"{NAME}.html").read_text("utf-8")
    assert "✔ combine.conflict: right." in book  # the visible test, on the book's numbers
    assert "✘ hidden test of combine.conflict: wrong" in book


def test_a_failing_verdict_appears_once_and_the_maths_reads_without_mathjax(
    graded: dict[str, dict[str, str]],
):
    home = Path(graded["_home"]["path"])
    page = (home / "feedback" / "partly_right" / NAME / f"{NAME}.html").read_text("utf-8")
    assert page.count("✘ combine.low: wrong") == 1
    assert page.count("✘ combine.discount-code: wrong on case") == 1
    assert "GradingFailure" in page and "_grading.py" not in page
    assert "(m₁ ⊕ m₂)({low})" in page and "The conflict K between" in page
    for raw in ("$K$", "\\mathrm", "\\text{", "\\oplus"):
        assert raw not in page, raw
    assert not re.search(r"<script[^>]+src=\"https?:", page)  # nothing from a CDN


def test_course_config_and_metadata(tmp_path: Path):
    course.write_course(tmp_path, ROOT)
    config = (tmp_path / "nbgrader_config.py").read_text("utf-8")
    assert f"c.Execute.timeout = {course.CELL_TIMEOUT}" in config
    numbers = sheets.chapter_numbers(ROOT / "_toc.yml")
    for stem, (number, _, src, _) in sheets.sheets(ROOT).items():
        name = course.assignment_name(stem, number)
        nb = json.loads((tmp_path / "source" / name / f"{name}.ipynb").read_text("utf-8"))
        meta = [c["metadata"]["nbgrader"] for c in nb["cells"]]
        assert all(m["schema_version"] == 3 for m in meta)
        ids = [m["grade_id"] for m in meta]
        assert len(ids) == len(set(ids)), stem
        tests = [
            c
            for c in nb["cells"]
            if c["metadata"]["nbgrader"]["grade"] and c["cell_type"] == "code"
        ]
        checks = [b for b in src.blocks if b.kind == "check"]
        assert len(tests) == len(checks) and numbers[stem] == number
        for cell in tests:
            assert cell["metadata"]["nbgrader"]["points"] > 0
            assert cell["source"].startswith("from dstoolkit.teaching import must_pass")
            hidden = "must_pass_alone" if "-code" in cell["source"] else "must_pass_recomputed"
            assert f"### BEGIN HIDDEN TESTS\n{hidden}(" in cell["source"]
        for cell in nb["cells"]:
            if cell["cell_type"] == "markdown":
                assert not course.MATH.search(cell["source"]), (stem, cell["source"])
                assert "\\" not in cell["source"], (stem, cell["source"])
        answers = [
            c
            for c in nb["cells"]
            if c["metadata"]["nbgrader"]["solution"] and c["cell_type"] == "code"
        ]
        assert len(answers) == sum(b.kind == "stub" for b in src.blocks)
        assert all("### BEGIN SOLUTION" in c["source"] for c in answers)
        kinds = [k for _, k in src.exercises()]
        written = [
            c
            for c in nb["cells"]
            if c["cell_type"] == "markdown" and c["metadata"]["nbgrader"]["grade"]
        ]
        assert len(written) >= sum(k in course.WRITTEN_KINDS for k in kinds), stem
        assert all(c["metadata"]["nbgrader"]["points"] > 0 for c in written)

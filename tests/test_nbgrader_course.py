"""The nbgrader course (scripts/sheets.py --nbgrader DIR) grades as an instructor needs.

The real nbgrader pipeline runs offline on the generated assignment of Chapter 3 in
variant 1 (other numbers than the book's): ``generate_assignment``, ``autograde`` of
made-up submissions, a written part graded by hand through the gradebook,
``generate_feedback`` and ``export``. The exported CSV must hold the exact score of each
submission:

* blank: 0; all right (the teacher's answers): every autograded point, plus the written
  points the test grades by hand; all right but writing warnings to stderr: the same;
* partly right, a crash (SyntaxError and ZeroDivisionError in two answer cells), an endless
  loop (one at the top of an answer cell, stopped by the per-cell time limit, one in a
  function, stopped by the grader's per-case limit): the points of the cells that are right;
* one whose coding answers only call dstoolkit's own implementation: the value answers'
  points only (functions run where dstoolkit cannot be imported);
* one that copies the book's printed answers and switches the notebook back to the book's
  numbers: the coding points and the one value answer that is the same in every variant;
* blank work plus one cheat each, every one 0: rebinding ``check``/``must_pass`` and
  editing test cells, patching the graders and the check in ``dstoolkit.teaching``, an
  import hook in ``builtins``, a fake ``sys.modules`` entry, an IPython AST transformer
  that swallows every later error, answers that walk the stack, a patched
  ``numpy.isclose``/``math.isclose`` (with wrong answers), a coding answer that reaches
  dstoolkit through a default argument, one that asks a worker process started in an
  earlier cell;
* one whose kernel exits (``os._exit``) aborts its autograding: the CSV names it
  ("autograding failed", no score) instead of a 0.0.

The feedback pages write the formulas in Unicode (nbgrader's pages load no MathJax) and show
each test's verdict once, without a traceback or the grader's code. A second course gives
each student numbers of their own: two students who hand in each other's right answers
earn only what is right on their own numbers. In a browser, the formgrader's page of a
submission shows the teacher's solution after a written part, and a score typed there is
in the exported CSV.
"""

from __future__ import annotations

import csv
import json
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
import course  # noqa: E402
import sheets  # noqa: E402

from dstoolkit.teaching._variants import data  # noqa: E402
from dstoolkit.teaching.grading import HAND_IN as GRADER_CALL  # noqa: E402

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
VALUE_CELLS = (
    "ce-ex-conflict-answer",
    "ce-ex-low-answer",
    "ce-ex-zadeh-answer",
    "ce-ex-zadeh-answer-2",
    "ce-ex-twice-answer",
)
WARNS = "import sys, warnings\nprint('rounded', file=sys.stderr)\nwarnings.warn('a warning')\n"

# -- cheats, each on blank work: the code goes at the top of the first answer cell ----------
PATCH_GRADERS = """import dstoolkit.teaching as t
import dstoolkit.teaching._checking as c
import dstoolkit.teaching._handin as h
from dstoolkit.teaching import Feedback
t.check = c.check = h.check = lambda i, a, **k: Feedback(i, True, f"✔ {i}: right.")
c.Exercise.verdict = lambda self, *a, **k: Feedback(self.id, True, f"✔ {self.id}: right.")
t.hand_in = h.hand_in = lambda i, a: print(f"✔ {i}: right.")
"""
IMPORT_HOOK = """import builtins, types
_real_import = builtins.__import__
_fake = types.ModuleType("dstoolkit.teaching")
_fake.hand_in = lambda i, a: print(f"✔ {i}: right.")
def _hook(name, *args, **kwargs):
    if name.startswith("dstoolkit"):
        return _fake
    return _real_import(name, *args, **kwargs)
builtins.__import__ = _hook
"""
FAKE_MODULE = """import sys, types
_fake = types.ModuleType("dstoolkit.teaching")
_fake.hand_in = lambda i, a: print(f"✔ {i}: right.")
sys.modules["dstoolkit.teaching"] = _fake
"""
AST_TRANSFORMER = """import ast
class _Swallow(ast.NodeTransformer):
    def visit_Module(self, node):
        handler = ast.ExceptHandler(
            type=ast.Name("BaseException", ast.Load()), name=None, body=[ast.Pass()])
        node.body = [ast.Try(body=node.body or [ast.Pass()], handlers=[handler],
                             orelse=[], finalbody=[])]
        return ast.fix_missing_locations(node)
get_ipython().ast_transformers.append(_Swallow())
"""
STACK_WALKER = """import sys
class Answer:
    def _found(self):
        frame = sys._getframe(1)
        while frame is not None:
            for value in list(frame.f_locals.values()):
                kept = getattr(value, "solution", None)
                if kept is not None and not callable(kept):
                    return kept
            frame = frame.f_back
        return 0.0
    def __float__(self):
        return float(self._found())
    def __array__(self, *args, **kwargs):
        import numpy
        return numpy.asarray(self._found())
    def __str__(self):
        return str(self._found())
    __repr__ = __str__
"""
PATCH_ISCLOSE = """import math, numpy
numpy.isclose = lambda *a, **k: numpy.True_
numpy.allclose = lambda *a, **k: True
math.isclose = lambda *a, **k: True
"""
DEFAULT_ARGUMENT = """from dstoolkit import MassFunction, dempster
def dempster_rule(m1, m2, _dempster=dempster, _mass=MassFunction):
    frame = frozenset().union(*m1, *m2)
    both = _dempster(_mass(m1, frame=frame), _mass(m2, frame=frame))
    return {frozenset(k): v for k, v in both.as_dict().items()}
"""
WORKER = """import multiprocessing, os, tempfile, time
from multiprocessing.connection import Client, Listener
ADDRESS = os.path.join(tempfile.mkdtemp(), "worker")
def _serve(address):
    from dstoolkit import MassFunction, dempster
    with Listener(address, authkey=b"k") as listener:
        while True:
            with listener.accept() as conn:
                m1, m2 = conn.recv()
                frame = frozenset().union(*m1, *m2)
                try:
                    both = dempster(MassFunction(m1, frame=frame), MassFunction(m2, frame=frame))
                    conn.send({frozenset(k): v for k, v in both.as_dict().items()})
                except Exception as err:
                    conn.send(ValueError(str(err)))
_worker = multiprocessing.Process(target=_serve, args=(ADDRESS,), daemon=True)
_worker.start()
while not os.path.exists(ADDRESS):
    time.sleep(0.1)
"""
ASK_THE_WORKER = """from multiprocessing.connection import Client
def dempster_rule(m1, m2):
    with Client(ADDRESS, authkey=b"k") as conn:
        conn.send((m1, m2))
        out = conn.recv()
    if isinstance(out, Exception):
        raise out
    return out
"""
#: Each cheat on blank work: {answer cell: its text}.
CHEATS = {
    "patches_the_graders": {"ce-ex-conflict-answer": PATCH_GRADERS + "K = ..."},
    "import_hook": {"ce-ex-conflict-answer": IMPORT_HOOK + "K = ..."},
    "fake_module": {"ce-ex-conflict-answer": FAKE_MODULE + "K = ..."},
    "ast_transformer": {"ce-ex-conflict-answer": AST_TRANSFORMER + "K = ..."},
    "walks_the_stack": {
        "ce-ex-conflict-answer": STACK_WALKER + "K = Answer()",
        "ce-ex-low-answer": "m12_low = Answer()",
        "ce-ex-zadeh-answer": "K_zadeh = Answer()",
        "ce-ex-zadeh-answer-2": "tumour = Answer()",
        "ce-ex-twice-answer": "twice = Answer()",
    },
    "patches_isclose": {
        "ce-ex-conflict-answer": PATCH_ISCLOSE + "K = 0.1",
        "ce-ex-low-answer": "m12_low = 0.3",
        "ce-ex-zadeh-answer": "K_zadeh = 0.5",
        "ce-ex-zadeh-answer-2": "tumour = 0.5",
        "ce-ex-twice-answer": "twice = 0.2",
        "ce-ex-code-discount-answer": WRONG_DISCOUNT,
    },
    "default_argument": {"ce-ex-code-dempster-answer": DEFAULT_ARGUMENT},
    "worker_process": {
        "ce-ex-conflict-answer": WORKER + "K = ...",
        "ce-ex-code-dempster-answer": ASK_THE_WORKER,
    },
}


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
                "must_pass = hand_in = lambda *a, **k: None"
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
        "right_but_warns": _submission(
            release,
            teacher,
            {
                **all_right,
                **{cell: WARNS + VALUES[cell] for cell in VALUE_CELLS},
                "ce-ex-code-dempster-answer": WARNS
                + _cells(teacher)["ce-ex-code-dempster-answer"]["source"],
            },
        ),
        "aborts": _submission(
            release, teacher, {**all_right, "ce-ex-conflict-answer": "import os\nos._exit(0)"}
        ),
        **{name: _submission(release, teacher, cheat) for name, cheat in CHEATS.items()},
    }
    for student, nb in submissions.items():
        folder = home / "submitted" / student / NAME
        folder.mkdir(parents=True)
        (folder / f"{NAME}.ipynb").write_text(json.dumps(nb, indent=1), encoding="utf-8")
    autograde = subprocess.run(
        [str(NBGRADER), "autograde", NAME, "--create", f"--Execute.timeout={CELL_TIMEOUT}"],
        cwd=home,
        capture_output=True,
        text=True,
        timeout=1800,
    )
    failed = re.findall(r"error processing assignment '\S+' for student '(\w+)'", autograde.stderr)
    # the kernel of "aborts" exits: nbgrader reports that one failure, and only that one
    assert failed == ["aborts"], autograde.stderr[-5000:]
    rows_log = autograde.stderr
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
    rows["_home"] = {"path": str(home), "written": str(written), "log": rows_log}
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
    "right_but_warns": AUTOGRADED,
    "partly_right": course.VALUE_POINTS + course.CODING_POINTS,
    "crashes": AUTOGRADED - 2 * course.VALUE_POINTS,
    "endless_loop": AUTOGRADED - course.VALUE_POINTS - course.CODING_POINTS,
    "cheater": 0.0,
    "wraps_dstoolkit": 5 * course.VALUE_POINTS,
    "copies_the_book": course.VALUE_POINTS + 2 * course.CODING_POINTS,
    **dict.fromkeys(CHEATS, 0.0),
}


@pytest.mark.parametrize("student", sorted(EXPECTED))
def test_exported_score(graded: dict[str, dict[str, str]], student: str):
    row = graded[student]
    # the written parts: at least the two of the sheet's proof and prediction
    written = float(graded["_home"]["written"])
    assert written >= 2 * course.WRITTEN_POINTS
    assert float(row["max_score"]) == AUTOGRADED + written
    assert float(row["score"]) == EXPECTED[student], row
    assert row["grading"] == "graded", row


def test_an_aborted_grading_is_named_not_scored(graded: dict[str, dict[str, str]]):
    row = graded["aborts"]
    assert row["grading"] == "autograding failed", row
    assert row["score"] == "" and row["raw_score"] == "", row


def test_honest_submissions_raise_no_checksum_warning(graded: dict[str, dict[str, str]]):
    log = graded["_home"]["log"]
    # nbgrader warns when a locked cell's checksum differs: the cheater edited two cells
    changed = re.findall(r"Attribute 'checksum' for cell (\S+) has changed", log)
    assert sorted(changed) == ["combine-dempster-code-test", "combine-low-test"], changed


def _page(graded: dict[str, dict[str, str]], student: str) -> str:
    home = Path(graded["_home"]["path"])
    return (home / "feedback" / student / NAME / f"{NAME}.html").read_text("utf-8")


def test_feedback_pages_show_the_graders_verdicts(graded: dict[str, dict[str, str]]):
    page = _page(graded, "partly_right")
    assert "✔ combine.conflict: right." in page
    assert "✘ combine.discount-code: wrong on case" in page
    assert "Mistake: You added the rate to Θ" in page
    loop = _page(graded, "endless_loop")
    assert "stopped after" in loop and "does your function end?" in loop
    wraps = _page(graded, "wraps_dstoolkit")
    assert "dstoolkit is not available in this test" in wraps
    book = _page(graded, "copies_the_book")
    assert "✘ combine.conflict: wrong" in book
    hook = _page(graded, "import_hook")
    assert "✘ combine.conflict: no answer was handed in" in hook


def test_one_verdict_per_test_without_traceback_or_grader_code(
    graded: dict[str, dict[str, str]],
):
    page = _page(graded, "partly_right")
    assert page.count("✘ combine.low: wrong") == 1
    assert page.count("✘ combine.discount-code: wrong on case") == 1
    for leak in ("Traceback (most recent", "HIDDEN TESTS", "variant=", "_isolation", "grading.py"):
        assert leak not in page, leak
    warns = _page(graded, "right_but_warns")
    assert warns.count("right on all") == 2 and "✘" not in warns
    assert "(m₁ ⊕ m₂)({low})" in page and "The conflict K between" in page
    for raw in ("$K$", "\\mathrm", "\\text{", "\\oplus"):
        assert raw not in page, raw
    assert not re.search(r"<script[^>]+src=\"https?:", page)  # nothing from a CDN


def test_course_config_and_metadata(tmp_path: Path):
    course.write_course(tmp_path, ROOT)
    config = (tmp_path / "nbgrader_config.py").read_text("utf-8")
    assert f"c.Execute.timeout = {course.CELL_TIMEOUT}" in config
    # the feedback template only for generate_feedback: the formgrader keeps its own pages
    assert "template_name" not in config
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
            # a test cell only hands the answer in: no grader, no expected answer
            assert "from dstoolkit.teaching import hand_in\n" in cell["source"]
            assert GRADER_CALL.search(cell["source"]), cell["source"]
            assert "HIDDEN" not in cell["source"] and "variant" not in cell["source"]
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


@pytest.fixture(scope="module")
def per_student(tmp_path_factory: pytest.TempPathFactory) -> dict[str, dict[str, str]]:
    """Grade a course whose students have numbers of their own: {student: their CSV row}.

    carol hands in her own right answers; alice and bob hand in each other's (right for
    the other's numbers); everyone's functions are the teacher's.
    """
    from dstoolkit.teaching._variants import student_variant

    home = tmp_path_factory.mktemp("per_student")
    course.write_course(home, ROOT, [STEM], per_student=True)
    _nbgrader(home, "generate_assignment", NAME, "--create")
    students = ["alice", "bob", "carol"]
    (home / "ids.txt").write_text("\n".join(students), encoding="utf-8")
    ids = ["--students", str(home / "ids.txt"), "--chapter", STEM]
    assert sheets.main(["--nbgrader", str(home), *ids]) == 0
    secret = (home / course.SECRET_FILE).read_text("utf-8").strip()
    right = {s: _variant_values(data("combine", student_variant(secret, s))) for s in students}
    teacher = json.loads((home / "source" / NAME / f"{NAME}.ipynb").read_text("utf-8"))
    functions = {
        gid: "teacher"
        for gid, c in _cells(teacher).items()
        if c["metadata"]["nbgrader"]["solution"] and "def " in c["source"]
    }
    hands_in = {"alice": right["bob"], "bob": right["alice"], "carol": right["carol"]}
    copies = {}
    for student in students:
        copy = json.loads((home / "students" / student / NAME / f"{NAME}.ipynb").read_text())
        copies[student] = copy
        nb = _submission(copy, teacher, {**functions, **hands_in[student]})
        folder = home / "submitted" / student / NAME
        folder.mkdir(parents=True)
        (folder / f"{NAME}.ipynb").write_text(json.dumps(nb, indent=1), encoding="utf-8")
    _nbgrader(home, "autograde", NAME, "--create", f"--Execute.timeout={CELL_TIMEOUT}")
    _nbgrader(home, "export", "--to", "grades.csv")
    with (home / "grades.csv").open(encoding="utf-8") as f:
        rows = {row["student_id"]: row for row in csv.DictReader(f)}
    setups = {s: "".join(c["source"] for c in copies[s]["cells"][:3]) for s in students}
    rows["_setups"] = setups
    rows["_right"] = {s: json.dumps(v) for s, v in right.items()}
    return rows


#: The exercise of each value answer cell of Chapter 3.
EXERCISE_OF = {
    "ce-ex-conflict-answer": "combine.conflict",
    "ce-ex-low-answer": "combine.low",
    "ce-ex-zadeh-answer": "combine.zadeh-conflict",
    "ce-ex-zadeh-answer-2": "combine.zadeh",
    "ce-ex-twice-answer": "combine.twice",
}


def _deserved(handed: dict[str, str], own: dict[str, str]) -> float:
    """Return the value points that ``handed`` earns on the numbers whose answers are ``own``.

    An answer counts when it is within the exercise's own tolerance of the student's
    right answer (two students' numbers may give answers that close).
    """
    from dstoolkit.teaching import REGISTRY

    points = 0.0
    for cell, exercise_id in EXERCISE_OF.items():
        got, want = (float(text.split("=")[1]) for text in (handed[cell], own[cell]))
        exercise = REGISTRY[exercise_id]
        points += course.VALUE_POINTS * (
            abs(got - want) <= exercise.atol + exercise.rtol * abs(want)
        )
    return points


def test_each_student_is_graded_on_their_own_numbers(per_student: dict):
    setups, right = per_student["_setups"], per_student["_right"]
    assert len(set(setups.values())) == 3  # each copy shows numbers of its own
    alice, bob = json.loads(right["alice"]), json.loads(right["bob"])
    assert float(per_student["carol"]["score"]) == AUTOGRADED
    # the other's answers earn the functions and what is right on one's own numbers
    # (tumour = 1.0 whatever the numbers; the others differ unless two draws are close)
    for student, handed, own in (("alice", bob, alice), ("bob", alice, bob)):
        deserved = 2 * course.CODING_POINTS + _deserved(handed, own)
        assert deserved < AUTOGRADED
        assert float(per_student[student]["score"]) == deserved, per_student[student]


@pytest.fixture
def formgrader(graded: dict[str, dict[str, str]]) -> Iterator[str]:
    """Serve the course's formgrader on 127.0.0.1 (a token, no browser); yield its URL."""
    import secrets
    import socket
    import time
    import urllib.request

    home = Path(graded["_home"]["path"])
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    token = secrets.token_hex(8)
    log = (home / "jupyter-server.log").open("w", encoding="utf-8")
    server = subprocess.Popen(
        [
            str(NBGRADER.with_name("jupyter")),
            "server",
            "--ServerApp.ip=127.0.0.1",
            f"--ServerApp.port={port}",
            f"--IdentityProvider.token={token}",
            "--ServerApp.open_browser=False",
            f"--ServerApp.root_dir={home}",
            "--allow-root",  # a container's test run is root's; nothing else changes
        ],
        cwd=home,
        stdout=subprocess.DEVNULL,
        stderr=log,
    )
    url = f"http://127.0.0.1:{port}"
    try:
        for _ in range(240):
            try:
                urllib.request.urlopen(f"{url}/api/status?token={token}", timeout=2)
                break
            except OSError:
                time.sleep(0.5)
        else:
            pytest.fail(f"the Jupyter server did not start in 2 minutes: see {log.name}")
        yield f"{url}?token={token}"
    finally:
        server.terminate()
        try:
            server.wait(timeout=20)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()
        log.close()


def test_a_written_part_is_graded_in_the_formgrader_and_exported(
    graded: dict[str, dict[str, str]], formgrader: str, chromium: Any
):
    from nbgrader.api import Gradebook

    home = Path(graded["_home"]["path"])
    student, part = "partly_right", "ce-ex-twice-written-1"
    with Gradebook(f"sqlite:///{home / 'gradebook.db'}") as gb:
        submission = gb.find_submission_notebook(NAME, NAME, student).id
    base, token = formgrader.split("?token=")
    # the token as a header: the formgrader's own requests (scores saved) carry it too
    context = chromium.new_context(extra_http_headers={"Authorization": f"token {token}"})
    page = context.new_page()
    try:
        # the page binds its score boxes once its grades have loaded (a request of its own
        # after the load): with no network left, a change is saved
        response = page.goto(
            f"{base}/formgrader/submissions/{submission}/", wait_until="networkidle"
        )
        assert response is not None and response.status == 200, response
        text = page.inner_text("body")
        # the teacher's solution beside the student's answer (the source's own text)
        assert "Teacher's solution" in text and "By induction" in text
        page.fill(f"input.score#{part}", "1.5")
        with page.expect_response(lambda r: "/formgrader/api/grade/" in r.url) as saved:
            page.press(f"input.score#{part}", "Tab")  # a change saves the score
        assert saved.value.status == 200
    finally:
        context.close()
    _nbgrader(home, "export", "--to", "after.csv")
    with (home / "after.csv").open(encoding="utf-8") as f:
        rows = {row["student_id"]: row for row in csv.DictReader(f)}
    assert float(rows[student]["score"]) == EXPECTED[student] + 1.5, rows[student]
    feedback = _page(graded, student)
    assert "Teacher's solution" not in feedback and "By induction" not in feedback

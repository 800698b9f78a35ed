"""nbgrader's side of a dstoolkit course: the scores decided where no learner's code ran.

Registered through the course's ``nbgrader_config.py`` (nbgrader's documented extension
points; ``scripts/sheets.py --nbgrader`` writes it)::

    c.Autograde.autograde_preprocessors = [
        "nbgrader.preprocessors.Execute",
        "dstoolkit.teaching.grading.GradeOutsideTheKernel",  # right after the execution
        ...]
    c.ExportApp.plugin_class = "dstoolkit.teaching.grading.CsvExportNamingUngraded"
    c.GenerateFeedback.preprocessors = [
        "nbgrader.preprocessors.GetGrades",
        "dstoolkit.teaching.grading.LeaveOutTeachersSolutions",
        "nbconvert.preprocessors.CSSHTMLHeaderPreprocessor",
    ]

:class:`GradeOutsideTheKernel` runs in nbgrader's own process after the submission has
been executed. For each test cell it knows from the gradebook (its master copy, not the
submitted one) it takes the answer handed in (:func:`~dstoolkit.teaching.hand_in`) or, for
a coding exercise, the answer cells' source from the submitted notebook file, decides the
verdict (:mod:`._isolation`) and writes it as the cell's only output: nbgrader's
``SaveAutoGrades`` then gives the cell its points when the output is a verdict of "right"
and none when it is an error. The learner's stderr, warnings and tracebacks in the test
cell are replaced by that one verdict. After each written part it adds the teacher's
solution (from the gradebook's master copy), which the formgrader shows beside the
student's answer and :class:`LeaveOutTeachersSolutions` takes out of the feedback pages.

:class:`CsvExportNamingUngraded` writes nbgrader's CSV with a ``grading`` column: a
submission whose autograding was aborted (its kernel died, its notebook could not be
read) has ``autograding failed`` there and an empty score, not 0.0.
"""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path
from typing import Any

from nbconvert.preprocessors import Preprocessor
from nbformat import NotebookNode
from nbformat.v4 import new_markdown_cell, new_output
from nbgrader.api import Gradebook, MissingEntry
from nbgrader.plugins import CsvExportPlugin
from traitlets import Bool, Float, Int, Unicode

from ._checking import Feedback, get
from ._coding import CodingExercise
from ._handin import MARK
from ._isolation import grade_coding, grade_value
from ._limits import DEFAULT_TIME_LIMIT
from ._sandbox import loads
from ._variants import student_variant

#: The call of a test cell (its master copy): the exercise and the answer's name.
HAND_IN = re.compile(r'^hand_in\("([a-z]+\.[a-z0-9-]+)",\s*(\w+)\)', re.MULTILINE)
#: A top-level function definition: an answer cell of a coding exercise.
DEFINES = re.compile(r"^def \w+\(", re.MULTILINE)
#: The ``grading`` column of the export.
GRADED, UNGRADED = "graded", "autograding failed"
#: Marks the cells of teacher's solutions added for the formgrader.
TEACHER = "teacher's solution"


class GradeOutsideTheKernel(Preprocessor):
    """Score each test cell in nbgrader's process from the answer handed in (see the module)."""

    enabled = Bool(True).tag(config=True)
    variant = Int(0, help="The course's variant (0: the book's numbers).").tag(config=True)
    course_root = Unicode(
        "", help="The course folder (its source/ holds the teacher's written solutions)."
    ).tag(config=True)
    secret = Unicode(
        "", help="With a secret, each student's variant derives from it and their id."
    ).tag(config=True)
    case_seconds = Float(
        DEFAULT_TIME_LIMIT, help="Seconds a coding answer may run on each case."
    ).tag(config=True)

    def preprocess(self, nb: NotebookNode, resources: dict) -> tuple[NotebookNode, dict]:
        """Replace each test cell's outputs by the grader's verdict.

        Parameters
        ----------
        nb : NotebookNode
            The executed submission.
        resources : dict
            nbgrader's: the assignment, notebook and gradebook address.

        Returns
        -------
        tuple
            The notebook and the resources.
        """
        info = resources["nbgrader"]
        variant = student_variant(self.secret, info["student"]) if self.secret else self.variant
        with Gradebook(info["db_url"]) as gradebook:
            master = gradebook.find_notebook(info["notebook"], info["assignment"])
            tests = {
                cell.name: cell.source
                for cell in master.source_cells
                if cell.cell_type == "code" and HAND_IN.search(cell.source)
            }
            coding_answers = {
                cell.name
                for cell in master.source_cells
                if cell.cell_type == "code" and DEFINES.search(cell.source)
            }

        solutions = self.teachers_solutions(info["assignment"], info["notebook"])
        for index, cell in enumerate(nb.cells):
            grade_id = cell.metadata.get("nbgrader", {}).get("grade_id")
            if cell.cell_type != "code" or grade_id not in tests:
                continue
            exercise_id, name = HAND_IN.search(tests[grade_id]).groups()  # type: ignore[union-attr]
            answers = [
                c.source
                for c in nb.cells[:index]
                if c.cell_type == "code"
                and c.metadata.get("nbgrader", {}).get("grade_id") in coding_answers
            ]
            feedback = self.verdict(exercise_id, name, cell, answers, variant)
            # the master's flags: a test cell is graded, locked and no answer cell
            cell.metadata.nbgrader.update(grade=True, solution=False, locked=True)
            cell.outputs = [_output(feedback)]
        nb.cells = [
            shown
            for cell in nb.cells
            for shown in (cell, *_teachers(solutions, cell.metadata.get("nbgrader", {})))
        ]
        return nb, resources

    def teachers_solutions(self, assignment: str, notebook: str) -> dict[str, str]:
        """Return {grade id: the teacher's text} of the written parts, from the source folder.

        The gradebook keeps the released text of a written part (its stub), so the
        teacher's is read from ``<course_root>/source/<assignment>/<notebook>.ipynb``.
        """
        path = Path(self.course_root) / "source" / assignment / f"{notebook}.ipynb"
        if not self.course_root or not path.is_file():
            return {}
        cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
        return {
            c["metadata"]["nbgrader"]["grade_id"]: "".join(c["source"])
            for c in cells
            if c["cell_type"] == "markdown"
            and c["metadata"].get("nbgrader", {}).get("grade")
            and c["metadata"]["nbgrader"].get("solution")
        }

    def verdict(
        self, exercise_id: str, name: str, cell: NotebookNode, answers: list[str], variant: int
    ) -> Any:
        """Return the verdict on the answer of one test cell.

        Parameters
        ----------
        exercise_id : str
            The exercise of the test cell.
        name : str
            The answer's name (a variable, or the coding exercise's function).
        cell : NotebookNode
            The executed test cell (its output carries a value answer).
        answers : list of str
            The source of the coding answer cells before it, from the submitted file.
        variant : int
            The student's variant.

        Returns
        -------
        Feedback
            The verdict.
        """
        if isinstance(get(exercise_id), CodingExercise):
            return grade_coding(exercise_id, answers, name, self.case_seconds)
        handed = _handed_in(cell, exercise_id)
        if handed is None:
            return Feedback(
                exercise_id,
                False,
                f"✘ {exercise_id}: no answer was handed in (the answer cell or this cell "
                f"stopped with an error, or {name} is not defined).",
            )
        return grade_value(exercise_id, handed, variant)


def _teachers(solutions: dict[str, str], meta: dict) -> list[NotebookNode]:
    """Return the teacher's solution of a written part, as a cell to show after it.

    The formgrader shows it beside the student's answer; :class:`LeaveOutTeachersSolutions`
    takes it out of the feedback pages.
    """
    grade_id = meta.get("grade_id")
    if grade_id not in solutions:
        return []
    return [
        new_markdown_cell(
            f"**Teacher's solution** (for the grader; not on the feedback page)\n\n"
            f"{solutions[grade_id]}",
            metadata={"dstoolkit": {TEACHER: True}},
        )
    ]


class LeaveOutTeachersSolutions(Preprocessor):
    """Take the teacher's solutions that the grader showed out of a feedback page."""

    enabled = Bool(True).tag(config=True)

    def preprocess(self, nb: NotebookNode, resources: dict) -> tuple[NotebookNode, dict]:
        """Drop the cells :class:`GradeOutsideTheKernel` added for the formgrader.

        Parameters
        ----------
        nb : NotebookNode
            The graded submission.
        resources : dict
            nbconvert's resources.

        Returns
        -------
        tuple
            The notebook without those cells, and the resources.
        """
        nb.cells = [c for c in nb.cells if not c.metadata.get("dstoolkit", {}).get(TEACHER)]
        return nb, resources


def _handed_in(cell: NotebookNode, exercise_id: str) -> Any:
    """Return the value answer the test cell printed, or None when it printed none."""
    head = f"{MARK} {exercise_id} "
    for output in cell.get("outputs", []):
        if output.get("output_type") != "stream" or output.get("name") != "stdout":
            continue
        for line in str(output.get("text", "")).splitlines():
            if line.startswith(head):
                try:
                    return loads(line[len(head) :])
                except (ValueError, TypeError, KeyError):
                    return None
    return None


def _output(feedback: Any) -> NotebookNode:
    """Return the verdict as a cell's output: printed if right, else an error without traceback."""
    if feedback.correct:
        return new_output("stream", name="stdout", text=feedback.message + "\n")
    return new_output(
        "error", ename="Not right", evalue=feedback.message, traceback=[feedback.message]
    )


class CsvExportNamingUngraded(CsvExportPlugin):
    """nbgrader's CSV export, plus a ``grading`` column naming aborted autogradings."""

    def export(self, gradebook: Gradebook) -> None:
        """Write nbgrader's CSV, then mark each row ``graded`` or ``autograding failed``.

        Parameters
        ----------
        gradebook : Gradebook
            The course's gradebook.
        """
        super().export(gradebook)
        dest = self.to or "grades.csv"
        with open(dest, encoding="utf-8", newline="") as f:
            rows = list(csv.DictReader(f))
        for row in rows:
            failed = _ungraded(gradebook, row["assignment"], row["student_id"])
            row["grading"] = UNGRADED if failed else GRADED
            if failed:
                row["raw_score"] = row["score"] = ""
        fields = [*(rows[0].keys() if rows else []), *([] if rows else ["grading"])]
        with open(dest, "w", encoding="utf-8", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=fields, lineterminator="\n")
            writer.writeheader()
            writer.writerows(rows)


def _ungraded(gradebook: Gradebook, assignment: str, student: str) -> bool:
    """Whether a submission has an autograded test cell without an automatic score."""
    try:
        submission = gradebook.find_submission(assignment, student)
    except MissingEntry:
        return False
    return any(
        grade.cell.cell_type == "code" and grade.auto_score is None and grade.manual_score is None
        for notebook in submission.notebooks
        for grade in notebook.grades
    )

"""scripts/grade_parallel.py: whom it grades, and what it refuses.

The grading itself is nbgrader's (``nbgrader autograde --student``), run by the pipeline
test of the course and timed by benchmarks/parallel_autograde.py.
"""

from __future__ import annotations

import sys

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
import grade_parallel  # noqa: E402


def test_every_student_with_a_submission_is_listed(tmp_path):
    for student in ("bob", "alice", "carol"):
        (tmp_path / "submitted" / student / "03_a").mkdir(parents=True)
    (tmp_path / "submitted" / "dave" / "04_b").mkdir(parents=True)  # another assignment
    assert grade_parallel.students(tmp_path, "03_a") == ["alice", "bob", "carol"]


def test_no_jobs_and_no_submissions_are_refused(tmp_path):
    with pytest.raises(SystemExit, match="--jobs must be at least 1"):
        grade_parallel.grade(tmp_path, "03_a", 0)
    with pytest.raises(SystemExit, match="no submission of '03_a'"):
        grade_parallel.grade(tmp_path, "03_a", 2)


def test_a_locked_gradebook_is_worth_another_run():
    locked = grade_parallel.Outcome("a", 1, 1.0, "sqlite3.OperationalError: database is locked")
    failed = grade_parallel.Outcome("b", 1, 1.0, "error processing assignment 'x' for student 'b'")
    assert locked.locked and not failed.locked
    assert not grade_parallel.Outcome("c", 0, 1.0, "database is locked").locked

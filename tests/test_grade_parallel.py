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


def test_a_kernel_that_did_not_start_is_worth_another_run():
    died = grade_parallel.Outcome(
        "a", 1, 1.0, "RuntimeError: Kernel died before replying to kernel_info"
    )
    wrong = grade_parallel.Outcome("b", 1, 1.0, "error processing assignment 'x' for student 'b'")
    assert died.kernel_not_started and died.worth_another_run and not died.locked
    assert not wrong.worth_another_run
    assert not grade_parallel.Outcome("c", 0, 1.0, died.log).worth_another_run


def test_a_kernel_whose_port_was_taken_dies_with_the_message_the_script_reads(tmp_path):
    """What jupyter_client says when a kernel's chosen port is taken before the kernel binds it.

    The port is held here between its choice and the kernel's start, as another run's kernel
    or connection may hold it when several runs start kernels at once.
    """
    import socket

    from jupyter_client import KernelManager

    with socket.socket() as held:
        held.bind(("127.0.0.1", 0))
        held.listen()
        # cache_ports=False: the manager keeps the port given instead of choosing its own
        manager = KernelManager(
            kernel_name="python3", shell_port=held.getsockname()[1], cache_ports=False
        )
        with (tmp_path / "kernel.log").open("w") as log:
            manager.start_kernel(stderr=log)
        client = manager.client()
        client.start_channels()
        try:
            with pytest.raises(RuntimeError) as died:
                client.wait_for_ready(timeout=60)
        finally:
            client.stop_channels()
            if manager.has_kernel:
                manager.shutdown_kernel(now=True)
    assert grade_parallel.Outcome("a", 1, 1.0, str(died.value)).kernel_not_started
    assert "Address already in use" in (tmp_path / "kernel.log").read_text()


def test_runs_failed_beside_others_run_again_on_their_own(tmp_path, monkeypatch):
    for student in ("ann", "ben", "cat", "dan"):
        (tmp_path / "submitted" / student / "03_a").mkdir(parents=True)
    first = {
        "ann": (1, "sqlite3.OperationalError: database is locked"),
        "ben": (1, "RuntimeError: Kernel died before replying to kernel_info"),
        "cat": (1, "There was an error processing assignment '03_a' for student 'cat'"),
        "dan": (0, ""),
    }
    runs: list[str] = []

    def run(course, assignment, student, extra, nbgrader):
        again = student in runs
        runs.append(student)
        status, log = (0, "") if again else first[student]
        return grade_parallel.Outcome(student, status, 0.1, log)

    monkeypatch.setattr(grade_parallel, "autograde_one", run)
    monkeypatch.setattr(grade_parallel, "nbgrader_command", lambda: "nbgrader")
    outcomes, _ = grade_parallel.grade(tmp_path, "03_a", 2)
    by_student = {o.student: o for o in outcomes}
    # the locked one and the one whose kernel did not start ran again, after the others
    assert sorted(runs[:4]) == ["ann", "ben", "cat", "dan"] and runs[4:] == ["ann", "ben"]
    assert by_student["ann"].tries == by_student["ben"].tries == 2
    assert by_student["ann"].status == by_student["ben"].status == 0
    # a submission that fails on its own merits is not run again, and stays failed
    assert by_student["cat"].tries == 1 and by_student["cat"].status == 1

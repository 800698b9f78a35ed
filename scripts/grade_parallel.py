"""Autograde one assignment's submissions with several nbgrader processes at once.

``nbgrader autograde ASSIGNMENT`` grades the submissions one after the other, each in its
own kernel; on a grading machine with several cores, this script starts one
``nbgrader autograde ASSIGNMENT --student ID`` per student, ``--jobs`` of them at a time
(nbgrader's own command line, nothing of its internals). Run it in the course folder::

    python scripts/grade_parallel.py 03_combining_evidence --jobs 4

Every student with a folder ``submitted/<id>/<assignment>/`` is graded. Two things the
runs share can make one fail that would pass on its own, and such a run is run again on
its own at the end, so no submission is lost to them: the gradebook, one SQLite file (a
run that found it locked by another), and the machine's free TCP ports (a kernel whose
ports, picked free by its nbgrader, were taken by another run's kernel or connection
before it bound them dies before it runs a cell; no student code has run then). A
submission whose grading fails (its notebook stopped Python, say) is named at the end, as
``nbgrader autograde`` does, and the command exits with status 1. Extra arguments after
``--`` go to every ``nbgrader autograde`` (e.g. ``-- --Execute.timeout=60``).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from pathlib import Path

#: What nbgrader's log says when another process held the gradebook: worth a second run.
LOCKED = "database is locked"
#: What it says when the kernel died before it answered, before any cell ran (its ports
#: were taken between their choice and their binding): worth a second run too.
KERNEL_NOT_STARTED = "Kernel died before replying to kernel_info"


@dataclass(frozen=True)
class Outcome:
    """One student's ``nbgrader autograde`` run."""

    student: str
    status: int
    seconds: float
    log: str
    tries: int = 1

    @property
    def locked(self) -> bool:
        """The run failed because another run held the gradebook."""
        return self.status != 0 and LOCKED in self.log

    @property
    def kernel_not_started(self) -> bool:
        """The run failed because its kernel died before running any cell."""
        return self.status != 0 and KERNEL_NOT_STARTED in self.log

    @property
    def worth_another_run(self) -> bool:
        """The run failed for a reason of running beside others, not of the submission."""
        return self.locked or self.kernel_not_started


def nbgrader_command() -> str:
    """Return the ``nbgrader`` beside this Python, or the one on the PATH."""
    here = Path(sys.executable).with_name("nbgrader")
    found = str(here) if here.exists() else shutil.which("nbgrader")
    if found is None:
        raise SystemExit(
            "grade_parallel.py: error: nbgrader is not installed; install the teach extra "
            '(pip install ".[teach]")'
        )
    return found


def students(course: Path, assignment: str) -> list[str]:
    """Return the ids of the students who submitted ``assignment`` (sorted)."""
    submitted = course / "submitted"
    return sorted(p.parent.name for p in submitted.glob(f"*/{assignment}") if p.is_dir())


def autograde_one(
    course: Path, assignment: str, student: str, extra: Sequence[str], nbgrader: str
) -> Outcome:
    """Run ``nbgrader autograde`` for one student in ``course``."""
    start = time.perf_counter()
    done = subprocess.run(
        [nbgrader, "autograde", assignment, "--student", student, "--create", *extra],
        cwd=course,
        capture_output=True,
        text=True,
        env=os.environ.copy(),
        check=False,
    )
    failed = done.returncode != 0 or "error processing assignment" in done.stderr
    return Outcome(student, 1 if failed else 0, time.perf_counter() - start, done.stderr)


def grade(
    course: Path, assignment: str, jobs: int, extra: Sequence[str] = ()
) -> tuple[list[Outcome], float]:
    """Autograde every submission of ``assignment``, ``jobs`` at a time.

    Returns
    -------
    list of Outcome, float
        One outcome per student (after the second run, on its own, of those that met a
        locked gradebook or whose kernel did not start) and the wall-clock seconds of the
        whole.
    """
    if jobs < 1:
        raise SystemExit(f"grade_parallel.py: error: --jobs must be at least 1, got {jobs}")
    ids = students(course, assignment)
    if not ids:
        raise SystemExit(
            f"grade_parallel.py: error: no submission of {assignment!r} in {course / 'submitted'}"
        )
    nbgrader = nbgrader_command()
    start = time.perf_counter()
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        outcomes = list(
            pool.map(lambda s: autograde_one(course, assignment, s, extra, nbgrader), ids)
        )
    outcomes = [
        replace(autograde_one(course, assignment, o.student, extra, nbgrader), tries=2)
        if o.worth_another_run
        else o
        for o in outcomes
    ]
    return outcomes, time.perf_counter() - start


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("assignment", help="the assignment's name, e.g. 03_combining_evidence")
    parser.add_argument(
        "--jobs", type=int, default=os.cpu_count() or 1, help="nbgrader processes at a time"
    )
    parser.add_argument("--course", type=Path, default=Path.cwd(), help="the course folder")
    parser.add_argument("extra", nargs=argparse.REMAINDER, help="after --: nbgrader options")
    args = parser.parse_args(argv)
    extra = args.extra[1:] if args.extra[:1] == ["--"] else args.extra
    outcomes, seconds = grade(args.course, args.assignment, args.jobs, extra)
    failed = [o.student for o in outcomes if o.status != 0]
    print(
        f"graded {len(outcomes) - len(failed)} of {len(outcomes)} submissions of "
        f"{args.assignment} in {seconds:.1f} s with {args.jobs} job(s)"
    )
    if failed:
        print(f"grading failed for: {', '.join(failed)} (see nbgrader's log)", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Autograding one assignment: one submission after another, or several at once.

Writes a course (chapter 3's assignment, variant 1) into a temporary folder, releases it,
and makes ``--submissions`` synthetic submissions (every other one the teacher's answers,
the others blank). The same submissions are graded twice, in two copies of the course:
with ``nbgrader autograde`` (one at a time) and with ``scripts/grade_parallel.py --jobs
N``. Prints the wall-clock time of each and the seconds per submission, names the
submissions whose grading failed either way (nbgrader's log), and checks that both exports
give every student the same score.

Run: python benchmarks/parallel_autograde.py [--submissions 50] [--jobs 2]
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

import course  # noqa: E402
import grade_parallel  # noqa: E402

STEM, NAME, VARIANT = "combining_evidence", "03_combining_evidence", 1
#: How nbgrader names a submission whose grading failed, at the end of its log.
FAILED = re.compile(r"There was an error processing assignment '[^']*' for student '([^']*)'")


def _nbgrader(home: Path, *args: str) -> None:
    subprocess.run(
        [grade_parallel.nbgrader_command(), *args], cwd=home, check=True, capture_output=True
    )


def _submissions(home: Path, count: int) -> None:
    """Write ``count`` submissions: the teacher's answers, then a blank one, and so on."""
    release = json.loads((home / "release" / NAME / f"{NAME}.ipynb").read_text("utf-8"))
    source = json.loads((home / "source" / NAME / f"{NAME}.ipynb").read_text("utf-8"))
    answers = {
        c["metadata"]["nbgrader"]["grade_id"]: c["source"]
        for c in source["cells"]
        if c["metadata"].get("nbgrader", {}).get("solution") and c["cell_type"] == "code"
    }
    for i in range(count):
        nb = json.loads(json.dumps(release))
        if i % 2 == 0:
            for cell in nb["cells"]:
                grade_id = cell["metadata"].get("nbgrader", {}).get("grade_id")
                if grade_id in answers:
                    cell["source"] = answers[grade_id]
        folder = home / "submitted" / f"s{i:03d}" / NAME
        folder.mkdir(parents=True)
        (folder / f"{NAME}.ipynb").write_text(json.dumps(nb), encoding="utf-8")


def _scores(home: Path) -> dict[str, str]:
    _nbgrader(home, "export", "--to", "grades.csv")
    with (home / "grades.csv").open(encoding="utf-8") as f:
        return {row["student_id"]: row["raw_score"] for row in csv.DictReader(f)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--submissions", type=int, default=50)
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        serial, parallel = Path(tmp) / "serial", Path(tmp) / "parallel"
        course.write_course(serial, ROOT, [STEM], VARIANT)
        _nbgrader(serial, "generate_assignment", NAME, "--create")
        _submissions(serial, args.submissions)
        shutil.copytree(serial, parallel)
        start = time.perf_counter()
        done = subprocess.run(
            [grade_parallel.nbgrader_command(), "autograde", NAME, "--create"],
            cwd=serial,
            capture_output=True,
            text=True,
            check=False,
            env=os.environ.copy(),
        )
        one_by_one = time.perf_counter() - start
        failed_serial = sorted(set(FAILED.findall(done.stderr)))
        outcomes, at_once = grade_parallel.grade(parallel, NAME, args.jobs)
        failed = [o.student for o in outcomes if o.status != 0]
        again = sum(o.tries > 1 for o in outcomes)
        mean = sum(o.seconds for o in outcomes) / len(outcomes)
        one, other = _scores(serial), _scores(parallel)
        same = one == other
        differ = {
            k: (one.get(k), other.get(k))
            for k in sorted({*one, *other})
            if one.get(k) != other.get(k)
        }
    n = args.submissions
    print(f"{n} submissions of {NAME} on {os.cpu_count()} cores")
    print(
        f"  nbgrader autograde, one at a time: {one_by_one:7.1f} s  ({one_by_one / n:.2f} s each)"
    )
    print(
        f"  grade_parallel.py --jobs {args.jobs}:      {at_once:7.1f} s  ({at_once / n:.2f} s each)"
    )
    print(f"  speed-up: {one_by_one / at_once:.2f}x; failed in parallel: {failed or 'none'}")
    print(f"  failed one at a time: {failed_serial or 'none'}")
    print(
        f"  in parallel, one nbgrader run takes {mean:.1f} s on average; {again} run(s) met "
        "a locked gradebook or a kernel that did not start, and ran again"
    )
    print(f"  the same score for every student both ways: {same}")
    if differ:
        print(f"  scores (one at a time, in parallel) that differ: {differ}")
    return 0 if same and not failed and not failed_serial else 1


if __name__ == "__main__":
    raise SystemExit(main())

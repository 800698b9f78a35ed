"""Grading where the learner's code never ran: the scores of an nbgrader course.

Whatever runs in the learner's kernel can be changed by the learner (the checks, numpy,
the import system, even the cells that follow). So a graded answer is decided elsewhere:

* a value answer arrives as plain data (:mod:`._sandbox`'s JSON, written by
  :func:`~dstoolkit.teaching.hand_in` in the test cell) and is compared, in the grader's
  own process, with the solution the grader computes from the data of the student's
  variant (:func:`grade_value`);
* a coding answer arrives as the *source* of the answer cells, read from the submitted
  notebook file, and runs in a fresh interpreter (:func:`run_isolated`): ``python -I -S``
  in an empty temporary folder, with nothing inherited from the kernel, dstoolkit not
  importable, no files, sockets or new processes, limited memory and a time limit per
  case; its outcomes come back as plain data and are compared, in the grader, with the
  reference's outcomes on the exercise's cases and on hidden random ones
  (:func:`grade_coding`).
"""

from __future__ import annotations

import json
import os
import re
import selectors
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import dstoolkit.teaching._sandbox as sandbox

from ._checking import Exercise, Feedback, check, get
from ._coding import Case, CodingExercise, Raised, _pending, seed_shift, untouched
from ._limits import DEFAULT_TIME_LIMIT, _TimeLimitReached
from ._variants import using_variant

#: Added to the seeds of a coding exercise's random cases in its hidden cases.
HIDDEN_SEED_SHIFT = 7919
#: Seconds the isolated interpreter may take to start and define the learner's function.
STARTUP_SECONDS = 30.0
UNREACHABLE = "dstoolkit is not available in this test: write the computation yourself"


def hidden_cases(exercise: CodingExercise) -> list[tuple[Case, Any]]:
    """Return the hidden cases of a coding exercise with the reference's outcomes (kept).

    They are its random cases drawn from other seeds (its chosen cases when it has none).
    """
    if "hidden" not in exercise._cache:
        with seed_shift(HIDDEN_SEED_SHIFT):
            cases = exercise.cases()
        random = [c for c in cases if c.label.startswith("random")]
        exercise._cache["hidden"] = exercise.expected(random or cases)
    return exercise._cache["hidden"]


def grade_value(exercise_id: str, answer: Any, variant: int) -> Feedback:
    """Return the verdict on a value answer (plain data) in the data of ``variant``.

    Parameters
    ----------
    exercise_id : str
        A value exercise, e.g. ``"mass.bel"``.
    answer : object
        The answer as :func:`~dstoolkit.teaching._sandbox.loads` returned it.
    variant : int
        The student's variant (0: the book's numbers).

    Returns
    -------
    Feedback
        The verdict; the solution is computed afresh, nothing kept from a kernel.
    """
    exercise = get(exercise_id)
    if not isinstance(exercise, Exercise):
        raise TypeError(f"{exercise_id!r} is a coding exercise; see grade_coding")
    if isinstance(answer, sandbox.Opaque):
        return Feedback(
            exercise_id,
            False,
            f"✘ {exercise_id}: wrong: the answer is {answer!r}, not a number, a string, "
            "True/False or a collection of them.",
        )
    if answer is ... or answer is None:
        return check(exercise_id, answer)
    with using_variant(variant):
        return replace(exercise).verdict(answer)


@dataclass
class Isolated:
    """What the isolated interpreter reported.

    Parameters
    ----------
    ready : bool
        The answer cells defined the function.
    problems : list of dict
        The errors the answer cells raised (type and text).
    outcomes : iterator
        The outcome of each case in turn (a value, or a :class:`Raised`); it raises the
        time limit's stop when a case runs out of time.
    """

    ready: bool
    problems: list[dict[str, str]]
    outcomes: Iterator[Any]


def _numpy_folder(into: Path) -> str:
    """Make ``into`` hold numpy alone (links to it) and return it: the runner's import path."""
    import numpy

    package = Path(numpy.__file__).resolve().parent
    into.mkdir()
    for name in ("numpy", "numpy.libs"):
        target = package.parent / name
        if target.exists():
            (into / name).symlink_to(target)
    return str(into)


def _outcome(record: dict[str, Any]) -> Any:
    if "raised" in record:
        import builtins

        error = getattr(builtins, record["raised"], None)
        if not (isinstance(error, type) and issubclass(error, BaseException)):
            error = BaseException
        return Raised(error, record.get("text", ""))
    return sandbox.decode(record.get("value"))


def run_isolated(
    sources: list[str], function: str, cases: list[Case], per_case: float
) -> Iterator[Isolated]:
    """Run the answer cells' ``sources`` in a fresh interpreter; yield its report.

    A generator: the interpreter is killed when the report's outcomes are no longer read.

    Parameters
    ----------
    sources : list of str
        The code of the answer cells, in notebook order (each runs on its own: an error in
        one leaves the functions the others define).
    function : str
        The name of the function to grade.
    cases : list of Case
        Its arguments, case by case (the expected outcomes never reach the interpreter).
    per_case : float
        Seconds each case may run.

    Yields
    ------
    Isolated
        Whether the function exists, and its outcomes case by case.
    """
    job = {
        "sources": sources,
        "function": function,
        "cases": [sandbox.encode(case.args) for case in cases],
    }
    program = Path(sandbox.__file__).read_text(encoding="utf-8")
    with tempfile.TemporaryDirectory(prefix="dstoolkit-grading-") as folder:
        job["paths"] = [_numpy_folder(Path(folder) / "lib")]
        work = Path(folder) / "work"
        work.mkdir()
        env = {
            "PATH": os.defpath,
            "LANG": "C.UTF-8",
            "HOME": str(work),
            "OPENBLAS_NUM_THREADS": "1",
            "OMP_NUM_THREADS": "1",
            "MKL_NUM_THREADS": "1",
        }
        process = subprocess.Popen(
            [sys.executable, "-I", "-S", "-c", program],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            cwd=work,
            env=env,
            start_new_session=True,
        )
        try:
            assert process.stdin is not None and process.stdout is not None
            process.stdin.write(json.dumps(job).encode("utf-8"))
            process.stdin.close()
            reader = _Reader(process.stdout)
            first = reader.read(STARTUP_SECONDS)
            if first is None or not first.get("ready"):
                problems = [] if first is None else list(first.get("problems", []))
                yield Isolated(False, problems, iter(()))
                return
            yield Isolated(True, list(first.get("problems", [])), _cases(reader, per_case))
        finally:
            _stop(process)


class _Reader:
    """Reads the runner's records, one line each, waiting at most until a deadline."""

    EOF: dict[str, Any] = {"eof": True}
    #: Bytes of one record at most (an answer's value of ``MAX_TEXT`` characters, encoded
    #: with its case number, fits many times over).
    MAX_LINE = 8 * sandbox.MAX_TEXT

    def __init__(self, stream: Any) -> None:
        self.stream = stream
        self.selector = selectors.DefaultSelector()
        self.selector.register(stream, selectors.EVENT_READ)
        self.buffer = b""

    def read(self, seconds: float) -> dict[str, Any] | None:
        """Return the next record, :attr:`EOF` when the runner ended, None when out of time."""
        deadline = time.monotonic() + seconds
        while b"\n" not in self.buffer:
            if len(self.buffer) > self.MAX_LINE:  # no record is that long: the learner's
                self.buffer = b""  # code writes to the channel; read no more of it
                return {"garbled": True}
            left = deadline - time.monotonic()
            if left <= 0 or not self.selector.select(left):
                return None
            chunk = os.read(self.stream.fileno(), 65536)
            if not chunk:
                return self.EOF
            self.buffer += chunk
        line, self.buffer = self.buffer.split(b"\n", 1)
        try:
            record = json.loads(line)
        except (ValueError, RecursionError):  # not a record the runner wrote
            record = None
        return record if isinstance(record, dict) else {"garbled": True}


def _cases(reader: _Reader, per_case: float) -> Iterator[Any]:
    number = 0
    while True:
        record = reader.read(per_case)
        if record is None:
            raise _TimeLimitReached
        if record.get("eof"):
            yield Raised(SystemExit, "your code ended the grading process")
            continue
        if record.get("case") != number:
            yield Raised(RuntimeError, "your code wrote to the grader's channel")
        else:
            yield _outcome(record)
        number += 1


def _stop(process: subprocess.Popen) -> None:
    """Kill the runner and anything it started (its own session), then reap it."""
    if process.poll() is None:
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    process.wait()
    if process.stdout is not None:
        process.stdout.close()


def grade_coding(
    exercise_id: str,
    sources: list[str],
    function: str,
    per_case: float = DEFAULT_TIME_LIMIT,
) -> Feedback:
    """Return the verdict on a coding answer run in isolation (see the module docstring).

    Parameters
    ----------
    exercise_id : str
        A coding exercise, e.g. ``"combine.dempster-code"``.
    sources : list of str
        The answer cells' source, as read from the submitted notebook file.
    function : str
        The name of the learner's function.
    per_case : float
        Seconds each case may run.

    Returns
    -------
    Feedback
        Right on every case (the exercise's own and hidden random ones), or the first
        failure with its diagnosis.
    """
    exercise = get(exercise_id)
    if not isinstance(exercise, CodingExercise):
        raise TypeError(f"{exercise_id!r} is not a coding exercise; see grade_value")
    defining = [s for s in sources if re.search(rf"^def {re.escape(function)}\(", s, re.M)]
    if defining and all(untouched(s, function) for s in defining):
        return _pending(exercise_id)
    cases = [*exercise.expected(), *hidden_cases(exercise)]
    for report in run_isolated(sources, function, [c for c, _ in cases], per_case):
        if not report.ready:
            why = "; ".join(f"{p['raised']}: {p['text']}" for p in report.problems)
            return Feedback(
                exercise_id,
                False,
                f"✘ {exercise_id}: your answer cell does not define {function}()"
                + (f" when run on its own ({why})." if why else "."),
            )
        outcomes = report.outcomes
        return exercise.judge(
            cases,
            _reader(outcomes),
            f"stopped after {per_case:g} s",
        )
    raise AssertionError("run_isolated yields one report")  # pragma: no cover


def _reader(outcomes: Iterator[Any]) -> Callable[[Case], Any]:
    def outcome_of(case: Case) -> Any:
        return next(outcomes)

    return outcome_of

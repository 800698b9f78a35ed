"""The test cells of a graded notebook: they hand the answers in, they do not grade them.

A test cell of an nbgrader course reads::

    from dstoolkit.teaching import hand_in
    hand_in("combine.conflict", K)

:func:`hand_in` prints the answer as plain data (one line of JSON); the grader reads that
line from the executed notebook and decides the score in its own process
(:mod:`dstoolkit.teaching.grading`). A coding answer is not taken from the kernel at all:
the grader reads the answer cell from the submitted notebook file. So nothing the learner's
code does in the kernel (patching this function, numpy or the import system) can decide a
score: it can only change the answer handed in.
"""

from __future__ import annotations

import os
from typing import Any

from ._checking import _canonical, check, get
from ._coding import CodingExercise
from ._sandbox import dumps

#: Starts the line that carries a value answer in a test cell's output.
MARK = "handed in:"


def hand_in(exercise_id: str, answer: Any) -> None:
    """Print the answer to ``exercise_id`` for the grader, then the self-study check's verdict.

    Parameters
    ----------
    exercise_id : str
        The exercise, e.g. ``"combine.conflict"``.
    answer : object
        The learner's answer (a coding exercise's function is graded from the notebook
        file instead: only its name matters here).

    Notes
    -----
    The verdict shown in the notebook is the self-study check's, for the learner; the
    grade is decided when the notebook is graded (nbgrader sets ``NBGRADER_EXECUTION``
    then, and the check is left out).

    Examples
    --------
    >>> from dstoolkit.teaching import hand_in
    >>> hand_in("mass.bel", 0.8)  # doctest: +ELLIPSIS
    handed in: mass.bel 0.8
    ✔ mass.bel: right.
    """
    exercise = get(exercise_id)
    if isinstance(exercise, CodingExercise):
        name = getattr(answer, "__name__", "your function")
        print(f"{MARK} {exercise_id}: {name} (graded from the answer cell's code)")
    else:
        print(f"{MARK} {exercise_id} {dumps(_canonical(answer))}")
    if os.environ.get("NBGRADER_EXECUTION") != "autograde":
        print(check(exercise_id, answer).message)

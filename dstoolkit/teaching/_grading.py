"""The tests of graded work (the autograder cells of an nbgrader course).

A test cell imports what it needs itself, so a name the learner rebinds in the notebook
(``check``, ``dempster``) changes nothing::

    from dstoolkit.teaching import must_pass, must_pass_alone
    must_pass("combine.dempster-code", dempster_rule)
    ### BEGIN HIDDEN TESTS
    must_pass_alone("combine.dempster-code", dempster_rule)
    ### END HIDDEN TESTS

:func:`must_pass` is the check of the self-study sheets, turned into a pass or a failure.
:func:`must_pass_alone` runs a coding answer on other cases (the random ones drawn from
another seed) where dstoolkit cannot be reached: a function that only calls the library's
own implementation fails it.
"""

from __future__ import annotations

import linecache
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import replace
from importlib.abc import MetaPathFinder
from types import CellType, FunctionType, ModuleType
from typing import Any

from dstoolkit.errors import GradingFailure, InvalidInputError

from ._checking import Exercise, check, get
from ._coding import Case, CodingExercise, seed_shift
from ._variants import using_variant

#: Added to the seeds of a coding exercise's random cases in the hidden tests.
HIDDEN_SEED_SHIFT = 7919
UNREACHABLE = "dstoolkit is not available in this test: write the computation yourself"


def must_pass(exercise_id: str, answer: Any, *, time_limit: float | None = None) -> None:
    """Print the check's verdict on a right ``answer``; raise with the verdict otherwise.

    The verdict appears once on a feedback page: printed when right, as the error's
    message when not (and IPython leaves this function out of the traceback).

    Parameters
    ----------
    exercise_id : str
        The exercise, e.g. ``"mass.bel"``.
    answer : object
        The learner's answer (for a coding exercise, the function).
    time_limit : float, optional
        Seconds the learner's function may run (see :func:`~dstoolkit.teaching.check`).

    Raises
    ------
    GradingFailure
        The answer is not right (or not given); the message is the check's.

    See Also
    --------
    must_pass_alone : the hidden tests of a coding answer.
    must_pass_recomputed : the hidden test of a value answer.

    Examples
    --------
    >>> from dstoolkit.teaching import must_pass
    >>> must_pass("mass.bel", 0.8)
    ✔ mass.bel: right.
    >>> must_pass("mass.bel", 0.3)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    dstoolkit.errors.GradingFailure: ... mass.bel: wrong. That is m({low, mid}) alone; ...
    """
    __tracebackhide__ = True  # noqa: F841 - IPython shows the verdict, not this frame
    feedback = check(exercise_id, answer, time_limit=time_limit)
    _report(feedback.message, feedback.correct)


def _report(message: str, correct: bool) -> None:
    """Print a right verdict; raise a wrong one (shown once, as the error's message)."""
    __tracebackhide__ = True  # noqa: F841 - IPython shows the verdict, not this frame
    if not correct:
        # raised from a one-line frame of its own: IPython always shows the frame that
        # raised, and this one shows nothing of the grading code
        exec(_RAISE, {"failure": GradingFailure(message)})  # noqa: S102 - fixed code
    print(message)


_RAISE_SOURCE = "raise failure  # the answer is not right: the verdict is below\n"
_RAISE = compile(_RAISE_SOURCE, "<test>", "exec")
# its one line, for the traceback (an entry without a modification time stays cached)
linecache.cache["<test>"] = (len(_RAISE_SOURCE), None, [_RAISE_SOURCE], "<test>")


def must_pass_recomputed(exercise_id: str, answer: Any, *, variant: int) -> None:
    """Check a value answer against its solution computed afresh from the data of ``variant``.

    Raise unless it is right.

    The hidden test of a value answer in a course: it does not read the kept solution nor
    the variant the notebook chose (:func:`~dstoolkit.teaching.set_variant`), so an answer
    copied from the book's solutions fails in a variant, and so does one that switched the
    notebook back to the book's numbers or altered a kept solution.

    Parameters
    ----------
    exercise_id : str
        A value exercise, e.g. ``"mass.bel"``.
    answer : object
        The learner's answer.
    variant : int
        The course's variant (0: the book's numbers).

    Raises
    ------
    GradingFailure
        The answer is not right (or not given).
    InvalidInputError
        ``exercise_id`` is a coding exercise (its hidden test is :func:`must_pass_alone`).

    See Also
    --------
    must_pass : the visible test, the sheet's check.

    Examples
    --------
    >>> from dstoolkit.teaching import must_pass_recomputed
    >>> must_pass_recomputed("mass.bel", 0.8, variant=0)
    ✔ hidden test of mass.bel: right.
    """
    exercise = get(exercise_id)
    if not isinstance(exercise, Exercise):
        raise InvalidInputError(
            f"{exercise_id!r} is a coding exercise; its hidden tests are must_pass_alone's"
        )
    if answer is ... or answer is None:
        feedback = check(exercise_id, answer)
    else:
        fresh = replace(exercise)  # a new cache: nothing kept, the solver runs again
        with using_variant(variant):
            feedback = fresh.verdict(answer)
    __tracebackhide__ = True  # noqa: F841 - IPython shows the verdict, not this frame
    _report(
        feedback.message.replace("✔ ", "✔ hidden test of ", 1).replace(
            "✘ ", "✘ hidden test of ", 1
        ),
        feedback.correct,
    )


def must_pass_alone(
    exercise_id: str, answer: Callable[..., Any], *, time_limit: float | None = None
) -> None:
    """Run a coding answer on hidden cases where dstoolkit cannot be reached.

    Raise unless it is right on all of them.

    The hidden cases are the exercise's random cases drawn from other seeds (its chosen
    cases when it has no random ones). While the answer runs, dstoolkit cannot be
    imported, and every dstoolkit object the notebook's functions refer to by a global
    name raises when used.

    Parameters
    ----------
    exercise_id : str
        A coding exercise, e.g. ``"combine.dempster-code"``.
    answer : callable
        The learner's function.
    time_limit : float, optional
        Seconds for all hidden cases together (by default the sheet's).

    Raises
    ------
    GradingFailure
        The answer fails a hidden case, runs out of time, or calls dstoolkit.
    InvalidInputError
        ``exercise_id`` is not a coding exercise.

    See Also
    --------
    must_pass : the visible test.

    Examples
    --------
    >>> from dstoolkit.teaching import must_pass_alone, solution
    >>> must_pass_alone("mass.bel-pl-code", solution("mass.bel-pl-code"))  # doctest: +ELLIPSIS
    ✔ hidden tests of mass.bel-pl-code: right on all ... cases (...).
    """
    exercise = get(exercise_id)
    if not isinstance(exercise, CodingExercise):
        raise InvalidInputError(
            f"{exercise_id!r} is not a coding exercise; hidden tests with "
            "dstoolkit out of reach are for coding exercises"
        )
    cases = hidden_cases(exercise)
    target = alone(answer) if isinstance(answer, FunctionType) else answer
    with library_hidden():
        feedback = exercise.verdict(target, time_limit, cases)
    __tracebackhide__ = True  # noqa: F841 - IPython shows the verdict, not this frame
    _report(
        feedback.message.replace("✔ ", "✔ hidden tests of ").replace("✘ ", "✘ hidden tests of "),
        feedback.correct,
    )


def hidden_cases(exercise: CodingExercise) -> list[tuple[Case, Any]]:
    """Return the hidden cases of a coding exercise with the reference's outcomes (kept)."""
    if "hidden" not in exercise._cache:
        with seed_shift(HIDDEN_SEED_SHIFT):
            cases = exercise.cases()
        random = [c for c in cases if c.label.startswith("random")]
        exercise._cache["hidden"] = exercise.expected(random or cases)
    return exercise._cache["hidden"]


# -- dstoolkit out of reach -----------------------------------------------------------------


class _Unreachable:
    """Stands for a dstoolkit object in a hidden test: any use raises ImportError."""

    def __init__(self, name: str) -> None:
        object.__setattr__(self, "_name", name)

    def _refuse(self, *args: Any, **kwargs: Any) -> Any:
        raise ImportError(f"{object.__getattribute__(self, '_name')}: {UNREACHABLE}")

    __call__ = _refuse
    __iter__ = _refuse
    __getitem__ = _refuse

    def __getattr__(self, attr: str) -> Any:
        return self._refuse()

    def __repr__(self) -> str:
        return f"<dstoolkit's {object.__getattribute__(self, '_name')}: not available here>"


def _from_dstoolkit(value: Any) -> bool:
    if isinstance(value, ModuleType):
        name = value.__name__
    elif isinstance(value, type | FunctionType) or callable(value):
        name = getattr(value, "__module__", None) or type(value).__module__
    else:
        name = type(value).__module__
    return isinstance(name, str) and (name == "dstoolkit" or name.startswith("dstoolkit."))


def alone(fn: FunctionType) -> FunctionType:
    """Return a copy of ``fn`` whose references to dstoolkit objects raise on use.

    The global names and closure variables of ``fn`` (and those of the functions of its
    notebook it calls) that refer to dstoolkit objects are replaced by objects that raise on use.
    """
    source = fn.__globals__
    names: dict[str, Any] = {}
    for key, value in source.items():
        names[key] = (
            _Unreachable(key) if (_from_dstoolkit(value) and not key.startswith("__")) else value
        )
    for key, value in source.items():
        if isinstance(value, FunctionType) and value.__globals__ is source:
            names[key] = _rebound(value, names)
    return _rebound(fn, names)


def _cell(name: str, cell: CellType) -> CellType:
    """Return a closure cell, with a dstoolkit object replaced by one that raises on use."""
    try:
        value = cell.cell_contents
    except ValueError:  # an empty cell
        return cell
    return CellType(_Unreachable(name)) if _from_dstoolkit(value) else cell


def _rebound(fn: FunctionType, names: dict[str, Any]) -> FunctionType:
    closure = (
        None
        if fn.__closure__ is None
        else tuple(
            _cell(name, cell)
            for name, cell in zip(fn.__code__.co_freevars, fn.__closure__, strict=True)
        )
    )
    twin = FunctionType(fn.__code__, names, fn.__name__, fn.__defaults__, closure)
    twin.__kwdefaults__ = fn.__kwdefaults__
    twin.__qualname__ = fn.__qualname__
    twin.__module__ = fn.__module__
    twin.__doc__ = fn.__doc__
    return twin


class _Refuse(MetaPathFinder):
    def find_spec(self, fullname: str, path: Any, target: Any = None) -> Any:
        if fullname == "dstoolkit" or fullname.startswith("dstoolkit."):
            raise ImportError(UNREACHABLE)
        return None


@contextmanager
def library_hidden() -> Iterator[None]:
    """Inside the ``with`` block ``import dstoolkit`` (and any submodule) fails."""
    kept = {
        name: module
        for name, module in sys.modules.items()
        if name == "dstoolkit" or name.startswith("dstoolkit.")
    }
    finder = _Refuse()
    for name in kept:
        del sys.modules[name]
    sys.meta_path.insert(0, finder)
    try:
        yield
    finally:
        sys.meta_path.remove(finder)
        sys.modules.update(kept)

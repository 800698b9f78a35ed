"""Coding exercises: the learner writes a function; the check runs it on test cases.

A coding exercise is registered with a *reference* (the computation done with dstoolkit,
taking and returning the same plain data as the learner's function), a list of *cases*
(fixed ones, edge cases such as total conflict or a degenerate interval, and seeded random
ones) and wrong implementations that stand for named mistakes (the teacher's plain
solution is in the repository's ``answer_key``, not in this package)::

    coding_exercise("combine.dempster-code", reference=..., cases=...,
                    mistakes=((wrong_fn, "You forgot to renormalise ..."),), hint="...")

``check(id, learner_function)`` runs the learner's function on every case (a fresh copy of
the inputs each time) and reports the first case that fails with its input, the expected
and the obtained result, naming the mistake when the result is that of a registered wrong
implementation. An exception raised by the learner's code is reported, not propagated; a
function that still raises NotImplementedError (the stub) is "not answered yet".
"""

from __future__ import annotations

import ast
import copy
import inspect
import math
import textwrap
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from dstoolkit.errors import InvalidInputError

from ._checking import NOT_ANSWERED, Feedback, isolated_feedback, register
from ._limits import _TimeLimitReached, describe, run_limited, too_big, valid_limit
from ._limits import time_limit as default_limit


@dataclass(frozen=True)
class Case:
    """One test case of a coding exercise.

    Parameters
    ----------
    label : str
        What the case is, shown in the feedback (e.g. ``"total conflict"``); labels of
        seeded random cases start with ``"random"``.
    args : tuple
        The arguments the learner's function is called with (a fresh copy each time).

    Examples
    --------
    >>> from dstoolkit.teaching import Case
    >>> Case("a point", ([[1.0, 1.0, 1.0]],)).label
    'a point'
    """

    label: str
    args: tuple


@dataclass(frozen=True)
class Raised:
    """The outcome "raised an exception of this type" (an expected error, or a crash)."""

    error: type[BaseException]
    text: str = ""

    def __repr__(self) -> str:
        return f"raises {self.error.__name__}" + (f" ({self.text})" if self.text else "")


def _outcome(fn: Callable[..., Any], args: tuple, end: float | None = None) -> Any:
    """``fn`` on a copy of ``args`` (stopped at ``end``, monotonic time, if given).

    An exception it raises becomes a :class:`Raised`.
    """
    try:
        if end is None:
            return fn(*copy.deepcopy(args))
        return run_limited(fn, copy.deepcopy(args), end)
    except Exception as err:  # noqa: BLE001 - the learner's code may raise anything
        return Raised(type(err), str(err)[:120])


def _documented(outcome: Any) -> Any:
    """Report dstoolkit's own errors as the built-in error the exercises ask for (ValueError)."""
    if isinstance(outcome, Raised) and issubclass(outcome.error, ValueError):
        return Raised(ValueError, "as the docstring asks")
    return outcome


def _plain(x: Any) -> Any:
    """Numbers, arrays, tuples, lists and dicts → floats, lists and dicts (keys as sets).

    Parameters
    ----------
    x : object
        An outcome of a function under test.

    Returns
    -------
    object
        Its plain form, compared by ``same``.
    """
    if isinstance(x, Raised | str | bool | np.bool_) or x is None:
        return x
    if isinstance(x, Mapping):
        return {
            (frozenset(k) if isinstance(k, set | frozenset | tuple | list) else k): _plain(v)
            for k, v in x.items()
        }
    if isinstance(x, np.ndarray):
        return _plain(x.tolist())
    if isinstance(x, Sequence):
        return [_plain(v) for v in x]
    try:
        return float(x)
    except (TypeError, ValueError):
        return x


def same(got: Any, expected: Any, atol: float = 1e-9, rtol: float = 1e-6) -> bool:
    """Equal as plain data.

    Numbers within tolerance, dicts without zero-mass entries, an expected exception matched by the
    same type or a subclass.
    """
    got, expected = _plain(got), _plain(expected)
    if isinstance(expected, Raised):
        return isinstance(got, Raised) and issubclass(got.error, expected.error)
    if isinstance(got, Raised):
        return False
    if isinstance(expected, dict):
        if not isinstance(got, dict):
            return False
        keys = {
            k
            for k, v in {**got, **expected}.items()
            if not (isinstance(v, float) and abs(v) < atol)
        }
        return all(same(got.get(k, 0.0), expected.get(k, 0.0), atol, rtol) for k in keys)
    if isinstance(expected, list):
        return (
            isinstance(got, list)
            and len(got) == len(expected)
            and all(same(g, e, atol, rtol) for g, e in zip(got, expected, strict=True))
        )
    if isinstance(expected, float):
        return (
            isinstance(got, float)
            and not math.isnan(got)
            and math.isclose(got, expected, abs_tol=atol, rel_tol=rtol)
        )
    return got == expected


def show(x: Any, limit: int = 300) -> str:
    """Return a short, readable form of a value (sets as {a, b}, floats to 6 digits)."""
    x = _plain(x)
    if isinstance(x, float):
        text = f"{x:.6g}"
    elif isinstance(x, frozenset):
        text = "{" + ", ".join(sorted(map(str, x))) + "}"
    elif isinstance(x, dict):
        text = "{" + ", ".join(f"{show(k)}: {show(v)}" for k, v in x.items()) + "}"
    elif isinstance(x, list):
        text = "[" + ", ".join(show(v) for v in x) + "]"
    elif callable(x) and hasattr(x, "__name__"):
        text = x.__name__
    else:
        text = repr(x)
    return text if len(text) <= limit else text[: limit - 1] + "…"


@dataclass(frozen=True)
class CodingExercise:
    """A coding exercise: the learner writes a function, the check runs it on cases.

    Parameters
    ----------
    id : str
        ``"<chapter>.<name>-code"``.
    reference : callable
        The computation done with dstoolkit, on the same plain data as the learner's.
    cases : callable
        Returns the list of :class:`Case` (chosen and seeded random ones).
    hint : str
        Shown after a wrong result.
    mistakes : tuple of (callable, str)
        Wrong implementations and the explanation each one gets.
    normalise : callable
        Brings an outcome to the form compared (plain data by default).
    arg_names : tuple of str
        The names of the function's arguments, for the feedback.

    See Also
    --------
    coding_exercise : registers one.

    Examples
    --------
    >>> from dstoolkit.teaching import REGISTRY, check
    >>> ex = REGISTRY["mass.bel-pl-code"]
    >>> bool(check(ex.id, lambda m, a: (0.5, 1.0)))
    False
    """

    id: str
    reference: Callable[..., Any]
    cases: Callable[[], list[Case]]
    hint: str
    mistakes: tuple[tuple[Callable[..., Any], str], ...] = ()
    normalise: Callable[[Any], Any] = _plain
    arg_names: tuple[str, ...] = ()
    _cache: dict[str, Any] = field(default_factory=dict, init=False, compare=False, repr=False)

    def wrong_answer(self) -> Callable[..., Any]:
        """Return the first registered wrong implementation.

        Returns
        -------
        callable
            A function the check rejects, naming its mistake.
        """
        return self.mistakes[0][0]

    def _normalised(self, x: Any) -> Any:
        """``normalise`` applied to an outcome; an error in it becomes the outcome."""
        if isinstance(x, Raised):
            return x
        try:
            return self.normalise(x)
        except Exception as err:  # noqa: BLE001 - the learner's result may be anything
            return Raised(type(err), f"the result could not be read: {err}"[:120])

    def expected(self, cases: list[Case] | None = None) -> list[tuple[Case, Any]]:
        """Every case with the reference's outcome.

        Parameters
        ----------
        cases : list of Case, optional
            The cases; by default the exercise's own (kept after the first call).

        Returns
        -------
        list of (Case, object)
            Each case with the outcome the learner's function must give.
        """
        if cases is not None:
            return [
                (case, _documented(self._normalised(_outcome(self.reference, case.args))))
                for case in cases
            ]
        if "expected" not in self._cache:
            self._cache["expected"] = self.expected(self.cases())
        return self._cache["expected"]

    def _inputs(self, case: Case) -> str:
        names = self.arg_names or tuple(f"arg{i + 1}" for i in range(len(case.args)))
        return ", ".join(f"{n} = {show(a, 160)}" for n, a in zip(names, case.args, strict=True))

    def verdict(
        self,
        answer: Any,
        time_limit: float | None = None,
        cases: list[tuple[Case, Any]] | None = None,
    ) -> Feedback:
        """Run ``answer`` on every case within a time limit; report the first failure.

        Parameters
        ----------
        answer : callable
            The learner's function.
        time_limit : float, optional
            Seconds for all cases together (by default the sheet's, see
            :func:`~dstoolkit.teaching.set_time_limit`).
        cases : list of (Case, object), optional
            Cases with the reference's outcomes; by default :meth:`expected`.

        Returns
        -------
        Feedback
            Right on all cases, or the first failing case with a diagnosis.
        """
        if not callable(answer):
            return Feedback(
                self.id,
                False,
                f"✘ {self.id}: give the function itself (its name, "
                f"without parentheses), not {type(answer).__name__}.",
            )
        if _untouched(answer):
            return _pending(self.id)
        cases = self.expected() if cases is None else cases
        seconds = valid_limit(time_limit) if time_limit is not None else default_limit()
        return isolated_feedback(
            lambda: self._run_cases(answer, cases, seconds),
            seconds,
            Feedback(
                self.id,
                False,
                f"✘ {self.id}: stopped after {seconds:g} s: does your function end? "
                "(check(..., time_limit=60) gives it longer.)",
                {"timeout": True},
            ),
        )

    def _run_cases(
        self, answer: Callable[..., Any], cases: list[tuple[Case, Any]], seconds: float
    ) -> Feedback:
        """Run ``answer`` on the cases until the first failure, stopping it at the limit."""
        end = time.monotonic() + seconds
        return self.judge(
            cases,
            lambda case: _outcome(answer, case.args, end),
            f"stopped after {seconds:g} s",
            " (check(..., time_limit=60) gives it longer.)",
        )

    def judge(
        self,
        cases: list[tuple[Case, Any]],
        outcome_of: Callable[[Case], Any],
        stopped: str,
        longer: str = "",
    ) -> Feedback:
        """Compare the outcome of each case with the expected one; report the first failure.

        Parameters
        ----------
        cases : list of (Case, object)
            Cases with the reference's outcomes.
        outcome_of : callable
            Returns the learner's outcome of a case (a ``Raised`` for an error); it
            raises the time limit's stop when the case ran out of time.
        stopped : str
            How the verdict names a stop, e.g. ``"stopped after 5 s"``.
        longer : str
            What the verdict adds after a stop (how to give the function more time).

        Returns
        -------
        Feedback
            Right on all cases, or the first failing case with a diagnosis.
        """
        for number, (case, want) in enumerate(cases, 1):
            where = f"case {number} of {len(cases)} ({case.label})"
            try:
                got = outcome_of(case)
                if isinstance(got, Raised) and issubclass(got.error, NotImplementedError):
                    return _pending(self.id)
                if too_big(got):
                    return Feedback(
                        self.id,
                        False,
                        f"✘ {self.id}: wrong on {where}: your "
                        f"function returned {describe(got)}, far more than this "
                        "case needs.",
                        {"case": number},
                    )
                got = self._normalised(got)
            except _TimeLimitReached:
                return Feedback(
                    self.id,
                    False,
                    f"✘ {self.id}: {stopped} on {where}: does your function end?{longer}",
                    {"case": number, "timeout": True},
                )
            if same(got, want):
                continue
            return Feedback(
                self.id,
                False,
                self._diagnosis(case, number, len(cases), want, got),
                self._details(case, got, number),
            )
        fixed = sum(not c.label.startswith("random") for c, _ in cases)
        return Feedback(
            self.id,
            True,
            f"✔ {self.id}: right on all {len(cases)} cases "
            f"({fixed} chosen, {len(cases) - fixed} random).",
        )

    def _details(self, case: Case, got: Any, number: int) -> dict[str, Any]:
        why = self._mistake(case, got)
        return {"case": number, **({"mistake": why} if why else {})}

    def _mistake(self, case: Case, got: Any) -> str:
        """Return the explanation of the registered mistake whose outcome ``got`` is, or ''."""
        for wrong, why in self.mistakes:
            if same(got, self._normalised(_outcome(wrong, case.args))):
                return why
        return ""

    def _diagnosis(self, case: Case, number: int, total: int, want: Any, got: Any) -> str:
        """Return what a learner sees for a failing case.

        The expected outcome is shown only for a random case or an expected error: a chosen case may
        be another exercise's answer.
        """
        shown = isinstance(want, Raised) or case.label.startswith("random")
        head = (
            f"✘ {self.id}: wrong on case {number} of {total} ({case.label}).\n"
            f"  input:    {self._inputs(case)}\n"
            + (f"  expected: {show(want)}\n" if shown else "")
            + f"  got:      {show(got)}\n"
        )
        if got is None:
            return head + "  Your function returned None: did you forget `return`?"
        if isinstance(want, Raised) and not isinstance(got, Raised):
            return head + (
                f"  This case must be refused: raise {want.error.__name__} (the "
                "docstring says when) instead of returning a result."
            )
        why = self._mistake(case, got)
        if why:
            return head + f"  Mistake: {why}"
        if isinstance(got, Raised) and not isinstance(want, Raised):
            return head + f"  Your function raised an error; fix it first. Hint: {self.hint}"
        total_mass = _mass_total(got) if _is_masses(want) else None
        if total_mass is not None and abs(total_mass - 1.0) > 1e-6:
            return head + (f"  Your masses add up to {total_mass:.6g}, not 1. Hint: {self.hint}")
        return head + f"  Hint: {self.hint}"


def _pending(exercise_id: str) -> Feedback:
    return Feedback(
        exercise_id,
        False,
        f"{exercise_id}: {NOT_ANSWERED} — write the body "
        "of the function (it still raises NotImplementedError).",
        {"pending": True},
    )


def _untouched(fn: Any) -> bool:
    """Return True for a function whose body is only its docstring (and ``...`` or ``pass``)."""
    try:
        source = textwrap.dedent(inspect.getsource(fn))
    except (OSError, TypeError):
        return False
    return untouched(source, getattr(fn, "__name__", ""))


def untouched(source: str, name: str) -> bool:
    """Return True when every definition of ``name`` in ``source`` is a stub.

    A stub's body is only its docstring (and ``...`` or ``pass``); a source without a
    definition of ``name`` is not one.
    """
    try:
        tree = ast.parse(source)
    except (SyntaxError, ValueError):
        return False
    found = [n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == name]
    return bool(found) and all(
        isinstance(stmt, ast.Pass)
        or (
            isinstance(stmt, ast.Expr)
            and isinstance(stmt.value, ast.Constant)
            and (isinstance(stmt.value.value, str) or stmt.value.value is Ellipsis)
        )
        for node in found
        for stmt in node.body
    )


def _is_masses(value: Any) -> bool:
    """Return a dict of masses on sets (plain form) that add up to 1."""
    return (
        isinstance(value, dict)
        and bool(value)
        and all(isinstance(k, frozenset) for k in value)
        and all(isinstance(v, float) for v in value.values())
        and abs(sum(value.values()) - 1.0) < 1e-6
    )


def _mass_total(value: Any) -> float | None:
    if not isinstance(value, dict):
        return None
    try:
        return float(sum(float(v) for v in value.values()))
    except (TypeError, ValueError):
        return None


def coding_exercise(
    exercise_id: str,
    *,
    reference: Callable[..., Any],
    cases: Callable[[], list[Case]],
    hint: str,
    mistakes: tuple[tuple[Callable[..., Any], str], ...],
    normalise: Callable[[Any], Any] = _plain,
    arg_names: tuple[str, ...] = (),
) -> CodingExercise:
    """Register a coding exercise (see the module docstring) and return it.

    Parameters
    ----------
    exercise_id : str
        ``"<chapter>.<name>-code"``.
    reference : callable
        The computation done with dstoolkit, on plain data.
    cases : callable
        Returns the list of :class:`Case`.
    hint : str
        Shown after a wrong result.
    mistakes : tuple of (callable, str)
        Wrong implementations and their explanations; at least one (the sheets' tests
        feed it to the check cell, which must name it).
    normalise : callable
        Brings an outcome to the form compared.
    arg_names : tuple of str
        The names of the function's arguments, for the feedback.

    Returns
    -------
    CodingExercise
        The registered exercise.

    Raises
    ------
    InvalidInputError
        No mistake given, or the id is taken or has no chapter part.

    Examples
    --------
    >>> from dstoolkit.teaching import REGISTRY, Case, check, coding_exercise
    >>> ex = coding_exercise("demo.twice-code", reference=lambda x: 2 * x,
    ...                      cases=lambda: [Case("one", (1.0,))],
    ...                      hint="Twice x.", mistakes=((lambda x: x, "That is x."),))
    >>> check("demo.twice-code", lambda x: x).message.splitlines()[-1]
    '  Mistake: That is x.'
    >>> del REGISTRY["demo.twice-code"]
    """
    if not mistakes:
        raise InvalidInputError(f"coding exercise {exercise_id!r} needs at least one mistake")
    item = CodingExercise(exercise_id, reference, cases, hint, mistakes, normalise, arg_names)
    register(item)
    return item


_SHIFT = [0]


def seeded(seed: int) -> np.random.Generator:
    """Return the random generator of a coding exercise's random cases.

    Its seed is fixed: the same cases on every run, so a failing case can be looked at again;
    hidden tests shift it, see :func:`seed_shift`.
    """
    return np.random.default_rng(seed + _SHIFT[0])


@contextmanager
def seed_shift(shift: int) -> Iterator[None]:
    """Inside the ``with`` block :func:`seeded` draws from ``seed + shift``.

    Other random cases, the same kinds.
    """
    before = _SHIFT[0]
    _SHIFT[0] = shift
    try:
        yield
    finally:
        _SHIFT[0] = before

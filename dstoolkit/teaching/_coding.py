"""Coding exercises: the learner writes a function; the check runs it on test cases.

A coding exercise is registered with a *reference* (the computation done with dstoolkit,
taking and returning the same plain data as the learner's function), a list of *cases*
(fixed ones, edge cases such as total conflict or a degenerate interval, and seeded random
ones), a *plain* reference implementation (the solution shown to teachers: no dstoolkit
inside) and wrong implementations that stand for named mistakes::

    coding_exercise("combine.dempster-code", reference=..., plain=..., cases=...,
                    mistakes=((wrong_fn, "You forgot to renormalise ..."),), hint="...")

``check(id, learner_function)`` runs the learner's function on every case (a fresh copy of
the inputs each time) and reports the first case that fails with its input, the expected
and the obtained result, naming the mistake when the result is that of a registered wrong
implementation. An exception raised by the learner's code is reported, not propagated; a
function that still raises NotImplementedError (the stub) is "not answered yet".
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from dstoolkit.errors import InvalidInputError

from ._checking import NOT_ANSWERED, Feedback, register


@dataclass(frozen=True)
class Case:
    """One test case: a short label (e.g. ``"total conflict"``) and the arguments."""

    label: str
    args: tuple


@dataclass(frozen=True)
class Raised:
    """The outcome "raised an exception of this type" (an expected error, or a crash)."""

    error: type[BaseException]
    text: str = ""

    def __repr__(self) -> str:
        return f"raises {self.error.__name__}" + (f" ({self.text})" if self.text else "")


def _outcome(fn: Callable[..., Any], args: tuple) -> Any:
    try:
        return fn(*copy.deepcopy(args))
    except Exception as err:  # noqa: BLE001 - the learner's code may raise anything
        return Raised(type(err), str(err)[:120])


def _documented(outcome: Any) -> Any:
    """dstoolkit's own errors as the built-in error the exercises ask for (ValueError)."""
    if isinstance(outcome, Raised) and issubclass(outcome.error, ValueError):
        return Raised(ValueError, "as the docstring asks")
    return outcome


def _plain(x: Any) -> Any:
    """Numbers, arrays, tuples, lists and dicts → floats, lists and dicts (keys as sets)."""
    if isinstance(x, Raised | str | bool | np.bool_) or x is None:
        return x
    if isinstance(x, Mapping):
        return {(frozenset(k) if isinstance(k, set | frozenset | tuple | list) else k): _plain(v)
                for k, v in x.items()}
    if isinstance(x, np.ndarray):
        return _plain(x.tolist())
    if isinstance(x, Sequence):
        return [_plain(v) for v in x]
    try:
        return float(x)
    except (TypeError, ValueError):
        return x


def same(got: Any, expected: Any, atol: float = 1e-9, rtol: float = 1e-6) -> bool:
    """Equal as plain data: numbers within tolerance, dicts without zero-mass entries,
    an expected exception matched by the same type or a subclass."""
    got, expected = _plain(got), _plain(expected)
    if isinstance(expected, Raised):
        return isinstance(got, Raised) and issubclass(got.error, expected.error)
    if isinstance(got, Raised):
        return False
    if isinstance(expected, dict):
        if not isinstance(got, dict):
            return False
        keys = {k for k, v in {**got, **expected}.items()
                if not (isinstance(v, float) and abs(v) < atol)}
        return all(same(got.get(k, 0.0), expected.get(k, 0.0), atol, rtol) for k in keys)
    if isinstance(expected, list):
        return (isinstance(got, list) and len(got) == len(expected)
                and all(same(g, e, atol, rtol) for g, e in zip(got, expected, strict=True)))
    if isinstance(expected, float):
        return (isinstance(got, float) and not math.isnan(got)
                and math.isclose(got, expected, abs_tol=atol, rel_tol=rtol))
    return got == expected


def show(x: Any, limit: int = 300) -> str:
    """A short, readable form of a value (sets as {a, b}, floats to 6 digits)."""
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
    """A coding exercise; see the module docstring."""

    id: str
    reference: Callable[..., Any]
    plain: Callable[..., Any]
    cases: Callable[[], list[Case]]
    hint: str
    mistakes: tuple[tuple[Callable[..., Any], str], ...] = ()
    normalise: Callable[[Any], Any] = _plain
    arg_names: tuple[str, ...] = ()
    _cache: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)

    @property
    def solution(self) -> Callable[..., Any]:
        """The plain reference implementation (what a teacher shows)."""
        return self.plain

    def wrong_answer(self) -> Callable[..., Any]:
        """The first registered wrong implementation."""
        return self.mistakes[0][0]

    def _normalised(self, x: Any) -> Any:
        """``normalise`` applied to an outcome; an error in it becomes the outcome."""
        if isinstance(x, Raised):
            return x
        try:
            return self.normalise(x)
        except Exception as err:  # noqa: BLE001 - the learner's result may be anything
            return Raised(type(err), f"the result could not be read: {err}"[:120])

    def expected(self) -> list[tuple[Case, Any]]:
        """Every case with the reference's outcome (computed once)."""
        if "expected" not in self._cache:
            self._cache["expected"] = [
                (case, _documented(self._normalised(_outcome(self.reference, case.args))))
                for case in self.cases()]
        return self._cache["expected"]

    def _inputs(self, case: Case) -> str:
        names = self.arg_names or tuple(f"arg{i + 1}" for i in range(len(case.args)))
        return ", ".join(f"{n} = {show(a, 160)}" for n, a in zip(names, case.args, strict=True))

    def verdict(self, answer: Any) -> Feedback:
        """Run ``answer`` on every case; report the first failure."""
        if not callable(answer):
            return Feedback(self.id, False, f"✘ {self.id}: give the function itself (its name, "
                            f"without parentheses), not {type(answer).__name__}.")
        cases = self.expected()
        for number, (case, want) in enumerate(cases, 1):
            got = _outcome(answer, case.args)
            if isinstance(got, Raised) and issubclass(got.error, NotImplementedError):
                return Feedback(self.id, False, f"{self.id}: {NOT_ANSWERED} — write the body "
                                "of the function (it still raises NotImplementedError).",
                                {"pending": True})
            got = self._normalised(got)
            if same(got, want):
                continue
            head = (f"✘ {self.id}: wrong on case {number} of {len(cases)} ({case.label}).\n"
                    f"  input:    {self._inputs(case)}\n"
                    f"  expected: {show(want)}\n"
                    f"  got:      {show(got)}\n")
            for wrong, why in self.mistakes:
                if same(got, self._normalised(_outcome(wrong, case.args))):
                    return Feedback(self.id, False, head + f"  Mistake: {why}",
                                    {"mistake": why, "case": number})
            if isinstance(got, Raised) and not isinstance(want, Raised):
                return Feedback(self.id, False, head + "  Your function raised an error; "
                                f"fix it first. Hint: {self.hint}", {"case": number})
            return Feedback(self.id, False, head + f"  Hint: {self.hint}", {"case": number})
        fixed = sum(not c.label.startswith("random") for c, _ in cases)
        return Feedback(self.id, True, f"✔ {self.id}: right on all {len(cases)} cases "
                        f"({fixed} chosen, {len(cases) - fixed} random).")


def coding_exercise(
    exercise_id: str,
    *,
    reference: Callable[..., Any],
    plain: Callable[..., Any],
    cases: Callable[[], list[Case]],
    hint: str,
    mistakes: tuple[tuple[Callable[..., Any], str], ...],
    normalise: Callable[[Any], Any] = _plain,
    arg_names: tuple[str, ...] = (),
) -> CodingExercise:
    """Register a coding exercise (see the module docstring) and return it.

    At least one mistake (a wrong implementation with its explanation) is required: the
    sheets' tests feed it to the check cell, which must name it.
    """
    if not mistakes:
        raise InvalidInputError(f"coding exercise {exercise_id!r} needs at least one mistake")
    item = CodingExercise(exercise_id, reference, plain, cases, hint, mistakes, normalise,
                          arg_names)
    register(item)
    return item


def seeded(seed: int) -> np.random.Generator:
    """The random generator of a coding exercise's random cases (fixed seed: the same cases
    on every run, so a failing case can be looked at again)."""
    return np.random.default_rng(seed)

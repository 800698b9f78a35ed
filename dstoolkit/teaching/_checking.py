"""Check cells for the exercise sheets: ``check("mass.bel", answer)`` says right or wrong.

Every exercise with a checked answer is registered with a function that *computes* the
expected answer with dstoolkit (no typed-in numbers), a hint shown after a wrong answer, and a
tolerance. Adding one is a few lines in the module of its chapter::

    @exercise("gauge.fundamental", hint="f_F = c / (2L); c comes from eq. (31).")
    def _() -> float:
        return speed_of_sound(20.0) / (2 * 1.3)

Answers may be numbers, sequences or arrays of numbers (compared element by element with
``|answer − solution| ≤ atol + rtol·|solution|``), dicts of numbers, booleans, strings,
sets, :class:`~dstoolkit.evidence.MassFunction` or :class:`~dstoolkit.evidence.IntervalEvidence`.

``mistakes`` lists plausible wrong answers, each as a function computing it and the hint
to give when a learner's answer matches it. They are recognised *before* the checker
says "close, keep more decimals". Coding exercises (the learner writes a function) are
registered with :func:`dstoolkit.teaching.coding_exercise` and checked by the same
:func:`check`.
"""

from __future__ import annotations

import dataclasses
import html
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from dstoolkit.errors import InvalidInputError
from dstoolkit.evidence import IntervalEvidence, MassFunction

from ._child_checks import plain_data, run_isolated
from ._limits import describe, too_big, valid_limit
from ._limits import time_limit as time_limit_default
from ._variants import current_variant, using_variant

Solver = Callable[[], Any]
#: Message of an exercise that still holds its placeholder.
NOT_ANSWERED = "not answered yet"


@dataclass(frozen=True)
class Exercise:
    """One exercise with a checked answer (registered by :func:`exercise`).

    Parameters
    ----------
    id : str
        ``"<chapter>.<name>"``, e.g. ``"mass.bel"``.
    solve : callable
        Computes the solution with dstoolkit, from the chapter's data.
    hint : str
        Shown after a wrong answer.
    atol, rtol : float
        Tolerance of a numerical answer: ``|answer − solution| ≤ atol + rtol·|solution|``.
    mistakes : tuple of (callable, str)
        Plausible wrong answers, each computed by a function, with the hint each gets.
    canonical : callable, optional
        Applied to answers and solutions before comparing (e.g. to sort rows).
    varies : bool
        The solver reads its chapter's variant data, so a variant has other answers.
    distinct : bool
        With ``varies``: every variant's answer differs from the book's (variants are drawn
        so). False for a choice among a few named options, whose answer follows the
        variant's data but may be the book's.

    See Also
    --------
    exercise : registers one.
    check : the verdict on an answer.

    Examples
    --------
    >>> from dstoolkit.teaching import REGISTRY
    >>> ex = REGISTRY["mass.bel"]
    >>> ex.varies, ex.atol
    (True, 0.0005)
    """

    id: str
    solve: Solver
    hint: str
    atol: float = 5e-4
    rtol: float = 1e-3
    mistakes: tuple[tuple[Solver, str], ...] = ()
    canonical: Callable[[Any], Any] | None = None
    """Applied to answers and solutions before comparing (e.g. sort rows of evidence)."""
    varies: bool = False
    """True when the solver reads its chapter's variant data (see ``set_variant``)."""
    distinct: bool = True
    """With ``varies``: a variant's answer differs from the book's (False: a choice may not)."""
    _cache: dict[Any, Any] = field(default_factory=dict, init=False, compare=False, repr=False)

    def _expected(self) -> Any:
        """Return the answer the check expects in the current variant (computed once, kept)."""
        key = ("expected", current_variant() if self.varies else 0)
        if key not in self._cache:
            self._cache[key] = self.solve()
        return self._cache[key]

    def _expected_in(self, variant: int) -> Any:
        """Return the answer the check expects in the data of ``variant`` (0: the book's)."""
        with using_variant(variant):
            return self._expected()

    def verdict(self, answer: Any, time_limit: float | None = None) -> Feedback:
        """Right, a named mistake, close, or wrong with the hint.

        Parameters
        ----------
        answer : object
            The learner's answer.
        time_limit : float, optional
            Seconds the comparison may take (by default the sheet's, see
            :func:`~dstoolkit.teaching.set_time_limit`); it matters only for an answer that
            is not plain numbers, strings, arrays or evidence, whose own methods (its
            ``__float__``, say) are run in a child process stopped at the limit.

        Returns
        -------
        Feedback
            The verdict, in the current variant.
        """
        if not plain_data(answer):
            seconds = valid_limit(time_limit) if time_limit is not None else time_limit_default()
            return isolated_feedback(
                lambda: self._verdict(answer),
                seconds,
                Feedback(
                    self.id,
                    False,
                    f"✘ {self.id}: stopped after {seconds:g} s comparing your answer "
                    f"(a {type(answer).__name__}); give plain numbers.",
                    {"timeout": True},
                ),
            )
        return self._verdict(answer)

    def _verdict(self, answer: Any) -> Feedback:
        if too_big(answer):
            return Feedback(
                self.id,
                False,
                f"✘ {self.id}: wrong: the answer is "
                f"{describe(answer)}, far more than this exercise asks for.",
            )
        if self.canonical is not None:
            try:
                answer = self.canonical(answer)
            except (TypeError, ValueError, IndexError) as err:
                return Feedback(self.id, False, f"✘ {self.id}: wrong ({err}). Hint: {self.hint}")
        ok, reason = _compare(answer, self._canonical(self._expected()), self)
        if ok:
            return Feedback(self.id, True, f"✔ {self.id}: right.")
        for wrong, why in self.mistakes:
            if _compare(answer, self._canonical(wrong()), self)[0]:
                return Feedback(self.id, False, f"✘ {self.id}: wrong. {why}", {"mistake": why})
        sol = self._canonical(self._expected())
        if not reason and _nearly(answer, sol, self):
            off = float(
                np.max(
                    np.abs(
                        np.asarray(_canonical(answer), float) - np.asarray(_canonical(sol), float)
                    )
                )
            )
            reason = f"close, but off by {off:.2g}; keep more decimals in the intermediate steps"
        reason = f" ({reason})" if reason else ""
        return Feedback(self.id, False, f"✘ {self.id}: wrong{reason}. Hint: {self.hint}")

    def _canonical(self, value: Any) -> Any:
        return value if self.canonical is None else self.canonical(value)

    def wrong_answer(self) -> Any:
        """Return a plausible wrong answer: the first listed mistake, else the solution moved.

        A listed mistake that is the right answer in the current variant (a choice among
        a few options can be) is passed over.

        Returns
        -------
        object
            An answer the check rejects.
        """
        right = self._canonical(self._expected())
        for wrong, _ in self.mistakes:
            value = wrong()
            if not _compare(value, right, self)[0]:
                return value
        return _moved(self._expected())


@dataclass(frozen=True)
class Feedback:
    """The verdict of :func:`check`; true when right. Shown as its message in a notebook.

    Parameters
    ----------
    exercise_id : str
        The exercise checked.
    correct : bool
        Whether the answer is right.
    message : str
        What the learner reads: "✔ …: right.", or "✘ …" with a hint.
    details : dict
        Machine-readable extras: ``"mistake"`` (the named mistake's text), ``"case"`` (a
        coding exercise's failing case), ``"pending"`` (not answered yet), ``"timeout"``.

    Examples
    --------
    >>> from dstoolkit.teaching import check
    >>> feedback = check("mass.bel", 0.8)
    >>> feedback.correct, feedback.message
    (True, '✔ mass.bel: right.')
    """

    exercise_id: str
    correct: bool
    message: str
    details: dict[str, Any] = field(default_factory=dict)

    def __bool__(self) -> bool:
        return self.correct

    def __repr__(self) -> str:
        return self.message

    def _repr_html_(self) -> str:
        colour = (
            "#1b7f3b" if self.correct else "#5f6368" if self.details.get("pending") else "#b00020"
        )
        body = html.escape(self.message).replace("\n", "<br>")
        return f"<p style='color:{colour};font-family:monospace;white-space:pre-wrap'>{body}</p>"


def isolated_feedback(work: Callable[[], Feedback], seconds: float, stopped: Feedback) -> Feedback:
    """Give ``work()``'s verdict, run in a child process killed past ``seconds``.

    ``stopped`` is the verdict when it had to be killed (see
    :func:`~dstoolkit.teaching._child_checks.run_isolated`). The verdict comes back as plain
    values, so that it crosses even while a test hides dstoolkit's modules from the learner.
    """
    fields = run_isolated(lambda: dataclasses.astuple(work()), seconds, lambda: None)
    return stopped if fields is None else Feedback(*fields)


REGISTRY: dict[str, Any] = {}


def register(item: Any) -> None:
    """Add an exercise (any object with ``id`` and ``verdict``) to :data:`REGISTRY`."""
    if "." not in item.id:
        raise InvalidInputError(f"exercise id {item.id!r} must look like 'chapter.name'")
    if item.id in REGISTRY:
        raise InvalidInputError(f"exercise {item.id!r} is registered twice; rename one")
    REGISTRY[item.id] = item


def exercise(
    exercise_id: str,
    *,
    hint: str,
    atol: float = 5e-4,
    rtol: float = 1e-3,
    mistakes: tuple[tuple[Solver, str], ...] = (),
    canonical: Callable[[Any], Any] | None = None,
    varies: bool = False,
    distinct: bool = True,
) -> Callable[[Solver], Solver]:
    """Register the decorated function as the solver of ``exercise_id``.

    Parameters
    ----------
    exercise_id : str
        ``"<chapter>.<name>"``, e.g. ``"mass.bel"``; registering an id twice is an error.
    hint : str
        Shown after a wrong answer; it must not state the answer.
    atol, rtol : float
        The tolerance of a numerical answer: ``|answer − solution| ≤ atol + rtol·|solution|``.
    mistakes : tuple of (callable, str)
        Plausible wrong answers (each computed by a function) and the hint each one gets.
    canonical : callable, optional
        Applied to answers and solutions before comparing (e.g. to sort rows).
    varies : bool
        The solver reads its chapter's variant data (``data(chapter)``), so that a
        variant's sheet has other answers than the book's.
    distinct : bool
        With ``varies``: whether every variant's answer must differ from the book's; False
        for a choice among a few named options (its answer follows the data, and a variant
        may share the book's choice).

    Returns
    -------
    callable
        A decorator that registers the solver and returns it unchanged.

    Raises
    ------
    InvalidInputError
        The id has no chapter part.

    See Also
    --------
    check : says whether an answer is right.
    coding_exercise : registers an exercise whose answer is a function.

    Examples
    --------
    >>> from dstoolkit.teaching import REGISTRY, check, exercise
    >>> @exercise("demo.double", hint="Twice 21.")
    ... def _():
    ...     return 2 * 21
    >>> bool(check("demo.double", 42))
    True
    >>> del REGISTRY["demo.double"]
    """
    if "." not in exercise_id:
        raise InvalidInputError(f"exercise id {exercise_id!r} must look like 'chapter.name'")

    def add(solve: Solver) -> Solver:
        register(
            Exercise(exercise_id, solve, hint, atol, rtol, mistakes, canonical, varies, distinct)
        )
        return solve

    return add


def exercises(prefix: str = "") -> list[str]:
    """Return the ids of the registered exercises, those starting with ``prefix`` only.

    Parameters
    ----------
    prefix : str
        E.g. ``"mass."`` for the exercises of the chapter on mass functions.

    Returns
    -------
    list of str
        The ids, sorted.

    Examples
    --------
    >>> from dstoolkit.teaching import exercises
    >>> exercises("mass.b")
    ['mass.bel', 'mass.bel-pl-code', 'mass.betp', 'mass.betp-code']
    """
    return sorted(k for k in REGISTRY if k.startswith(prefix))


def get(exercise_id: str) -> Any:
    """Return the registered exercise ``exercise_id`` (a KeyError lists its chapter's ids)."""
    if not isinstance(exercise_id, str):
        raise InvalidInputError(
            f"an exercise id is a string such as 'mass.bel', got {exercise_id!r}; "
            "see exercises() for the ids"
        )
    try:
        return REGISTRY[exercise_id]
    except KeyError:
        close = [k for k in REGISTRY if k.split(".")[0] == exercise_id.split(".")[0]]
        raise KeyError(
            f"no exercise {exercise_id!r}; exercises of that chapter: {close or exercises()}"
        ) from None


def mistake(exercise_id: str) -> Any:
    """Return a plausible wrong answer to an exercise; the tests feed it to the check cells.

    It is the exercise's first listed mistake, or for a coding exercise its first wrong
    implementation.

    Parameters
    ----------
    exercise_id : str
        The exercise, e.g. ``"mass.bel"``.

    Returns
    -------
    object
        An answer (or function) the check rejects, naming the mistake.

    Examples
    --------
    >>> from dstoolkit.teaching import check, mistake
    >>> bool(check("mass.bel", mistake("mass.bel")))
    False
    """
    return get(exercise_id).wrong_answer()


def check(
    exercise_id: str, answer: Any, *, time_limit: float | None = None, variant: int | None = None
) -> Feedback:
    """Compare ``answer`` with the solution of ``exercise_id``: right, or wrong with a hint.

    In a notebook, end a cell with ``check("mass.bel", answer)`` to see the verdict. An
    answer left as ``...`` (or ``None``) is reported as not answered yet.

    Parameters
    ----------
    exercise_id : str
        The exercise, ``"<chapter>.<name>"`` (e.g. ``"mass.bel"``).
    answer : object
        A number, a sequence or dict of numbers, a bool, a string, a set, evidence; for a
        coding exercise the function itself (``check("combine.dempster-code",
        dempster_rule)``).
    time_limit : float, optional
        Seconds a coding exercise's function may run, all cases together (by default
        :func:`~dstoolkit.teaching.set_time_limit`'s, 5 s).
    variant : int, optional
        Whose data the solution is computed from: 0 is the book's, ``N`` the sheet of
        ``scripts/sheets.py --variant N`` (by default the one
        :func:`~dstoolkit.teaching.set_variant` chose, 0 unless a sheet's setup cell set it).

    Returns
    -------
    Feedback
        True when right; its message says right, or wrong with a hint.

    Raises
    ------
    KeyError
        No exercise ``exercise_id`` (the message lists its chapter's exercises).

    See Also
    --------
    hand_in : what a graded test cell calls instead (the grader decides, not the kernel).
    set_variant : the data the checks compute with.

    Examples
    --------
    >>> from dstoolkit.teaching import check
    >>> check("mass.bel", 0.8)
    ✔ mass.bel: right.
    >>> bool(check("mass.bel", 0.3))
    False
    """
    ex = get(exercise_id)
    if answer is ... or answer is None:
        return Feedback(
            exercise_id,
            False,
            f"{exercise_id}: {NOT_ANSWERED} — replace ... by your answer.",
            {"pending": True},
        )
    with using_variant(variant):
        return ex.verdict(answer, time_limit)


def answers_differ(ex: Exercise, first: Any, second: Any) -> bool:
    """Whether two solutions of ``ex`` are told apart by its check (its tolerance)."""
    return not _compare(ex._canonical(first), ex._canonical(second), ex)[0]


# -- comparison -------------------------------------------------------------------------


def _canonical(value: Any) -> Any:
    """Evidence → plain data; other values unchanged."""
    if isinstance(value, IntervalEvidence):
        return value.to_rows()
    if isinstance(value, MassFunction):
        return {frozenset(k): v for k, v in value.as_dict().items()}
    return value


def _compare(answer: Any, sol: Any, ex: Exercise) -> tuple[bool, str]:
    """(equal within tolerance?, reason when not)."""
    answer, sol = _canonical(answer), _canonical(sol)
    if isinstance(sol, bool | np.bool_):
        if not isinstance(answer, bool | np.bool_):
            return False, "the answer is True or False"
        return bool(answer) == bool(sol), ""
    if isinstance(sol, str):
        return str(answer).strip().lower() == sol.strip().lower(), ""
    if isinstance(sol, frozenset | set):
        got = frozenset([answer]) if isinstance(answer, str) else frozenset(answer)
        return got == frozenset(sol), ""
    if isinstance(sol, Mapping):
        if not isinstance(answer, Mapping):
            return False, f"give a dict with keys {sorted(map(str, sol))}"
        norm = {_key(k): v for k, v in answer.items()}
        missing = [k for k in sol if _key(k) not in norm]
        if missing:
            return False, f"keys missing: {[_show(k) for k in missing]}"
        return _close([norm[_key(k)] for k in sol], list(sol.values()), ex)
    return _close(answer, sol, ex)


def _key(k: Any) -> Any:
    """Return a dict key as a set.

    ``"low"``, ``("low",)`` and ``frozenset({"low"})`` are one key.
    """
    if isinstance(k, set | frozenset | tuple | list):
        return frozenset(k)
    if isinstance(k, str):
        return frozenset([k])
    return k


def _show(k: Any) -> str:
    return "{" + ", ".join(sorted(map(str, k))) + "}" if isinstance(k, frozenset) else str(k)


def _close(answer: Any, sol: Any, ex: Exercise) -> tuple[bool, str]:
    if isinstance(answer, np.ma.MaskedArray) and np.ma.getmaskarray(answer).any():
        return False, "the answer has masked entries; give plain numbers (no mask)"
    try:
        a = np.asarray(answer, dtype=float)
    except OverflowError:
        return False, "expected a number or numbers, got one too large for a float"
    except (TypeError, ValueError):
        return False, f"expected a number or numbers, got {type(answer).__name__}"
    s = np.asarray(sol, dtype=float)
    if a.size != s.size:
        return False, f"expected {s.size} number(s), got {a.size}"
    return bool(np.all(np.isclose(a.reshape(s.shape), s, atol=ex.atol, rtol=ex.rtol))), ""


def _nearly(answer: Any, sol: Any, ex: Exercise) -> bool:
    """Within 20 tolerances (numbers only): a rounding slip rather than a wrong method."""
    try:
        a = np.asarray(_canonical(answer), dtype=float)
        s = np.asarray(_canonical(sol), dtype=float)
    except (TypeError, ValueError, OverflowError):
        return False
    return a.size == s.size and bool(
        np.all(np.isclose(a.reshape(s.shape), s, atol=20 * ex.atol, rtol=20 * ex.rtol))
    )


def _moved(value: Any) -> Any:
    """Return an answer that is clearly not ``value`` (same type and shape)."""
    value = _canonical(value)
    if isinstance(value, bool | np.bool_):
        return not value
    if isinstance(value, str):
        return value + " (not)"
    if isinstance(value, set | frozenset):
        return frozenset(list(value)[1:]) if len(value) > 1 else frozenset({"?"})
    if isinstance(value, Mapping):
        return {k: _moved(v) for k, v in value.items()}
    arr = np.asarray(value, dtype=float)
    moved = arr + 0.1 + 0.1 * np.abs(arr)
    return moved.tolist() if moved.ndim else float(moved)

"""The exercise checker: every registered exercise accepts its solution, rejects a wrong
answer with a hint, and recognises the common mistakes it lists."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pytest

from dstoolkit import IntervalEvidence, MassFunction
from dstoolkit.teaching import REGISTRY, Feedback, check, exercise, exercises, solution

IDS = exercises()


def perturbed(value: object) -> object:
    """An answer that is clearly not ``value`` (same type and shape)."""
    if isinstance(value, bool | np.bool_):
        return not value
    if isinstance(value, str):
        return value + " (not)"
    if isinstance(value, set | frozenset):
        return frozenset(list(value)[1:]) if value else frozenset({"?"})
    if isinstance(value, Mapping):
        return {k: perturbed(v) for k, v in value.items()}
    if isinstance(value, IntervalEvidence):
        value = value.to_rows()
    if isinstance(value, MassFunction):
        return perturbed({k: v for k, v in value.as_dict().items()})
    arr = np.asarray(value, dtype=float)
    return arr + 0.1 + 0.1 * np.abs(arr)


def test_registry_is_not_empty_and_covers_the_evidence_chapters():
    for chapter in ("bounded.", "mass.", "combine.", "dependent.", "noise."):
        assert exercises(chapter), f"no exercise registered for {chapter}"


@pytest.mark.parametrize("exercise_id", IDS)
def test_solution_is_accepted(exercise_id: str):
    feedback = check(exercise_id, solution(exercise_id))
    assert isinstance(feedback, Feedback)
    assert feedback.correct, feedback.message
    assert "right" in repr(feedback)


@pytest.mark.parametrize("exercise_id", IDS)
def test_wrong_answer_is_rejected_with_a_hint(exercise_id: str):
    feedback = check(exercise_id, perturbed(solution(exercise_id)))
    assert not feedback.correct
    assert "wrong" in feedback.message
    hint = REGISTRY[exercise_id].hint
    mistakes = [why for _, why in REGISTRY[exercise_id].mistakes]
    assert hint in feedback.message or any(why in feedback.message for why in mistakes)


@pytest.mark.parametrize(
    ("exercise_id", "index"),
    [(k, i) for k in IDS for i in range(len(REGISTRY[k].mistakes))],
)
def test_listed_mistakes_get_their_own_hint(exercise_id: str, index: int):
    wrong, why = REGISTRY[exercise_id].mistakes[index]
    feedback = check(exercise_id, wrong())
    assert not feedback.correct, "a listed mistake must not be accepted as right"
    assert why in feedback.message


@pytest.mark.parametrize("exercise_id", [k for k in IDS
                                         if np.ndim(solution(k)) == 0
                                         and isinstance(solution(k), float)])
def test_numeric_tolerance(exercise_id: str):
    ex = REGISTRY[exercise_id]
    value = solution(exercise_id)
    assert check(exercise_id, value + 0.5 * ex.atol).correct
    assert not check(exercise_id, value + 3 * (ex.atol + ex.rtol * abs(value))).correct


def test_paper_slips_are_rejected():
    # The values the paper prints are wrong answers for the exact computations.
    assert not check("dependent.en1-exact", 0.8655)
    assert not check("dependent.a6", 0.1890)
    assert not check("noise.theta2", (-129.7, 115.7))


def test_unanswered_and_malformed_answers_give_feedback_not_errors():
    assert "not answered yet" in check("mass.bel", ...).message
    assert "not answered yet" in check("mass.bel", None).message
    assert "number" in check("mass.bel", "0.8 please").message
    assert "2 number(s), got 3" in check("noise.cut", (0.1, 0.2, 0.3)).message
    assert "True or False" in check("bounded.too-tight", 1).message
    assert "keys missing" in check("mass.vacuous-betp", {"low": 1 / 3}).message


def test_dict_answers_accept_set_keys_and_close_answers_say_so():
    betp = solution("mass.vacuous-betp")
    assert check("mass.vacuous-betp", {k: round(v, 4) for k, v in betp.items()})
    close = check("mass.bel", solution("mass.bel") + 0.005)
    assert not close and "close" in close.message


def test_unknown_id_lists_the_chapter_exercises():
    with pytest.raises(KeyError, match="mass.bel"):
        check("mass.nonexistent", 1.0)


def test_registering_is_short_and_guarded():
    @exercise("testonly.half", hint="Half of one.")
    def _() -> float:
        return 0.5

    try:
        assert check("testonly.half", 0.5)
        assert "Half of one." in check("testonly.half", 0.9).message
        with pytest.raises(ValueError, match="twice"):
            exercise("testonly.half", hint="again")(lambda: 1.0)
        with pytest.raises(ValueError, match="chapter.name"):
            exercise("nodot", hint="x")
    finally:
        REGISTRY.pop("testonly.half", None)

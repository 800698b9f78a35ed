"""The exercise checker and the coding exercises' checks.

Every registered exercise accepts its solution, rejects a wrong answer with a hint, and
recognises the common mistakes it lists; every coding exercise accepts its plain reference
solution, names each registered wrong implementation, reports the first failing case with
input, expected and got, and survives the learner's exceptions.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pytest

from answer_key import solution
from dstoolkit import IntervalEvidence, MassFunction
from dstoolkit.teaching import (
    REGISTRY,
    CodingExercise,
    Exercise,
    Feedback,
    check,
    exercise,
    exercises,
    mistake,
)
from dstoolkit.teaching._coding import Raised

IDS = [k for k in exercises() if isinstance(REGISTRY[k], Exercise)]
CODING = [k for k in exercises() if isinstance(REGISTRY[k], CodingExercise)]


def perturbed(value: object) -> object:
    """Return an answer that is clearly not ``value`` (same type and shape)."""
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


@pytest.mark.parametrize("exercise_id", [k for k in IDS if isinstance(solution(k), float)])
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


# -- coding exercises ---------------------------------------------------------------------------


def test_there_are_at_least_fifteen_coding_exercises():
    assert len(CODING) >= 15


@pytest.mark.parametrize("exercise_id", CODING)
def test_plain_solution_passes_every_case(exercise_id: str):
    feedback = check(exercise_id, solution(exercise_id))
    assert feedback.correct, feedback.message
    assert "right on all" in feedback.message


@pytest.mark.parametrize(
    ("exercise_id", "index"), [(k, i) for k in CODING for i in range(len(REGISTRY[k].mistakes))]
)
def test_each_wrong_implementation_is_named(exercise_id: str, index: int):
    wrong, why = REGISTRY[exercise_id].mistakes[index]
    feedback = check(exercise_id, wrong)
    assert not feedback.correct
    for part in ("wrong on case", "input:", "got:", f"Mistake: {why}"):
        assert part in feedback.message, feedback.message
    # the expected outcome is shown for a random case or an expected error only: a chosen
    # case may be the answer of another exercise
    case, want = REGISTRY[exercise_id].expected()[feedback.details["case"] - 1]
    shown = case.label.startswith("random") or isinstance(want, Raised)
    assert ("expected:" in feedback.message) == shown, feedback.message


@pytest.mark.parametrize("exercise_id", CODING)
def test_stub_crash_and_non_function_give_feedback_not_errors(exercise_id: str):
    def stub(*args):
        raise NotImplementedError("write the body of this function")

    def crash(*args):
        return 1 / 0

    assert "not answered yet" in check(exercise_id, stub).message
    crashed = check(exercise_id, crash)
    assert not crashed and "raises ZeroDivisionError" in crashed.message
    assert "case 1 of" in crashed.message
    assert "give the function itself" in check(exercise_id, 3.0).message
    assert "not answered yet" in check(exercise_id, ...).message


@pytest.mark.parametrize("exercise_id", CODING)
def test_cases_are_seeded_and_include_chosen_and_random_ones(exercise_id: str):
    ex = REGISTRY[exercise_id]
    first, again = ex.cases(), ex.cases()
    assert [c.label for c in first] == [c.label for c in again]
    assert repr([c.args for c in first]) == repr([c.args for c in again])
    labels = [c.label for c in first]
    assert any(lab.startswith("random") for lab in labels)
    assert sum(not lab.startswith("random") for lab in labels) >= 2


def test_the_required_edge_cases_are_there():
    labels = {k: " | ".join(c.label for c in REGISTRY[k].cases()) for k in CODING}
    assert "total conflict" in labels["combine.dempster-code"]
    assert "vacuous source" in labels["combine.dempster-code"]
    assert "degenerate interval" in labels["dependent.energy-code"]
    assert "total conflict" in labels["filter.step-code"]
    assert "degenerate box" in labels["random.vertex-code"]
    for required in (
        "combine.dempster-code",
        "dependent.energy-code",
        "dependent.coefficients-code",
        "dependent.combine-code",
        "random.vertex-code",
        "noise.triangular-code",
        "filter.step-code",
    ):
        assert required in CODING


def test_an_expected_error_is_matched_by_type():
    """Total conflict: raising ValueError is right, returning something is wrong."""

    def returns_empty(m1, m2):
        return (
            solution("combine.dempster-code")(m1, m2) if any(b & c for b in m1 for c in m2) else {}
        )

    feedback = check("combine.dempster-code", returns_empty)
    assert not feedback and "(total conflict)" in feedback.message
    assert "expected: raises ValueError" in feedback.message


def test_filter_step_reference_is_dstoolkits_filter_and_plain_agrees():
    from dstoolkit.teaching._ex_coding import HAND_STEP, filter_record

    step = filter_record(*HAND_STEP)
    rows, estimate = solution("filter.step-code")(*HAND_STEP)
    assert estimate == pytest.approx(float(step.estimate[0]), abs=1e-12)
    assert sum(m for _, _, m in rows) == pytest.approx(1.0)


def test_mistake_gives_a_wrong_answer_for_every_exercise():
    for k in exercises():
        assert not check(k, mistake(k)).correct, k


def test_reference_solutions_are_plain_python():
    """What teachers show is written out, not a call to dstoolkit."""
    import inspect

    from answer_key import plain_solutions

    source = inspect.getsource(plain_solutions)
    assert "dstoolkit" not in source.split('"""', 2)[2]
    for k in CODING:
        assert solution(k).__module__ == plain_solutions.__name__, k

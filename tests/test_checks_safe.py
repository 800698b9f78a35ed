"""Self-study checks cannot hang and do not mislead.

* A function that never ends gets a one-line verdict naming the running case, in about the
  time limit (a sheet can raise it); an ``except Exception`` in the loop or a wait in C
  (``time.sleep``) does not keep it running.
* A huge or odd result gets its verdict at once, with a short description.
* No feedback gives away an answer: a failing chosen case does not show its expected
  outcome, and no hint or mistake text holds the numbers of its exercise's solution.
* The diagnoses: total conflict not refused, frozenset keys, ``None`` returned, masses that
  do not add up to 1.
* Stubs never shadow a name the sheet imported; a check run before the setup cell says
  "run the setup cell first"; ``solution()`` hands out copies.
* Graded work: a coding answer that only calls dstoolkit passes the visible check and fails
  the hidden tests, and dstoolkit is importable again afterwards.
"""

from __future__ import annotations

import re
import sys
import time

import numpy as np
import pytest
from conftest import ROOT

from answer_key import solution
from dstoolkit.errors import InvalidInputError
from dstoolkit.teaching import REGISTRY, CodingExercise, Exercise, check, set_time_limit
from dstoolkit.teaching._checking import _canonical

sys.path.insert(0, str(ROOT / "scripts"))
import sheets  # noqa: E402

CODING = sorted(k for k, v in REGISTRY.items() if isinstance(v, CodingExercise))


def endless(m, a):
    while True:
        pass


def stubborn(m, a):
    while True:
        try:
            while True:
                pass
        except Exception:  # noqa: BLE001 - the learner's code swallows errors
            pass


def sleeper(m, a):
    time.sleep(3600)


@pytest.mark.parametrize("fn", [endless, stubborn, sleeper])
def test_an_endless_loop_is_stopped_with_one_line_naming_the_case(fn):
    start = time.monotonic()
    feedback = check("mass.bel-pl-code", fn, time_limit=1)
    took = time.monotonic() - start
    assert not feedback.correct and took < 4, took  # the timer rings 0.5 s after
    assert "\n" not in feedback.message
    assert feedback.message.startswith("✘ mass.bel-pl-code: stopped after 1 s on case 1 of ")
    assert "(running example, A = {low, mid})" in feedback.message
    assert "does your function end?" in feedback.message
    assert feedback.details["timeout"]


def test_the_default_limit_is_a_few_seconds_and_a_sheet_can_raise_it():
    previous = set_time_limit(0.5)
    try:
        start = time.monotonic()
        assert "stopped after 0.5 s" in check("mass.bel-pl-code", endless).message
        assert time.monotonic() - start < 3
    finally:
        assert set_time_limit(previous) == 0.5
    assert 1 <= previous <= 10
    with pytest.raises(InvalidInputError, match="above 0"):
        set_time_limit(-1)
    with pytest.raises(InvalidInputError, match="above 0"):
        check("mass.bel-pl-code", endless, time_limit=float("nan"))


def test_a_slow_but_finishing_function_passes_under_a_raised_limit():
    right = solution("mass.bel-pl-code")

    def slow(m, a):
        time.sleep(0.02)
        return right(m, a)

    assert check("mass.bel-pl-code", slow, time_limit=30)
    assert not check("mass.bel-pl-code", slow, time_limit=0.05)


@pytest.mark.parametrize(
    "result", [np.zeros(10**7), list(range(10**6)), {i: 0.0 for i in range(10**6)}]
)
def test_huge_results_get_a_fast_short_verdict(result):
    start = time.monotonic()
    feedback = check("mass.bel-pl-code", lambda m, a: result)
    assert time.monotonic() - start < 1.5
    assert not feedback.correct and len(feedback.message) < 300
    assert "far more than this case needs" in feedback.message
    value = check("mass.bel", result)
    assert not value.correct and "far more than this exercise asks for" in value.message


def test_none_returned_asks_about_return():
    def forgot(m, a):
        bel = sum(v for b, v in m.items() if b <= frozenset(a))  # noqa: F841

    message = check("mass.bel-pl-code", forgot).message
    assert "did you forget `return`?" in message


def test_an_untouched_stub_is_not_answered_yet():
    def bel_pl(m, a):
        """Stand for the released stub: docstring only."""

    assert "not answered yet" in check("mass.bel-pl-code", bel_pl).message


def test_total_conflict_not_refused_is_named_as_such():
    def renormalises(m1, m2):
        out, k = {}, 0.0
        for b, x in m1.items():
            for c, y in m2.items():
                if b & c:
                    out[b & c] = out.get(b & c, 0.0) + x * y
                else:
                    k += x * y
        return {a: v / (1 - k) for a, v in out.items()}

    message = check("combine.dempster-code", renormalises).message
    assert "(total conflict)" in message
    assert "This case must be refused: raise ValueError" in message
    assert "renormalise" not in message


def test_masses_that_do_not_add_up_to_one_are_named():
    def adds_rate(m, rate, frame):
        return {**m, frozenset(frame): 0.5}

    message = check("combine.discount-code", adds_rate).message
    assert "Your masses add up to 1.3, not 1." in message


def test_frozenset_keys_are_the_books_own_notation():
    third = 1 / 3
    as_sets = {frozenset({"low"}): third, frozenset({"mid"}): third, frozenset({"high"}): third}
    assert check("mass.vacuous-betp", as_sets)
    assert check("mass.vacuous-betp", {("low",): third, ("mid",): third, ("high",): third})
    assert "keys missing" in check("mass.vacuous-betp", {frozenset({"low"}): 1.0}).message


def _numbers(value) -> list[float]:
    value = _canonical(value)
    if isinstance(value, bool | str) or value is None:
        return []
    if isinstance(value, dict):
        return [x for v in value.values() for x in _numbers(v)]
    try:
        return [float(x) for x in np.asarray(value, dtype=float).ravel()]
    except (TypeError, ValueError):
        return []


def _written(x: float) -> set[str]:
    """Return how a number may be written in a text (2–4 decimals, either minus sign).

    That is when the number says more than a round number does.
    """
    if x == int(x) or abs(x) in (0.1, 0.2, 0.25, 0.5, 0.75):
        return set()
    out = set()
    for decimals in (2, 3, 4):
        text = f"{x:.{decimals}f}".rstrip("0").rstrip(".")
        if len(text.lstrip("-0.").replace(".", "")) >= 2:
            out |= {text, text.replace("-", "−")}
    return out


@pytest.mark.parametrize(
    "exercise_id", sorted(k for k, v in REGISTRY.items() if isinstance(v, Exercise))
)
def test_no_hint_or_mistake_text_states_the_solution(exercise_id):
    exercise = REGISTRY[exercise_id]
    texts = [exercise.hint, *(why for _, why in exercise.mistakes)]
    for x in _numbers(solution(exercise_id)):
        for form in _written(x):
            pattern = r"(?<![\d.])" + re.escape(form) + r"(?!\d)"
            assert not any(re.search(pattern, t) for t in texts), (exercise_id, form)


def _value_answers() -> set[str]:
    return {
        form
        for k, v in REGISTRY.items()
        if isinstance(v, Exercise)
        for x in _numbers(solution(k))
        for form in _written(x)
    }


@pytest.mark.parametrize("exercise_id", CODING)
def test_coding_feedback_shows_no_answer_of_an_exercise(exercise_id):
    answers = _value_answers()
    exercise = REGISTRY[exercise_id]
    for answer in (lambda *a: 0.0, *(wrong for wrong, _ in exercise.mistakes)):
        message = check(exercise_id, answer).message
        expected = [line for line in message.splitlines() if "expected:" in line]
        for line in expected:
            shown = re.findall(r"-?\d+\.\d+", line)
            assert not set(shown) & answers, (exercise_id, line)


def test_filter_step_feedback_does_not_give_exercise_7_1():
    message = check("filter.step-code", lambda *a: ([], 0.0)).message
    assert "1.4991" not in message and "expected:" not in message


def test_solution_hands_out_copies():
    value = solution("mass.vacuous-betp")
    value["low"] = 7.0
    assert solution("mass.vacuous-betp")["low"] == pytest.approx(1 / 3)
    assert check("mass.vacuous-betp", {"low": 1 / 3, "mid": 1 / 3, "high": 1 / 3})
    fn = solution("combine.dempster-code")
    fn.__defaults__ = (1, 2)
    assert solution("combine.dempster-code").__defaults__ is None
    assert check("combine.dempster-code", solution("combine.dempster-code"))


def test_stubs_do_not_shadow_the_sheets_imports():
    for stem, (_, _, src, _) in sheets.sheets(ROOT).items():
        sheets.unshadowed(src)  # raises on a clash
        imported = set()
        for block in src.blocks:
            if block.kind == "setup":
                imported |= sheets.imported_names(block.text)
            if block.kind == "stub":
                assert not sheets.stub_names(block) & imported, stem
    clash = sheets.Source(
        "x",
        "",
        [
            sheets.Block("setup", "", "from dstoolkit import discount"),
            sheets.Block("stub", "", "discount = ..."),
        ],
    )
    with pytest.raises(ValueError, match="imports"):
        sheets.unshadowed(clash)


def test_a_check_run_before_the_setup_cell_says_so():
    for stem, (number, title, src, labels) in sheets.sheets(ROOT).items():
        nb = sheets.build(src, number, title, labels, False)
        for cell in nb["cells"]:
            if "check" in cell["metadata"].get("tags", []):
                assert cell["source"].startswith(sheets.SETUP_GUARD), stem
    fresh: dict = {}
    with pytest.raises(RuntimeError, match="run the setup cell first"):
        exec(sheets.SETUP_GUARD, fresh)  # noqa: S102 - a check cell in a fresh kernel
    exec(sheets.SETUP_GUARD, {"check": check})  # noqa: S102 - after the setup cell


def test_hidden_cases_differ_from_the_visible_ones():
    from dstoolkit.teaching._isolation import hidden_cases

    for exercise_id in CODING:
        exercise = REGISTRY[exercise_id]
        visible = {repr(case.args) for case, _ in exercise.expected()}
        hidden = {repr(case.args) for case, _ in hidden_cases(exercise)}
        assert hidden and not hidden & visible, exercise_id


def test_no_chapter_notebook_carries_a_solution_call():
    import jupytext
    from chapter_notebook import strip_glue, strip_solution

    calls = 0
    for chapter in sorted((ROOT / "book").glob("*.md")):
        if "kernelspec:" not in chapter.read_text("utf-8")[:2000]:
            continue  # a page without code cells
        cells = [c for c in jupytext.read(chapter).cells if c.cell_type == "code"]
        sources = [c.source for c in cells]
        calls += sum("solution(" in s for s in sources)
        for source in strip_glue(sources):
            cleaned = strip_solution(source)
            assert "solution" not in cleaned.replace("solutions", ""), (chapter.name, cleaned)
    assert calls > 0  # the book glues solutions: the notebooks leave them out
    assert (
        strip_solution("from answer_key import solution\nx = solution('mass.bel')\ny = 2")
        == "y = 2"
    )
    with pytest.raises(ValueError, match="uses the answer key"):
        strip_solution("from answer_key import solution\ndef f():\n    return solution('mass.bel')")
    assert strip_solution(
        "from answer_key import solution\nfrom dstoolkit.teaching import check\nprint(1)"
    ) == ("from dstoolkit.teaching import check\nprint(1)")

"""Variants of the sheets (scripts/sheets.py --variant N): other numbers, same questions.

* Two variants show other data than each other and than the book in every sheet of
  Chapters 2–12; a student's own numbers differ from another's.
* The teacher's answers of each variant (run from its teacher's edition) pass its own
  checks and fail the other variant's and the book's, for every exercise that varies; the
  exercises that do not vary are the few listed here (data-free choices, a uniform
  distribution, Zadeh's example and the paper's own worked example). A choice among a few
  named options whose answer follows the data (``distinct=False``) is recomputed in each
  variant and may equal the book's.
* The hidden test of a value answer computes the answer afresh from the variant's data:
  the book's answer fails it even after the notebook switched back to the book's numbers
  and overwrote a kept solution.
"""

from __future__ import annotations

import sys

import pytest
from conftest import ROOT

from answer_key import solution
from dstoolkit.errors import InvalidInputError
from dstoolkit.teaching import REGISTRY, check, set_variant
from dstoolkit.teaching._isolation import grade_value
from dstoolkit.teaching._variants import SHEET_CHAPTER, current_variant, data

sys.path.insert(0, str(ROOT / "scripts"))
import sheets  # noqa: E402

VARIANTS = (1, 2)
#: Value exercises of the varying chapters whose answer is the same in every variant because
#: it reads no data: choices between named rules, a uniform distribution, Zadeh's tumour (1
#: whatever the doctors' numbers), and the paper's own worked example of Appendix A.
NOT_VARYING = {
    "mass.vacuous-betp",
    "combine.zadeh",
    "dependent.a2",
    "dependent.en1-exact",
    "dependent.a6",
    "dependent.theta-merges",
    "filter.mass-rule",
}
#: The exercises of Chapter 11 with data and Chapter 10's on the paper's Table 3.
TABLE3_AND_BEYOND = [
    "estimating.outlier-orders",
    "estimating.improvement",
    "estimating.improvement-choice",
    "beyond.start-error",
    "beyond.kalman-sigma",
    "beyond.products",
    "beyond.nassreddine-correction",
    "beyond.failures",
    "beyond.failures-choice",
    "beyond.offset-ratio",
]


@pytest.fixture(autouse=True)
def _book_variant_afterwards():
    yield
    set_variant(0)


def _teacher_answers(stem: str, variant: int) -> tuple[dict, list[tuple[str, str]]]:
    """Run the setup, code and answer cells of the teacher's edition of ``variant``.

    Return the namespace and the (exercise id, variable) of its check cells.
    """
    number, title, src, labels = sheets.sheets()[stem]
    notebook = sheets.build(src, number, title, labels, True, variant)
    namespace: dict = {}
    checks = []
    for cell in notebook["cells"]:
        tags = cell["metadata"].get("tags", [])
        if cell["cell_type"] != "code" or "explorer" in tags:
            continue
        if "check" in tags:
            checks.extend(sheets.CHECK.findall(cell["source"]))
            continue
        exec(cell["source"], namespace)  # noqa: S102 - the project's own teacher sheet
    set_variant(0)
    return namespace, checks


def test_chapters_two_to_twelve_have_variants():
    numbers = {stem: n for stem, (n, *_rest) in sheets.sheets().items()}
    assert sorted(numbers[stem] for stem in SHEET_CHAPTER) == list(range(2, 13))


@pytest.mark.parametrize("chapter", ["gauge", "lab", "estimating"])
def test_the_gauge_and_lab_exercises_vary_with_the_students_own_numbers(chapter: str):
    from answer_key import solution
    from dstoolkit.teaching._variants import student_variant

    alice, bob = student_variant("s3cret", "alice"), student_variant("s3cret", "bob")
    assert data(chapter, alice) != data(chapter, bob) != data(chapter, 0)
    ids = [
        k
        for k in REGISTRY
        if k.startswith(f"{chapter}.") and not k.endswith("-code") and k not in NOT_VARYING
    ]
    assert len(ids) >= 2
    for exercise_id in ids:
        assert REGISTRY[exercise_id].varies, exercise_id
        if not REGISTRY[exercise_id].distinct:
            continue  # a choice that may be the same (test_a_choice_follows_its_variants_data)
        mine = solution(exercise_id, variant=alice)
        assert check(exercise_id, mine, variant=alice), exercise_id
        assert not check(exercise_id, mine, variant=bob), exercise_id
        assert not check(exercise_id, solution(exercise_id, variant=0), variant=alice)


@pytest.mark.parametrize("stem", sorted(SHEET_CHAPTER))
def test_the_data_differ_between_variants_and_from_the_book(stem: str):
    number, title, src, labels = sheets.sheets()[stem]
    setups = {}
    for variant in (0, *VARIANTS):
        notebook = sheets.build(src, number, title, labels, False, variant)
        statements = [
            c["source"]
            for c in notebook["cells"]
            if c["metadata"].get("dstoolkit")
            or "set_variant" in c["source"]
            or c is notebook["cells"][1]
        ]
        setups[variant] = "\n".join(statements)
        assert "{{" not in "".join(c["source"] for c in notebook["cells"])
    assert len(set(setups.values())) == 3
    chapter = SHEET_CHAPTER[stem]
    assert data(chapter, 1) != data(chapter, 2) != data(chapter, 0)


@pytest.mark.parametrize("stem", sorted(SHEET_CHAPTER))
def test_each_variants_answers_pass_its_checks_and_fail_the_others(stem: str):
    runs = {variant: _teacher_answers(stem, variant) for variant in VARIANTS}
    varying = 0
    for variant, (namespace, checks) in runs.items():
        assert checks
        other = VARIANTS[1] if variant == VARIANTS[0] else VARIANTS[0]
        for exercise_id, name in checks:
            answer = namespace[name]
            assert check(exercise_id, answer, variant=variant), (exercise_id, variant)
            exercise = REGISTRY[exercise_id]
            if getattr(exercise, "varies", False) and exercise.distinct:
                varying += 1
                assert not check(exercise_id, answer, variant=other), (exercise_id, variant)
                assert not check(exercise_id, answer, variant=0), (exercise_id, variant)
            elif not exercise_id.endswith("-code") and not exercise.varies:
                assert exercise_id in NOT_VARYING, f"{exercise_id} does not vary"
    assert varying >= 2


def test_the_set_of_exercises_that_do_not_vary_is_small_and_named():
    prefixes = set(SHEET_CHAPTER.values())
    values = [
        k for k, v in REGISTRY.items() if k.split(".")[0] in prefixes and not k.endswith("-code")
    ]
    fixed = {k for k in values if not REGISTRY[k].varies}
    assert fixed == NOT_VARYING
    assert len(values) - len(fixed) >= 30
    # the choices that follow the data are exactly the two of Chapters 10 and 11
    follows = {k for k in values if REGISTRY[k].varies and not REGISTRY[k].distinct}
    assert follows == {"estimating.improvement-choice", "beyond.failures-choice"}


STUDENTS = ("alice", "bob")


def test_two_students_with_swapped_table3_and_beyond_answers_get_what_their_work_deserves():
    from dstoolkit.teaching._checking import answers_differ
    from dstoolkit.teaching._variants import student_variant

    variants = {s: student_variant("s3cret", s) for s in STUDENTS}
    own = {s: {k: solution(k, variant=v) for k in TABLE3_AND_BEYOND} for s, v in variants.items()}
    lost = 0
    for student, other in (STUDENTS, STUDENTS[::-1]):
        for exercise_id in TABLE3_AND_BEYOND:
            # the grader's verdict (nbgrader's process) on their own work: full marks
            assert grade_value(exercise_id, own[student][exercise_id], variants[student]).correct
            # the other's work earns the points only where both have the same answer (a
            # choice among four, or a count with ten possible values, can coincide)
            swapped = grade_value(exercise_id, own[other][exercise_id], variants[student])
            same = not answers_differ(
                REGISTRY[exercise_id], own[other][exercise_id], own[student][exercise_id]
            )
            assert swapped.correct == same, (exercise_id, student)
            lost += not swapped.correct
    distinct = sum(REGISTRY[k].distinct for k in TABLE3_AND_BEYOND)
    assert lost >= 2 * (distinct - 1), own  # at most one drawn answer shared by chance
    # the book's own answers earn nothing in a student's variant (a choice aside)
    for exercise_id in TABLE3_AND_BEYOND:
        if REGISTRY[exercise_id].distinct:
            assert not grade_value(exercise_id, solution(exercise_id), variants["alice"]).correct


def test_a_choice_follows_its_variants_data():
    """The failure-share choice is recomputed from the variant's runs: some variant's differs."""
    book = solution("beyond.failures-choice")
    shares = {v: solution("beyond.failures", variant=v) for v in range(1, 7)}
    choices = {v: solution("beyond.failures-choice", variant=v) for v in shares}
    differing = [v for v, c in choices.items() if c != book]
    assert differing, choices
    for v in differing:
        assert not check("beyond.failures-choice", book, variant=v)
        assert check("beyond.failures-choice", choices[v], variant=v)
    for v, share in shares.items():
        # the choice names the share of failed runs of the variant's own simulation
        expected = (
            "none"
            if share == 0
            else "all"
            if share == 1
            else "under half"
            if share < 0.5
            else "half or more"
        )
        assert choices[v] == expected, (v, share)


def test_a_choices_named_mistake_is_never_its_variants_right_answer():
    """A choice's listed mistake (``mistake``) is passed over where it is the right answer."""
    from dstoolkit.teaching import mistake

    listed = {s for s in range(1, 41) if solution("estimating.improvement-choice", variant=s) == 1}
    assert listed  # some variants' right choice is 1, the book's first listed mistake
    for exercise_id in ("estimating.improvement-choice", "beyond.failures-choice"):
        for v in range(1, 41):
            set_variant(v)
            assert not check(exercise_id, mistake(exercise_id)), (exercise_id, v)
            assert check(exercise_id, solution(exercise_id, variant=v)), (exercise_id, v)
        set_variant(0)


def test_the_book_keeps_its_table3_and_beyond_answers():
    """Variant 0 is the book's: the paper's Table 3 case, noises and worked example.

    Each answer equals the same computation written with the book's constants (no
    variant data), to the last bit.
    """
    import numpy as np

    from dstoolkit.filters import filter_named
    from dstoolkit.gauge import GAUGE_OBS_NOISE, gauge_state_space_model, resonance_orders
    from dstoolkit.gauge import speed_of_sound as c
    from dstoolkit.studies import (
        TABLE3_MEAN_ABS_ERROR_M,
        bounded_error_failures,
        run_table3,
        scaled_noise,
        tracking_data,
    )
    from dstoolkit.teaching import FAILURE_RUNS, FAILURE_SCALE

    assert solution("beyond.start-error") == -float(GAUGE_OBS_NOISE.mean[0])
    assert solution("beyond.kalman-sigma") == float(np.sqrt(GAUGE_OBS_NOISE.variance[0]))
    # the statement's count: 4 × 4 boxes per evidence (p = 3), 16 → 256 → 256·16 → ·256
    assert solution("beyond.products") == 256 * 16 * 256
    # the solution's hand computation: the empty product [0, 2] ∩ [3, 5] has 0.6 · 0.3
    assert solution("beyond.nassreddine-correction")[0] == pytest.approx(0.18, abs=1e-12)
    # abs 1e-12: a product of two one-decimal masses, exact but for its rounding
    runs = tracking_data(4.6, 26.5, runs=FAILURE_RUNS, seed=0)
    tight = gauge_state_space_model(
        scaled_noise(runs.state_noise, FAILURE_SCALE), scaled_noise(runs.obs_noise, FAILURE_SCALE)
    )
    assert solution("beyond.failures") == bounded_error_failures(tight, runs)[0]
    orders = resonance_orders(1.3, float(c(27.0)), (1000.0, 2500.0))
    assert solution("estimating.outlier-orders") == TABLE3_MEAN_ABS_ERROR_M[1.3]["direct"] / float(
        np.mean(1.3 / orders)
    )
    paper = filter_named("paper")
    table = run_table3(
        runs=30,
        seed=0,
        cases=[(4.6, 26.5)],
        methods=(paper, "direct"),
        order_rule="true",
        progress=False,
    )
    assert solution("estimating.improvement") == table.error(4.6, "direct") / table.error(
        4.6, paper
    )


def test_the_book_sheets_are_variant_zero():
    for stem, (number, title, src, labels) in sheets.sheets().items():
        path = sheets.sheet_path(stem, number, ROOT / "notebooks")
        assert sheets.dump(sheets.build(src, number, title, labels, False, 0)) == path.read_text(
            encoding="utf-8"
        ), stem


def test_the_grader_recomputes_from_the_variants_data():
    book_answer = solution("mass.bel")
    set_variant(1)
    right = solution("mass.bel")
    assert book_answer != pytest.approx(right)
    # the grader's verdict does not depend on the variant or the kept solutions of its
    # process (a kernel's, in the old design): it computes the variant's answer afresh
    set_variant(0)
    REGISTRY["mass.bel"]._cache[("solution", 1)] = book_answer
    try:
        assert grade_value("mass.bel", right, 1).correct
        wrong = grade_value("mass.bel", book_answer, 1)
    finally:
        del REGISTRY["mass.bel"]._cache[("solution", 1)]
    assert not wrong.correct and wrong.message.startswith("✘ mass.bel: wrong")
    assert current_variant() == 0
    with pytest.raises(TypeError, match="coding exercise"):
        grade_value("combine.dempster-code", None, 1)


def test_variants_are_checked_and_restored():
    with pytest.raises(InvalidInputError, match="whole number"):
        set_variant(-1)
    with pytest.raises(InvalidInputError, match="whole number"):
        set_variant(1.5)  # type: ignore[arg-type]
    assert current_variant() == 0
    assert check("mass.bel", solution("mass.bel"), variant=2) is not None
    assert current_variant() == 0


def test_the_command_line_writes_a_variant_and_refuses_the_book_folder(tmp_path):
    assert sheets.main(["--variant", "1", "--out", str(tmp_path / "s")]) == 0
    assert (tmp_path / "s" / "02_mass_functions.ipynb").exists()
    text = (tmp_path / "s" / "02_mass_functions.ipynb").read_text(encoding="utf-8")
    assert "set_variant(1)" in text and "Variant 1" in text
    with pytest.raises(SystemExit):
        sheets.main(["--variant", "1"])


@pytest.mark.slow
def test_any_variant_can_be_drawn_and_differs_from_the_book():
    # variant 6 of Chapter 3 was out of reach when every variant had to differ from the
    # ten before it: the chapter's grid of data has fewer answers than that
    book = {ex_id: solution(ex_id) for ex_id in REGISTRY if ex_id.startswith("combine.")}
    for variant in (6, 14):
        d = data("combine", variant)
        assert d != data("combine", 0)
        with_variant = set_variant(variant)
        try:
            for ex_id, answer in book.items():
                if getattr(REGISTRY[ex_id], "varies", False):
                    assert not check(ex_id, answer), (ex_id, variant)
        finally:
            set_variant(with_variant)


def test_a_failed_course_leaves_no_folder_and_the_course_id_is_the_folders(tmp_path, monkeypatch):
    import course

    def broken(*args, **kwargs):
        raise ValueError("no plain form for a formula")

    monkeypatch.setattr(course, "course_notebook", broken)
    with pytest.raises(ValueError, match="no plain form"):
        course.write_course(tmp_path / "never", ROOT, ["combining_evidence"])
    assert not (tmp_path / "never").exists()
    monkeypatch.undo()
    course.write_course(tmp_path / "group b", ROOT, ["combining_evidence"])
    config = (tmp_path / "group b" / "nbgrader_config.py").read_text("utf-8")
    assert 'c.CourseDirectory.course_id = "group-b"' in config
    course.write_course(tmp_path / "c", ROOT, ["combining_evidence"], course_id="ds-2027")
    assert 'course_id = "ds-2027"' in (tmp_path / "c" / "nbgrader_config.py").read_text("utf-8")
    with pytest.raises(ValueError, match="course id"):
        course.write_course(tmp_path / "d", ROOT, ["combining_evidence"], course_id="a b")
    assert not (tmp_path / "d").exists()

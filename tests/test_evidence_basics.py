"""Unit tests of the evidence toolkit: finite frames, intervals, and clear errors."""

import numpy as np
import pytest

from dstoolkit import (
    EvidenceError,
    IntervalEvidence,
    MassFunction,
    TotalConflictError,
    combine_dependent,
    conflict,
    decorrelate,
    dempster,
    dependence,
    discount,
    energy,
    joint_energy,
    triangular_evidence,
    triangular_from_samples,
)


def test_belief_plausibility_commonality_pignistic():
    m = MassFunction({"a": 0.5, "ab": 0.3, "abc": 0.2})
    assert m.belief("ab") == pytest.approx(0.8)
    assert m.plausibility("b") == pytest.approx(0.5)
    assert m.commonality("ab") == pytest.approx(0.5)
    betp = m.pignistic()
    assert betp["a"] == pytest.approx(0.5 + 0.15 + 0.2 / 3)
    assert sum(betp.values()) == pytest.approx(1.0)
    assert m.belief("abc") == pytest.approx(1.0)


def test_frame_of_any_hashables_and_string_hypotheses():
    frame = ("low", "mid", "high")
    m = MassFunction({frozenset({"low", "mid"}): 0.7, "high": 0.3}, frame)
    assert m.belief(frozenset({"low", "mid"})) == pytest.approx(0.7)
    assert m.plausibility("high") == pytest.approx(0.3)
    assert m.mass_of("high") == pytest.approx(0.3)


def test_dempster_zadeh_example():
    frame = ("M", "C", "T")
    a = MassFunction({"M": 0.99, "T": 0.01}, frame)
    b = MassFunction({"C": 0.99, "T": 0.01}, frame)
    assert conflict(a, b) == pytest.approx(1 - 1e-4)
    c = dempster(a, b)
    assert c.mass_of("T") == pytest.approx(1.0)


def test_energy_vacuous_and_bayesian():
    assert energy(MassFunction.vacuous("abc")) == 0.0
    assert energy(MassFunction.bayesian({"a": 0.2, "b": 0.8})) == pytest.approx(1.0)


def test_discount_and_conditioning():
    m = MassFunction({"a": 0.6, "b": 0.4})
    d = discount(m, 0.1)
    assert d.mass_of("ab") == pytest.approx(0.1)
    assert d.mass_of("a") == pytest.approx(0.54)
    c = MassFunction(
        {
            "a": 0.5,
            "ab": 0.5,
        },
        frame="abc",
    ).condition("b")
    assert c.mass_of("b") == pytest.approx(1.0)


def test_finite_dependent_combination_mass_rules():
    frame = tuple("abc")
    a = MassFunction({"a": 0.6, "ab": 0.4}, frame)
    b = MassFunction({"a": 0.3, "ab": 0.7}, frame)
    assert joint_energy(a, b) == pytest.approx(0.3 + 0.4 / 2)
    assert joint_energy(a, b, mass_rule="m1") == pytest.approx(0.6 + 0.4 / 2)
    assert joint_energy(a, b, mass_rule="m2") == pytest.approx(0.3 + 0.7 / 2)
    dep = dependence(a, b)
    assert 0 < dep.r12 <= 1 and 0 < dep.r21 <= 1
    c = combine_dependent(a, b)
    assert c.mass.sum() == pytest.approx(1.0)
    # Decorrelation puts 1 − R on the frame
    a2, b2, dep2 = decorrelate(a, b)
    assert a2.mass_of("abc") == pytest.approx(1 - dep2.r12)


def test_interval_belief_plausibility_pbox_and_expectation():
    e = IntervalEvidence([0.0, 1.0], [2.0, 3.0], [0.4, 0.6])
    assert e.belief(0, 2) == pytest.approx(0.4)
    assert e.plausibility(2.5, 4) == pytest.approx(0.6)
    lower, upper = e.cdf_bounds([0.5, 2.0, 3.0])
    np.testing.assert_allclose(lower, [0.0, 0.4, 1.0])
    np.testing.assert_allclose(upper, [0.4, 1.0, 1.0])
    assert e.pignistic_expectation_1d() == pytest.approx(0.4 * 1.0 + 0.6 * 2.0)


def test_interval_evidence_has_one_shape_whatever_its_dimension():
    """Lo and hi are (n, d) for intervals too, and pignistic_expectation() is (d,).

    The 1-D conveniences are named, and refuse boxes with a message naming the general
    ones.
    """
    e = IntervalEvidence([0.0, 1.0], [1.0, 3.0], [0.4, 0.6])
    assert e.lo.shape == e.hi.shape == (2, 1)
    assert e.lo_1d.tolist() == [0.0, 1.0] and e.hi_1d.tolist() == [1.0, 3.0]
    expectation = e.pignistic_expectation()
    assert isinstance(expectation, np.ndarray) and expectation.shape == (1,)
    assert isinstance(e.pignistic_expectation_1d(), float)
    assert e.pignistic_expectation_1d() == expectation[0]
    boxes = IntervalEvidence([[0, 0], [1, 1]], [[2, 2], [3, 3]], [0.5, 0.5])
    assert boxes.lo.shape == (2, 2) and boxes.pignistic_expectation().shape == (2,)
    for name in ("lo_1d", "hi_1d"):
        with pytest.raises(EvidenceError, match=r"use (lo|hi), shape \(n, d\)"):
            getattr(boxes, name)
    with pytest.raises(EvidenceError, match=r"use pignistic_expectation\(\)"):
        boxes.pignistic_expectation_1d()


def test_interval_merging_of_equal_focal_elements():
    e = IntervalEvidence([0, 0, -0.0], [1, 1, 2], [0.2, 0.3, 0.5])
    assert len(e) == 2
    assert e.belief(0, 1) == pytest.approx(0.5)


def test_box_evidence_in_two_dimensions():
    e = IntervalEvidence([[0, 0], [1, 1]], [[2, 2], [3, 3]], [0.5, 0.5])
    assert e.dim == 2
    np.testing.assert_allclose(e.pignistic_expectation(), [1.5, 1.5])
    f = IntervalEvidence.vacuous([0.5, 0.5], [1.5, 1.5])
    c = dempster(e, f)
    np.testing.assert_allclose(c.boxes_lo, [[0.5, 0.5], [1, 1]])
    assert 0 <= energy(e) <= 1


def test_triangular_from_samples():
    rng = np.random.default_rng(1)
    x = rng.normal(-6.9, 1.23, 20000)
    b = triangular_from_samples(x)
    assert b.mode == pytest.approx(-6.9, abs=0.05)
    assert b.sigma == pytest.approx(1.23, rel=0.03)
    ev = triangular_evidence(*b)
    assert len(ev) == 4


# -- clear errors --------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("build", "words"),
    [
        (lambda: MassFunction({"a": 0.5, "b": 0.43}), "sum to 0.93"),
        (lambda: IntervalEvidence([0, 1], [1, 2], [0.5, 0.6]), "sum to 1.1"),
        (lambda: MassFunction({"a": 1.2, "b": -0.2}), "non-negative"),
        (lambda: IntervalEvidence([0, 1], [1, 2], [np.nan, 1.0]), "NaN"),
        (lambda: IntervalEvidence([0, np.nan], [1, 2], [0.5, 0.5]), "NaN"),
        (lambda: IntervalEvidence([2.0], [1.0], [1.0]), "lo > hi"),
        (lambda: IntervalEvidence([], [], []), "empty evidence"),
        (lambda: MassFunction({}), "empty evidence"),
        (lambda: MassFunction({"a": 0.5, "z": 0.5}, frame="abc"), "not in the frame"),
        (lambda: MassFunction({frozenset(): 1.0}, frame="ab"), "empty set"),
        (lambda: triangular_evidence(1, 0, 2), "lower <= mode <= upper"),
        (lambda: triangular_evidence(-1, 0, 1, p=0), "whole number in [1, 10000]"),
        (lambda: discount(MassFunction({"a": 1.0}), 1.5), "discount rate"),
    ],
)
def test_bad_input_is_named(build, words):
    with pytest.raises(EvidenceError) as info:
        build()
    assert words in str(info.value)


def test_total_conflict_is_an_error_finite_and_intervals():
    a = MassFunction({"a": 1.0}, "ab")
    b = MassFunction({"b": 1.0}, "ab")
    with pytest.raises(TotalConflictError, match="total conflict"):
        dempster(a, b)
    x = IntervalEvidence([0.0], [1.0], [1.0])
    y = IntervalEvidence([2.0], [3.0], [1.0])
    with pytest.raises(TotalConflictError, match="K = 1"):
        dempster(x, y)
    assert conflict(x, y) == 1.0


def test_incompatible_frames_and_kinds():
    with pytest.raises(EvidenceError, match="frames differ"):
        dempster(MassFunction({"a": 1.0}, "ab"), MassFunction({"a": 1.0}, "abc"))
    with pytest.raises(EvidenceError, match="cannot combine"):
        dempster(MassFunction({"a": 1.0}), IntervalEvidence([0], [1], [1]))


def test_m2_rule_reports_a_coefficient_outside_unit_interval():
    a = IntervalEvidence([0, 0], [1, 10], [0.1, 0.9])
    b = IntervalEvidence([0, -5], [1, 5], [0.9, 0.1])
    dep = dependence(a, b, mass_rule="m2")
    assert dep.r12 < 0
    with pytest.raises(EvidenceError, match="outside"):
        combine_dependent(a, b, mass_rule="m2")

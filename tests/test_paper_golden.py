"""Golden numbers printed in the paper: Tables 1–2 and the worked example of Appendix A."""

import numpy as np
import pytest

from dstoolkit import (
    IntervalEvidence,
    combine_dependent,
    dependence,
    energy,
    joint_energy,
    triangular_evidence,
)

# Appendix A
E1 = IntervalEvidence.from_pairs([[-0.30, 2.60, 0.3], [0.30, 1.90, 0.6], [0.32, 1.93, 0.1]])
E2 = IntervalEvidence.from_pairs([[0.21, 3.50, 0.1], [0.41, 1.61, 0.3], [0.30, 1.90, 0.6]])
PAPER_EN1 = 0.8655  # the paper reused the two-element value; computed exactly it is 0.8649


def test_table1_state_noise_evidence():
    ev = triangular_evidence(-0.3, 0.0, 0.3, p=3, epsilon=0.05, theta=(-10, 10))
    expected = [[-0.1, 0.1, 0.3167], [-0.2, 0.2, 0.3167], [-0.3, 0.3, 0.3167], [-10, 10, 0.05]]
    np.testing.assert_allclose(ev.to_rows(), expected, atol=5e-5)


def test_table2_observation_noise_evidence():
    ev = triangular_evidence(-10.59, -6.9, -3.21, p=3, epsilon=0.05)
    cuts = ev.to_rows()[:3]
    np.testing.assert_allclose(
        cuts,
        [[-8.13, -5.67, 0.3167], [-9.36, -4.44, 0.3167], [-10.59, -3.21, 0.3167]],
        atol=5e-5,
    )
    # Θ = c ± 100σ gives [−129.9, 116.1]; the paper prints [−129.7, 115.7] (rounded in the paper).
    np.testing.assert_allclose(ev.to_rows()[3], [-129.9, 116.1, 0.05], atol=5e-5)


def test_appendix_energies():
    assert energy(E2) == pytest.approx(0.7865, abs=5e-5)
    assert joint_energy(E1, E2) == pytest.approx(0.45, abs=5e-5)
    # The exact A1 value for E1; the paper prints 0.8655.
    assert energy(E1) == pytest.approx(0.8649, abs=5e-5)


def test_appendix_dependence_with_paper_energy():
    dep = dependence(E1, E2, energy1=PAPER_EN1)
    assert dep.degree == pytest.approx(0.5448, abs=5e-5)
    assert dep.r12 == pytest.approx(0.7525, abs=5e-5)
    assert dep.r21 == pytest.approx(0.7002, abs=5e-5)


def test_appendix_dependence_computed_exactly():
    dep = dependence(E1, E2)
    en1 = 0.3 * 1.6 / 2.9 + 0.6 + 0.1 * 1.6 / 1.61
    en2 = 0.1 * 1.2 / 3.29 + 0.3 + 0.6 * 1.2 / 1.6
    d = 2 * 0.45 / (en1 + en2)
    assert dep.energy1 == pytest.approx(en1, rel=1e-12)
    assert dep.degree == pytest.approx(d, rel=1e-12)
    assert dep.r12 == pytest.approx(1 - d / 2 * en2 / en1, rel=1e-12)
    assert dep.r21 == pytest.approx(1 - d / 2 * en1 / en2, rel=1e-12)
    # Rounded as the paper rounds, the exact values differ in the 4th decimal only.
    assert dep.degree == pytest.approx(0.5448, abs=5e-4)
    assert dep.r12 == pytest.approx(0.7525, abs=5e-4)
    assert dep.r21 == pytest.approx(0.7002, abs=5e-4)


def test_appendix_nine_combined_focal_elements():
    combined = combine_dependent(E1, E2, energy1=PAPER_EN1, merge=False)
    paper = [
        [0.21, 2.60, 0.1749],
        [0.41, 1.61, 0.0994],
        [0.30, 1.90, 0.1988],
        [0.30, 1.90, 0.1669],
        [0.41, 1.61, 0.0948],
        # The paper prints 0.1890 for A6 and its masses sum to 0.9988: computed, A6 = 0.1896.
        [0.30, 1.90, 0.1890],
        [0.32, 1.93, 0.0278],
        [0.41, 1.61, 0.0157],
        [0.32, 1.90, 0.0315],
    ]
    rows = combined.to_rows()
    assert rows.shape == (9, 3)
    np.testing.assert_allclose(rows[:, :2], np.array(paper)[:, :2], atol=1e-12)
    np.testing.assert_allclose(rows[:, 2], np.array(paper)[:, 2], atol=1e-3)
    # A6 = 0.36 · R12 · R21 = 0.18968 (the paper prints it truncated as 0.1896).
    assert rows[5, 2] == pytest.approx(0.36 * 0.7524707 * 0.7002274, abs=1e-6)
    assert abs(rows[5, 2] - 0.1890) > 5e-4  # the paper's printed A6 is a slip
    assert rows[:, 2].sum() == pytest.approx(1.0, abs=1e-12)
    assert sum(r[2] for r in paper) == pytest.approx(0.9988, abs=1e-9)


def test_appendix_merged_result_has_five_distinct_intervals():
    merged = combine_dependent(E1, E2, energy1=PAPER_EN1)
    assert len(merged) == 5
    assert merged.mass.sum() == pytest.approx(1.0)

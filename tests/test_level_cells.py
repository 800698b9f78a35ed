"""Step 6 of the paper's filter on a frame of cells: the cautious rule beside the paper's."""

import numpy as np
import pytest

from dstoolkit.errors import EvidenceError
from dstoolkit.evidence import IntervalEvidence, MassFunction, cautious, dempster
from dstoolkit.studies import CELL_RULES, cell_frame, filter_case, level_cell_filter


def test_cell_frame_by_hand():
    a = IntervalEvidence.from_pairs([(0.0, 1.0, 0.5), (0.0, 4.0, 0.5)])
    b = IntervalEvidence.from_pairs([(2.5, 4.0, 0.7), (0.5, 1.5, 0.3)])
    edges, ma, mb = cell_frame(a, b, 4)
    # hull [0, 4] in 4 cells of 1: [0, 1] → cell 0; [0, 4] → all; [2.5, 4] → cells 2, 3;
    # [0.5, 1.5] overlaps cells 0 and 1
    assert edges.tolist() == [0.0, 1.0, 2.0, 3.0, 4.0]
    assert ma.as_dict() == {frozenset({0}): 0.5, frozenset({0, 1, 2, 3}): 0.5}
    assert mb.as_dict() == {frozenset({2, 3}): 0.7, frozenset({0, 1}): 0.3}


def test_the_paper_column_is_the_paper_filter():
    run = level_cell_filter(9.6, 23.9, first=12)
    _, _, result = filter_case(9.6, 23.9, first=12)
    # the same steps; run() takes the filter's array path, step() its reference path, whose
    # sums differ in order: rounding of frequencies near 1e3 Hz (relative 1e-12 allows it)
    np.testing.assert_allclose(run.estimates["paper"], result.estimates[:, 0], rtol=1e-12)


def test_cell_rules_track_the_gauge():
    run = level_cell_filter(9.6, 23.9, first=30)
    assert set(run.estimates) == set(CELL_RULES)
    truth = run.truth
    for rule, x in run.estimates.items():
        assert x.shape == truth.shape
        # every rule stays within the reading's noise band (|w| ≤ 10.59 Hz, Table 2) of the
        # truth: a filter that diverged would leave it
        assert np.max(np.abs(x - truth)) < 10.59, rule
    # the cell rules differ from the paper's (another Step 6)
    assert not np.allclose(run.estimates["cautious"], run.estimates["paper"])


def test_the_cautious_step_counts_shared_evidence_once():
    # one Step 6 by hand: E2 (prediction) fused with itself by the cautious rule is E2; by
    # Dempster's rule it is sharper than E2 (the shared evidence counted twice)
    pred = IntervalEvidence.from_pairs([(0.0, 2.0, 0.6), (1.0, 3.0, 0.3), (0.0, 4.0, 0.1)])
    _, m, _ = cell_frame(pred, pred, 8)
    assert cautious(m, m).as_dict() == pytest.approx(m.as_dict())
    assert dempster(m, m).mass_of(frozenset(range(8))) < m.mass_of(frozenset(range(8)))
    assert isinstance(m, MassFunction)


def test_bad_input_is_refused():
    with pytest.raises(EvidenceError, match="cells"):
        level_cell_filter(9.6, 23.9, cells=40, first=3)
    with pytest.raises(EvidenceError, match="at least 2 readings"):
        level_cell_filter(9.6, 23.9, first=1)

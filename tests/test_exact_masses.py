"""Combination rules renormalise by the mass they keep (eq. 1), so masses sum to 1 exactly.

Dividing by 1 − K computed as a difference loses the digits of 1 − K when the conflict K
comes near 1: at 1 − K = 3e-12 the masses summed to 0.99998511. Summing the kept products
instead gives masses that sum to 1 within rounding however close K comes to 1.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from dstoolkit.evidence import (
    IntervalEvidence,
    MassFunction,
    combine_dependent,
    conflict,
    dempster,
    yager,
)


def _near_total_conflict(kept: float, split: int, seed: int) -> tuple[IntervalEvidence, ...]:
    """Two interval evidences that overlap only on product masses summing to ``kept``."""
    rng = np.random.default_rng(seed)
    share = rng.uniform(0.1, 1.0, split)
    share /= share.sum()
    eps = np.sqrt(kept)
    # A: mass 1 − eps on [0, 1], the rest on small intervals inside [10, 11];
    # B: mass 1 − eps on [20, 21], the rest on [10, 11]: only A's small ones meet B's.
    a_lo = np.concatenate([[0.0], 10.0 + 0.5 * np.arange(split) / split])
    a = IntervalEvidence(
        a_lo,
        a_lo + np.concatenate([[1.0], np.full(split, 0.1)]),
        np.concatenate([[1.0 - eps], eps * share]),
    )
    b = IntervalEvidence([20.0, 10.0], [21.0, 11.0], [1.0 - eps, eps])
    return a, b


@settings(max_examples=80, deadline=None, derandomize=True)
@given(exponent=st.floats(1.0, 15.0), split=st.integers(1, 6), seed=st.integers(0, 100))
def test_dempster_masses_sum_to_one_as_conflict_nears_one(exponent, split, seed):
    kept = 10.0**-exponent  # 1 − K from 0.1 down to 1e-15
    a, b = _near_total_conflict(kept, split, seed)
    assert 1.0 - conflict(a, b) < 2 * kept + 1e-15
    for merge in (True, False):
        fused = dempster(a, b, merge=merge)
        assert abs(float(np.sum(fused.mass)) - 1.0) <= 1e-12
        IntervalEvidence(fused.boxes_lo, fused.boxes_hi, fused.mass)  # accepted again
    again = yager(a, b)
    assert abs(float(np.sum(again.mass)) - 1.0) <= 1e-12


def test_dempster_at_one_minus_k_of_1e_15_on_a_finite_frame():
    eps = np.sqrt(1e-15)
    a = MassFunction({"a": 1 - eps, "b": eps}, "abc")
    b = MassFunction({"c": 1 - eps, "bc": eps}, "abc")
    fused = dempster(a, b)
    assert fused.as_dict() == {frozenset("b"): 1.0}
    MassFunction(fused.as_dict(), fused.frame)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(exponent=st.floats(1.0, 12.0), seed=st.integers(0, 100))
def test_combine_dependent_masses_sum_to_one(exponent, seed):
    a, b = _near_total_conflict(10.0**-exponent, 3, seed)
    fused = combine_dependent(a, b)
    assert abs(float(np.sum(fused.mass)) - 1.0) <= 1e-12
    IntervalEvidence(fused.boxes_lo, fused.boxes_hi, fused.mass)

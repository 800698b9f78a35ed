"""The memory budget bounds the real peak that tracemalloc measures.

Dempster's rule (eq. 1) on a 24-hypothesis frame and the Cartesian product of 3 marginals
(eq. 16) run at the largest size the budget allows with a peak under the budget, and are
refused one size above; the bytes the budget checks count per product are above the peak
per product for mass functions and interval evidence, merged or not.
"""

from __future__ import annotations

import pytest
from hostile_inputs import boxes_evidence, frame_evidence, traced_peak

import dstoolkit.evidence as ev
from dstoolkit.errors import MemoryBudgetError
from dstoolkit.evidence._combination import PRODUCT_BYTES
from dstoolkit.evidence._extension import product_row_bytes

MIB = 2**20


@pytest.fixture
def budget():
    yield ev.set_memory_budget
    ev.set_memory_budget(None)


@pytest.mark.parametrize("mib", [8, 32])
def test_dempster_on_24_hypotheses_peaks_under_the_budget(budget, mib):
    budget(mib * MIB)
    n = int((mib * MIB / (2 * 8 + PRODUCT_BYTES)) ** 0.5)  # the most the check lets through
    a, b = frame_evidence(n, 24, 1), frame_evidence(n, 24, 2)
    combined, peak = traced_peak(lambda: ev.dempster(a, b))
    assert len(combined) > 0
    assert peak <= mib * MIB, f"peak {peak / MIB:.1f} MiB over a {mib} MiB budget"
    bigger = frame_evidence(n + 1, 24, 3), frame_evidence(n + 1, 24, 4)
    with pytest.raises(MemoryBudgetError):
        ev.dempster(*bigger)


@pytest.mark.parametrize("mib", [8, 32])
def test_a_product_of_3_marginals_peaks_under_the_budget(budget, mib):
    budget(mib * MIB)
    k = int((mib * MIB / product_row_bytes(3, 3)) ** (1 / 3))
    product, peak = traced_peak(
        lambda: ev.cartesian_product([boxes_evidence(k, 1, i) for i in range(3)])
    )
    assert len(product) == k**3
    assert peak <= mib * MIB, f"peak {peak / MIB:.1f} MiB over a {mib} MiB budget"
    with pytest.raises(MemoryBudgetError):
        ev.cartesian_product([boxes_evidence(k + 1, 1, i) for i in range(3)])


@pytest.mark.parametrize("merge", [True, False])
@pytest.mark.parametrize(
    ("make", "row"),
    [
        (lambda n, s: frame_evidence(n, 24, s), 8),
        (lambda n, s: frame_evidence(n, 64, s), 8),
        (lambda n, s: boxes_evidence(n, 1, s), 16),
        (lambda n, s: boxes_evidence(n, 3, s), 48),
    ],
    ids=["24 hypotheses", "64 hypotheses", "boxes d=1", "boxes d=3"],
)
def test_the_count_per_product_is_above_the_measured_peak(make, row, merge):
    n = 300
    a, b = make(n, 1), make(n, 2)
    _, peak = traced_peak(lambda: ev.dempster(a, b, merge=merge))
    assert peak <= n * n * (2 * row + PRODUCT_BYTES)


@pytest.mark.parametrize("merge", [True, False])
@pytest.mark.parametrize(("marginals", "dim", "k"), [(2, 1, 300), (4, 1, 14), (2, 3, 200)])
def test_the_count_per_box_is_above_the_measured_peak(marginals, dim, k, merge):
    parts = [boxes_evidence(k, dim, i) for i in range(marginals)]
    _, peak = traced_peak(lambda: ev.cartesian_product(parts, merge=merge))
    assert peak <= k**marginals * product_row_bytes(marginals * dim, marginals)

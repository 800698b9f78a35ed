"""Step 6's products formed in blocks of rows: the same combination as all at once."""

import numpy as np
import pytest
from hostile_inputs import traced_peak

from dstoolkit.evidence import Boxes
from dstoolkit.evidence import _batch_kernels as kernels
from dstoolkit.evidence import boxes as bk
from dstoolkit.filters import DependentEvidenceFilter, simulate_lotka_volterra

#: The sums over A of a block are BLAS matrix–vector products: the library groups a row's
#: additions by how many rows it is given (and by thread), so a block may move a sum by a
#: few units in the last place of the sums (≈ 1e-16 relative), nothing more.
SUM_RTOL = 1e-13


def random_boxes(rng: np.random.Generator, runs: int, n: int, d: int) -> Boxes:
    lo = rng.uniform(-1.0, 1.0, (runs, n, d))
    mass = rng.uniform(0.0, 1.0, (runs, n)) * (rng.uniform(size=(runs, n)) > 0.2)
    return Boxes(lo, lo + rng.uniform(0.0, 1.5, (runs, n, d)), mass / mass.sum(1, keepdims=True))


@pytest.mark.parametrize("d", [1, 2])
@pytest.mark.parametrize("rows", [1, 2, 5])
@pytest.mark.parametrize("theta_last", [False, True])
def test_blocks_of_rows_give_the_combination_of_all_products(d, rows, theta_last):
    rng = np.random.default_rng(10 * d + rows)
    a, b = random_boxes(rng, 3, 11, d), random_boxes(rng, 3, 7, d)
    if theta_last:  # the last focal element of each holds the others, as after discounting
        a = bk.discount_onto_hull(a, np.array([0.9, 0.5, 1.0]))
        b = bk.discount_onto_hull(b, np.array([0.8, 1.0, 0.3]))
    whole = bk.dempster_expectation(a, b, bounds=True, theta_last=theta_last)
    work = bk.ProductWork.allocate(3, d, a.lo.shape[1], b.lo.shape[1], rows=rows)
    assert work.ends.shape[3] == rows < b.lo.shape[1]  # several blocks, the last one short
    blocked = bk.dempster_expectation(a, b, bounds=True, work=work, theta_last=theta_last)
    np.testing.assert_allclose(blocked[0], whole[0], rtol=SUM_RTOL, atol=0)
    # K = 1 − the sum of the kept masses (eq. 1): a few units in the last place of 1
    np.testing.assert_allclose(blocked[1], whole[1], rtol=SUM_RTOL, atol=1e-14)
    np.testing.assert_array_equal(blocked[2], whole[2])
    for blocked_end, whole_end in zip(blocked[3], whole[3], strict=True):
        np.testing.assert_array_equal(blocked_end, whole_end)  # min and max are exact


def test_block_rows_bound_the_products_of_a_block():
    assert bk.block_rows(runs=2, na=100, nb=50, block=10_000) == 50
    assert bk.block_rows(runs=2, na=100, nb=50, block=1_000) == 5
    assert bk.block_rows(runs=2, na=100, nb=50, block=10) == 1  # one row at least


def test_the_filter_in_tiny_blocks_gives_its_numbers(monkeypatch):
    """One step of Steps 2–6 on 2-D Lotka–Volterra, 3 runs (N_a·N_b = 730·82 products, p = 2).

    One step only: from the second on, x̂ differs by the last bits and the widths hi − lo
    of the next steps' boxes amplify that difference (the filter does so for any rounding).
    """
    model, _, z = simulate_lotka_volterra(steps=2, runs=3, seed=3)
    flt = DependentEvidenceFilter(p=2, on_conflict="predict")
    whole = flt.run_batch(model, z)
    monkeypatch.setattr(kernels, "PRODUCT_BLOCK", 3 * 730 * 2)  # 2 rows of E2 a block
    assert bk.block_rows(3, 730, 82) == 2
    blocked = flt.run_batch(model, z)
    np.testing.assert_allclose(blocked.estimates, whole.estimates, rtol=SUM_RTOL, atol=0)
    np.testing.assert_array_equal(blocked.lower, whole.lower)  # min and max are exact
    np.testing.assert_array_equal(blocked.upper, whole.upper)
    # K = 1 − the sum of the kept masses (eq. 1): a few units in the last place of 1
    np.testing.assert_allclose(
        blocked.diagnostics["conflict_step6"], whole.diagnostics["conflict_step6"], atol=1e-14
    )
    for key, value in whole.diagnostics.items():
        if key != "conflict_step6":  # the rest comes before Dempster's rule of Step 6
            np.testing.assert_array_equal(blocked.diagnostics[key], value, err_msg=key)


def test_the_memory_of_a_combination_is_that_of_one_block(monkeypatch):
    """2,000 × 300 products: all at once their buffers take 19 MB, a block of 8 rows 0.5 MB."""
    rng = np.random.default_rng(7)
    a, b = random_boxes(rng, 1, 2000, 1), random_boxes(rng, 1, 300, 1)
    whole = bk.dempster_expectation(a, b, bounds=True)
    monkeypatch.setattr(kernels, "PRODUCT_BLOCK", 2**14)
    blocked, peak = traced_peak(lambda: bk.dempster_expectation(a, b, bounds=True))
    assert peak < 2 * 2**20, f"peak {peak / 2**20:.1f} MiB"
    np.testing.assert_allclose(blocked[0], whole[0], rtol=SUM_RTOL, atol=0)
    np.testing.assert_array_equal(blocked[3][0], whole[3][0])
    np.testing.assert_array_equal(blocked[3][1], whole[3][1])

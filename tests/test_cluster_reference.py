"""Nassreddine's focal-element cap gives, bit for bit, what its rule says, run by run.

:func:`dstoolkit.evidence.boxes.cluster_boxes` is vectorised over runs and takes shortcuts (in one
dimension it does not sort again after the first round; a run that fits leaves the rounds).
Here a plain-Python rendering of the rule in its docstring (Denœux's clustering: sort by
centre along the dimension of the round, merge the neighbour pairs whose Δ is a local
minimum, cheapest first, never below the cap; then merge equal boxes, eq. 14) is run on
each run alone, with the same floating-point operations in the same order, and the two
must agree exactly. Box coordinates sit on a coarse grid so that equal boxes, equal
centres and equal Δ (ties) are common. One and two dimensions: the state dimensions of the
gauge and of the Lotka–Volterra example.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from golden_inputs import nudged

from dstoolkit.evidence import Boxes
from dstoolkit.evidence.boxes import TIE_RTOL, cluster_boxes, merge_equal_boxes

Box = tuple[tuple[float, ...], tuple[float, ...], float]


def tie_chains(values: list[float], scales: list[float]) -> list[list[int]]:
    """Split into the tie rule's classes: sorted exactly, neighbours within TIE_RTOL chained."""
    chains: list[list[int]] = []
    for i in sorted(range(len(values)), key=lambda i: values[i]):
        prev = chains[-1][-1] if chains else None
        if prev is not None and values[i] - values[prev] <= TIE_RTOL * max(scales[i], scales[prev]):
            chains[-1].append(i)
        else:
            chains.append([i])
    return chains


def tie_sorted(values: list[float], scales: list[float]) -> list[int]:
    """Positions sorted by tie class, then by position."""
    return [i for chain in tie_chains(values, scales) for i in sorted(chain)]


def snapped(boxes: list[Box]) -> list[Box]:
    """Bounds that tie along a dimension become the smallest (lo) or largest (hi) of them."""
    boxes = [b for b in boxes if b[2] > 0]
    lo = [list(b[0]) for b in boxes]
    hi = [list(b[1]) for b in boxes]
    for d in range(len(lo[0]) if lo else 0):
        reach = max(abs(a[d]) + abs(b[d]) for a, b in zip(lo, hi, strict=True))
        scales = [reach] * len(lo)  # the run's largest |lo| + |hi|
        for side, pick in ((lo, min), (hi, max)):
            values = [row[d] for row in side]
            for chain in tie_chains(values, scales):
                value = pick(values[i] for i in chain)
                for i in chain:
                    side[i][d] = value
    return [(tuple(a), tuple(b), m) for a, b, (_, _, m) in zip(lo, hi, boxes, strict=True)]


def merged_equal(boxes: list[Box]) -> list[Box]:
    """Eq. 14 after snapping: masses of equal boxes added in the order given, (lo, hi) order."""
    total: dict[tuple[tuple[float, ...], tuple[float, ...]], float] = {}
    for lo, hi, m in snapped(boxes):
        total[(lo, hi)] = total.get((lo, hi), 0.0) + m
    return [(lo, hi, m) for (lo, hi), m in sorted(total.items())]


def clustered(boxes: list[Box], cap: int) -> tuple[list[Box], float]:
    """Apply the clustering rule to one run's boxes; return the capped boxes and merged mass."""
    n = len(boxes[0][0])
    mass_total = sum(m for _, _, m in boxes)
    unit = [sum(m * (hi[d] - lo[d]) for lo, hi, m in boxes) / mass_total for d in range(n)]
    unit = [u if u > 0 else 1.0 for u in unit]

    def size(lo: tuple[float, ...], hi: tuple[float, ...]) -> float:
        return sum((hi[d] - lo[d]) / unit[d] for d in range(n))

    def clearly_less(a: float, b: float, scale_a: float, scale_b: float) -> bool:
        return b - a > TIE_RTOL * max(scale_a, scale_b)

    reach = [max(abs(lo[d]) + abs(hi[d]) for lo, hi, _ in boxes) for d in range(n)]
    # [lo, hi, mass, mass·size, merged]
    items = [[lo, hi, m, m * size(lo, hi), False] for lo, hi, m in boxes]
    rnd = 0
    while len(items) > cap:
        d = rnd % n
        if rnd == 0 or n > 1:  # by centre; ties keep their order
            centre = [b[0][d] + b[1][d] for b in items]
            items = [items[i] for i in tie_sorted(centre, [reach[d]] * len(items))]
        hulls, cost = [], []
        for a, b in zip(items, items[1:], strict=False):
            lo = tuple(min(x, y) for x, y in zip(a[0], b[0], strict=True))
            hi = tuple(max(x, y) for x, y in zip(a[1], b[1], strict=True))
            m = a[2] + b[2]
            ms = m * size(lo, hi)
            hulls.append([lo, hi, m, ms, True])
            cost.append(ms - a[3] - b[3])
        last = len(cost) - 1
        ms = [h[3] for h in hulls]  # the scale of ties between Δ: the hull's mass·size
        local = [
            i
            for i, c in enumerate(cost)
            if math.isfinite(c)
            and (i == 0 or not clearly_less(cost[i - 1], c, ms[i - 1], ms[i]))
            and (i == last or clearly_less(c, cost[i + 1], ms[i], ms[i + 1]))
        ]
        ranked = [local[j] for j in tie_sorted([cost[i] for i in local], [ms[i] for i in local])]
        chosen = set(ranked[: len(items) - cap])
        assert chosen, "the reference found no pair to merge"
        items = [hulls[i] if i in chosen else b for i, b in enumerate(items) if i - 1 not in chosen]
        rnd += 1
    moved = sum(sorted(b[2] for b in items if b[4]))
    return merged_equal([(b[0], b[1], b[2]) for b in items]), moved


def run_boxes(bm: Boxes, r: int) -> list[Box]:
    return [
        (tuple(bm.lo[r, i].tolist()), tuple(bm.hi[r, i].tolist()), float(bm.mass[r, i]))
        for i in range(bm.mass.shape[1])
        if bm.mass[r, i] > 0
    ]


def random_boxes(rng: np.random.Generator, runs: int, rows: int, n: int) -> Boxes:
    """Rows on a grid (many equal boxes and ties), some massless, merged as the filter does."""
    lo = rng.integers(0, 8, size=(runs, rows, n)) * rng.choice([0.5, 0.1, 1 / 3])
    hi = lo + rng.integers(0, 5, size=(runs, rows, n)) * rng.choice([0.25, 0.1, 0.7])
    mass = rng.random((runs, rows)) * (rng.random((runs, rows)) > 0.15)
    mass[:, 0] += 0.01  # every run keeps a box
    return merge_equal_boxes(lo, hi, mass / mass.sum(axis=1, keepdims=True))


#: The numpy functions, and the compiled ones of ``NassreddineFilter(kernel="numba")``.
KERNELS = ["numpy", pytest.param("numba", marks=pytest.mark.extras)]  # numba: extra "speed"


def kernels(kind: str):
    """(merge_equal_boxes, cluster_boxes) of ``kind``."""
    if kind == "numpy":
        return merge_equal_boxes, cluster_boxes
    from dstoolkit.evidence.boxes import (
        cluster_boxes_compiled,
        merge_equal_boxes_compiled,
    )

    return merge_equal_boxes_compiled, lambda bm, cap: cluster_boxes_compiled(bm, cap, 10_000)


@pytest.mark.parametrize("kind", KERNELS)
@pytest.mark.parametrize("n", [1, 2, 3])
def test_cluster_boxes_gives_the_rule_s_numbers_exactly(n, kind):
    cluster_boxes = kernels(kind)[1]
    rng = np.random.default_rng(14 + n)
    compared = merged_runs = 0
    for _ in range(40):
        runs, rows, cap = (
            int(rng.integers(1, 5)),
            int(rng.integers(4, 160)),
            int(rng.integers(2, 13)),
        )
        bm = random_boxes(rng, runs, rows, n)
        out, moved = cluster_boxes(bm, cap)
        for r in range(runs):
            want, want_moved = clustered(run_boxes(bm, r), cap)
            assert run_boxes(out, r) == want
            assert float(moved[r]) == want_moved
            compared += 1
            merged_runs += want_moved > 0
    assert merged_runs > compared // 2  # the cap did work in most runs


@pytest.mark.parametrize("kind", KERNELS)
def test_merge_equal_boxes_adds_masses_in_the_order_given(kind):
    merge_equal_boxes = kernels(kind)[0]
    rng = np.random.default_rng(3)
    for n in (1, 2):
        lo = rng.integers(0, 3, size=(3, 300, n)) * 0.1
        hi = lo + rng.integers(0, 3, size=(3, 300, n)) * 0.1
        mass = rng.random((3, 300)) * (rng.random((3, 300)) > 0.1)
        out = merge_equal_boxes(lo, hi, mass)
        for r in range(3):
            rows = [
                (tuple(lo[r, i].tolist()), tuple(hi[r, i].tolist()), float(mass[r, i]))
                for i in range(300)
            ]
            assert run_boxes(out, r) == merged_equal(rows)


@pytest.mark.extras  # numba, the extra "speed"
def test_the_compiled_merge_and_cluster_return_the_numpy_arrays_whole():
    """The compiled functions return the numpy ones' arrays, element for element.

    Padding, widths and runs without mass included.
    """
    compiled_merge, compiled_cluster = kernels("numba")
    rng = np.random.default_rng(21)
    for case in range(60):
        n = 1 + case % 3
        runs, rows = int(rng.integers(1, 6)), int(rng.integers(1, 120))
        lo = rng.integers(0, 6, size=(runs, rows, n)) * 0.25
        hi = lo + rng.integers(0, 4, size=(runs, rows, n)) * 0.5
        mass = rng.random((runs, rows)) * (rng.random((runs, rows)) > 0.3)
        if case % 4 == 0:
            mass[0] = 0.0  # a run without mass
        for want, got in zip(
            merge_equal_boxes(lo, hi, mass), compiled_merge(lo, hi, mass), strict=True
        ):
            assert want.shape == got.shape
            np.testing.assert_array_equal(want, got)
        mass[:, 0] += 0.01
        bm = merge_equal_boxes(lo, hi, mass / mass.sum(axis=1, keepdims=True))
        cap = int(rng.integers(2, 12))
        (want_bm, want_moved), (got_bm, got_moved) = (
            cluster_boxes(bm, cap),
            compiled_cluster(bm, cap),
        )
        for want, got in zip((*want_bm, want_moved), (*got_bm, got_moved), strict=True):
            assert want.shape == got.shape
            np.testing.assert_array_equal(want, got)


@pytest.mark.parametrize("kind", KERNELS)
@pytest.mark.parametrize("n", [1, 2])
def test_bounds_moved_by_a_few_ulps_give_the_same_clusters(n, kind):
    """Boxes on a grid (exact ties everywhere) moved by ±4 ulp cluster as before.

    Another CPU's rounding moves the boxes a filter computes by a few ulps; without the tie
    rule (``TIE_RTOL = 0``) the merges then follow the last bits and the capped boxes move
    by whole grid steps. With it, they move by a few ulps: 1e-12 (absolute, on
    coordinates of order 1–10) is a thousand times that and far below a grid step.
    """
    merge_equal_boxes, cluster_boxes = kernels(kind)
    rng = np.random.default_rng(40 + n)
    for trial in range(30):
        runs, rows, cap = int(rng.integers(1, 4)), int(rng.integers(20, 120)), 5
        bm = random_boxes(rng, runs, rows, n)
        moved = Boxes(nudged(bm.lo, trial), nudged(bm.hi, trial + 100), bm.mass)
        want, want_moved = cluster_boxes(bm, cap)
        got, got_moved = cluster_boxes(merge_equal_boxes(moved.lo, moved.hi, moved.mass), cap)
        assert got.mass.shape == want.mass.shape
        np.testing.assert_allclose(got.lo, want.lo, rtol=0, atol=1e-12)
        np.testing.assert_allclose(got.hi, want.hi, rtol=0, atol=1e-12)
        np.testing.assert_allclose(got.mass, want.mass, rtol=0, atol=1e-12)
        np.testing.assert_allclose(got_moved, want_moved, rtol=0, atol=1e-12)

"""Optional compiled box kernels (extra ``speed``: numba).

The merge of equal boxes (eq. 14) and Denœux's clustering, run by run in plain loops.

They give the numbers of :func:`~dstoolkit.evidence.boxes.merge_equal_boxes` and
:func:`~dstoolkit.evidence.boxes.cluster_boxes` bit for bit (tested): the same rules, the
same floating-point operations in the same order. In numpy both are a few dozen calls per
round on every run at once; compiled, one pass per run. Nothing requires them
(Nassreddine's filter uses them with ``kernel="numba"`` or ``"auto"``).
"""

from __future__ import annotations

import functools
from collections.abc import Callable

import numpy as np

from dstoolkit.errors import require_extra

from . import _clustering as clustering
from ._boxes import Boxes
from ._ties import clearly_less, snap_bounds, tie_classes

#: The codes the clustering kernel returns: clustered; too many rounds; no pair to merge;
#: NaN or infinite masses, or unbounded boxes with mass; every run within the cap already.
FITS, TOO_MANY_ROUNDS, NO_PAIR, NOT_BOUNDED, ALL_FIT = 0, 1, 2, 3, 4


def _row_less(key: np.ndarray, a: int, b: int) -> bool:  # pragma: no cover - numba
    """Row a's key before row b's (lexicographic; equal keys: not before)."""
    for j in range(key.shape[1]):
        if key[a, j] < key[b, j]:
            return True
        if key[a, j] > key[b, j]:
            return False
    return False


def _stable_order(
    key: np.ndarray, order: np.ndarray, work: np.ndarray
) -> None:  # pragma: no cover - numba
    """Set ``order`` to the rows of ``key`` sorted lexicographically, stable, as ``np.lexsort``.

    Equal keys keep their order: insertion sort of blocks of 16 rows, then merges of
    neighbouring blocks (skipped where two blocks are in order already).
    """
    rows = key.shape[0]
    for i in range(rows):
        order[i] = i
    for start in range(0, rows, 16):
        for i in range(start + 1, min(start + 16, rows)):
            row, j = order[i], i
            while j > start and _row_less(key, row, order[j - 1]):
                order[j] = order[j - 1]
                j -= 1
            order[j] = row
    src, dst = order, work
    width = 16
    while width < rows:
        for start in range(0, rows, 2 * width):
            mid, end = min(start + width, rows), min(start + 2 * width, rows)
            if mid >= end or not _row_less(key, src[mid], src[mid - 1]):
                for k in range(start, end):  # in order already
                    dst[k] = src[k]
                continue
            i, j, k = start, mid, start
            while i < mid and j < end:
                if _row_less(key, src[j], src[i]):
                    dst[k] = src[j]
                    j += 1
                else:
                    dst[k] = src[i]
                    i += 1
                k += 1
            while i < mid:
                dst[k] = src[i]
                i += 1
                k += 1
            while j < end:
                dst[k] = src[j]
                j += 1
                k += 1
        src, dst = dst, src
        width *= 2
    if src is not order:
        for i in range(rows):
            order[i] = src[i]


def _group_equal(
    key: np.ndarray, table: np.ndarray, tbits: int, group_of: np.ndarray, first: np.ndarray
) -> int:  # pragma: no cover - numba
    """Give the distinct rows of ``key`` numbers in order of first appearance; count them.

    ``group_of[k]`` is row k's group, ``first[g]`` the first row of group g. Rows are equal
    when every column compares equal (0.0 and −0.0 alike, as the sort's comparisons have
    them; no NaN). An open-addressing hash table of the columns' bits, ``table``
    (2**tbits slots, at least twice the rows), finds each row's group in one probe or a
    few, so only the distinct rows need sorting.
    """
    size = table.shape[0]
    shift = np.uint64(64 - tbits)
    table[:] = -1
    bits = np.empty(1)
    as_int = bits.view(np.uint64)
    groups = 0
    for k in range(key.shape[0]):
        h = np.uint64(0)
        for j in range(key.shape[1]):
            bits[0] = key[k, j] + 0.0  # −0.0 + 0.0 = 0.0: equal rows, equal bits
            h = (h ^ as_int[0]) * np.uint64(0x9E3779B97F4A7C15)
        t = np.int64(h >> shift)
        while True:
            g = table[t]
            if g < 0:  # a new box
                table[t] = groups
                first[groups] = k
                group_of[k] = groups
                groups += 1
                break
            same = True
            for j in range(key.shape[1]):
                if key[first[g], j] != key[k, j]:
                    same = False
                    break
            if same:
                group_of[k] = g
                break
            t = np.int64((t + 1) & (size - 1))
    return groups


def _merge(
    lo: np.ndarray,
    hi: np.ndarray,
    mass: np.ndarray,
    out_lo: np.ndarray,
    out_hi: np.ndarray,
    out_mass: np.ndarray,
) -> int:  # pragma: no cover - numba
    """Merge equal boxes per run (eq. 14) as ``merge_equal_boxes``.

    Rows are sorted by (no mass, lo, hi), stable; equal rows' masses added in that order;
    padding copies the first row. Returns the width (the most boxes with mass in a run, at
    least 1). Only the rows with mass are sorted (the others come last and are dropped), all
    of them in a run without mass (its first row in that order is the padding).

    A run whose rows with mass hold no NaN is merged first and sorted after: equal rows are
    grouped by :func:`_group_equal` (each group's box is its first row, its masses added in
    the order the rows came in, which is the order a stable sort keeps them in), then only
    the distinct boxes are sorted. The same boxes, masses and order as sorting every row.
    """
    runs, rows, n = lo.shape
    key = np.empty((rows, 2 * n))
    rows_of, order, work = (
        np.empty(rows, np.int64),
        np.empty(rows, np.int64),
        np.empty(rows, np.int64),
    )
    tbits = 1
    while 2**tbits < 2 * rows:
        tbits += 1
    table = np.empty(2**tbits, np.int64)
    group_of, first = np.empty(rows, np.int64), np.empty(rows, np.int64)
    group_key, group_mass = np.empty((rows, 2 * n)), np.empty(rows)
    counts = np.zeros(runs, np.int64)
    for r in range(runs):
        m = 0
        for i in range(rows):
            if mass[r, i] > 0:
                rows_of[m] = i
                m += 1
        dead = m == 0
        if dead:
            for i in range(rows):
                rows_of[i] = i
            m = rows
        finite = not dead
        for k in range(m):
            i = rows_of[k]
            for j in range(n):
                key[k, j], key[k, n + j] = lo[r, i, j], hi[r, i, j]
                if np.isnan(lo[r, i, j]) or np.isnan(hi[r, i, j]):
                    finite = False
        if finite:  # group equal rows, then sort the distinct ones
            groups = _group_equal(key[:m], table, tbits, group_of, first)
            for g in range(groups):
                group_mass[g] = 0.0
                for j in range(2 * n):
                    group_key[g, j] = key[first[g], j]
            for k in range(m):
                group_mass[group_of[k]] += mass[r, rows_of[k]]
            _stable_order(group_key[:groups], order[:groups], work[:groups])
            for t in range(groups):
                g = order[t]
                i = rows_of[first[g]]
                for j in range(n):
                    out_lo[r, t, j], out_hi[r, t, j] = lo[r, i, j], hi[r, i, j]
                out_mass[r, t] = group_mass[g]
            counts[r] = groups
            continue
        _stable_order(key[:m], order[:m], work[:m])
        groups = 0
        for k in range(m):
            new = k == 0
            if not new:
                for j in range(2 * n):
                    if key[order[k], j] != key[order[k - 1], j]:
                        new = True
                        break
            i = rows_of[order[k]]
            if new:
                for j in range(n):
                    out_lo[r, groups, j], out_hi[r, groups, j] = lo[r, i, j], hi[r, i, j]
                out_mass[r, groups] = 0.0
                groups += 1
                if dead:
                    break
            out_mass[r, groups - 1] += mass[r, i]
        counts[r] = 0 if dead else groups
    width = max(1, counts.max())
    for r in range(runs):
        for g in range(counts[r], width):
            for j in range(n):
                out_lo[r, g, j], out_hi[r, g, j] = out_lo[r, 0, j], out_hi[r, 0, j]
            out_mass[r, g] = 0.0
    return width


def _size(
    lo: np.ndarray, hi: np.ndarray, i: int, unit: np.ndarray, r: int
) -> float:  # pragma: no cover - numba
    """Compute |A| of box i: the sum of its widths, each divided by run r's unit width.

    As ``_sizes`` does.
    """
    total = (hi[i, 0] - lo[i, 0]) / unit[r, 0]
    for j in range(1, lo.shape[1]):
        total += (hi[i, j] - lo[i, j]) / unit[r, j]
    return total


def _bounded_count(
    lo: np.ndarray, hi: np.ndarray, mass: np.ndarray, count: np.ndarray
) -> bool:  # pragma: no cover - numba
    """Count each run's boxes with mass, as ``bounded_count``; False where it would refuse.

    It refuses NaN or infinite masses and boxes with mass with a NaN or infinite bound.
    """
    runs, rows, n = lo.shape
    for r in range(runs):
        count[r] = 0
        for i in range(rows):
            if not np.isfinite(mass[r, i]):
                return False
            if mass[r, i] > 0:
                count[r] += 1
                for j in range(n):
                    if not (np.isfinite(lo[r, i, j]) and np.isfinite(hi[r, i, j])):
                        return False
    return True


def _unit_widths(
    lo: np.ndarray, hi: np.ndarray, mass: np.ndarray, unit: np.ndarray
) -> None:  # pragma: no cover - numba
    """Set ``unit`` to each run's mass-weighted mean widths, as ``unit_widths``.

    The same operations in the same order: m·(hi − lo) and m summed row after row (as
    ``row_sum``), their ratio, 1 where it is not > 0.
    """
    runs, rows, n = lo.shape
    for r in range(runs):
        total = mass[r, 0]
        for i in range(1, rows):
            total += mass[r, i]
        for j in range(n):
            moment = mass[r, 0] * (hi[r, 0, j] - lo[r, 0, j])
            for i in range(1, rows):
                moment += mass[r, i] * (hi[r, i, j] - lo[r, i, j])
            width = moment / total
            unit[r, j] = width if width > 0 else 1.0


def _moved_mass(
    mass: np.ndarray, merged: np.ndarray, moved: np.ndarray
) -> None:  # pragma: no cover
    """Set ``moved`` to the mass of the merged boxes per run, as ``merged_mass``.

    The masses of the merged boxes (0 for the others) sorted, then added smallest first.
    """
    for r in range(mass.shape[0]):
        values = np.sort(np.where(merged[r], mass[r], 0.0))
        total = values[0]
        for i in range(1, values.shape[0]):
            total += values[i]
        moved[r] = total


def _cluster(
    lo: np.ndarray,
    hi: np.ndarray,
    mass: np.ndarray,
    cap: int,
    max_rounds: int,
    out_lo: np.ndarray,
    out_hi: np.ndarray,
    out_mass: np.ndarray,
    out_moved: np.ndarray,
) -> int:  # pragma: no cover
    """Cluster boxes by Denœux's method as ``cluster_boxes``, run by run.

    First the checks and units of ``cluster_boxes`` (:func:`_bounded_count`,
    :func:`_unit_widths`; ``ALL_FIT`` when no run exceeds ``cap``). Each round sorts the
    boxes by centre along dimension round % n (only round 0 in 1-D; centres that tie keep
    their order, :func:`~dstoolkit.evidence._ties.tie_order`; nothing is moved when the
    order stays), merges the neighbour pairs whose Δ is a local minimum (compared up to
    ties, :func:`~dstoolkit.evidence._ties.clearly_less`), cheapest first (ties: leftmost),
    never below ``cap``; a pair of boxes
    that were neighbours in the last round and did not change keeps its hull and Δ (the
    same numbers), only the pairs next to a new hull are computed again. Writes each run's
    boxes in their final order (zero-mass padding after) and the mass the merges moved
    (:func:`_moved_mass`).
    """
    runs, rows, n = lo.shape
    count = np.empty(runs, np.int64)
    if not _bounded_count(lo, hi, mass, count):
        return NOT_BOUNDED
    if count.max() <= cap:
        return ALL_FIT
    unit = np.empty((runs, n))
    _unit_widths(lo, hi, mass, unit)
    out_merged = np.zeros(out_mass.shape, np.bool_)
    b_lo, b_hi = np.empty((rows, n)), np.empty((rows, n))
    b_m, b_ms, b_merged = np.empty(rows), np.empty(rows), np.zeros(rows, np.bool_)
    t_lo, t_hi = np.empty((rows, n)), np.empty((rows, n))
    t_m, t_ms, t_merged = np.empty(rows), np.empty(rows), np.zeros(rows, np.bool_)
    p_lo, p_hi = np.empty((rows, n)), np.empty((rows, n))
    p_m, p_ms, cost = np.empty(rows), np.empty(rows), np.empty(rows)
    key, scale, local = np.empty(rows), np.empty(rows), np.empty(rows, np.int64)
    same_run = np.zeros(rows, np.int64)  # tie_order's group: one run at a time
    chosen, fresh = np.zeros(rows, np.bool_), np.ones(rows, np.bool_)
    reach = np.zeros(n)  # the run's largest |lo| + |hi| per dimension, as _ties.reach
    for r in range(runs):
        reach[:] = 0.0
        k = 0
        for i in range(rows):
            if mass[r, i] > 0:
                for j in range(n):
                    reach[j] = max(reach[j], abs(lo[r, i, j]) + abs(hi[r, i, j]))
                for j in range(n):
                    b_lo[k, j], b_hi[k, j] = lo[r, i, j], hi[r, i, j]
                b_m[k] = mass[r, i]
                b_ms[k] = b_m[k] * _size(b_lo, b_hi, k, unit, r)
                b_merged[k] = False
                k += 1
        rnd = 0
        every = True  # every pair's hull to be computed (a new run, or boxes reordered)
        while k > cap:
            if rnd == max_rounds:
                return TOO_MANY_ROUNDS
            d = rnd % n
            ordered = rnd > 0 and n == 1  # in 1-D the boxes stay in round 0's order
            if not ordered:  # by centre, ties keeping their order, as by_centre
                for i in range(k):
                    key[i] = b_lo[i, d] + b_hi[i, d]
                    scale[i] = reach[d]
                order = np.argsort(tie_classes(key[:k], scale[:k], same_run[:k]), kind="mergesort")
                ordered = True  # the order they have already: the pairs' hulls stay
                for i in range(k):
                    ordered = ordered and order[i] == i
            if not ordered:
                for i in range(k):
                    o = order[i]
                    for j in range(n):
                        t_lo[i, j], t_hi[i, j] = b_lo[o, j], b_hi[o, j]
                    t_m[i], t_ms[i], t_merged[i] = b_m[o], b_ms[o], b_merged[o]
                b_lo, t_lo, b_hi, t_hi = t_lo, b_lo, t_hi, b_hi
                b_m, t_m, b_ms, t_ms, b_merged, t_merged = t_m, b_m, t_ms, b_ms, t_merged, b_merged
                every = True
            for i in range(k - 1):  # each neighbour pair's hull and its Δ
                if not (every or fresh[i] or fresh[i + 1]):
                    continue  # two boxes that were neighbours last round: the same pair
                for j in range(n):
                    p_lo[i, j] = min(b_lo[i, j], b_lo[i + 1, j])
                    p_hi[i, j] = max(b_hi[i, j], b_hi[i + 1, j])
                p_m[i] = b_m[i] + b_m[i + 1]
                p_ms[i] = p_m[i] * _size(p_lo, p_hi, i, unit, r)
                cost[i] = p_ms[i] - b_ms[i] - b_ms[i + 1]
            for i in range(k - 1):  # the scale of ties between Δ, as in cluster_boxes
                scale[i] = p_ms[i]
            every = False
            found = 0
            for i in range(k - 1):  # not clearly above the left, clearly below the right
                c = cost[i]
                if (
                    np.isfinite(c)
                    and (i == 0 or not clearly_less(cost[i - 1], c, scale[i - 1], scale[i]))
                    and (i == k - 2 or clearly_less(c, cost[i + 1], scale[i], scale[i + 1]))
                ):
                    local[found] = i
                    found += 1
            if found == 0:
                return NO_PAIR
            chosen[: k - 1] = False
            if found <= k - cap:
                for i in range(found):
                    chosen[local[i]] = True
            else:  # the cheapest, ties leftmost
                at = local[:found]
                ranked = np.argsort(
                    tie_classes(cost[at], scale[at], same_run[:found]), kind="mergesort"
                )
                for i in range(k - cap):
                    chosen[local[ranked[i]]] = True
            kept = i = 0
            while i < k:  # in place: kept ≤ i
                if i < k - 1 and chosen[i]:  # the pair's hull; its second box goes
                    for j in range(n):
                        b_lo[kept, j], b_hi[kept, j] = p_lo[i, j], p_hi[i, j]
                    b_m[kept], b_ms[kept], b_merged[kept] = p_m[i], p_ms[i], True
                    fresh[kept] = True
                    i += 2
                else:
                    if kept != i:
                        for j in range(n):
                            b_lo[kept, j], b_hi[kept, j] = b_lo[i, j], b_hi[i, j]
                        b_m[kept], b_ms[kept], b_merged[kept] = b_m[i], b_ms[i], b_merged[i]
                        # its pair with the next box, kept if that box is unchanged too
                        for j in range(n):
                            p_lo[kept, j], p_hi[kept, j] = p_lo[i, j], p_hi[i, j]
                        p_m[kept], p_ms[kept], cost[kept] = p_m[i], p_ms[i], cost[i]
                    fresh[kept] = False
                    i += 1
                kept += 1
            k = kept
            rnd += 1
        for i in range(out_mass.shape[1]):
            inside = i < k
            for j in range(n):
                out_lo[r, i, j] = b_lo[i, j] if inside else 0.0
                out_hi[r, i, j] = b_hi[i, j] if inside else 0.0
            out_mass[r, i] = b_m[i] if inside else 0.0
            out_merged[r, i] = b_merged[i] if inside else False
    _moved_mass(out_mass, out_merged, out_moved)
    return FITS


@functools.cache
def _compiled() -> tuple[Callable[..., int], Callable[..., int]]:
    """Return the two box kernels, compiled on first use (and cached on disk by numba).

    The helpers they call are compiled first and take their names in this module: numba
    resolves a kernel's calls by name when it compiles it.
    """
    require_extra("numba", "speed", "the compiled box kernels (merge and clustering)")
    import numba

    jit = numba.njit(cache=True, nogil=True)
    names = globals()
    for name in (
        "_row_less",
        "_stable_order",
        "_group_equal",
        "_size",
        "_bounded_count",
        "_unit_widths",
        "_moved_mass",
        "clearly_less",
        "tie_classes",
    ):
        names[name] = jit(names[name])
    return jit(_merge), jit(_cluster)


def merge_equal_boxes_compiled(lo: np.ndarray, hi: np.ndarray, mass: np.ndarray) -> Boxes:
    """:func:`~dstoolkit.evidence.boxes.merge_equal_boxes`, compiled: the same numbers."""
    merge = _compiled()[0]
    mass = np.ascontiguousarray(mass, dtype=float)
    lo, hi = snap_bounds(lo, hi, mass)  # as merge_equal_boxes: tied bounds made equal
    out_lo, out_hi, out_mass = np.empty_like(lo), np.empty_like(hi), np.empty_like(mass)
    width = merge(lo, hi, mass, out_lo, out_hi, out_mass)
    return Boxes(out_lo[:, :width], out_hi[:, :width], out_mass[:, :width])


def cluster_boxes_compiled(
    bm: Boxes, max_focal: int, max_rounds: int | None = None
) -> tuple[Boxes, np.ndarray]:
    """Run :func:`~dstoolkit.evidence.boxes.cluster_boxes`, compiled.

    The same numbers and errors (``max_rounds``: its limit of rounds, default
    ``MAX_CLUSTER_ROUNDS``).
    """
    rounds = clustering.MAX_CLUSTER_ROUNDS if max_rounds is None else max_rounds
    runs, _, n = bm.lo.shape
    lo, hi = np.empty((runs, max_focal, n)), np.empty((runs, max_focal, n))
    mass, moved = np.empty((runs, max_focal)), np.empty(runs)
    code = _compiled()[1](
        np.ascontiguousarray(bm.lo, dtype=float),
        np.ascontiguousarray(bm.hi, dtype=float),
        np.ascontiguousarray(bm.mass, dtype=float),
        max_focal,
        rounds,
        lo,
        hi,
        mass,
        moved,
    )
    if code == NOT_BOUNDED:
        raise clustering.unbounded_boxes()
    if code == ALL_FIT:
        return merge_equal_boxes_compiled(bm.lo, bm.hi, bm.mass), np.zeros(runs)
    if code == TOO_MANY_ROUNDS:
        raise clustering.too_many_rounds(max_focal, rounds)
    if code == NO_PAIR:
        raise clustering.no_pair()
    return merge_equal_boxes_compiled(lo, hi, mass), moved

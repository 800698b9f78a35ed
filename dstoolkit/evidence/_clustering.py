"""Box operations on batches of evidence: equal boxes merged, and Denœux's clustering.

Equal boxes are merged by eq. 14; Denœux's hierarchical clustering caps the number of focal
elements by an outer approximation (Int. J. Approx. Reasoning 2001).

Both work on :class:`~dstoolkit.evidence.boxes.Boxes` with a leading run axis (every run
at once); :mod:`dstoolkit.evidence._compiled` holds their compiled twins (extra
``speed``), which give the same numbers bit for bit. Nassreddine's filter caps its
posterior with them; they are exported by :mod:`dstoolkit.evidence.boxes`.
"""

from __future__ import annotations

import numpy as np

from dstoolkit.errors import EvidenceError, WorkLimitError

from ._boxes import Boxes, row_sum
from ._ties import clearly_less, reach, snap_bounds, tie_order

#: Clustering rounds after which :func:`cluster_boxes` gives up (each round halves at most
#: the excess, so a few dozen suffice for any real posterior).
MAX_CLUSTER_ROUNDS = 10_000


def merge_equal_boxes(lo: np.ndarray, hi: np.ndarray, mass: np.ndarray) -> Boxes:
    """Merge equal boxes within each run, adding their masses (eq. 14).

    Input rows with mass 0 are dropped. The result is compacted and canonical: run r's
    distinct boxes fill its first slots in lexicographic order of (lo, hi), whatever order
    they came in; the remaining slots are zero-mass padding (with the run's first box).
    The masses of equal boxes are added in the order the boxes came in. Bounds that tie
    (within ``dstoolkit.evidence.boxes.TIE_RTOL``) are first snapped outwards to one
    value (``dstoolkit.evidence.boxes.snap_bounds``), so boxes equal in exact
    arithmetic merge whatever the CPU's rounding.

    Parameters
    ----------
    lo, hi : ndarray, shape (R, N, d)
        The boxes of each run.
    mass : ndarray, shape (R, N)
        Their masses.

    Returns
    -------
    Boxes
        Boxes (R, W, d) and masses (R, W), W the largest number of distinct boxes of
        positive mass in a run.

    Notes
    -----
    ``dstoolkit.evidence.boxes.merge_equal_boxes_compiled`` gives the same numbers, compiled (extra
    ``speed``).

    References
    ----------
    The paper's eq. (14).

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.evidence.boxes import Boxes
    >>> merged = merge_equal_boxes(np.array([[[0.0], [0.0], [1.0]]]),
    ...                            np.array([[[1.0], [1.0], [2.0]]]),
    ...                            np.array([[0.2, 0.3, 0.5]]))
    >>> merged.mass
    array([[0.5, 0.5]])
    """
    runs, rows, n = lo.shape
    lo, hi = snap_bounds(lo, hi, mass)
    valid = mass > 0
    keys = (
        *(hi[..., j] for j in range(n - 1, -1, -1)),
        *(lo[..., j] for j in range(n - 1, -1, -1)),
        ~valid,
    )
    order = np.lexsort(keys, axis=-1)
    order += (np.arange(runs) * rows)[:, None]  # index into the flattened rows
    lo, hi = np.take(lo.reshape(-1, n), order, axis=0), np.take(hi.reshape(-1, n), order, axis=0)
    weight = np.take(np.where(valid, mass, 0.0), order)
    valid = weight > 0
    start = np.ones((runs, rows), dtype=bool)  # first row of a group of equal boxes
    start[:, 1:] = valid[:, 1:] != valid[:, :-1]
    for side in (lo, hi):
        for j in range(n):
            start[:, 1:] |= side[:, 1:, j] != side[:, :-1, j]
    group = np.cumsum(start, axis=1)
    group -= 1
    summed = np.bincount(
        (group + (np.arange(runs) * rows)[:, None]).ravel(),
        weights=weight.ravel(),
        minlength=runs * rows,
    ).reshape(runs, rows)
    width = max(1, int(np.count_nonzero(summed > 0, axis=1).max()))
    heads = np.flatnonzero(start & valid)  # the first row of each group with mass
    dest = np.take(group, heads) + heads // rows * width
    out = []
    for side in (lo, hi):
        merged = np.empty((runs, width, n))
        merged[:] = side[:, :1]  # padding: the run's first box
        merged.reshape(-1, n)[dest] = np.take(side.reshape(-1, n), heads, axis=0)
        out.append(merged)
    return Boxes(out[0], out[1], summed[:, :width])


class _Rows:
    """Row layout of :func:`cluster_boxes`'s box table (C, N).

    One row per quantity, one column per box; the boxes of the runs still being clustered
    sit side by side, run after run, each run's boxes in the order of the round (n = state
    dim).

    ``[lo (n) | hi (n) | size | mass·size | merged | centre (n) | mass | unit (n)]``: a round
    drops the boxes merged away with one compaction and keeps each quantity contiguous. The
    per-box terms of Denœux's Δ (|A| and m_A·|A|), the sort keys (lo + hi per dimension) and
    the run's unit widths are computed once per box, when it is made, not in every round (the
    same operations on the same values, so the same numbers).
    """

    def __init__(self, n: int) -> None:
        self.n = n
        self.lo, self.hi = slice(0, n), slice(n, 2 * n)
        self.size, self.ms, self.merged = 2 * n, 2 * n + 1, 2 * n + 2
        self.centre, self.mass = 2 * n + 3, 3 * n + 3  # centre: first of n rows
        self.box = slice(0, 3 * n + 4)  # what a merge rewrites
        self.unit = slice(3 * n + 4, 4 * n + 4)
        self.count = 4 * n + 4

    def table(
        self, bm: Boxes, unit: np.ndarray, scale: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Tabulate the boxes with mass of every run, in round 0's order, and the run of each.

        Round 0's order is by centre along dimension 0 (:meth:`by_centre`): ties keep the
        order of ``bm``.
        """
        runs, width, n = bm.lo.shape
        live = np.flatnonzero(bm.mass > 0)  # the boxes with mass, run after run
        run = live // width
        first = live[
            self.by_centre(
                bm.lo.reshape(-1, n)[live].T, bm.hi.reshape(-1, n)[live].T, 0, run, scale
            )
        ]
        table = np.empty((self.count, len(first)))
        table[self.lo] = np.take(bm.lo.reshape(-1, n), first, axis=0).T
        table[self.hi] = np.take(bm.hi.reshape(-1, n), first, axis=0).T
        table[self.unit] = unit[run, 0].T
        table[self.size] = self.sizes(table[self.lo], table[self.hi], table[self.unit])
        np.take(bm.mass, first, out=table[self.mass])
        np.multiply(table[self.mass], table[self.size], out=table[self.ms])
        table[self.merged] = 0.0
        np.add(table[self.lo], table[self.hi], out=table[self.centre : self.mass])
        return table, run

    @staticmethod
    def by_centre(
        lo: np.ndarray, hi: np.ndarray, d: int, run: np.ndarray, scale: np.ndarray
    ) -> np.ndarray:
        """Order boxes given as rows (n, N) by their centre along dimension d, run by run.

        The key is lo + hi; centres within the tie tolerance of each other (relative to the
        run's ``scale`` (R, n), :func:`~dstoolkit.evidence._ties.reach`) keep their order
        (:func:`~dstoolkit.evidence._ties.tie_order`).
        """
        return tie_order(lo[d] + hi[d], scale[run, d], run)

    def sizes(self, lo: np.ndarray, hi: np.ndarray, unit: np.ndarray) -> np.ndarray:
        """Compute |A| of boxes given as rows (n, N).

        That is the sum of each box's widths, each divided by its run's unit width. The
        widths are summed along a contiguous last axis (N, n), the layout the stored results
        were computed with (it decides how the sum rounds).
        """
        if self.n == 1:
            return (hi[0] - lo[0]) / unit[0]
        widths = np.empty(lo.shape[::-1])
        np.subtract(hi.T, lo.T, out=widths)
        np.divide(widths, unit.T, out=widths)
        return np.sum(widths, axis=-1)

    def pair_hulls(self, table: np.ndarray) -> np.ndarray:
        """Fill rows lo, hi, size, mass and mass·size of each neighbour pair's hull A ∪ B.

        The hull has mass m_A + m_B (C, N − 1); the other rows are filled in for the pairs
        merged.
        """
        a, b = table[:, :-1], table[:, 1:]
        pair = np.empty(a.shape)
        np.minimum(a[self.lo], b[self.lo], out=pair[self.lo])
        np.maximum(a[self.hi], b[self.hi], out=pair[self.hi])
        pair[self.size] = self.sizes(pair[self.lo], pair[self.hi], a[self.unit])
        np.add(a[self.mass], b[self.mass], out=pair[self.mass])
        np.multiply(pair[self.mass], pair[self.size], out=pair[self.ms])
        return pair

    def merge_pairs(self, table: np.ndarray, pair: np.ndarray, picked: np.ndarray) -> None:
        """Write the hull of each picked pair (boxes i, i + 1) over box i, marked merged."""
        hulls = np.take(pair[self.box], picked, axis=1)
        hulls[self.merged] = 1.0
        np.add(hulls[self.lo], hulls[self.hi], out=hulls[self.centre : self.mass])
        table[self.box, picked] = hulls


def _local_minima(cost: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """Pairs whose finite Δ is not clearly above the left neighbour's, clearly below the right's.

    "Clearly" is beyond the tie tolerance (:func:`~dstoolkit.evidence._ties.clearly_less`,
    relative to the pairs' ``scale``). Two such pairs are never neighbours, so their merges
    do not overlap.
    """
    local = np.isfinite(cost)
    rises = clearly_less(cost[:-1], cost[1:], scale[:-1], scale[1:])  # pair i below i + 1
    local[1:] &= ~rises
    local[:-1] &= rises
    return local


def _cheapest(
    local: np.ndarray,
    cost: np.ndarray,
    scale: np.ndarray,
    run: np.ndarray,
    allowed: np.ndarray,
) -> np.ndarray:
    """Choose the pairs to merge, as indices: each run's ``allowed`` cheapest local minima.

    Ties: Δ within the tie tolerance of each other count as equal, and equal Δ go
    leftmost first (:func:`~dstoolkit.evidence._ties.tie_order`); ``run`` is the run of
    each pair. Ranking is skipped when every run may take all its local minima.
    """
    at = np.flatnonzero(local)
    per_run = np.bincount(run[at], minlength=len(allowed))
    if np.all(per_run <= allowed):
        return at
    at = at[tie_order(cost[at], scale[at], run[at])]  # by run, then by Δ, ties leftmost
    ranked = run[at]
    first = np.cumsum(per_run) - per_run  # where each run's local minima begin in that order
    return at[np.arange(len(at)) - first[ranked] < allowed[ranked]]


def cluster_boxes(bm: Boxes, max_focal: int) -> tuple[Boxes, np.ndarray]:
    """Cap each run at ``max_focal`` focal elements by merging similar boxes into their hull.

    Denœux's outer approximation by hierarchical clustering (2001): two focal elements A, B
    are replaced by their hull with mass m(A) + m(B), choosing pairs with the smallest
    increase of the mass-weighted size, Δ = (m_A + m_B)|A ∪ B| − m_A|A| − m_B|B|, where |·|
    is the sum of the box's widths, each divided by the run's mass-weighted mean width in
    that dimension. Every box lies in the box that receives its mass, so the result is an
    outer approximation. To stay vectorised, each round sorts the boxes by their centre
    along one dimension (the dimensions take turns) and merges, in parallel, the neighbour
    pairs whose Δ is a local minimum along that order, cheapest first, never going below
    ``max_focal``; rounds repeat until every run fits.

    Choices do not hang on the last bits of a float (another CPU rounds differently):
    centres and Δ within ``dstoolkit.evidence.boxes.TIE_RTOL`` of each other tie
    (relative to the run's largest |lo| + |hi|, and to the hull's mass·size: the largest
    term Δ is computed from), and ties go to a
    fixed order — the boxes' order so far, leftmost pair first. A pair is a local minimum
    when its Δ is not clearly above its left neighbour's and clearly below its right
    neighbour's. In 1-D the boxes are sorted in round 0 only, in n-D at every round.

    In one dimension sorting once is enough: a hull's centre lies between its pair's (it
    is lo + hi of one box, or lo_A + hi_B with lo_A ≤ lo_B and hi_B ≥ hi_A, which lies
    between lo_A + hi_A and lo_B + hi_B, rounding included), so the boxes stay in order up
    to ties. A run that fits leaves the rounds: later sorts would only reorder its boxes,
    and the closing merge of equal boxes (eq. 14) puts them in canonical order.

    Parameters
    ----------
    bm : Boxes
        Boxes (R, N, d) and masses (R, N); boxes of positive mass must be
        bounded.
    max_focal : int
        The cap, >= 2.

    Returns
    -------
    capped : Boxes
        At most ``max_focal`` focal elements per run.
    merged_mass : ndarray, shape (R,)
        The mass now carried by merged boxes.

    Raises
    ------
    EvidenceError
        For NaN or infinite masses, or unbounded boxes of positive mass.
    WorkLimitError
        When the rounds do not reach the cap.

    Notes
    -----
    ``dstoolkit.evidence.boxes.cluster_boxes_compiled`` gives the same numbers, compiled (extra
    ``speed``).

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.evidence.boxes import Boxes
    >>> capped, moved = cluster_boxes(Boxes(np.array([[[0.0], [1.0], [5.0]]]),
    ...                                     np.array([[[1.0], [2.0], [6.0]]]),
    ...                                     np.array([[0.3, 0.3, 0.4]])), 2)
    >>> capped.lo[..., 0], capped.hi[..., 0], moved
    (array([[0., 5.]]), array([[2., 6.]]), array([0.6]))
    """
    count = bounded_count(bm)
    runs, _, n = bm.lo.shape
    if int(count.max()) <= max_focal:
        return merge_equal_boxes(bm.lo, bm.hi, bm.mass), np.zeros(runs)
    unit = unit_widths(bm)[:, None, :]
    scale = reach(bm.lo, bm.hi, bm.mass)  # of ties between centres
    rows = _Rows(n)
    table, run = rows.table(bm, unit, scale)
    done = np.zeros((rows.count, runs, max_focal))  # each run's boxes once it fits
    active = np.ones(runs, dtype=bool)  # the runs still in the rounds
    for rnd in range(MAX_CLUSTER_ROUNDS + 1):
        fits = active & (count <= max_focal)
        if fits.any():
            start = np.cumsum(count * active) - count * active  # each run's first column
            leaving = fits[run]
            at = np.flatnonzero(leaving)
            place = run[at] * max_focal + at - start[run[at]]
            done.reshape(rows.count, -1)[:, place] = table[:, at]
            active &= ~fits
            if not active.any():
                break
            table, run = np.compress(~leaving, table, axis=1), run[~leaving]
        if rnd == MAX_CLUSTER_ROUNDS:
            raise too_many_rounds(max_focal, MAX_CLUSTER_ROUNDS, int(count[active].max()))
        if n > 1 and rnd > 0:  # by centre along dimension rnd % n, within each run
            order = rows.by_centre(table[rows.lo], table[rows.hi], rnd % n, run, scale)
            table = np.take(table, order, axis=1)
        pair = rows.pair_hulls(table)
        cost = pair[rows.ms] - table[rows.ms, :-1] - table[rows.ms, 1:]
        cost[run[1:] != run[:-1]] = np.inf  # no pair across two runs
        cost_scale = pair[rows.ms]  # Δ's largest term: its rounding error grows with it
        picked = _cheapest(
            _local_minima(cost, cost_scale),
            cost,
            cost_scale,
            run[:-1],
            np.where(active, count - max_focal, 0),
        )
        if not len(picked):
            raise no_pair()
        rows.merge_pairs(table, pair, picked)
        count = count - np.bincount(run[picked], minlength=runs)
        kept = np.ones(len(run), dtype=bool)
        kept[picked + 1] = False  # the second box of each pair merged
        table, run = np.compress(kept, table, axis=1), run[kept]
    lo, hi = np.moveaxis(done[rows.lo], 0, -1), np.moveaxis(done[rows.hi], 0, -1)
    mass = done[rows.mass]
    return merge_equal_boxes(lo, hi, mass), merged_mass(mass, done[rows.merged] > 0)


def bounded_count(bm: Boxes) -> np.ndarray:
    """Count the focal elements (boxes of positive mass) of each run.

    Refuses NaN or infinite masses, and boxes of positive mass with NaN or infinite bounds
    (clustering needs sizes).
    """
    live = bm.mass > 0
    if not (
        np.all(np.isfinite(bm.mass))
        and np.all(np.isfinite(bm.lo) | ~live[..., None])
        and np.all(np.isfinite(bm.hi) | ~live[..., None])
    ):
        raise unbounded_boxes()
    return live.sum(axis=1)


def unbounded_boxes() -> EvidenceError:
    """Return the error of a clustering given NaN or infinite masses, or unbounded boxes."""
    return EvidenceError(
        "cluster_boxes needs bounded boxes with finite masses; got NaN or infinite values "
        "(check the filter's inputs and noise bounds)"
    )


def unit_widths(bm: Boxes) -> np.ndarray:
    """Compute each run's mass-weighted mean width per dimension (R, n), 1 where it is 0.

    These are the units of the sizes |A| in Denœux's Δ.
    """
    unit = row_sum(bm.mass[..., None] * (bm.hi - bm.lo)) / row_sum(bm.mass)[:, None]
    return np.where(unit > 0, unit, 1.0)


def merged_mass(mass: np.ndarray, merged: np.ndarray) -> np.ndarray:
    """Sum the mass carried by merged boxes per run, smallest first.

    This canonical order does not depend on the order the rounds left the boxes in.
    """
    return row_sum(np.sort(np.where(merged, mass, 0.0), axis=1))


def too_many_rounds(max_focal: int, rounds: int, remain: int | None = None) -> WorkLimitError:
    """Return the error of a clustering that did not reach ``max_focal`` in ``rounds`` rounds."""
    left = "" if remain is None else f" ({remain} remain)"
    return WorkLimitError(
        f"clustering the focal elements did not reach max_focal = "
        f"{max_focal} in {rounds} rounds{left}; raise max_focal"
    )


def no_pair() -> WorkLimitError:
    """Return the error of a clustering round that finds no pair to merge."""
    return WorkLimitError(
        "clustering the focal elements found no pair to merge (their sizes "
        "are not finite numbers); check the model's f and g for NaN or "
        "infinite images"
    )

"""Choices between computed values that do not hang on their last bits.

Denœux's clustering (:func:`~dstoolkit.evidence.boxes.cluster_boxes`) chooses: which boxes
are neighbours (an order by centre) and which neighbour pairs merge (the smallest Δ). Many
of the values it compares are equal in exact arithmetic — the nested α-cuts of a
symmetric noise share their centre, and mirror-image pairs share their Δ — and differ
only by rounding, which differs between CPUs (another SIMD width, another ``exp``). An
exact comparison would then decide by the last bits, and one different merge changes the
whole posterior after it.

The rule: two values count as equal when they differ by at most :data:`TIE_RTOL` times
the larger of their scales (the magnitude of the terms they were computed from, which
bounds their rounding error), and equal values go to a fixed order — the position they
already have. The same rule is used by the numpy code and by the compiled kernels
(:func:`tie_order` is written in the numpy subset that numba compiles).
"""

from __future__ import annotations

import numpy as np

#: Relative tolerance within which two computed values count as equal, relative to the
#: larger scale (the magnitude of their terms). A few ulps of difference in the inputs, as
#: another CPU's rounding gives, move the clustering's values by about 1e-13 of that scale;
#: the differences that really decide a merge are far larger than 1e-9 of it.
TIE_RTOL = 1e-9


def snap_bounds(lo: np.ndarray, hi: np.ndarray, mass: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Snap the bounds of each run's boxes that tie to one value, outwards.

    Within a run, the lower bounds along one dimension that tie (:func:`tie_classes`,
    relative to the run's :func:`reach`) all become the smallest of them, the upper bounds
    the largest. Boxes equal in exact arithmetic but computed along different paths (their
    bounds a few ulps apart) then become equal bit for bit, so merging equal boxes (eq. 14)
    merges them on every CPU; every box only grows, so the mass function stays an outer
    approximation. Boxes of mass 0 are left as they are.

    Parameters
    ----------
    lo, hi : ndarray, shape (R, N, n)
        The boxes of each run.
    mass : ndarray, shape (R, N)
        Their masses.

    Returns
    -------
    lo, hi : ndarray, shape (R, N, n)
        New arrays, the bounds snapped.

    Examples
    --------
    >>> import numpy as np
    >>> lo, hi = snap_bounds(np.array([[[1.0], [1.0 + 1e-15]]]), np.array([[[2.0], [2.0]]]),
    ...                      np.array([[0.5, 0.5]]))
    >>> lo[0, :, 0].tolist()
    [1.0, 1.0]
    """
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    live = np.flatnonzero(mass > 0)
    run = live // mass.shape[1]
    scales = reach(lo, hi, mass)
    flat_lo, flat_hi = lo.reshape(-1, lo.shape[-1]), hi.reshape(-1, hi.shape[-1])
    for j in range(lo.shape[-1]):
        scale = scales[run, j]
        for side, extreme, start in ((flat_lo, np.minimum, np.inf), (flat_hi, np.maximum, -np.inf)):
            value = side[live, j]
            tie_class = tie_classes(value, scale, run)
            snapped = np.full(len(value) + 1, start)
            extreme.at(snapped, tie_class, value)
            side[live, j] = snapped[tie_class]
    return lo, hi


def reach(lo: np.ndarray, hi: np.ndarray, mass: np.ndarray) -> np.ndarray:
    """Return each run's largest |lo| + |hi| per dimension over its boxes of positive mass.

    The scale of ties between coordinates: rounding moves a bound by ulps of the largest
    magnitudes it was computed from, and a run's hulls never reach beyond its boxes, so
    this holds for every round of the clustering. Unbounded boxes are left out (they tie
    with nothing).

    Parameters
    ----------
    lo, hi : ndarray, shape (R, N, n)
        The boxes of each run.
    mass : ndarray, shape (R, N)
        Their masses.

    Returns
    -------
    ndarray, shape (R, n)
        The scale of each run and dimension (0 for a run without mass).
    """
    size = np.abs(lo) + np.abs(hi)
    size = np.where((mass > 0)[..., None] & np.isfinite(size), size, 0.0)
    return size.max(axis=1, initial=0.0)


def clearly_less(
    a: np.ndarray, b: np.ndarray, scale_a: np.ndarray, scale_b: np.ndarray
) -> np.ndarray:
    """Return where a < b by more than the tie tolerance (element-wise).

    ``not clearly_less(b, a, ...)`` is then "a is not clearly above b": a ≤ b up to a tie.
    """
    return b - a > TIE_RTOL * np.maximum(scale_a, scale_b)


def tie_classes(value: np.ndarray, scale: np.ndarray, group: np.ndarray) -> np.ndarray:
    """Give each value its tie class, the classes ascending within each group.

    Values are sorted exactly by (``group``, ``value``); each chain of neighbours in that
    order that lie within :data:`TIE_RTOL` of each other (relative to the larger of their
    ``scale``) is one tie class. The classes are numbered 1, 2, … in that order, so a
    stable sort by class (:func:`tie_order`) sorts the values with ties kept in their
    positions' order. A few ulps of change in the values change no class, unless two
    neighbours differ by almost exactly the tolerance. NaN and ±inf tie with nothing.
    Written in the numpy subset numba compiles (the compiled clustering calls it).

    Parameters
    ----------
    value : ndarray, shape (N,)
        The values.
    scale : ndarray, shape (N,)
        Nonnegative: the magnitude of the terms each value was computed from.
    group : ndarray of int, shape (N,)
        Groups kept apart, in ascending order (e.g. the run of each box).

    Returns
    -------
    ndarray of int, shape (N,)
        The class of each value.

    Examples
    --------
    >>> import numpy as np
    >>> tie_classes(np.array([2.0, 1.0 + 1e-15, 1.0]), np.ones(3), np.zeros(3, dtype=np.int64))
    array([2, 1, 1])
    """
    n = value.shape[0]
    order = np.argsort(value, kind="mergesort")
    order = order[np.argsort(group[order], kind="mergesort")]
    start = np.ones(n, dtype=np.bool_)
    if n > 1:
        v, s, g = value[order], scale[order], group[order]
        tied = v[1:] - v[:-1] <= TIE_RTOL * np.maximum(s[1:], s[:-1])
        start[1:] = (g[1:] != g[:-1]) | ~tied
    tie_class = np.empty(n, dtype=np.int64)
    tie_class[order] = np.cumsum(start)
    return tie_class


def tie_order(value: np.ndarray, scale: np.ndarray, group: np.ndarray) -> np.ndarray:
    """Return the order that sorts ``value`` within each group, ties kept in their order.

    The stable sort by :func:`tie_classes`: values that tie keep the order of their
    positions, so a few ulps of change in the values do not change the order.

    Parameters
    ----------
    value, scale, group
        As for :func:`tie_classes`.

    Returns
    -------
    ndarray of int, shape (N,)
        Positions in the sorted order.

    Examples
    --------
    >>> import numpy as np
    >>> order = tie_order(np.array([3.0, 2.0, 1.0 + 1e-15, 1.0]), np.ones(4),
    ...                   np.array([0, 0, 1, 1]))
    >>> order.tolist()  # run 0 sorted; in run 1 the tie keeps its order
    [1, 0, 2, 3]
    """
    return np.argsort(tie_classes(value, scale, group), kind="mergesort")

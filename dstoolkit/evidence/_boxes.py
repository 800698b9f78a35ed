"""Mass functions on boxes for a batch of runs, with their hull and pignistic expectation.

One layout serves every array path (the batch kernels, the paper's filter, Nassreddine's
filter) and :class:`~dstoolkit.evidence.IntervalEvidence` (one run): focal elements
``lo``/``hi`` of shape (R, N, d) and masses (R, N); a mass row of shape (1, N) broadcasts
over runs. Rows of mass 0 are placeholders or padding: they are not focal elements, and
every function here ignores them.

Sums over the focal elements are added in order (:func:`row_sum`), so the padding of a
run to a batch's width never changes its rounding: a run gives the same numbers alone as
in any batch.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Boxes(NamedTuple):
    """Focal elements ``lo``, ``hi`` (R, N, d) with masses ``mass`` (R, N).

    One row per run of a batch; entries of mass 0 are placeholders (padding).

    Parameters
    ----------
    lo, hi : ndarray, shape (R, N, d)
        The ends of the boxes (the variable's unit).
    mass : ndarray, shape (R, N)
        Their masses, each row summing to 1 (a row (1, N)
        broadcasts over the runs).

    See Also
    --------
    dstoolkit.evidence.IntervalEvidence.as_boxes : to the objects.

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.evidence.boxes import Boxes
    >>> b = Boxes(np.array([[[0.0], [1.0]]]), np.array([[[2.0], [3.0]]]),
    ...           np.array([[0.5, 0.5]]))
    >>> b.lo.shape, b.mass.shape
    ((1, 2, 1), (1, 2))
    """

    lo: np.ndarray
    hi: np.ndarray
    mass: np.ndarray


def row_sum(values: np.ndarray) -> np.ndarray:
    """Sum over axis 1 (the focal elements), added in order.

    numpy's pairwise summation groups terms by the array's length, so zero-mass padding
    would change the rounding; a sequential sum does not.
    """
    return np.cumsum(values, axis=1)[:, -1]


def hull(
    e: Boxes, out: tuple[np.ndarray, np.ndarray] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Return the smallest box holding every focal element of positive mass (Θ of eqs. A7–A8).

    Parameters
    ----------
    e : Boxes
        Boxes (R, N, d) and masses (R, N); mass-0 entries are ignored.
    out : tuple of ndarray, shape (R, d), optional
        Where to write the result.

    Returns
    -------
    lo, hi : ndarray, shape (R, d)
        The ends of the hull of each run.

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.evidence.boxes import Boxes
    >>> b = Boxes(np.array([[[0.0], [1.0]]]), np.array([[[2.0], [3.0]]]),
    ...           np.array([[0.5, 0.5]]))
    >>> hull(b)
    (array([[0.]]), array([[3.]]))
    """
    live = e.mass > 0
    lo, hi = (None, None) if out is None else out
    if live.all():
        return np.minimum.reduce(e.lo, axis=1, out=lo), np.maximum.reduce(e.hi, axis=1, out=hi)
    return (
        np.minimum.reduce(np.where(live[..., None], e.lo, np.inf), axis=1, out=lo),
        np.maximum.reduce(np.where(live[..., None], e.hi, -np.inf), axis=1, out=hi),
    )


def pignistic_expectation(e: Boxes) -> np.ndarray:
    """E = Σ_j m(A_j) (a_j⁻ + a_j⁺)/2 per run, the pignistic expectation (eq. 20).

    Parameters
    ----------
    e : Boxes
        Boxes (R, N, d) and masses (R, N); mass-0 entries are ignored.

    Returns
    -------
    ndarray, shape (R, d)
        E of each run (the variable's unit).

    See Also
    --------
    dstoolkit.evidence.IntervalEvidence.pignistic_expectation : for one object.

    References
    ----------
    The paper's eq. (20).

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.evidence.boxes import Boxes
    >>> b = Boxes(np.array([[[0.0], [1.0]]]), np.array([[[2.0], [3.0]]]),
    ...           np.array([[0.5, 0.5]]))
    >>> pignistic_expectation(b)
    array([[1.5]])
    """
    return row_sum(e.mass[..., None] * (0.5 * (e.lo + e.hi)))


__all__: list[str] = ["Boxes", "hull", "pignistic_expectation", "row_sum"]

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
    """Focal elements ``lo``, ``hi`` (R, N, d) with masses ``mass`` (R, N)."""

    lo: np.ndarray
    hi: np.ndarray
    mass: np.ndarray


def row_sum(values: np.ndarray) -> np.ndarray:
    """Sum over axis 1 (the focal elements), added in order.

    numpy's pairwise summation groups terms by the array's length, so zero-mass padding
    would change the rounding; a sequential sum does not.
    """
    return np.cumsum(values, axis=1)[:, -1]


def hull(e: Boxes, out: tuple[np.ndarray, np.ndarray] | None = None
         ) -> tuple[np.ndarray, np.ndarray]:
    """The smallest box holding every focal element of positive mass, (R, d) twice (Θ of
    eqs. A7–A8); written into ``out`` when given."""
    live = e.mass > 0
    lo, hi = (None, None) if out is None else out
    if live.all():
        return np.minimum.reduce(e.lo, axis=1, out=lo), np.maximum.reduce(e.hi, axis=1, out=hi)
    return (np.minimum.reduce(np.where(live[..., None], e.lo, np.inf), axis=1, out=lo),
            np.maximum.reduce(np.where(live[..., None], e.hi, -np.inf), axis=1, out=hi))


def pignistic_expectation(e: Boxes) -> np.ndarray:
    """E = Σ_j m(A_j) (a_j⁻ + a_j⁺)/2 per run (eq. 20), shape (R, d); masses sum to 1."""
    return row_sum(e.mass[..., None] * (0.5 * (e.lo + e.hi)))


__all__: list[str] = ["Boxes", "hull", "pignistic_expectation", "row_sum"]

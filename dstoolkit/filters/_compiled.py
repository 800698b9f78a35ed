"""Optional compiled kernels (extra ``speed``: numba) of the filters' own steps.

- The paper's filter, Step 6 (:func:`fuse_dependent`): the numpy path
  (:class:`~dstoolkit.evidence.boxes.DependenceKernel`,
  :class:`~dstoolkit.evidence.boxes.ProductKernel` and the hulls) makes some 27 numpy calls
  per step on arrays of 16–2,600 elements; one run of the filter is bound by their
  overhead, a batch by the passes over the 65 × 17 products and the 80 × 16 equality
  matrix, whose short inner loops numpy broadcasts slowly
  (``benchmarks/filter_profile.py``). :func:`fuse_dependent` does the same arithmetic in
  plain loops, once per run: the degree of dependence and the coefficients of E1, E2
  (Def. 5, eqs. A1, A3–A6), their discounting onto their hulls Θ1, Θ2 (eqs. A7–A8),
  Dempster's rule (eq. 1), the pignistic expectation (eq. 20) and the hull of the result.
  Its sums are added in another order than numpy's, so its results agree with the numpy
  path to rounding (tested), and they do not depend on the number of runs in a block.
- Nassreddine's filter, the correction (:func:`contracted_posterior_compiled`): the
  conflict and renormalisation of the contracted boxes, then the compiled merge of
  :mod:`dstoolkit.evidence.boxes`; bit for bit the numpy numbers.
- The particle filter: :func:`resample_compiled` is
  :func:`~dstoolkit.filters.systematic_resample`, one pass per run (the positions and the
  cumulative weights are both in order, so each position's particle follows the last
  one's; ``np.searchsorted`` searches each position afresh), with the quantised cumulative
  weights and positions computed as the search reaches them.

Nothing requires them: a filter uses them only with ``kernel="numba"`` (or ``"auto"``
where it gives the same numbers).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import numpy as np

from dstoolkit.errors import require_extra
from dstoolkit.evidence import CONFLICT_TOLERANCE, MASS_RULES, Boxes
from dstoolkit.evidence.boxes import TINY, merge_equal_boxes_compiled

#: Codes of the mass rules of eq. A3 in the compiled kernel.
RULE_CODES: dict[str, int] = {rule: code for code, rule in enumerate(MASS_RULES)}


def _fuse(
    cols: np.ndarray,
    back_mass: np.ndarray,
    rho: np.ndarray,
    n1: int,
    rule: int,
    est: np.ndarray,
    diag: np.ndarray,
    ok: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
) -> None:  # pragma: no cover - compiled by numba
    """See :func:`fuse_dependent`; plain loops for numba."""
    runs, _, d, _ = cols.shape
    np_ = rho.shape[0]
    e2 = n1
    on_b = np.empty(np_)
    merged = np.empty(np_)
    theta1 = np.empty((d, 2))
    theta2 = np.empty((d, 2))
    for r in range(runs):
        # m1(D) and m2(D) seen from each focal element of E2 (eq. A3)
        for j in range(np_):
            s1 = 0.0
            for i in range(n1):
                same = True
                for c in range(d):
                    if (
                        cols[r, 0, c, 1 + i] != cols[r, 0, c, 1 + e2 + j]
                        or cols[r, 1, c, 1 + i] != cols[r, 1, c, 1 + e2 + j]
                    ):
                        same = False
                        break
                if same:
                    s1 += back_mass[r, i]
            s2 = 0.0
            for k in range(np_):
                same = True
                for c in range(d):
                    if (
                        cols[r, 0, c, 1 + e2 + k] != cols[r, 0, c, 1 + e2 + j]
                        or cols[r, 1, c, 1 + e2 + k] != cols[r, 1, c, 1 + e2 + j]
                    ):
                        same = False
                        break
                if same:
                    s2 += rho[k]
            on_b[j] = s1
            merged[j] = s2
        # energies (eq. A1): smallest live width u, Σ m/(w + ε) times (u + ε)
        u1 = np.inf
        u2 = np.inf
        sum1 = 0.0
        sum2 = 0.0
        for i in range(n1):
            w = 1.0
            for c in range(d):
                w *= cols[r, 1, c, 1 + i] - cols[r, 0, c, 1 + i]
            if back_mass[r, i] > 0.0:
                u1 = min(u1, w)
            sum1 += back_mass[r, i] / (w + TINY)
        joint = 0.0
        for j in range(np_):
            w = 1.0
            for c in range(d):
                w *= cols[r, 1, c, 1 + e2 + j] - cols[r, 0, c, 1 + e2 + j]
            if rho[j] > 0.0:
                u2 = min(u2, w)
            sum2 += rho[j] / (w + TINY)
            if rule == 0:
                m_d = min(on_b[j], merged[j])
            elif rule == 1:
                m_d = on_b[j]
            else:
                m_d = merged[j] if on_b[j] > 0.0 else 0.0
            joint += m_d * rho[j] / merged[j] / (w + TINY)
        u1 += TINY
        u2 += TINY
        en1 = u1 * sum1
        en2 = u2 * sum2
        joint *= min(u1, u2)
        degree = 2.0 * joint / (en1 + en2 + TINY)
        r12 = 1.0 - 0.5 * degree * en2 / (en1 + TINY)
        r21 = 1.0 - 0.5 * degree * en1 / (en2 + TINY)
        # Θ1, Θ2: hulls of the live focal elements (eqs. A7–A8)
        for c in range(d):
            theta1[c, 0] = np.inf
            theta1[c, 1] = -np.inf
            theta2[c, 0] = np.inf
            theta2[c, 1] = -np.inf
        for i in range(n1):
            if back_mass[r, i] > 0.0:
                for c in range(d):
                    theta1[c, 0] = min(theta1[c, 0], cols[r, 0, c, 1 + i])
                    theta1[c, 1] = max(theta1[c, 1], cols[r, 1, c, 1 + i])
        for j in range(np_):
            if rho[j] > 0.0:
                for c in range(d):
                    theta2[c, 0] = min(theta2[c, 0], cols[r, 0, c, 1 + e2 + j])
                    theta2[c, 1] = max(theta2[c, 1], cols[r, 1, c, 1 + e2 + j])
        # Dempster's rule of the discounted evidence, its expectation and hull (eqs. 1, 20)
        kept = 0.0
        for c in range(d):
            est[r, c] = 0.0
            lower[r, c] = np.inf
            upper[r, c] = -np.inf
        for i in range(n1 + 1):
            m_a = back_mass[r, i] * r12 if i < n1 else 1.0 - r12
            for j in range(np_ + 1):
                m_b = rho[j] * r21 if j < np_ else 1.0 - r21
                nonempty = True
                for c in range(d):
                    a_lo = cols[r, 0, c, 1 + i] if i < n1 else theta1[c, 0]
                    a_hi = cols[r, 1, c, 1 + i] if i < n1 else theta1[c, 1]
                    b_lo = cols[r, 0, c, 1 + e2 + j] if j < np_ else theta2[c, 0]
                    b_hi = cols[r, 1, c, 1 + e2 + j] if j < np_ else theta2[c, 1]
                    if max(a_lo, b_lo) > min(a_hi, b_hi):
                        nonempty = False
                        break
                if not nonempty:
                    continue
                m = m_a * m_b
                kept += m
                for c in range(d):
                    a_lo = cols[r, 0, c, 1 + i] if i < n1 else theta1[c, 0]
                    a_hi = cols[r, 1, c, 1 + i] if i < n1 else theta1[c, 1]
                    b_lo = cols[r, 0, c, 1 + e2 + j] if j < np_ else theta2[c, 0]
                    b_hi = cols[r, 1, c, 1 + e2 + j] if j < np_ else theta2[c, 1]
                    lo, hi = max(a_lo, b_lo), min(a_hi, b_hi)
                    est[r, c] += m * (lo + hi)
                    if m > 0.0:
                        lower[r, c] = min(lower[r, c], lo)
                        upper[r, c] = max(upper[r, c], hi)
        ok[r] = kept > CONFLICT_TOLERANCE
        scale = 0.5 / kept if ok[r] else 0.5
        for c in range(d):
            est[r, c] *= scale
        diag[r, 0] = kept
        diag[r, 1] = en1
        diag[r, 2] = en2
        diag[r, 3] = joint
        diag[r, 4] = degree
        diag[r, 5] = r12
        diag[r, 6] = r21


@functools.cache
def _compiled() -> Callable[..., None]:
    require_extra("numba", "speed", "the compiled kernel of the paper's filter")
    import numba

    kernel: Callable[..., None] = numba.njit(cache=True, nogil=True)(_fuse)
    return kernel


def fuse_dependent(
    cols: np.ndarray,
    back_mass: np.ndarray,
    rho: np.ndarray,
    n1: int,
    mass_rule: str,
    est: np.ndarray,
    diag: np.ndarray,
    bounds: Any,
) -> np.ndarray:
    """Step 6 of the paper's filter for every run, compiled (extra ``speed``).

    ``cols`` (R, ≥ 2, d, N) holds the columns of the array path (lo, hi, ... on axis 1):
    one free column, E1 (n1 columns, masses ``back_mass`` (R, n1), 0 for placeholders),
    then E2 (masses ``rho`` (N_2,), all positive); writes the expectation into ``est``
    (R, d), (1 − K, En'(E1), En'(E2), En'(E1, E2), D, R12, R21) into ``diag`` (R, 7) and the
    hull into ``bounds`` (R, 2, d) (lower, upper); returns the mask of runs with K < 1.
    """
    runs = cols.shape[0]
    ok = np.empty(runs, dtype=bool)
    _compiled()(
        cols,
        np.ascontiguousarray(back_mass),
        np.ascontiguousarray(rho),
        n1,
        RULE_CODES[mass_rule],
        est,
        diag,
        ok,
        bounds[:, 0],
        bounds[:, 1],
    )
    return ok


def _contract(
    lo: np.ndarray,
    hi: np.ndarray,
    mass: np.ndarray,
    tolerance: float,
    kept_mass: np.ndarray,
    conflict: np.ndarray,
    dead: np.ndarray,
) -> None:  # pragma: no cover - numba
    """Do what ``contracted_posterior`` does before its merge.

    K (sequential sums, as ``row_sum``), the runs in total conflict, the masses renormalised
    by the mass kept.
    """
    runs, rows, n = lo.shape
    for r in range(runs):
        k_sum, m_sum = 0.0, 0.0
        for i in range(rows):
            empty = False
            for j in range(n):
                if lo[r, i, j] > hi[r, i, j]:
                    empty = True
                    break
            kept_mass[r, i] = 0.0 if empty else mass[r, i]
            lost = mass[r, i] if empty else 0.0
            k_sum = lost if i == 0 else k_sum + lost
            m_sum = kept_mass[r, i] if i == 0 else m_sum + kept_mass[r, i]
        conflict[r] = k_sum
        dead[r] = m_sum <= tolerance
        for i in range(rows):
            kept_mass[r, i] = 0.0 if dead[r] else kept_mass[r, i] / m_sum


@functools.cache
def _compiled_contract() -> Callable[..., None]:
    require_extra("numba", "speed", "the compiled kernels of Nassreddine's filter")
    import numba

    kernel: Callable[..., None] = numba.njit(cache=True, nogil=True)(_contract)
    return kernel


def contracted_posterior_compiled(
    lo: np.ndarray, hi: np.ndarray, mass: np.ndarray
) -> tuple[Boxes, np.ndarray, np.ndarray]:
    """Run :func:`~dstoolkit.filters._nassreddine.contracted_posterior`, compiled.

    The same numbers.
    """
    contract = _compiled_contract()
    lo, hi = np.ascontiguousarray(lo, dtype=float), np.ascontiguousarray(hi, dtype=float)
    mass = np.ascontiguousarray(mass, dtype=float)
    runs = mass.shape[0]
    kept, conflict, dead = np.empty_like(mass), np.empty(runs), np.empty(runs, dtype=bool)
    contract(lo, hi, mass, CONFLICT_TOLERANCE, kept, conflict, dead)
    return merge_equal_boxes_compiled(lo, hi, kept), conflict, dead


def _summary(
    lo: np.ndarray,
    hi: np.ndarray,
    mass: np.ndarray,
    est: np.ndarray,
    low: np.ndarray,
    high: np.ndarray,
    focal: np.ndarray,
) -> None:  # pragma: no cover - numba
    """Do what Nassreddine's filter computes from a posterior before its cap.

    Per run: the focal elements (boxes of positive mass), the pignistic expectation
    (eq. 20: m·(0.5·(lo + hi)) added row after row, as ``row_sum``) and the hull of the
    boxes with mass (NaN spreads, as in ``np.minimum.reduce``; ±inf for a run without mass).
    """
    runs, rows, n = lo.shape
    for r in range(runs):
        count = 0
        for i in range(rows):
            if mass[r, i] > 0:
                count += 1
        focal[r] = count
        for j in range(n):
            total = mass[r, 0] * (0.5 * (lo[r, 0, j] + hi[r, 0, j]))
            for i in range(1, rows):
                total += mass[r, i] * (0.5 * (lo[r, i, j] + hi[r, i, j]))
            est[r, j] = total
            a, b = np.inf, -np.inf
            for i in range(rows):
                if mass[r, i] > 0:
                    x, y = lo[r, i, j], hi[r, i, j]
                    if np.isnan(x) or x < a:
                        a = x
                    if np.isnan(y) or y > b:
                        b = y
            low[r, j], high[r, j] = a, b


@functools.cache
def _compiled_summary() -> Callable[..., None]:
    require_extra("numba", "speed", "the compiled kernels of Nassreddine's filter")
    import numba

    kernel: Callable[..., None] = numba.njit(cache=True, nogil=True)(_summary)
    return kernel


def posterior_summary_compiled(
    posterior: Boxes,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Return the focal elements (R,), pignistic expectation and hull (R, n) of a posterior.

    The numbers of ``(posterior.mass > 0).sum(axis=1)``,
    :func:`~dstoolkit.evidence.pignistic_expectation` and :func:`~dstoolkit.evidence.hull`,
    compiled.
    """
    lo = np.ascontiguousarray(posterior.lo, dtype=float)
    hi = np.ascontiguousarray(posterior.hi, dtype=float)
    mass = np.ascontiguousarray(posterior.mass, dtype=float)
    runs, _, n = lo.shape
    est, low, high = np.empty((runs, n)), np.empty((runs, n)), np.empty((runs, n))
    focal = np.empty(runs, dtype=np.int64)
    _compiled_summary()(lo, hi, mass, est, low, high, focal)
    return focal, est, low, high


def _search(
    weights: np.ndarray, offsets: np.ndarray, quantum: float, idx: np.ndarray
) -> None:  # pragma: no cover - numba
    """Systematic resampling's indices, as ``systematic_resample``'s numpy path, run by run.

    The same quantised numbers: cumulative weights added in order (as ``np.cumsum``),
    floor(c·quantum), the last set to quantum; positions floor((offset + i)/N·quantum).
    ``idx[r, i]`` is the number of cumulative weights ≤ position i (``np.searchsorted``,
    side right), at most N − 1. Positions and cumulative weights both ascend, so each
    position's search starts where the last one stopped, and each cumulative weight is
    computed when the search reaches it.
    """
    runs, n = weights.shape
    for r in range(runs):
        total = weights[r, 0]
        cum = quantum if n == 1 else np.floor(total * quantum)
        j = 0
        for i in range(n):
            pos = np.floor((offsets[r] + i) / n * quantum)
            while j < n and cum <= pos:
                j += 1
                if j < n:
                    total += weights[r, j]
                    cum = quantum if j == n - 1 else np.floor(total * quantum)
            idx[r, i] = min(j, n - 1)


@functools.cache
def _compiled_search() -> Callable[..., None]:
    require_extra("numba", "speed", "the compiled resampling of the particle filter")
    import numba

    kernel: Callable[..., None] = numba.njit(cache=True, nogil=True)(_search)
    return kernel


def resample_compiled(weights: np.ndarray, offsets: np.ndarray, quantum: float) -> np.ndarray:
    """Return the indices of :func:`~dstoolkit.filters.systematic_resample`, compiled.

    The same indices (runs, N) from the weights (runs, N) and offsets (runs,), in one pass
    per run.
    """
    weights = np.ascontiguousarray(weights, dtype=float)
    idx = np.empty(weights.shape, dtype=np.intp)
    _compiled_search()(weights, np.ascontiguousarray(offsets, dtype=float), quantum, idx)
    return idx

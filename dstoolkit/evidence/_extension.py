"""Random relations and the extension principle (paper §2.3, eqs. 11–20, Props. 1–2).

Independent marginal random sets on intervals form a random relation whose focal elements
are boxes with product masses (eq. 16). A function f maps each box A to its image f(A)
(eq. 13); equal images merge, their masses adding up (eq. 14). The image of a box is found

- by the **vertex method** (Prop. 1, eq. 17): min/max of f over the 2^n vertices; right
  when f is continuous with no extremum inside the box, otherwise too narrow (a check
  warns when an interior sample falls outside the vertex range);
- by the **monotone shortcut** (Prop. 2, eqs. 18–19): 2 evaluations per box when f is
  monotone in each argument with declared signs (a midpoint check raises
  :class:`~dstoolkit.errors.NotMonotoneError` when the declaration is visibly wrong);
- by **subdivision** for any continuous f: a grid of (k+1)^n points per box, then a zoom
  on the best local extrema of the grid until the spacing is below ``tol`` times the box
  width (an inner approximation, exact for monotone f; see :func:`image_subdivision`);
- by the **mean-value form** for a differentiable f with a bound on its slopes: an *outer*
  enclosure, never narrower than the true image (see :func:`image_mean_value`).

The first three return values that f takes (inner approximations); the mean-value form is
the one guaranteed to contain the image.

Array conventions: boxes are ``lo``/``hi`` arrays of shape (..., n); f is called with
points of shape (..., *extra, n) — the extra axes (vertices, samples) come just before the
last one, so leading axes such as runs stay first (see :func:`dstoolkit.filters.with_input`)
— and returns (..., *extra, m), or (..., *extra) for a scalar function.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from typing import Any, Literal

import numpy as np

from dstoolkit.errors import EvidenceError, NotMonotoneError, VertexMethodWarning
from dstoolkit.utils.budget import check_memory
from dstoolkit.utils.checks import whole_number

from ._intervals import IntervalEvidence

#: How the image of a box is found (see :func:`image`).
ImageMethod = Literal["auto", "vertex", "monotone", "subdivision", "mean_value"]
#: The values of :data:`ImageMethod`.
IMAGE_METHODS: tuple[str, ...] = ("auto", "vertex", "monotone", "subdivision", "mean_value")
#: A bound on f's slopes over boxes: ``slope(lo, hi) -> (d_lo, d_hi)``, each of shape
#: (..., n) for a scalar f or (..., m, n), with every ∂f_i/∂x_j on the box in [d_lo, d_hi].
SlopeBound = Callable[[np.ndarray, np.ndarray], tuple[Any, Any]]

#: Relative slack of the monotone and vertex checks (rounding, not modelling error).
CHECK_RTOL = 1e-10
#: The vertex method enumerates 2^n vertices; refuse beyond this dimension.
MAX_VERTEX_DIM = 16


# -- random relations (eqs. 11–12, 16) ---------------------------------------------------
def product_row_bytes(dims: int, marginals: int) -> float:
    """Memory per box of a Cartesian product of ``marginals`` marginals in ``dims`` dimensions.

    The index grids (8 bytes a marginal), the ends and their copies and sort keys when equal
    boxes merge (up to 64 bytes a dimension) and the masses: an upper bound, with a margin of
    about a fifth, of the peak that tracemalloc measures (``benchmarks/memory_peaks.py``), so
    that the memory budget bounds the real peak.

    Parameters
    ----------
    dims : int
        Σ d_i, the dimension of the product's boxes.
    marginals : int
        How many marginals.

    Returns
    -------
    float
        Bytes per box.

    Examples
    --------
    >>> from dstoolkit.evidence._extension import product_row_bytes
    >>> product_row_bytes(3, 3)
    348.0
    """
    return 72.0 * dims + 12.0 * marginals + 96.0


def cartesian_product(
    marginals: Sequence[IntervalEvidence], *, merge: bool = True
) -> IntervalEvidence:
    """Form the random relation of independent marginals (eq. 16).

    Boxes C_1 × … × C_n with masses m_1(C_1)···m_n(C_n) (decomposable Cartesian product).

    Rows follow ``itertools.product`` order (the first marginal varies slowest); the box
    dimension is the sum of the marginals' dimensions.

    Parameters
    ----------
    marginals : sequence of IntervalEvidence
        The independent marginals, d_i dimensions each.
    merge : bool
        Merge equal boxes (eq. 14).

    Returns
    -------
    IntervalEvidence
        Π_i n_i boxes in Σ_i d_i dimensions.

    Raises
    ------
    EvidenceError
        For an empty sequence or one holding something else than interval evidence.
    MemoryBudgetError
        When the product would exceed the memory budget.

    See Also
    --------
    projection : back to a marginal.

    References
    ----------
    The paper's eq. (16).

    Examples
    --------
    >>> from dstoolkit.evidence import appendix_pair
    >>> relation = cartesian_product(appendix_pair())
    >>> relation.dim, len(relation)
    (2, 9)
    """
    marginals = list(marginals)
    if not marginals or not all(isinstance(e, IntervalEvidence) for e in marginals):
        raise EvidenceError(
            "cartesian_product needs a non-empty sequence of IntervalEvidence marginals"
        )
    rows = math.prod(len(e) for e in marginals)
    dims = sum(e.dim for e in marginals)
    check_memory(
        rows * product_row_bytes(dims, len(marginals)),
        f"the Cartesian product of {len(marginals)} marginals ({rows} boxes in {dims} dimensions)",
        "use fewer focal elements per marginal (fewer α-cuts, a smaller p) or fewer marginals",
    )
    grids = np.meshgrid(*[np.arange(len(e)) for e in marginals], indexing="ij")
    idx = [g.reshape(-1) for g in grids]
    lo = np.concatenate([e.boxes_lo[i] for e, i in zip(marginals, idx, strict=True)], axis=1)
    hi = np.concatenate([e.boxes_hi[i] for e, i in zip(marginals, idx, strict=True)], axis=1)
    mass = np.prod([e.mass[i] for e, i in zip(marginals, idx, strict=True)], axis=0)
    return IntervalEvidence(lo, hi, mass, merge=merge)


def projection(evidence: IntervalEvidence, axes: Sequence[int]) -> IntervalEvidence:
    """Marginal random set on the chosen axes (eqs. 11–12): project each box, merge.

    Parameters
    ----------
    evidence : IntervalEvidence
        Boxes in d dimensions.
    axes : sequence of int
        The dimensions to keep, in order.

    Returns
    -------
    IntervalEvidence
        Boxes in ``len(axes)`` dimensions, equal ones merged (eq. 14).

    See Also
    --------
    cartesian_product : the relation of independent marginals.

    References
    ----------
    The paper's eqs. (11)–(12).

    Examples
    --------
    >>> from dstoolkit.evidence import appendix_pair
    >>> e1, e2 = appendix_pair()
    >>> projection(cartesian_product([e1, e2]), [1]).mass.round(4).tolist()
    [0.1, 0.3, 0.6]
    """
    if not isinstance(evidence, IntervalEvidence):
        raise EvidenceError(
            f"projection needs an IntervalEvidence, got {type(evidence).__name__}; build one "
            "with IntervalEvidence(lo, hi, mass)"
        )
    d = evidence.dim
    if isinstance(axes, np.ndarray) and axes.ndim == 1:
        axes = axes.tolist()
    shown = list(axes) if isinstance(axes, list | tuple) else axes
    wrong = EvidenceError(
        f"axes must name distinct dimensions among 0..{d - 1} of this {d}-dimensional "
        f"evidence, at least one, got {shown!r}"
    )
    if not isinstance(axes, Sequence) or isinstance(axes, str):
        raise wrong
    try:
        axes = [whole_number(a, "an axis", high=d - 1, error=EvidenceError) for a in axes]
    except EvidenceError:
        raise wrong from None
    if not axes or len(set(axes)) != len(axes):
        raise wrong
    return IntervalEvidence(
        evidence.boxes_lo[:, axes], evidence.boxes_hi[:, axes], evidence.mass, merge=True
    )


# -- helpers -------------------------------------------------------------------------------
def _call(f: Callable[[np.ndarray], Any], points: np.ndarray) -> np.ndarray:
    """f(points) for points (..., n) as floats (..., m); a scalar f gets m = 1."""
    out = np.asarray(f(points), dtype=float)
    if out.shape == points.shape[:-1]:
        return out[..., None]
    if out.shape[:-1] != points.shape[:-1]:
        raise EvidenceError(
            f"f returned shape {out.shape} for points of shape {points.shape}; it must map "
            "(..., n) to (..., m) (or (...,) for a scalar function), vectorised"
        )
    return out


def _evaluate(f: Callable[[np.ndarray], Any], points: np.ndarray, extra: int) -> np.ndarray:
    """Evaluate f at points laid out (*extra, ..., n), returned as (*extra, ..., m).

    The extra axes move just before the last one for the call (see the module notes).
    """
    src, dst = tuple(range(extra)), tuple(range(-extra - 1, -1))
    return np.moveaxis(_call(f, np.moveaxis(points, src, dst)), dst, src)


def _checked(f: Callable[[np.ndarray], Any]) -> Callable[[np.ndarray], Any]:
    """Wrap ``f``, refusing what it returns that is no image.

    That is complex values (their imaginary part would be dropped) and NaN or ±inf at
    points whose coordinates are finite.
    """

    def checked(points: np.ndarray) -> Any:
        raw = f(points)
        try:
            values = np.asarray(raw)
        except (TypeError, ValueError):
            return raw  # _call says what is wrong with the shape
        if values.dtype.kind == "c":
            raise EvidenceError(
                "f returned complex values; the extension principle needs a real function "
                "(take the real part or the modulus inside f, as the model means)"
            )
        if values.dtype.kind not in "biuf":
            return raw
        finite_in = np.all(np.isfinite(points), axis=-1)
        if values.shape == finite_in.shape:
            bad = ~np.isfinite(values)
        elif values.shape[:-1] == finite_in.shape:
            bad = ~np.all(np.isfinite(values), axis=-1)
        else:
            return raw
        bad &= finite_in
        if bad.any():
            where = np.argwhere(bad)[0]
            point = points[tuple(where)]
            raise EvidenceError(
                f"f returned NaN or an infinite value at the point {point.tolist()}: the image "
                "of a box would not be a box; check f's domain (or the boxes given)"
            )
        return raw

    return checked


def _outside(values: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Test values < lo or values > hi beyond rounding (CHECK_RTOL); NaN counts as inside."""
    with np.errstate(invalid="ignore"):
        slack = CHECK_RTOL * (np.abs(lo) + np.abs(hi))
        return np.minimum(values - lo, hi - values) < -slack


def parse_signs(monotone: Any, n: int) -> np.ndarray | None:
    """Monotonicity signs as an int array of shape (n,) or (m, n); None when unknown.

    Entries are +1 (increasing), −1 (decreasing) or 0 (neither/unknown).
    """
    if monotone is None:
        return None
    s = np.asarray(monotone)
    if s.ndim not in (1, 2) or s.shape[-1] != n:
        raise EvidenceError(
            f"monotone must give one sign per argument (shape ({n},) or (m, {n})), "
            f"got shape {s.shape}"
        )
    if not set(s.ravel().tolist()) <= {-1, 0, 1}:
        raise EvidenceError(f"monotone signs must be +1, −1 or 0, got {s.tolist()}")
    return s.astype(int)


def state_signs(monotone: Any, n: int) -> np.ndarray | None:
    """Read the signs of f(x, u) in x from a model's ``f_monotone``.

    ``f_monotone`` lists the n state arguments then the n noise arguments of f(x, u) + v
    (length 2n) or the state only (n).
    """
    if monotone is None:
        return None
    s = np.asarray(monotone)
    return parse_signs(s[..., :n] if s.ndim and s.shape[-1] == 2 * n else s, n)


def vertices(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Return the 2^n vertices of each box (eq. 17).

    Parameters
    ----------
    lo, hi : ndarray, shape (..., n)
        The boxes' ends.

    Returns
    -------
    ndarray, shape (..., 2^n, n)
        The vertices of each box.

    Raises
    ------
    EvidenceError
        For more dimensions than the vertex method allows.

    Examples
    --------
    >>> import numpy as np
    >>> vertices(np.array([0.0, 1.0]), np.array([1.0, 2.0])).tolist()
    [[0.0, 1.0], [1.0, 1.0], [0.0, 2.0], [1.0, 2.0]]
    """
    n = lo.shape[-1]
    if n > MAX_VERTEX_DIM:
        raise EvidenceError(
            f"the vertex method needs 2^{n} evaluations per box; use method='monotone' "
            f"or reduce the dimension (at most {MAX_VERTEX_DIM})"
        )
    bits = ((np.arange(2**n)[:, None] >> np.arange(n)) & 1).astype(bool)
    return np.where(bits, hi[..., None, :], lo[..., None, :])


def _interior_samples(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Return the centre and centre ± w/4 along each axis: shape (..., 2n + 1, n)."""
    n = lo.shape[-1]
    steps = np.concatenate([np.zeros((1, n)), np.eye(n), -np.eye(n)])
    return 0.5 * (lo + hi)[..., None, :] + steps * (0.25 * (hi - lo))[..., None, :]


# -- the three image kernels (arrays) -------------------------------------------------------
def image_vertex(
    lo: np.ndarray, hi: np.ndarray, f: Callable[[np.ndarray], Any], *, check: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """Vertex method (Prop. 1, eq. 17): per output, min and max of f over the vertices.

    With ``check``, f is also evaluated at 2n + 1 interior points; if one falls outside
    the vertex range, f has an extremum inside the box, the result is too narrow, and a
    :class:`~dstoolkit.errors.VertexMethodWarning` says so.
    """
    values = _call(f, vertices(lo, hi))  # (..., 2^n, m)
    out_lo, out_hi = values.min(axis=-2), values.max(axis=-2)
    if check:
        inner = _call(f, _interior_samples(lo, hi))
        bad = _outside(inner, out_lo[..., None, :], out_hi[..., None, :]).any(axis=(-2, -1))
        if bad.any():
            box = np.argwhere(bad)
            first = tuple(int(i) for i in box[0])
            warnings.warn(
                f"vertex method (Prop. 1) is wrong on {len(box)} of {max(bad.size, 1)} "
                f"boxes: f has an extremum inside, e.g. on box {first} = "
                f"[{lo[first].tolist()}, {hi[first].tolist()}] an interior value lies outside "
                f"the vertex range [{out_lo[first].tolist()}, {out_hi[first].tolist()}]; the "
                "image is too narrow. Use method='subdivision' (or declare monotonicity "
                "where it holds)",
                VertexMethodWarning,
                stacklevel=3,
            )
    return out_lo, out_hi


def image_monotone(
    lo: np.ndarray,
    hi: np.ndarray,
    f: Callable[[np.ndarray], Any],
    signs: np.ndarray,
    *,
    check: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """Monotone shortcut (Prop. 2, eqs. 18–19): f(A) = [f(v_min), f(v_max)] per output.

    ``signs`` (n,) or (m, n): +1 increasing, −1 decreasing in each argument. With
    ``check`` the centre of each box is evaluated too, in the same call; a centre value
    outside [f(v_min), f(v_max)], or f(v_min) > f(v_max), raises NotMonotoneError.
    """
    rows = signs.reshape(-1, signs.shape[-1])  # (k, n), k = 1 or m
    flat = rows.ravel().tolist()  # tiny: plain Python is faster than numpy here
    if 0 in flat:
        raise EvidenceError(
            f"the monotone shortcut needs a sign (+1/−1) for every argument, got "
            f"{signs.tolist()}; use method='vertex' or 'subdivision' for the others"
        )
    k = rows.shape[0]
    lo_, hi_ = lo[..., None, :], hi[..., None, :]
    mid = [0.5 * (lo_ + hi_)] if check else []
    if k == 1 and min(flat) > 0:  # increasing in every argument: v_min = lo, v_max = hi
        ends = [lo_, hi_]
    else:
        inc = rows > 0
        ends = [np.where(inc, lo_, hi_), np.where(inc, hi_, lo_)]
    values = _call(f, np.concatenate([*ends, *mid], axis=-2))
    if k == 1:
        out_lo, out_hi = values[..., 0, :], values[..., 1, :]
    elif values.shape[-1] != k:
        raise EvidenceError(
            f"{k} rows of monotonicity signs for a function with {values.shape[-1]} "
            "outputs; give one row per output or a single row"
        )
    else:
        out_lo = np.diagonal(values[..., :k, :], axis1=-2, axis2=-1)
        out_hi = np.diagonal(values[..., k : 2 * k, :], axis1=-2, axis2=-1)
    if check:
        centre = values[..., 2 * k, :]
        with np.errstate(invalid="ignore"):  # slack: rounding at the scale of f(centre)
            slack = CHECK_RTOL * np.abs(centre)
            bad = (centre < out_lo - slack) | (centre > out_hi + slack)
        if bad.any():
            where = tuple(int(i) for i in np.argwhere(bad)[0])
            box = where[:-1]
            raise NotMonotoneError(
                f"f was declared monotone with signs {signs.tolist()} (Prop. 2) but is not "
                f"on box {box} = [{lo[box].tolist()}, {hi[box].tolist()}] (output "
                f"{where[-1]}): f(v_min) = {out_lo[where]:.6g}, f(v_max) = "
                f"{out_hi[where]:.6g}, f(centre) = {centre[where]:.6g} is not between them "
                f"({int(bad.sum())} such case(s)); fix the signs, or use method='vertex' "
                "(no extremum inside) or 'subdivision' (any continuous f)"
            )
    return out_lo, out_hi


def _unit_grid(k: int, n: int) -> np.ndarray:
    t = np.linspace(0.0, 1.0, k + 1)
    return np.stack(np.meshgrid(*([t] * n), indexing="ij"), axis=-1).reshape(-1, n)


def _candidates(values: np.ndarray, k: int, n: int, c: int) -> np.ndarray:
    """Grid indices of the c lowest distinct values among the grid's local minima.

    ``values`` has shape (G, ..., m) with G = (k+1)^n grid points. A point is a local
    minimum when no axis neighbour is lower; equal values (plateaus, twins) count once, so
    the candidates lie in distinct basins. Returns shape (c, ..., m); with fewer than c
    distinct local minima the best one repeats.
    """
    rest = values.shape[1:]
    grid = values.reshape((k + 1,) * n + rest)
    local = np.ones(grid.shape, dtype=bool)
    for axis in range(n):
        lower = np.diff(grid, axis=axis) < 0  # next point is lower than this one
        pad = np.zeros_like(np.take(lower, [0], axis=axis))
        local &= ~np.concatenate([lower, pad], axis=axis)  # right neighbour not lower
        local &= ~np.concatenate([pad, np.diff(grid, axis=axis) > 0], axis=axis)
    score = np.where(local.reshape(values.shape), values, np.inf)
    order = np.argsort(score, axis=0, kind="stable")
    ranked = np.take_along_axis(score, order, axis=0)
    distinct = np.concatenate([np.ones((1, *rest), bool), ranked[1:] > ranked[:-1]])
    distinct &= np.isfinite(ranked)
    rank = np.cumsum(distinct, axis=0) - 1
    picks = [np.argmax(distinct & (rank == r), axis=0) for r in range(c)]
    return np.take_along_axis(order, np.stack(picks), axis=0)


def image_subdivision(
    lo: np.ndarray,
    hi: np.ndarray,
    f: Callable[[np.ndarray], Any],
    *,
    subdivisions: int = 8,
    tol: float = 1e-9,
    candidates: int = 4,
) -> tuple[np.ndarray, np.ndarray]:
    """Image of any continuous f: subdivide, then zoom on the best grid points.

    Each box is cut into k^n sub-boxes and f evaluated at their (k+1)^n vertices (the
    vertex method is the case k = 1). Then, for each output and each extreme, the grid's
    ``candidates`` best local extrema x* (distinct values, so distinct basins) are refined:
    the grid is laid again on [x* − h, x* + h] ∩ box (h the current spacing), h shrinking
    by 2/k per round until h ≤ ``tol`` × box width; the best refined value wins.

    Tolerance: the result is an inner approximation (never wider than the true image),
    exact wherever f is monotone (the grid holds the vertices), and an extremum whose basin
    holds one of those grid points is located to within ``tol`` × width (a value error of
    order f''·(tol·w)² at a smooth interior extremum). An extremum in no such basin — a
    feature narrower than w/k, or more than ``candidates`` rival basins — can be missed,
    with an error at most f's variation over one cell: raise ``subdivisions`` for wiggly
    functions.

    Why not interval arithmetic: it needs f rewritten in interval operations and returns
    an outer enclosure, wider than the image whenever a variable occurs twice (the
    dependency problem), so it would disagree with Props. 1–2 where they hold.

    Parameters
    ----------
    lo, hi
        Lower and upper ends of the boxes, arrays of shape (..., n), ``lo <= hi``.
    f
        Vectorised continuous map from points (..., n) to (..., m) or (...,).
    subdivisions
        k, the sub-boxes per axis: an even integer ≥ 4. The grid holds (k+1)^n points per
        box, so memory grows as (k+1)^n.
    tol
        Where the zoom stops, relative to the box width: in (0, 1).
    candidates
        How many of the grid's best local extrema are refined, per output and extreme.

    Returns
    -------
    lo, hi : numpy.ndarray
        Ends of the images, shape (..., m) (m = 1 for a scalar f).

    Raises
    ------
    EvidenceError
        ``subdivisions`` not an even integer ≥ 4, or ``tol`` outside (0, 1).
    MemoryBudgetError
        The grid would not fit in memory; use fewer subdivisions.

    See Also
    --------
    image : the extension principle on evidence, which picks a method.
    box_image : one box by any method, the vertex method (Prop. 1) among them.

    References
    ----------
    The paper's eqs. 13–15 (the image of a focal element) and Props. 1–2 (the vertex and
    monotone methods this one agrees with where they hold).

    Examples
    --------
    x² on [−1, 2] has its minimum inside the box, which the vertices miss:

    >>> import numpy as np
    >>> lo, hi = image_subdivision(np.array([-1.0]), np.array([2.0]),
    ...                            lambda x: x[..., 0] ** 2)
    >>> round(float(lo[0]), 9), float(hi[0])
    (0.0, 4.0)
    """
    k = int(subdivisions)
    if k < 4 or k % 2:
        raise EvidenceError(f"subdivisions must be an even integer >= 4, got {subdivisions}")
    if not 0 < tol < 1:
        raise EvidenceError(f"tol is relative to the box width and must lie in (0, 1), got {tol}")
    n, lead = lo.shape[-1], lo.shape[:-1]
    check_memory(
        float(k + 1) ** n * max(1, int(np.prod(lead))) * 8 * (2 * n + 2),
        f"the subdivision image's grid ({k + 1}^{n} points per box)",
        "use fewer subdivisions",
    )
    unit = _unit_grid(k, n)  # (G, n)
    grid = unit.reshape((-1,) + (1,) * len(lead) + (n,))
    width = hi - lo
    values = _evaluate(f, lo + grid * width, 1)  # (G, ..., m)
    c = max(1, int(candidates))
    # candidates: extreme e (0 = min, 1 = max) and rank r → axis E = 2c
    order = np.concatenate(
        [_candidates(values, k, n, c), _candidates(-values, k, n, c)]
    )  # (E, ..., m)
    sign = np.repeat([1.0, -1.0], c).reshape((2 * c, 1) + (1,) * len(lead))
    score = np.moveaxis(np.take_along_axis(values, order, axis=0), -1, 1) * sign  # (E, m, ...)
    order = np.moveaxis(order, -1, 1)  # (E, m, ...)
    where = lo + unit[order] * width  # (E, m, ..., n)
    h = np.broadcast_to(width / k, where.shape)
    rounds = int(np.ceil(np.log(tol * k) / np.log(2.0 / k)))
    grid2 = grid[:, None, None]  # (G, 1, 1, ..., n)
    for _ in range(max(rounds, 0)):
        w_lo = np.maximum(where - h, lo)
        w_hi = np.minimum(where + h, hi)
        pts = w_lo + grid2 * (w_hi - w_lo)  # (G, E, m, ..., n)
        vals = np.diagonal(_evaluate(f, pts, 3), axis1=2, axis2=-1)  # (G, E, ..., m)
        vals = np.moveaxis(vals, -1, 2) * sign  # (G, E, m, ...)
        idx = vals.argmin(axis=0)
        cand = np.take_along_axis(vals, idx[None], axis=0)[0]
        better = cand < score
        new_where = np.take_along_axis(pts, idx[None, ..., None], axis=0)[0]
        where = np.where(better[..., None], new_where, where)
        score = np.where(better, cand, score)
        h = (w_hi - w_lo) / k
    out_lo = np.moveaxis(score[:c].min(axis=0), 0, -1)
    out_hi = np.moveaxis(-score[c:].min(axis=0), 0, -1)
    return out_lo, out_hi


def image_mean_value(
    lo: np.ndarray,
    hi: np.ndarray,
    f: Callable[[np.ndarray], Any],
    slope: SlopeBound,
    *,
    pieces: int = 8,
) -> tuple[np.ndarray, np.ndarray]:
    """Mean-value form: an outer enclosure of f on boxes [lo, hi], never narrower than f(A).

    By the mean-value theorem f(x) = f(c) + Σ_j ∂f/∂x_j(ξ) (x_j − c_j) for some ξ in the box,
    c its centre; with every slope ∂f/∂x_j on the box in [d⁻_j, d⁺_j] and |x_j − c_j| ≤ h_j,

        f(A) ⊆ f(c) + Σ_j [d⁻_j, d⁺_j] · [−h_j, h_j] = f(c) ± Σ_j max(|d⁻_j|, |d⁺_j|) h_j.

    The excess width shrinks like the square of the width, so each box is cut into
    ``pieces`` parts per axis (``pieces``^n sub-boxes) and the hull of their enclosures is
    returned, widened outward by a few units of rounding so that floating point cannot make
    it too narrow.

    Parameters
    ----------
    lo, hi : numpy.ndarray, shape (..., n)
        The boxes' lower and upper ends.
    f : Callable
        Vectorised map from points (..., n) to (..., m) or (...,).
    slope : Callable
        ``slope(lo, hi) -> (d_lo, d_hi)``: bounds of f's partial derivatives over the boxes
        [lo, hi] of shape (..., n); each of shape (..., n) for a scalar f, (..., m, n) else.
        A bound that does not hold on the box voids the guarantee.
    pieces : int, optional
        Sub-boxes per axis (default 8).

    Returns
    -------
    tuple of numpy.ndarray, shape (..., m)
        The enclosures' lower and upper ends (m = 1 for a scalar f).

    Raises
    ------
    EvidenceError
        A slope bound of the wrong shape, with NaN, or with d_lo > d_hi; ``pieces`` < 1.

    See Also
    --------
    image : The image of evidence or boxes by any method (``method="mean_value"``).

    Examples
    --------
    >>> import numpy as np
    >>> lo, hi = np.array([-1.0]), np.array([2.0])
    >>> square, slope = (lambda x: x[..., 0] ** 2), (lambda l, h: (2 * l, 2 * h))
    >>> image_mean_value(lo, hi, square, slope, pieces=1)  # f(c) ± 4 · 1.5
    (array([-5.75]), array([6.25]))
    >>> a, b = image_mean_value(lo, hi, square, slope, pieces=64)
    >>> bool(a[0] <= 0.0 and b[0] >= 4.0), round(float(b[0] - a[0]) - 4.0, 3)
    (True, 0.002)
    """
    if int(pieces) != pieces or pieces < 1:
        raise EvidenceError(f"pieces must be a whole number >= 1, got {pieces!r}")
    k, n = int(pieces), lo.shape[-1]
    check_memory(
        float(k) ** n * lo.size * 8 * 8,
        f"the mean-value form on {k}^{n} sub-boxes per box",
        "use fewer pieces (subdivisions=) or fewer boxes",
    )
    steps = np.stack(np.meshgrid(*([np.arange(k)] * n), indexing="ij"), -1).reshape(-1, n)
    width = (hi - lo)[..., None, :]
    sub_lo = lo[..., None, :] + width * (steps / k)  # (..., k^n, n)
    sub_hi = lo[..., None, :] + width * ((steps + 1) / k)
    centre, half = 0.5 * (sub_lo + sub_hi), 0.5 * (sub_hi - sub_lo)
    at_centre = _call(f, centre)  # (..., k^n, m)
    d_lo, d_hi = (np.asarray(d, dtype=float) for d in slope(sub_lo, sub_hi))
    if d_lo.shape == centre.shape:  # a scalar f: one row of slopes
        d_lo, d_hi = d_lo[..., None, :], d_hi[..., None, :]
    want = (*at_centre.shape, n)
    if d_lo.shape != want or d_hi.shape != want:
        raise EvidenceError(
            f"slope(lo, hi) must return two arrays of shape {centre.shape} (scalar f) or "
            f"{want}, got {d_lo.shape} and {d_hi.shape}"
        )
    if np.isnan(d_lo).any() or np.isnan(d_hi).any() or np.any(d_lo > d_hi):
        raise EvidenceError(
            "slope(lo, hi) returned NaN or d_lo > d_hi; it must bound every "
            "partial derivative of f on the box from below and above"
        )
    spread = np.sum(np.maximum(np.abs(d_lo), np.abs(d_hi)) * half[..., None, :], axis=-1)
    slack = 4.0 * np.finfo(float).eps * (np.abs(at_centre) + spread)  # rounding, outward
    return ((at_centre - spread - slack).min(axis=-2), (at_centre + spread + slack).max(axis=-2))


def resolve_method(method: str, signs: np.ndarray | None) -> str:
    """``auto`` → ``monotone`` when every sign is known (non-zero), else ``vertex``."""
    if method not in IMAGE_METHODS:
        raise EvidenceError(f"method must be one of {IMAGE_METHODS}, got {method!r}")
    if method == "auto":
        return "monotone" if signs is not None and np.all(signs != 0) else "vertex"
    if method == "monotone" and signs is None:
        raise EvidenceError(
            "method='monotone' needs the signs: pass monotone=(+1 or −1 per argument)"
        )
    return method


def image_boxes(
    lo: np.ndarray,
    hi: np.ndarray,
    f: Callable[[np.ndarray], Any],
    method: str,
    signs: np.ndarray | None,
    *,
    check: bool = True,
    tol: float = 1e-9,
    subdivisions: int = 8,
    slope: SlopeBound | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Array kernel behind :func:`image`: ``method`` already resolved, signs parsed."""
    if method == "mean_value":
        if slope is None:
            raise EvidenceError(
                "method='mean_value' needs slope=: a function (lo, hi) -> "
                "(d_lo, d_hi) bounding f's derivatives on a box"
            )
        return image_mean_value(lo, hi, f, slope, pieces=subdivisions)
    if method == "monotone":
        if signs is None:
            raise EvidenceError("method='monotone' needs the signs of f (one +1/−1 per argument)")
        return image_monotone(lo, hi, f, signs, check=check)
    if method == "vertex":
        return image_vertex(lo, hi, f, check=check)
    return image_subdivision(lo, hi, f, subdivisions=subdivisions, tol=tol)


def box_image(
    f: Callable[[np.ndarray], Any],
    lo: Any,
    hi: Any,
    monotone: Any = None,
    *,
    method: ImageMethod = "auto",
    check: bool = True,
    tol: float = 1e-9,
    subdivisions: int = 8,
) -> tuple[np.ndarray, np.ndarray]:
    """Images f(A) of boxes [lo, hi] (..., n) for the filters (eqs. 13, 17–19).

    ``monotone`` follows :class:`~dstoolkit.filters.StateSpaceModel`: signs of the n state
    arguments, optionally followed by n noise signs (ignored), or None (vertex method).

    Parameters
    ----------
    f
        Vectorised map from points (..., n) to (..., m) or (...,).
    lo, hi
        Lower and upper ends of the boxes, array-likes of shape (..., n), ``lo <= hi``.
    monotone
        Signs of f per state argument, shape (n,) or (2n,) with the noise signs last
        (ignored): +1, −1 or 0 (unknown); None when no sign is known.
    method
        ``"monotone"``, ``"vertex"``, ``"subdivision"`` or ``"auto"`` (monotone when every
        sign is known, else vertex); see :func:`image`.
    check
        Verify the method's hypothesis cheaply (NotMonotoneError, VertexMethodWarning).
    tol
        Subdivision tolerance, relative to the box width, in (0, 1).
    subdivisions
        Sub-boxes per axis for ``"subdivision"``: an even integer ≥ 4.

    Returns
    -------
    lo, hi : numpy.ndarray
        Ends of the images, shape (..., m).

    Raises
    ------
    EvidenceError
        A monotone method without signs, or bad ``subdivisions``/``tol``.
    NotMonotoneError
        With ``check``, f visibly breaks the declared signs.

    See Also
    --------
    image : the same on :class:`IntervalEvidence`, with its checks of the boxes and of f.
    image_subdivision : the method for any continuous f.

    References
    ----------
    The paper's eq. 13 (image of a focal element) and eqs. 17–19 (the filter's predicted
    state and measurement evidence).

    Examples
    --------
    >>> lo, hi = box_image(lambda x: 2.0 * x[..., 0], [[-1.0], [0.0]], [[2.0], [1.0]],
    ...                    monotone=[1])
    >>> lo.ravel().tolist(), hi.ravel().tolist()
    ([-2.0, 0.0], [4.0, 2.0])
    """
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    signs = state_signs(monotone, lo.shape[-1])
    return image_boxes(
        lo,
        hi,
        f,
        resolve_method(method, signs),
        signs,
        check=check,
        tol=tol,
        subdivisions=subdivisions,
    )


def image(
    evidence_or_arrays: IntervalEvidence | tuple[Any, Any],
    f: Callable[[np.ndarray], Any],
    method: ImageMethod = "auto",
    monotone: Any = None,
    tol: float = 1e-9,
    *,
    subdivisions: int = 8,
    check: bool = True,
    merge: bool = True,
    slope: SlopeBound | None = None,
) -> IntervalEvidence | tuple[np.ndarray, np.ndarray]:
    """Image of a random relation through f (extension principle, eqs. 13–15).

    Parameters
    ----------
    evidence_or_arrays
        An :class:`IntervalEvidence` (boxes of dimension n), or a pair ``(lo, hi)`` of
        arrays of shape (..., n).
    f
        Vectorised map from points (..., n) to (..., m) or (...,); see the module notes.
    method
        ``"monotone"`` (Prop. 2, 2 evaluations per box), ``"vertex"`` (Prop. 1, 2^n),
        ``"subdivision"`` (any continuous f, see :func:`image_subdivision`),
        ``"mean_value"`` (an outer enclosure, needs ``slope``; see
        ``image_mean_value``), or ``"auto"``: monotone when every sign is known, else
        vertex.
    monotone
        Signs per argument, shape (n,) or (m, n): +1, −1, or 0 (neither/unknown).
    tol
        Subdivision tolerance, relative to the box width.
    check
        Verify the method's hypothesis cheaply: NotMonotoneError for a wrong monotone
        declaration, VertexMethodWarning when the vertex method visibly fails.
    merge
        For evidence input: merge equal images, adding masses (eq. 14).
    slope
        For ``"mean_value"``: ``slope(lo, hi) -> (d_lo, d_hi)``, bounds of f's partial
        derivatives on boxes (..., n), each (..., n) for a scalar f or (..., m, n). Its
        ``subdivisions`` are then the sub-boxes per axis.
    subdivisions
        For ``"subdivision"``: sub-boxes per axis, an even integer ≥ 4 (the grid holds
        (k+1)^n points per box); for ``"mean_value"``: pieces per axis.

    Returns
    -------
    IntervalEvidence with the same masses (merged), or the arrays ``(lo, hi)`` of the images.

    Raises
    ------
    EvidenceError
        Bad boxes, or an f that returns complex values, or NaN or ±inf at finite points.

    See Also
    --------
    box_image : the array kernel the filters call.
    image_subdivision : the method for any continuous f.

    References
    ----------
    The paper's eqs. 13–15 (extension principle), Prop. 1 (vertex method, eq. 17) and
    Prop. 2 (monotone functions).

    Examples
    --------
    x² through two focal elements; [−1, 1] has its minimum inside, so subdivision:

    >>> from dstoolkit.evidence import IntervalEvidence
    >>> e = IntervalEvidence([[-1.0], [0.0]], [[1.0], [2.0]], [0.5, 0.5])
    >>> image(e, lambda x: x[..., 0] ** 2, method="subdivision")
    IntervalEvidence([0, 1]: 0.5, [0, 4]: 0.5)
    """
    if isinstance(evidence_or_arrays, IntervalEvidence):
        lo, hi = evidence_or_arrays.boxes_lo, evidence_or_arrays.boxes_hi
    else:
        try:
            lo, hi = (np.asarray(a, dtype=float) for a in evidence_or_arrays)
        except (TypeError, ValueError) as err:
            raise EvidenceError(
                "image needs an IntervalEvidence or a pair (lo, hi) of arrays of shape (..., n)"
            ) from err
        if lo.shape != hi.shape or lo.ndim == 0:
            raise EvidenceError(
                f"lo and hi must have the same shape (..., n), got {lo.shape} and {hi.shape}"
            )
        if np.isnan(lo).any() or np.isnan(hi).any():
            raise EvidenceError("some box ends are NaN; every end must be a number")
        if np.any(lo > hi):
            raise EvidenceError("some boxes have lo > hi; swap the ends or check the data")
        if lo.shape[-1] == 0:
            raise EvidenceError(
                f"boxes of shape {lo.shape} have no dimension; give (..., n) with n >= 1"
            )
    if not callable(f):
        raise EvidenceError(f"f must be a function of the points, got {type(f).__name__}")
    signs = parse_signs(monotone, lo.shape[-1])
    resolved = resolve_method(method, signs)
    out_lo, out_hi = image_boxes(
        lo,
        hi,
        _checked(f),
        resolved,
        signs,
        check=check,
        tol=tol,
        subdivisions=subdivisions,
        slope=slope,
    )
    if np.isnan(out_lo).any() or np.isnan(out_hi).any():
        raise EvidenceError(
            "the image has NaN ends (f is not defined on all of a box); "
            "check f's domain or the boxes given"
        )
    if isinstance(evidence_or_arrays, IntervalEvidence):
        return IntervalEvidence(out_lo, out_hi, evidence_or_arrays.mass, merge=merge)
    return out_lo, out_hi

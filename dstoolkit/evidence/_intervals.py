"""Evidence whose focal elements are real intervals or boxes (paper §2.3, Appendix A).

Focal elements are stored as two arrays ``lo`` and ``hi`` of shape (n, d): one row per
focal element, one column per dimension (d = 1 for the scalar evidence of the paper).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from dstoolkit.errors import EvidenceError
from dstoolkit.utils.checks import real_array

from ._base import Evidence, validate_masses
from ._boxes import Boxes, hull, pignistic_expectation


def _as_box_array(values: Any, name: str) -> np.ndarray:
    arr = real_array(values, name, finite=False, error=EvidenceError)
    if arr.ndim == 0:
        arr = arr.reshape(1, 1)
    elif arr.ndim == 1:
        arr = arr[:, None]
    elif arr.ndim != 2:
        raise EvidenceError(f"{name} must have shape (n,) or (n, d), got {arr.shape}")
    return arr


def _check_widths(lo: np.ndarray, hi: np.ndarray) -> None:
    """Refuse finite ends whose width overflows to inf (|ends| near 1e308)."""
    with np.errstate(over="ignore", invalid="ignore"):
        overflow = np.isfinite(lo) & np.isfinite(hi) & ~np.isfinite(hi - lo)
    if overflow.any():
        i = int(np.argwhere(overflow)[0][0])
        raise EvidenceError(
            f"focal element {i} is too wide to compute with: its width overflows (ends "
            f"{lo[i].tolist()}, {hi[i].tolist()}); rescale the variable, or use ±inf for an "
            "unbounded end"
        )


def row_keys(rows: np.ndarray) -> np.ndarray:
    """One opaque key per row: equal keys ⇔ equal rows (−0.0 and 0.0 count as equal)."""
    rows = np.ascontiguousarray(rows + 0.0)
    return rows.view(np.dtype((np.void, rows.dtype.itemsize * rows.shape[1]))).reshape(-1)


class IntervalEvidence(Evidence):
    """A body of evidence with interval (or box) focal elements [lo_i, hi_i] and masses m_i.

    Parameters
    ----------
    lo, hi
        Lower and upper ends, shape (n,) for intervals or (n, d) for d-dimensional boxes.
        Infinite ends are allowed (an unbounded focal element). The attributes ``lo``
        and ``hi`` are (n, d) whatever d; ``lo_1d`` and ``hi_1d`` give (n,) for
        intervals.
    mass
        Masses, shape (n,), non-negative, summing to 1.
    merge
        Merge identical focal elements, adding their masses (eq. 14). Default True.

    Examples
    --------
    >>> e = IntervalEvidence([-0.3, 0.3], [2.6, 1.9], [0.3, 0.7])
    >>> round(e.pignistic_expectation_1d(), 4)
    1.115
    """

    def __init__(self, lo: Any, hi: Any, mass: Any, *, merge: bool = True) -> None:
        lo_arr, hi_arr = _as_box_array(lo, "lo"), _as_box_array(hi, "hi")
        if lo_arr.shape != hi_arr.shape:
            raise EvidenceError(
                f"lo and hi must have the same shape, got {lo_arr.shape} and {hi_arr.shape}"
            )
        if lo_arr.shape[1] == 0:
            raise EvidenceError(
                f"boxes of shape {lo_arr.shape} have no dimension; give at least one "
                "component per focal element, shape (n,) or (n, d) with d >= 1"
            )
        m = validate_masses(mass)
        if m.size != lo_arr.shape[0]:
            raise EvidenceError(
                f"{m.size} masses for {lo_arr.shape[0]} focal elements; give one mass each"
            )
        if np.isnan(lo_arr).any() or np.isnan(hi_arr).any():
            rows = np.flatnonzero(np.isnan(lo_arr).any(1) | np.isnan(hi_arr).any(1))
            raise EvidenceError(
                f"interval ends contain NaN in focal elements {rows.tolist()}; "
                "every end must be a number (±inf allowed)"
            )
        bad = np.flatnonzero((lo_arr > hi_arr).any(axis=1))
        if np.any(lo_arr == np.inf) or np.any(hi_arr == -np.inf):
            raise EvidenceError(
                "a lower end is +inf or an upper end is -inf: such an interval "
                "holds no number; use -inf for lo and +inf for hi"
            )
        _check_widths(lo_arr, hi_arr)
        if bad.size:
            i = int(bad[0])
            raise EvidenceError(
                f"lo > hi in focal element {i}: [{lo_arr[i].tolist()}, {hi_arr[i].tolist()}] "
                f"({bad.size} such); swap the ends or check the data"
            )
        self._set(np.concatenate([lo_arr, hi_arr], axis=1), m, merge)

    # -- construction helpers --------------------------------------------------------
    def _with(self, focal: np.ndarray, mass: np.ndarray, *, merge: bool = True) -> IntervalEvidence:
        new = object.__new__(IntervalEvidence)
        new._set(np.asarray(focal, dtype=float), np.asarray(mass, dtype=float), merge)
        return new

    def _state(self) -> tuple[Any, ...]:
        merged = self._merged()[0] is self._focal
        return (self.boxes_lo.copy(), self.boxes_hi.copy(), self._mass.copy(), merged)

    @classmethod
    def _restore(cls, *state: Any) -> IntervalEvidence:
        lo, hi, mass, merge = state
        return cls(lo, hi, mass, merge=bool(merge))

    @classmethod
    def _from_attributes(cls, state: dict[str, Any]) -> IntervalEvidence:
        focal = np.asarray(state["_focal"], dtype=float)
        if focal.ndim != 2 or focal.shape[1] % 2:
            raise EvidenceError(f"focal elements of shape {focal.shape} are not boxes")
        d = focal.shape[1] // 2
        return cls(focal[:, :d], focal[:, d:], state["_mass"], merge=False)

    @classmethod
    def from_pairs(cls, pairs: Any, *, merge: bool = True) -> IntervalEvidence:
        """Build from rows ``(lo, hi, mass)`` of scalar intervals.

        Parameters
        ----------
        pairs : array_like, shape (n, 3)
            Rows (lo, hi, mass).
        merge : bool
            Merge equal focal elements (eq. 14).

        Returns
        -------
        IntervalEvidence
            Scalar evidence (d = 1).
        """
        arr = real_array(pairs, "pairs", allow_inf=True, error=EvidenceError)
        if arr.ndim != 2 or arr.shape[1] != 3:
            raise EvidenceError(f"pairs must be rows (lo, hi, mass), got shape {arr.shape}")
        return cls(arr[:, 0], arr[:, 1], arr[:, 2], merge=merge)

    @classmethod
    def vacuous(cls, lo: Any, hi: Any) -> IntervalEvidence:
        """Total ignorance on the box [lo, hi]: one focal element with mass 1.

        Parameters
        ----------
        lo, hi : float or array_like, shape (d,)
            The box [lo, hi] (the variable's unit).

        Returns
        -------
        IntervalEvidence
            One focal element, [lo, hi], with mass 1.
        """
        return cls(np.atleast_1d(lo)[None, :], np.atleast_1d(hi)[None, :], [1.0])

    @classmethod
    def point(cls, value: Any) -> IntervalEvidence:
        """Certainty of one value: the degenerate interval [x, x] with mass 1.

        Parameters
        ----------
        value : float or array_like, shape (d,)
            x.

        Returns
        -------
        IntervalEvidence
            One focal element, [x, x], with mass 1.
        """
        return cls.vacuous(value, value)

    # -- array views -------------------------------------------------------------------
    @property
    def dim(self) -> int:
        """Dimension d of the boxes (1 for intervals)."""
        return self._focal.shape[1] // 2

    @property
    def boxes_lo(self) -> np.ndarray:
        """Lower ends, shape (n, d) (read-only)."""
        return self._focal[:, : self.dim]

    @property
    def boxes_hi(self) -> np.ndarray:
        """Upper ends, shape (n, d) (read-only)."""
        return self._focal[:, self.dim :]

    @property
    def lo(self) -> np.ndarray:
        """Lower ends, shape (n, d) whatever d (read-only); :attr:`lo_1d` for intervals."""
        return self.boxes_lo

    @property
    def hi(self) -> np.ndarray:
        """Upper ends, shape (n, d) whatever d (read-only); :attr:`hi_1d` for intervals."""
        return self.boxes_hi

    @property
    def lo_1d(self) -> np.ndarray:
        """Lower ends of scalar evidence (d = 1), shape (n,) (read-only).

        Raises
        ------
        EvidenceError
            If the focal elements are boxes (d > 1): use :attr:`lo`, shape (n, d).
        """
        return self._scalar_column(self.boxes_lo, "lo")

    @property
    def hi_1d(self) -> np.ndarray:
        """Upper ends of scalar evidence (d = 1), shape (n,) (read-only).

        Raises
        ------
        EvidenceError
            If the focal elements are boxes (d > 1): use :attr:`hi`, shape (n, d).
        """
        return self._scalar_column(self.boxes_hi, "hi")

    def _scalar_column(self, ends: np.ndarray, name: str) -> np.ndarray:
        if self.dim != 1:
            raise EvidenceError(
                f"{name}_1d is for scalar evidence (d = 1); this evidence has "
                f"{self.dim}-dimensional boxes: use {name}, shape (n, d)"
            )
        return ends[:, 0]

    @property
    def widths(self) -> np.ndarray:
        """Width (d = 1) or volume (d > 1) of each focal element."""
        return self._sizes()

    def as_boxes(self) -> Boxes:
        """Return the focal elements as a one-run :class:`~dstoolkit.evidence.Boxes`.

        Returns
        -------
        Boxes
            Boxes (1, n, d) and masses (1, n).
        """
        return Boxes(self.boxes_lo[None], self.boxes_hi[None], self._mass[None])

    @classmethod
    def from_boxes(cls, boxes: Boxes, run: int = 0) -> IntervalEvidence:
        """Return the mass function of one run of ``boxes``.

        Padding (mass 0) is dropped, masses renormalised, equal boxes not merged.

        Parameters
        ----------
        boxes : Boxes
            Boxes (R, N, d) and masses (R, N).
        run : int
            The run to take.

        Returns
        -------
        IntervalEvidence
            That run's evidence.
        """
        keep = boxes.mass[run] > 0
        mass = boxes.mass[run, keep]
        return cls(boxes.lo[run, keep], boxes.hi[run, keep], mass / mass.sum(), merge=False)

    def hull(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the smallest box containing every focal element (Θ in eqs. A7–A8).

        Returns
        -------
        lo, hi : ndarray, shape (d,)
            The ends of the hull.
        """
        lo, hi = hull(self.as_boxes())
        return lo[0], hi[0]

    # -- primitives ----------------------------------------------------------------------
    def _check_same_frame(self, other: IntervalEvidence) -> None:
        if other.dim != self.dim:
            raise EvidenceError(
                f"dimensions differ: {self.dim} vs {other.dim}; both evidences must "
                "describe the same variables"
            )

    def _intersect(self, other: Evidence) -> tuple[np.ndarray, np.ndarray]:
        d = self.dim
        lo = np.maximum(self._focal[:, None, :d], other._focal[None, :, :d]).reshape(-1, d)
        hi = np.minimum(self._focal[:, None, d:], other._focal[None, :, d:]).reshape(-1, d)
        return np.concatenate([lo, hi], axis=1), np.all(lo <= hi, axis=1)

    def _sizes(self) -> np.ndarray:
        widths = self.boxes_hi - self.boxes_lo
        with np.errstate(invalid="ignore", over="ignore"):
            volume = np.prod(widths, axis=1)
        # a box unbounded in some direction is unbounded (0 · ∞ would give NaN)
        return np.where(np.isinf(widths).any(axis=1), np.inf, volume)

    def _energy_unit(self, counted: np.ndarray | None = None) -> float:
        sizes = self._sizes() if counted is None else self._sizes()[counted]
        finite = sizes[np.isfinite(sizes)]
        return float(finite.min()) if finite.size else 1.0

    def _counts_in_energy(self) -> np.ndarray:
        return np.isfinite(self._sizes())

    def _theta(self) -> np.ndarray:
        lo, hi = self.hull()
        return np.concatenate([lo, hi])[None, :]

    def _keys(self) -> np.ndarray:
        return row_keys(self._focal)

    def _check_theta(self, theta: Any) -> np.ndarray:
        row = real_array(theta, "theta", allow_inf=True, error=EvidenceError).reshape(-1)
        d = self.dim
        if row.size != 2 * d:
            raise EvidenceError(
                f"theta must be [lo..., hi...] with {2 * d} numbers for "
                f"{d}-dimensional boxes, got {row.size}"
            )
        if np.any(row[:d] > row[d:]):
            raise EvidenceError(
                f"theta {row.tolist()} is not a box: need lo <= hi in every dimension"
            )
        _check_widths(row[None, :d], row[None, d:])
        return row[None, :]

    def _query(self, lo: Any, hi: Any) -> np.ndarray:
        lo_a = np.atleast_1d(real_array(lo, "lo", allow_inf=True, error=EvidenceError))
        hi_a = np.atleast_1d(real_array(hi, "hi", allow_inf=True, error=EvidenceError))
        if lo_a.size != self.dim or hi_a.size != self.dim:
            raise EvidenceError(f"query box must have {self.dim} lower and upper ends")
        if np.any(lo_a > hi_a) or np.isnan(lo_a).any() or np.isnan(hi_a).any():
            raise EvidenceError(f"query [{lo}, {hi}] is not an interval: need lo <= hi")
        return np.concatenate([lo_a, hi_a])[None, :]

    def _subset_mask(self, query: np.ndarray) -> np.ndarray:
        d = self.dim
        return np.all((self.boxes_lo >= query[0, :d]) & (self.boxes_hi <= query[0, d:]), axis=1)

    def _meets_mask(self, query: np.ndarray) -> np.ndarray:
        d = self.dim
        return np.all((self.boxes_lo <= query[0, d:]) & (self.boxes_hi >= query[0, :d]), axis=1)

    # -- public API ------------------------------------------------------------------------
    def belief(self, lo: Any, hi: Any) -> float:
        """Bel([lo, hi]) = Σ of masses of focal elements inside [lo, hi] (Def. 3).

        Parameters
        ----------
        lo, hi : float or array_like, shape (d,)
            The box [lo, hi] (the variable's unit).

        Returns
        -------
        float
            Bel([lo, hi]) in [0, 1].
        """
        return self._bel(self._query(lo, hi))

    def plausibility(self, lo: Any, hi: Any) -> float:
        """Pl([lo, hi]) = Σ of masses of focal elements meeting [lo, hi] (Def. 3).

        Parameters
        ----------
        lo, hi : float or array_like, shape (d,)
            The box [lo, hi] (the variable's unit).

        Returns
        -------
        float
            Pl([lo, hi]) in [0, 1].
        """
        return self._pl(self._query(lo, hi))

    def cdf_bounds(self, x: Any) -> tuple[np.ndarray, np.ndarray]:
        """Return the p-box: lower F_*(x) = Bel((−∞, x]) and upper F^*(x) = Pl((−∞, x]) (d = 1).

        Parameters
        ----------
        x : array_like
            Where to evaluate (the variable's unit).

        Returns
        -------
        lower, upper : ndarray, shape of ``x``
            F_*(x) and F^*(x).

        Raises
        ------
        EvidenceError
            For boxes (d > 1).
        """
        if self.dim != 1:
            raise EvidenceError("cdf_bounds is defined for scalar (d = 1) evidence only")
        x = real_array(x, "x", allow_inf=True, error=EvidenceError)
        lower = (self.hi_1d[None, :] <= x.reshape(-1, 1)) @ self._mass
        upper = (self.lo_1d[None, :] <= x.reshape(-1, 1)) @ self._mass
        return lower.reshape(x.shape), upper.reshape(x.shape)

    def pignistic_expectation(self) -> np.ndarray:
        """E = Σ_j m(A_j) (a_j⁻ + a_j⁺)/2, the pignistic expectation (eq. 20).

        Returns
        -------
        ndarray, shape (d,)
            One value per dimension, for intervals (d = 1) too;
            :meth:`pignistic_expectation_1d` gives the float of scalar evidence.

        Raises
        ------
        EvidenceError
            If a focal element is unbounded: it has no expectation.

        Examples
        --------
        >>> IntervalEvidence([0.0, 1.0], [2.0, 3.0], [0.5, 0.5]).pignistic_expectation()
        array([1.5])
        """
        value = pignistic_expectation(self.as_boxes())[0]
        if not np.all(np.isfinite(value)):
            raise EvidenceError(
                "the pignistic expectation needs bounded focal elements; replace ±inf ends "
                "by a finite frame (e.g. discount onto a finite Θ)"
            )
        return value

    def pignistic_expectation_1d(self) -> float:
        """Return the pignistic expectation (eq. 20) of scalar evidence (d = 1), as a float.

        Returns
        -------
        float
            E, in the variable's unit.

        Raises
        ------
        EvidenceError
            If the focal elements are boxes (d > 1): use :meth:`pignistic_expectation`,
            or if a focal element is unbounded.

        Examples
        --------
        >>> IntervalEvidence([0.0, 1.0], [2.0, 3.0], [0.5, 0.5]).pignistic_expectation_1d()
        1.5
        """
        if self.dim != 1:
            raise EvidenceError(
                f"pignistic_expectation_1d is for scalar evidence (d = 1); "
                f"this evidence has {self.dim}-dimensional boxes: use "
                "pignistic_expectation(), shape (d,)"
            )
        return float(self.pignistic_expectation()[0])

    def shift(self, offset: Any) -> IntervalEvidence:
        """Return the evidence about X + offset (same masses).

        Parameters
        ----------
        offset : float or array_like, shape (d,)
            The offset (the variable's unit).

        Returns
        -------
        IntervalEvidence
            Every focal element moved by ``offset``.
        """
        off = np.atleast_1d(real_array(offset, "offset", error=EvidenceError)).reshape(-1)
        if off.size != self.dim:
            raise EvidenceError(f"offset must have {self.dim} component(s), got {off.size}")
        moved = self._focal + np.concatenate([off, off])
        _check_widths(moved[:, : self.dim], moved[:, self.dim :])
        if not np.array_equal(np.isinf(moved), np.isinf(self._focal)):
            raise EvidenceError(
                f"shifting by {off.tolist()} overflows the interval ends; rescale the variable"
            )
        return self._with(moved, self._mass, merge=False)

    def to_rows(self) -> np.ndarray:
        """Rows (lo, hi, mass) for d = 1, handy for tables.

        Returns
        -------
        ndarray, shape (n, 3)
            Rows (lo, hi, mass).

        Raises
        ------
        EvidenceError
            For boxes (d > 1).
        """
        return np.column_stack([self.lo_1d, self.hi_1d, self._mass])

    def __repr__(self) -> str:
        focal, mass = self._merged()  # equal focal elements shown once, masses added
        n, d = len(mass), self.dim
        if d == 1:
            body = ", ".join(
                f"[{a:.4g}, {b:.4g}]: {m:.4g}"
                for a, b, m in zip(focal[:8, 0], focal[:8, 1], mass[:8], strict=True)
            )
        else:
            body = f"{n} boxes in {d} dimensions"
        more = f", … ({n} focal elements)" if d == 1 and n > 8 else ""
        return f"IntervalEvidence({body}{more})"

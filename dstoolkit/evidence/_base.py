"""What every body of evidence shares, whatever its focal elements are.

A body of evidence is a list of focal elements with masses (paper §2.1, Def. 2). Two
representations live in dstoolkit: subsets of a finite frame (:class:`MassFunction`) and
real intervals or boxes (:class:`IntervalEvidence`). Both store their focal elements as
numpy arrays and implement the handful of set primitives below; belief, plausibility and
every combination rule of :mod:`dstoolkit.evidence` are written once on top of these
primitives.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any, Self

import numpy as np

from dstoolkit.errors import EvidenceError
from dstoolkit.utils.checks import real_array

MASS_TOLERANCE = 1e-9


def validate_masses(mass: Any, *, what: str = "masses") -> np.ndarray:
    """Return ``mass`` as a float array after checking it is a probability vector.

    Parameters
    ----------
    mass : array_like, shape (n,)
        The masses.
    what : str
        What to call them in a message.

    Returns
    -------
    ndarray, shape (n,)
        The masses as floats.

    Raises
    ------
    EvidenceError
        For an empty vector, NaN or infinite entries, negative entries, or a sum that
        differs from 1 by more than ``MASS_TOLERANCE``.

    Examples
    --------
    >>> validate_masses([0.5, 0.5])
    array([0.5, 0.5])
    """
    m = real_array(mass, what, finite=False, error=EvidenceError).reshape(-1)
    if m.size == 0:
        raise EvidenceError(
            "empty evidence: no focal element was given; give at least one focal element "
            "with mass 1 (the vacuous evidence puts mass 1 on the whole frame)"
        )
    if not np.all(np.isfinite(m)):
        bad = np.flatnonzero(~np.isfinite(m))
        raise EvidenceError(
            f"{what} contain NaN or infinite values at positions {bad.tolist()}; "
            "every mass must be a finite number in [0, 1]"
        )
    if np.any(m < 0):
        bad = np.flatnonzero(m < 0)
        raise EvidenceError(
            f"{what} must be non-negative, got {m[bad].tolist()} at positions {bad.tolist()}"
        )
    total = float(m.sum())
    if abs(total - 1.0) > MASS_TOLERANCE:
        raise EvidenceError(
            f"{what} sum to {total:.6g}, expected 1 (±{MASS_TOLERANCE:g}): off by "
            f"{total - 1.0:+.3g}; normalise them or add the missing mass to the frame "
            "(ignorance)"
        )
    return m


class Evidence(ABC):
    """Abstract body of evidence: focal elements (an array, one row each) with masses.

    Subclasses implement the set primitives; the algebra lives in :mod:`dstoolkit.evidence`.

    See Also
    --------
    MassFunction : evidence on a finite frame.
    IntervalEvidence : evidence on intervals and boxes.

    Examples
    --------
    >>> from dstoolkit.evidence import Evidence, MassFunction
    >>> isinstance(MassFunction({"a": 1.0}), Evidence)
    True
    """

    _focal: np.ndarray
    _mass: np.ndarray

    # -- primitives every representation implements ---------------------------------
    @abstractmethod
    def _with(self, focal: np.ndarray, mass: np.ndarray, *, merge: bool = True) -> Self:
        """Return a new evidence of the same kind and frame with these focal elements."""

    @abstractmethod
    def _check_same_frame(self, other: Self) -> None:
        """Raise EvidenceError unless ``other`` (of the same type) lives on the same frame."""

    def _check_compatible(self, other: Evidence) -> None:
        """Raise EvidenceError unless ``other`` is of the same kind and on the same frame."""
        if type(other) is not type(self):
            raise EvidenceError(
                f"cannot combine {type(self).__name__} with {type(other).__name__}; "
                "convert both to the same representation"
            )
        self._check_same_frame(other)

    @abstractmethod
    def _intersect(self, other: Evidence) -> tuple[np.ndarray, np.ndarray]:
        """All pairwise intersections, row i*len(other)+j = A_i ∩ B_j, and a non-empty mask."""

    @abstractmethod
    def _sizes(self) -> np.ndarray:
        """Size of each focal element: cardinality |A| or width (volume) w(A)."""

    @abstractmethod
    def _energy_unit(self, counted: np.ndarray | None = None) -> float:
        """Return the size a focal element must have to count fully in the energy (eqs. 2, A1).

        Among the focal elements ``counted`` (a mask; all by default).
        """

    @abstractmethod
    def _counts_in_energy(self) -> np.ndarray:
        """Mask of focal elements that enter the energy sum (eq. 2 leaves Θ out)."""

    @abstractmethod
    def _theta(self) -> np.ndarray:
        """Return the frame Θ as one focal element (one row), where discounting puts its mass."""

    @abstractmethod
    def _keys(self) -> np.ndarray:
        """One hashable/sortable key per focal element; equal keys ⇔ equal focal elements."""

    @abstractmethod
    def _check_theta(self, theta: Any) -> np.ndarray:
        """``theta`` as one focal-element row after checking it is a valid frame Θ."""

    @abstractmethod
    def _subset_mask(self, query: np.ndarray) -> np.ndarray:
        """Which focal elements are contained in the query set (one row)."""

    @abstractmethod
    def _meets_mask(self, query: np.ndarray) -> np.ndarray:
        """Which focal elements intersect the query set (one row)."""

    # -- shared behaviour -------------------------------------------------------------
    def _set(self, focal: np.ndarray, mass: np.ndarray, merge: bool) -> None:
        """Store the focal elements with positive mass, merging equal ones (eq. 14).

        The stored arrays are the object's own copies, made read-only: every array a body
        of evidence hands out (masses, interval ends) is a view that cannot change it.
        """
        keep = mass > 0
        focal, mass = focal[keep], mass[keep]  # boolean indexing copies
        if merge:
            focal, mass = merge_equal(focal, mass)
        focal.flags.writeable = False
        mass.flags.writeable = False
        self._focal, self._mass = focal, mass
        self._merged_cache: tuple[np.ndarray, np.ndarray] | None = (
            None if not merge else (focal, mass)
        )

    def _merged(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the focal elements and masses with equal focal elements merged (eq. 14).

        This is what every reader of the evidence (``as_dict``, ``repr``, the dependence)
        sees, so that the merged and the unmerged form of one evidence give one answer.
        Read-only.
        """
        if self._merged_cache is None:
            focal, mass = merge_equal(self._focal, self._mass)
            focal.flags.writeable = False
            mass.flags.writeable = False
            self._merged_cache = (focal, mass)
        return self._merged_cache

    def merged(self) -> Self:
        """Return the same evidence with equal focal elements merged, their masses added (eq. 14).

        ``self`` when it has no equal focal elements.

        Returns
        -------
        MassFunction or IntervalEvidence
            The merged evidence, of the type of ``self``.
        """
        focal, mass = self._merged()
        if focal is self._focal:
            return self
        return self._with(focal, mass, merge=False)

    # -- copies: pickle, copy and deepcopy rebuild through the constructor's checks ----
    @abstractmethod
    def _state(self) -> tuple[Any, ...]:
        """Return what :meth:`_restore` needs to rebuild this evidence (plain values and arrays)."""

    @classmethod
    @abstractmethod
    def _restore(cls, *state: Any) -> Self:
        """Rebuild an evidence from :meth:`_state`, validating it as the constructor does."""

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self)._restore, self._state())

    @classmethod
    @abstractmethod
    def _from_attributes(cls, state: dict[str, Any]) -> Self:
        """Rebuild an evidence from the attributes a plain pickle of it holds.

        The attributes are validated as the constructor does.
        """

    def __setstate__(self, state: Any) -> None:
        """Restore a pickle in the plain form (attributes, no constructor call).

        It is rebuilt through the checks, so that crafted attributes cannot make an invalid
        evidence.
        """
        if not isinstance(state, dict):
            raise EvidenceError(
                f"cannot unpickle a {type(self).__name__} from "
                f"{type(state).__name__}; pickle it with dstoolkit"
            )
        try:
            rebuilt = self._from_attributes(state)
        except (KeyError, TypeError, ValueError, IndexError) as exc:
            if isinstance(exc, EvidenceError):
                raise
            raise EvidenceError(
                f"cannot unpickle a {type(self).__name__}: its attributes are "
                f"not those of one ({exc}); pickle it with dstoolkit"
            ) from None
        self.__dict__.update(rebuilt.__dict__)

    @property
    def mass(self) -> np.ndarray:
        """Masses of the focal elements (a read-only array)."""
        return self._mass

    def __len__(self) -> int:
        return int(self._mass.size)

    def _bel(self, query: np.ndarray) -> float:
        return float(self._mass[self._subset_mask(query)].sum())

    def _pl(self, query: np.ndarray) -> float:
        return float(self._mass[self._meets_mask(query)].sum())


def merge_equal(focal: np.ndarray, mass: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge equal focal elements (rows of ``focal``), adding their masses (eq. 14).

    Returns each distinct focal element once, in order of first appearance, with the
    summed mass. A stable lexicographic sort groups equal rows (−0.0 equals 0.0).

    Why this merge stays beside :func:`~dstoolkit.evidence.boxes.merge_equal_boxes`: this
    one serves the evidence objects, one at a time, on any focal element (rows of
    booleans on a finite frame, boxes on intervals), and keeps the order in which the
    focal elements first appear, which is what an object shows (``to_rows``, ``repr``).
    The batch one puts each run's boxes in a canonical order with padding, so that every
    run of a batch keeps one shape; its compiled twin is the one fast kernel of eq. 14.
    """
    rows = focal.reshape(len(focal), -1)
    order = np.lexsort(rows.T[::-1]) if rows.shape[1] > 1 else np.argsort(rows[:, 0], kind="stable")
    ranked = rows[order]
    starts = np.ones(len(ranked), dtype=bool)
    starts[1:] = np.any(ranked[1:] != ranked[:-1], axis=1)
    group = np.cumsum(starts) - 1
    summed = np.bincount(group, weights=mass[order])
    first = order[starts]  # stable sort: the first original index of each group
    by_appearance = np.argsort(first, kind="stable")
    return focal[first[by_appearance]], summed[by_appearance]

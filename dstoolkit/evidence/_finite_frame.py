"""Mass functions on a finite frame of discernment (paper §2.1, Defs. 1–4).

Focal elements are stored as bit masks over the frame (one ``uint64`` each), so a frame
holds at most 64 hypotheses; the algebra in :mod:`dstoolkit.evidence` runs on arrays.
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Mapping
from typing import Any

import numpy as np

from dstoolkit.errors import EvidenceError

from ._base import Evidence, validate_masses

MAX_FRAME = 64


def _popcount(masks: np.ndarray) -> np.ndarray:
    return np.bitwise_count(masks.astype(np.uint64)).astype(float)


class MassFunction(Evidence):
    """A mass function m: 2^Θ → [0, 1] with m(∅) = 0 and Σ m = 1 (Def. 2).

    Parameters
    ----------
    masses
        Mapping from focal elements to masses. A focal element is a set, frozenset, tuple or
        list of hypotheses; as a short form for small frames, a string is the set of its
        characters (``"ab"`` is {a, b}) unless the frame has that string as a hypothesis.
    frame
        The frame Θ (any hashable hypotheses, order kept). Default: the union of the focal
        elements, in order of appearance.
    merge : bool
        Merge equal focal elements, adding their masses (eq. 14). Default True.

    Raises
    ------
    EvidenceError
        For masses that are negative or do not sum to 1, or focal elements outside the
        frame.

    References
    ----------
    The paper's Defs. 1–3.

    Examples
    --------
    >>> m = MassFunction({"a": 0.5, "ab": 0.3, "abc": 0.2})
    >>> m.belief("ab"), m.plausibility("b")
    (0.8, 0.5)
    """

    def __init__(
        self,
        masses: Mapping[Any, float],
        frame: Iterable[Hashable] | None = None,
        *,
        merge: bool = True,
    ) -> None:
        if not isinstance(masses, Mapping):
            raise EvidenceError(
                f"masses must be a mapping {{focal element: mass}}, got {type(masses).__name__}"
            )
        if not masses:
            validate_masses([])  # raises the "empty evidence" error
        keys = list(masses.keys())
        if frame is None:
            seen: dict[Hashable, None] = {}
            for key in keys:
                for h in self._elements(key, None):
                    seen.setdefault(h, None)
            frame = tuple(seen)
        self.frame: tuple[Hashable, ...] = tuple(frame)
        try:
            distinct = len(set(self.frame))
        except TypeError as exc:
            raise EvidenceError(
                f"hypotheses of the frame must be hashable (numbers, strings, tuples): {exc}"
            ) from exc
        if distinct != len(self.frame):
            raise EvidenceError(f"the frame {self.frame!r} lists a hypothesis twice")
        if not 0 < len(self.frame) <= MAX_FRAME:
            raise EvidenceError(f"a frame needs 1 to {MAX_FRAME} hypotheses, got {len(self.frame)}")
        self._index = {h: i for i, h in enumerate(self.frame)}
        focal = np.array([self._mask_of(k) for k in keys], dtype=np.uint64)
        mass = validate_masses(list(masses.values()))
        self._set(focal, mass, merge)

    # -- construction helpers -----------------------------------------------------------
    @staticmethod
    def _elements(key: Any, frame: tuple | None) -> tuple:
        """Return the hypotheses of a focal element.

        A string or a tuple that the frame lists is one hypothesis; otherwise a string is
        the set of its characters and a set, frozenset, tuple or list the set of its
        members.
        """
        if isinstance(key, str | tuple) and frame and key in frame:
            return (key,)
        if isinstance(key, str | set | frozenset | tuple | list):
            return tuple(key)
        return (key,)

    def _mask_of(self, key: Any) -> int:
        elements = self._elements(key, self.frame)
        if not elements:
            raise EvidenceError(
                "the empty set cannot be a focal element (m(∅) = 0); give its mass to "
                "another set or drop it"
            )
        mask = 0
        for h in elements:
            try:
                known = h in self._index
            except TypeError as exc:
                raise EvidenceError(
                    f"hypothesis {h!r} of focal element {key!r} is not "
                    f"hashable: {exc}; use numbers, strings or tuples"
                ) from exc
            if not known:
                raise EvidenceError(
                    f"hypothesis {h!r} of focal element {key!r} is not in the frame "
                    f"{self.frame!r}; add it to the frame or correct the focal element"
                )
            mask |= 1 << self._index[h]
        return mask

    def _with(self, focal: np.ndarray, mass: np.ndarray, *, merge: bool = True) -> MassFunction:
        new = object.__new__(MassFunction)
        new.frame, new._index = self.frame, self._index
        new._set(np.asarray(focal, dtype=np.uint64), np.asarray(mass, dtype=float), merge)
        return new

    def _state(self) -> tuple[Any, ...]:
        merged = self._merged()[0] is self._focal
        return (self.frame, [int(f) for f in self._focal], self._mass.tolist(), merged)

    @classmethod
    def _from_attributes(cls, state: dict[str, Any]) -> MassFunction:
        masks = [int(f) for f in np.asarray(state["_focal"]).reshape(-1)]
        masses = np.asarray(state["_mass"], dtype=float).reshape(-1).tolist()
        return cls._restore(tuple(state["frame"]), masks, masses, False)

    @classmethod
    def _restore(cls, *state: Any) -> MassFunction:
        frame, masks, masses, merge = state
        probe = cls({frozenset(frame): 1.0}, frame)  # checks the frame
        focal = np.array(masks, dtype=object)
        if focal.ndim != 1 or not all(isinstance(f, int) and 0 < f <= probe._full for f in masks):
            raise EvidenceError(
                f"focal elements {masks!r} are not bit masks of non-empty "
                f"subsets of the frame {probe.frame!r}"
            )
        if len(masks) != len(validate_masses(masses)):
            raise EvidenceError(f"{len(masses)} masses for {len(masks)} focal elements")
        return probe._with(
            np.array(masks, dtype=np.uint64), validate_masses(masses), merge=bool(merge)
        )

    @classmethod
    def vacuous(cls, frame: Iterable[Hashable]) -> MassFunction:
        """Total ignorance: m(Θ) = 1.

        Parameters
        ----------
        frame : iterable of hashable
            Θ, the hypotheses.

        Returns
        -------
        MassFunction
            m(Θ) = 1.
        """
        frame = tuple(frame)
        return cls({frozenset(frame): 1.0}, frame)

    @classmethod
    def bayesian(cls, probabilities: Mapping[Hashable, float]) -> MassFunction:
        """Make a mass function on singletons from a probability distribution.

        Parameters
        ----------
        probabilities : mapping of hypothesis to float
            P(θ) for each θ, summing to 1; the frame is
            their keys.

        Returns
        -------
        MassFunction
            m({θ}) = P(θ).
        """
        return cls({frozenset([h]): p for h, p in probabilities.items()}, probabilities)

    # -- primitives -----------------------------------------------------------------------
    @property
    def _full(self) -> int:
        return (1 << len(self.frame)) - 1

    def _check_same_frame(self, other: MassFunction) -> None:
        if other.frame != self.frame:
            raise EvidenceError(
                f"frames differ: {self.frame!r} vs {other.frame!r}; build both mass "
                "functions on the same frame (pass frame=...)"
            )

    def _intersect(self, other: Evidence) -> tuple[np.ndarray, np.ndarray]:
        inter = (self._focal[:, None] & other._focal[None, :]).reshape(-1)
        return inter, inter != 0

    def _sizes(self) -> np.ndarray:
        return _popcount(self._focal)

    def _energy_unit(self, counted: np.ndarray | None = None) -> float:
        return 1.0

    def _counts_in_energy(self) -> np.ndarray:
        return self._focal != np.uint64(self._full)

    def _theta(self) -> np.ndarray:
        return np.array([self._full], dtype=np.uint64)

    def _keys(self) -> np.ndarray:
        return self._focal

    def _check_theta(self, theta: Any) -> np.ndarray:
        """Θ as a bit mask (an int, or a one-element integer array) or as a subset."""
        if isinstance(theta, np.ndarray) and theta.size == 1 and theta.dtype.kind in "iu":
            theta = int(theta.reshape(-1)[0])
        if isinstance(theta, int | np.integer) and not isinstance(theta, bool):
            if not 0 < int(theta) <= self._full:
                raise EvidenceError(
                    f"theta must be the bit mask of a non-empty subset of the frame (1 to "
                    f"{self._full}), got {theta!r}"
                )
            return np.array([int(theta)], dtype=np.uint64)
        return self._query(theta)

    def _subset_mask(self, query: np.ndarray) -> np.ndarray:
        return (self._focal & ~query[0]) == 0

    def _meets_mask(self, query: np.ndarray) -> np.ndarray:
        return (self._focal & query[0]) != 0

    def _query(self, subset: Any) -> np.ndarray:
        return np.array([self._mask_of(subset)], dtype=np.uint64)

    # -- public API -------------------------------------------------------------------------
    def _decode(self, mask: int) -> frozenset:
        return frozenset(h for h, i in self._index.items() if (int(mask) >> i) & 1)

    @property
    def focal_elements(self) -> list[frozenset]:
        """The focal elements, as frozensets of hypotheses."""
        return [self._decode(f) for f in self._focal]

    def as_dict(self) -> dict[frozenset, float]:
        """``{focal element: mass}``, equal focal elements merged (their masses added).

        Returns
        -------
        dict of frozenset to float
            The mass of each focal element.
        """
        focal, mass = self._merged()
        return dict(zip((self._decode(f) for f in focal), mass.tolist(), strict=True))

    def mass_of(self, subset: Any) -> float:
        """m(A) (0 when A is not a focal element).

        Parameters
        ----------
        subset : iterable of hypotheses, or a single hypothesis
            A, a subset of the frame.

        Returns
        -------
        float
            m(A).
        """
        q = self._query(subset)[0]
        return float(self._mass[self._focal == q].sum())

    def belief(self, subset: Any) -> float:
        """Bel(A) = Σ_{B ⊆ A} m(B) (Def. 3).

        Parameters
        ----------
        subset : iterable of hypotheses, or a single hypothesis
            A, a subset of the frame.

        Returns
        -------
        float
            Bel(A) in [0, 1].
        """
        return self._bel(self._query(subset))

    def plausibility(self, subset: Any) -> float:
        """Pl(A) = Σ_{B ∩ A ≠ ∅} m(B) (Def. 3).

        Parameters
        ----------
        subset : iterable of hypotheses, or a single hypothesis
            A, a subset of the frame.

        Returns
        -------
        float
            Pl(A) in [0, 1].
        """
        return self._pl(self._query(subset))

    def commonality(self, subset: Any) -> float:
        """Q(A) = Σ_{B ⊇ A} m(B).

        Parameters
        ----------
        subset : iterable of hypotheses, or a single hypothesis
            A, a subset of the frame.

        Returns
        -------
        float
            Q(A) in [0, 1].
        """
        q = self._query(subset)[0]
        return float(self._mass[(self._focal & q) == q].sum())

    def pignistic(self) -> dict[Hashable, float]:
        """Pignistic probability BetP(θ) = Σ_{A ∋ θ} m(A)/|A| (Smets; eq. 20's discrete form).

        Returns
        -------
        dict of hypothesis to float
            BetP(θ) for every θ of the frame, summing to 1.
        """
        share = self._mass / self._sizes()
        bits = (self._focal[:, None] >> np.arange(len(self.frame), dtype=np.uint64)) & 1
        probs = share @ bits.astype(float)
        return dict(zip(self.frame, probs.tolist(), strict=True))

    def condition(self, subset: Any) -> MassFunction:
        """Dempster conditioning on A: combine with the categorical m(A) = 1.

        Parameters
        ----------
        subset : iterable of hypotheses, or a single hypothesis
            A, a subset of the frame.

        Returns
        -------
        MassFunction
            m(· | A).

        Raises
        ------
        TotalConflictError
            If no focal element meets A.
        """
        from ._combination import dempster

        return dempster(self, MassFunction({self._decode(self._query(subset)[0]): 1.0}, self.frame))

    def __repr__(self) -> str:
        def name(s: frozenset) -> str:
            return "{" + ", ".join(map(str, sorted(s, key=lambda h: self._index[h]))) + "}"

        body = ", ".join(f"{name(s)}: {m:.4g}" for s, m in self.as_dict().items())
        return f"MassFunction({body})"

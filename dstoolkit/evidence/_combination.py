"""Combination rules, written once for every representation of evidence (paper §2.2, App. A).

Dempster's rule (eq. 1), the energy of evidence (eqs. 2, A1), the energy of the
intersection (eqs. 3, A3), the degree of dependence (Def. 5, eq. A4), the dependency
coefficients (eqs. 7–8, A5–A6), discounting and the combination of dependent evidence
(eqs. 9–10, A7–A8). Each works on :class:`~dstoolkit.evidence.MassFunction` and
:class:`~dstoolkit.evidence.IntervalEvidence` alike, through the set primitives of
:class:`~dstoolkit.evidence.Evidence`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, TypeVar

import numpy as np

from dstoolkit._reprs import short_repr
from dstoolkit.errors import EvidenceError, TotalConflictError
from dstoolkit.utils.budget import check_memory
from dstoolkit.utils.checks import real_number

from ._base import Evidence

E = TypeVar("E", bound=Evidence)
#: m(D) in the energy of the intersection (eq. A3): the smaller mass, or one side's.
MassRule = Literal["min", "m1", "m2"]
#: The values of :data:`MassRule`.
MASS_RULES: tuple[str, ...] = ("min", "m1", "m2")
#: Which focal elements the energy counts: ``"paper"`` as the paper defines it (eq. 2 leaves
#: Θ out on a finite frame; eq. A1 counts every bounded interval, Θ = the hull included),
#: ``"left_out"`` leaves Θ out on intervals too (so that the vacuous evidence has energy 0).
ThetaRule = Literal["paper", "left_out"]
#: The values of :data:`ThetaRule`.
THETA_RULES: tuple[str, ...] = ("paper", "left_out")

#: Kept mass 1 − K (summed over the non-empty products, not computed as a difference) at or
#: below this counts as total conflict: the smallest normal float, below which dividing by
#: it would lose precision.
CONFLICT_TOLERANCE = float(np.finfo(float).tiny)


#: Memory per product of Dempster's rule besides twice its focal element's bytes: the
#: intersection, its emptiness, the product mass, the kept rows and the merge of equal focal
#: elements (sort keys, inverse indices). An upper bound of the peak that tracemalloc
#: measures (benchmarks/memory_peaks.py), so that the budget bounds the real peak.
PRODUCT_BYTES = 128


def _products(a: Evidence, b: Evidence) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    _check_evidence(a, "the first evidence")
    _check_evidence(b, "the second evidence")
    a._check_compatible(b)
    row = a._focal.itemsize * (a._focal[0].size if a._focal.ndim > 1 else 1)
    check_memory(
        len(a) * len(b) * (2 * row + PRODUCT_BYTES),
        f"combining {len(a)} by {len(b)} focal elements ({len(a) * len(b)} products)",
        "merge or coarsen the focal elements first (fewer α-cuts, a smaller p)",
    )
    focal, nonempty = a._intersect(b)
    mass = np.multiply.outer(a._mass, b._mass).reshape(-1)
    return focal, mass, nonempty


def _check_evidence(e: object, name: str) -> None:
    if not isinstance(e, Evidence):
        raise EvidenceError(
            f"{name} must be a MassFunction or IntervalEvidence, got {type(e).__name__}"
        )


def conflict(a: Evidence, b: Evidence) -> float:
    """K = Σ_{B ∩ C = ∅} m1(B) m2(C), the mass of conflicting products (eq. 1).

    Parameters
    ----------
    a, b : MassFunction or IntervalEvidence
        E1 and E2, on the same frame (mass functions)
        or of the same dimension d (interval evidence, boxes (n, d)).

    Returns
    -------
    float
        K in [0, 1]; 1 means total conflict (no focal element of E1 meets one of E2).

    Raises
    ------
    EvidenceError
        If ``a`` or ``b`` is not evidence, or the two do not share a frame or dimension.

    See Also
    --------
    dempster : renormalises the products that do not conflict by 1 − K.
    yager : gives K to Θ instead.

    References
    ----------
    The paper's eq. (1).

    Examples
    --------
    >>> from dstoolkit.evidence import MassFunction
    >>> m1 = MassFunction({"a": 0.6, "abc": 0.4})
    >>> m2 = MassFunction({"b": 0.5, "abc": 0.5}, frame=m1.frame)
    >>> round(conflict(m1, m2), 4)
    0.3
    """
    _, mass, nonempty = _products(a, b)
    return float(mass[~nonempty].sum())


def dempster(a: E, b: E, *, merge: bool = True) -> E:
    """Combine two bodies of evidence by Dempster's rule m = m1 ⊕ m2 (eq. 1).

    Products on intersections, renormalised by 1 − K (computed as the sum of the kept
    products, so that the masses sum to 1 however close K comes to 1).

    Parameters
    ----------
    a, b : MassFunction or IntervalEvidence
        E1 and E2, on the same frame (mass functions)
        or of the same dimension d (interval evidence, boxes (n, d)).
    merge : bool
        Merge equal focal elements (default, eq. 14). With ``merge=False`` the
        non-empty products are kept in order (row i·n2 + j is A_i ∩ B_j), as in the
        paper's worked example.

    Returns
    -------
    MassFunction or IntervalEvidence
        m1 ⊕ m2, of the type of ``a``.

    Raises
    ------
    TotalConflictError
        When K = 1: the two bodies of evidence contradict each other entirely.
    EvidenceError
        If ``a`` or ``b`` is not evidence, or the two do not share a frame or dimension.

    See Also
    --------
    conflict : K alone.
    combine_dependent : Dempster's rule after discounting what two sources share.
    yager : the rival that gives K to Θ.

    References
    ----------
    The paper's eq. (1); equal focal elements merge by eq. (14).

    Examples
    --------
    >>> from dstoolkit.evidence import MassFunction
    >>> m1 = MassFunction({"a": 0.6, "abc": 0.4})
    >>> m2 = MassFunction({"b": 0.5, "abc": 0.5}, frame=m1.frame)
    >>> round(conflict(m1, m2), 4)
    0.3
    >>> dempster(m1, m2)
    MassFunction({a}: 0.4286, {b}: 0.2857, {a, b, c}: 0.2857)
    """
    focal, mass, nonempty = _products(a, b)
    kept = mass[nonempty]
    total = float(kept.sum())
    k = float(mass[~nonempty].sum())
    if total <= CONFLICT_TOLERANCE:
        raise TotalConflictError(
            f"total conflict (K = {k:.12g}): no focal element of the first evidence meets "
            "one of the second, so Dempster's rule is undefined; check that both describe "
            "the same quantity, widen the noise bounds, or discount one source first"
        )
    # renormalise by the mass actually kept (= 1 − K in exact arithmetic): 1 − K computed
    # as a difference loses all its digits when K is near 1
    return a._with(focal[nonempty], kept / total, merge=merge)


def product_sources(a: Evidence, b: Evidence) -> tuple[np.ndarray, np.ndarray]:
    """Return the focal elements of ``a`` and ``b`` behind each product Dempster's rule keeps.

    With ``merge=False``, :func:`dempster` keeps the products A_i ∩ B_j (eq. 1) that are
    non-empty and of positive mass, in the order of the rows i·n2 + j: here are their i
    and j, so that a step can follow each product back to its sources (the paper's Step 5
    maps each product back within the predicted box it came from).

    Parameters
    ----------
    a, b : MassFunction or IntervalEvidence
        E1 and E2, as given to :func:`dempster`.

    Returns
    -------
    i, j : ndarray of int
        For each kept product, its focal element of ``a`` and of ``b``.

    Raises
    ------
    EvidenceError
        If ``a`` or ``b`` is not evidence, or the two do not share a frame or dimension.

    Examples
    --------
    >>> from dstoolkit.evidence import IntervalEvidence, product_sources
    >>> a = IntervalEvidence([0.0, 5.0], [2.0, 6.0], [0.5, 0.5])
    >>> b = IntervalEvidence([1.0, 1.5], [3.0, 2.5], [0.5, 0.5])
    >>> [list(map(int, ix)) for ix in product_sources(a, b)]
    [[0, 0], [0, 1]]
    """
    _, mass, nonempty = _products(a, b)
    kept = np.flatnonzero(nonempty & (mass > 0))
    return kept // len(b), kept % len(b)


def _specificity(sizes: np.ndarray, unit: float) -> np.ndarray:
    """Compute unit / size with 0-size elements counting 1 (a point is fully specific)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(sizes > 0, unit / sizes, 1.0)
    return np.where(np.isfinite(sizes), ratio, 0.0)


def _energy_terms(e: Evidence, theta: ThetaRule) -> tuple[np.ndarray, float]:
    """Return the mask of the focal elements that enter the energy, and the unit.

    The unit is the size that counts fully: 1 on a finite frame, the smallest counted width
    on intervals.
    """
    if theta not in THETA_RULES:
        raise EvidenceError(f"theta must be one of {THETA_RULES}, got {theta!r}")
    counts = e._counts_in_energy()
    if theta == "paper":
        return counts, e._energy_unit()
    rows = e._focal.reshape(len(e._mass), -1)
    counts = counts & ~np.all(rows == e._theta().reshape(1, -1), axis=1)
    return counts, e._energy_unit(counts)


def energy(e: Evidence, *, theta: ThetaRule = "paper") -> float:
    """Compute the energy of evidence En(E) = Σ_{A ≠ Θ} m(A)/|A| (eq. 2).

    On intervals En'(E) = Σ m(A_i) w_min / w(A_i) (eq. A1). Always in [0, 1], 1 for a
    Bayesian evidence.

    Parameters
    ----------
    e : MassFunction or IntervalEvidence
        The evidence E.
    theta : {"paper", "left_out"}
        ``"paper"`` (default): the paper's definitions. Eq. 2
        leaves Θ out, so the vacuous mass function has energy 0; eq. A1 counts every bounded
        focal element, the hull (Θ of interval evidence) included, so the vacuous interval
        evidence {Θ: 1} has energy 1. ``"left_out"``: Θ (the frame, or the hull of the focal
        elements) is left out on intervals too, and w_min is the smallest width of the
        others: the vacuous evidence then has energy 0 in both cases, and discounting by R
        multiplies the energy by R, as eq. 5 of the paper assumes.

    Returns
    -------
    float
        En(E) in [0, 1] (dimensionless: widths divide widths).

    Raises
    ------
    EvidenceError
        If ``theta`` is not one of the two rules.

    See Also
    --------
    joint_energy : the energy of what two bodies of evidence share.
    dependence : the degree of dependence built from the energies.

    References
    ----------
    The paper's eqs. (2) and (A1); eq. (A2) is the worked value below.

    Examples
    --------
    >>> from dstoolkit.evidence import IntervalEvidence, MassFunction
    >>> energy(MassFunction({"a": 0.6, "abc": 0.4}))  # Θ = {a, b, c} does not count
    0.6
    >>> energy(MassFunction({"a": 0.5, "b": 0.5}))  # a probability: energy 1
    1.0
    >>> round(energy(IntervalEvidence([-0.3, 0.3], [2.6, 1.9], [0.3, 0.7])), 4)  # eq. A2
    0.8655
    >>> vacuous = IntervalEvidence([-10.0], [10.0], [1.0])
    >>> energy(vacuous), energy(vacuous, theta="left_out")
    (1.0, 0.0)
    """
    counts, unit = _energy_terms(e, theta)
    ratio = _specificity(e._sizes(), unit)
    return float(np.sum(e._mass * ratio * counts))


def _common(a: Evidence, b: Evidence) -> tuple[np.ndarray, np.ndarray]:
    """Find the indices (i, j) of focal elements that a and b share (equal sets or intervals)."""
    ka, kb = a._keys(), b._keys()
    _, ia, ib = np.intersect1d(ka, kb, assume_unique=False, return_indices=True)
    return ia, ib


def joint_energy(
    a: Evidence, b: Evidence, *, mass_rule: MassRule = "min", theta: ThetaRule = "paper"
) -> float:
    """Energy of the intersection En(E1, E2) = Σ_{D ∈ F1 ∩ F2} m(D)·u/|D| (eqs. 3, A3, A9).

    The sum runs over the focal elements common to both, each counted once with its whole
    mass (equal focal elements merged, eq. 14); u = 1 on a finite frame and
    u = min(w_min(E1), w_min(E2)) on intervals. The paper leaves m(D) open:
    ``mass_rule`` = ``"min"`` (default) takes min(m1(D), m2(D)), ``"m1"`` or ``"m2"`` one side.
    ``theta`` as in :func:`energy`: with ``"left_out"`` a common D counts only if it is
    neither evidence's Θ, and the widths w_min are those of :func:`energy`.

    Parameters
    ----------
    a, b : MassFunction or IntervalEvidence
        E1 and E2, on the same frame (mass functions)
        or of the same dimension d (interval evidence, boxes (n, d)).
    mass_rule : {"min", "m1", "m2"}
        The mass m(D) of a common focal element.
    theta : {"paper", "left_out"}
        The energy's definition, as in :func:`energy`.

    Returns
    -------
    float
        En(E1, E2) ≥ 0 (dimensionless); 0 when E1 and E2 share no focal element.

    Raises
    ------
    EvidenceError
        For an unknown ``mass_rule``, or evidence that does not share a frame or dimension.

    See Also
    --------
    energy : the energy of one body of evidence.
    dependence : D, R12 and R21 from the three energies.

    References
    ----------
    The paper's eqs. (3), (A3) and the worked value (A9).

    Examples
    --------
    >>> from dstoolkit.evidence import appendix_pair
    >>> round(joint_energy(*appendix_pair()), 4)  # eq. A9
    0.45
    """
    if mass_rule not in MASS_RULES:
        raise EvidenceError(f"mass_rule must be one of {MASS_RULES}, got {mass_rule!r}")
    _check_evidence(a, "the first evidence")
    _check_evidence(b, "the second evidence")
    a._check_compatible(b)
    a, b = a.merged(), b.merged()  # a focal element counts once, with its whole mass
    counts_a, unit_a = _energy_terms(a, theta)
    counts_b, unit_b = _energy_terms(b, theta)
    ia, ib = _common(a, b)
    if ia.size == 0:
        return 0.0
    ma, mb = a._mass[ia], b._mass[ib]
    m = {"min": np.minimum(ma, mb), "m1": ma, "m2": mb}[mass_rule]
    ratio = _specificity(a._sizes()[ia], min(unit_a, unit_b)) * counts_a[ia] * counts_b[ib]
    return float(np.sum(m * ratio))


@dataclass(frozen=True)
class Dependence:
    """How much two bodies of evidence share (Def. 5, eqs. 5–8, A4–A6).

    Parameters
    ----------
    energy1, energy2 : float
        En(E1) and En(E2) (eq. 2 / A1).
    joint_energy : float
        En(E1, E2) (eq. 3 / A3).
    degree : float
        D (Def. 5, eq. A4).
    r12, r21 : float
        The dependency coefficients (eqs. 7–8, A5–A6).

    See Also
    --------
    dependence : computes it.
    """

    energy1: float
    """En(E1) (eq. 2 / A1)."""
    energy2: float
    """En(E2)."""
    joint_energy: float
    """En(E1, E2), the energy of the intersection (eq. 3 / A3)."""
    degree: float
    """Degree of dependence D = 2 En(E1,E2) / (En(E1) + En(E2)) (Def. 5, eq. A4)."""
    r12: float
    """Dependency coefficient R12 = 1 − (D/2) En(E2)/En(E1) (eq. 7, A5)."""
    r21: float
    """Dependency coefficient R21 = 1 − (D/2) En(E1)/En(E2) (eq. 8, A6)."""

    def __repr__(self) -> str:
        return short_repr(self)

    @property
    def independent_energy1(self) -> float:
        """Final independent energy of E1, Enf(E1) = R12 · En(E1) (eq. 5)."""
        return self.r12 * self.energy1

    @property
    def independent_energy2(self) -> float:
        """Final independent energy of E2, Enf(E2) = R21 · En(E2)."""
        return self.r21 * self.energy2


def dependence(
    a: Evidence,
    b: Evidence,
    *,
    mass_rule: MassRule = "min",
    energy1: float | None = None,
    energy2: float | None = None,
    theta: ThetaRule = "paper",
) -> Dependence:
    """Degree of dependence and dependency coefficients of E1 = ``a`` and E2 = ``b``.

    ``energy1``/``energy2`` override En(E1)/En(E2), e.g. to reproduce the paper's printed
    En'(E1) = 0.8655 in Appendix A. With D = 0 (nothing shared) both coefficients are 1.
    ``theta`` chooses the energy's definition (:func:`energy`); ``"paper"`` by default.

    Parameters
    ----------
    a, b : MassFunction or IntervalEvidence
        E1 and E2, on the same frame (mass functions)
        or of the same dimension d (interval evidence, boxes (n, d)).
    mass_rule : {"min", "m1", "m2"}
        The mass m(D) of a common focal element (eq. A3).
    energy1, energy2 : float in [0, 1], optional
        En(E1) and En(E2) to use instead of computing them.
    theta : {"paper", "left_out"}
        The energy's definition, as in :func:`energy`.

    Returns
    -------
    Dependence
        En(E1), En(E2), En(E1, E2), D, R12 and R21.

    Raises
    ------
    EvidenceError
        For an energy outside [0, 1], energies that share energy while one is 0, or
        coefficients that overflow.

    See Also
    --------
    decorrelate : discounts E1 and E2 by the coefficients.
    combine_dependent : the whole combination of dependent evidence.

    References
    ----------
    The paper's Def. 5 and eqs. (4)–(8), (A4)–(A6).

    Examples
    --------
    E1 and E2 of the paper's Appendix A share the focal element [0.3, 1.9]:

    >>> from dstoolkit.evidence import appendix_pair
    >>> e1, e2 = appendix_pair()
    >>> dep = dependence(e1, e2)
    >>> round(dep.joint_energy, 4), round(dep.degree, 4)
    (0.45, 0.545)
    >>> round(dep.r12, 4), round(dep.r21, 4)
    (0.7522, 0.7003)
    """
    en1 = (
        energy(a, theta=theta)
        if energy1 is None
        else real_number(energy1, "energy1", low=0.0, high=1.0, error=EvidenceError)
    )
    en2 = (
        energy(b, theta=theta)
        if energy2 is None
        else real_number(energy2, "energy2", low=0.0, high=1.0, error=EvidenceError)
    )
    joint = joint_energy(a, b, mass_rule=mass_rule, theta=theta)
    if joint > 0 and min(en1, en2) <= 0:
        raise EvidenceError(
            f"energy1 = {en1:g} and energy2 = {en2:g} with a joint energy of {joint:.4g}: an "
            "evidence that shares energy has some; give positive energies (or leave them out)"
        )
    total = en1 + en2
    degree = 2.0 * joint / total if total > 0 else 0.0
    r12 = 1.0 - 0.5 * degree * en2 / en1 if degree > 0 else 1.0
    r21 = 1.0 - 0.5 * degree * en1 / en2 if degree > 0 else 1.0
    if not (math.isfinite(r12) and math.isfinite(r21)):
        raise EvidenceError(
            f"energy1 = {en1:.3g} and energy2 = {en2:.3g} are too far apart for the shared "
            f"energy {joint:.3g}: the dependency coefficients (eqs. 7–8) overflow; give "
            "energies of the evidences' own size (or leave them out)"
        )
    return Dependence(en1, en2, joint, degree, r12, r21)


def discount(e: E, rate: float, theta: np.ndarray | None = None) -> E:
    """Classical discounting: m'(A) = (1 − rate)·m(A), and m'(Θ) gains ``rate`` (eqs. 9–10).

    Θ is the frame for a mass function and, by default, the hull of the focal elements for
    interval evidence (eqs. A7–A8); pass ``theta`` (one focal-element row: a bit mask, or
    ``[lo..., hi...]``) to discount onto another Θ.

    Parameters
    ----------
    e : MassFunction or IntervalEvidence
        The evidence to discount.
    rate : float in [0, 1]
        The discount rate 1 − R, R the reliability of the source.
    theta : ndarray, optional
        Θ as one focal-element row: a boolean mask over the frame,
        or ``[lo..., hi...]`` (2d numbers) for interval evidence.

    Returns
    -------
    MassFunction or IntervalEvidence
        The discounted evidence, of the type of ``e``.

    Raises
    ------
    EvidenceError
        If ``rate`` lies outside [0, 1] or ``theta`` is not a focal element of the frame.

    See Also
    --------
    decorrelate : discounts two dependent bodies of evidence by their coefficients.

    References
    ----------
    The paper's eqs. (9)–(10) and (A7)–(A8).

    Examples
    --------
    >>> from dstoolkit.evidence import MassFunction
    >>> discount(MassFunction({"a": 0.6, "abc": 0.4}), 0.5)
    MassFunction({a}: 0.3, {a, b, c}: 0.7)
    """
    _check_evidence(e, "the evidence")
    try:
        rate = real_number(rate, "rate", low=0.0, high=1.0, error=EvidenceError)
    except EvidenceError as exc:
        raise EvidenceError(
            f"discount {exc}; a reliability R corresponds to rate = 1 − R"
        ) from None
    theta_row = e._theta() if theta is None else e._check_theta(theta)
    focal = np.concatenate([e._focal, theta_row.reshape(1, *e._focal.shape[1:])])
    mass = np.append((1.0 - rate) * e._mass, rate)
    return e._with(focal, mass)


def decorrelate(
    a: E,
    b: E,
    *,
    mass_rule: MassRule = "min",
    energy1: float | None = None,
    energy2: float | None = None,
    theta: ThetaRule = "paper",
) -> tuple[E, E, Dependence]:
    """Discount E1 by R12 and E2 by R21 so they can be combined as if independent.

    Parameters
    ----------
    a, b : MassFunction or IntervalEvidence
        E1 and E2, on the same frame (mass functions)
        or of the same dimension d (interval evidence, boxes (n, d)).
    mass_rule, energy1, energy2, theta
        As in :func:`dependence`.

    Returns
    -------
    tuple of (evidence, evidence, Dependence)
        E1 discounted at rate 1 − R12, E2 at rate 1 − R21, and the :class:`Dependence`.

    Raises
    ------
    EvidenceError
        If a coefficient lies outside [0, 1] (``mass_rule="m2"`` can do that), or as
        :func:`dependence` raises.

    See Also
    --------
    dependence : the coefficients alone.
    combine_dependent : this, then Dempster's rule.

    References
    ----------
    The paper's eqs. (9)–(10) and (A7)–(A8).

    Examples
    --------
    >>> from dstoolkit.evidence import appendix_pair
    >>> e1, e2, dep = decorrelate(*appendix_pair())
    >>> round(dep.r12, 4), round(float(e1.mass.sum()), 4)
    (0.7522, 1.0)
    """
    dep = dependence(a, b, mass_rule=mass_rule, energy1=energy1, energy2=energy2, theta=theta)
    for name, r in (("R12", dep.r12), ("R21", dep.r21)):
        if not 0.0 <= r <= 1.0:
            raise EvidenceError(
                f"dependency coefficient {name} = {r:.4g} lies outside [0, 1] with "
                f"mass_rule={mass_rule!r} (degree of dependence D = {dep.degree:.4g}); "
                "such a coefficient is not a discount factor; use mass_rule='min'"
            )
    return discount(a, 1.0 - dep.r12), discount(b, 1.0 - dep.r21), dep


def combine_dependent(
    a: E,
    b: E,
    *,
    mass_rule: MassRule = "min",
    energy1: float | None = None,
    energy2: float | None = None,
    merge: bool = True,
    theta: ThetaRule = "paper",
) -> E:
    """Combine dependent evidence (§2.2, eqs. 9–10; App. A, eqs. A7–A8).

    Decorrelate both by their dependency coefficients, then apply Dempster's rule (eq. 1).
    ``theta`` chooses the energy's definition (:func:`energy`): the paper's by default.

    Parameters
    ----------
    a, b : MassFunction or IntervalEvidence
        E1 and E2, on the same frame (mass functions)
        or of the same dimension d (interval evidence, boxes (n, d)).
    mass_rule, energy1, energy2, theta
        As in :func:`dependence`.
    merge : bool
        Merge equal focal elements of the result (eq. 14), as in :func:`dempster`.

    Returns
    -------
    MassFunction or IntervalEvidence
        The combination, of the type of ``a``.

    Raises
    ------
    TotalConflictError
        When the discounted bodies of evidence conflict totally.
    EvidenceError
        As :func:`decorrelate` raises.

    See Also
    --------
    decorrelate : the discounting step.
    dempster : the combination of independent evidence.

    References
    ----------
    The paper's §2.2, eqs. (9)–(10), and Appendix A, eqs. (A7)–(A8).

    Examples
    --------
    >>> from dstoolkit.evidence import appendix_pair
    >>> e1, e2 = appendix_pair()
    >>> combined = combine_dependent(e1, e2)
    >>> len(combined), round(combined.pignistic_expectation_1d(), 4)
    (5, 1.1355)
    """
    a2, b2, _ = decorrelate(
        a, b, mass_rule=mass_rule, energy1=energy1, energy2=energy2, theta=theta
    )
    return dempster(a2, b2, merge=merge)


def yager(a: E, b: E) -> E:
    """Yager's rule: the conflict K goes to Θ instead of being normalised away.

    It equals Dempster's result discounted at rate K (same products, then K to Θ); under
    total conflict (K = 1) everything goes to Θ.

    Parameters
    ----------
    a, b : MassFunction or IntervalEvidence
        E1 and E2, on the same frame (mass functions)
        or of the same dimension d (interval evidence, boxes (n, d)).

    Returns
    -------
    MassFunction or IntervalEvidence
        The combination, of the type of ``a``.

    Raises
    ------
    EvidenceError
        If ``a`` or ``b`` is not evidence, or the two do not share a frame or dimension.

    See Also
    --------
    dempster : normalises K away instead.

    References
    ----------
    Yager, Inf. Sci. 41 (1987); a rival of the paper's eq. (1).

    Examples
    --------
    >>> from dstoolkit.evidence import MassFunction
    >>> m1 = MassFunction({"a": 0.6, "abc": 0.4})
    >>> yager(m1, MassFunction({"b": 0.5, "abc": 0.5}, frame=m1.frame))
    MassFunction({a}: 0.3, {b}: 0.2, {a, b, c}: 0.5)
    """
    k = conflict(a, b)
    try:
        fused = dempster(a, b)
    except TotalConflictError:
        return discount(a, 1.0)
    return discount(fused, k)

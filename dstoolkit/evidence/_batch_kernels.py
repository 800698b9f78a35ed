"""Interval-evidence algebra on raw arrays with a leading run axis (for batch filters).

The object path (:class:`~dstoolkit.IntervalEvidence` with :mod:`dstoolkit.combination`)
merges equal focal elements; these kernels never merge, so every run of a batch keeps the
same number of focal elements and a whole batch is one numpy expression. Layout: boxes
``lo``/``hi`` of shape (R, N, d) and masses (R, N) (a mass row of shape (1, N) broadcasts).
Entries of mass 0 are placeholders (e.g. conflicting products): they are ignored.

Merging changes nothing here, because

- Dempster's rule (eq. 1), K and the pignistic expectation (eq. 20) are sums of products
  over focal elements: splitting a mass over copies of a focal element splits each term;
- the energy (eq. A1) is Σ m·u/w with u = the smallest width, equally additive;
- the energy of the intersection (eq. A3) takes min(m1(D), m2(D)) (or one side) of the
  *merged* masses of each common D: :func:`dependence` recovers them with equality
  matrices — m1(D) = Σ_i [A_i = D] m1_i, m2(D) likewise — and spreads each D's term over
  D's copies in E2 by m2_j / m2(D);
- discounting onto Θ = the hull (eqs. A7–A8) appends Θ as one more focal element; if Θ
  equals an existing one the object path merges them, with the same products.

``tests/test_dependent_filter.py`` checks all of this against the object path.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from dstoolkit.errors import EvidenceError

from ._combination import CONFLICT_TOLERANCE, MASS_RULES, MassRule


class Boxes(NamedTuple):
    """Focal elements ``lo``, ``hi`` (R, N, d) with masses ``mass`` (R, N)."""

    lo: np.ndarray
    hi: np.ndarray
    mass: np.ndarray


class BatchDependence(NamedTuple):
    """Per-run energies, degree of dependence and coefficients (Def. 5, eqs. A1–A6)."""

    energy1: np.ndarray
    energy2: np.ndarray
    joint_energy: np.ndarray
    degree: np.ndarray
    r12: np.ndarray
    r21: np.ndarray


def dempster(a: Boxes, b: Boxes) -> tuple[Boxes, np.ndarray, np.ndarray]:
    """Dempster's rule (eq. 1) per run, products in order i·N_b + j, not merged.

    Returns the combined boxes (empty products keep mass 0), the conflict K (R,) and a
    mask (R,) of runs whose combination exists (1 − K above the tolerance); runs in total
    conflict get all-zero masses and the caller applies its policy.
    """
    d = a.lo.shape[-1]
    lo = np.maximum(a.lo[:, :, None], b.lo[:, None])
    lo = lo.reshape(lo.shape[0], -1, d)
    hi = np.minimum(a.hi[:, :, None], b.hi[:, None]).reshape(lo.shape)
    nonempty = (lo[..., 0] <= hi[..., 0]) if d == 1 else (lo <= hi).all(axis=-1)
    products = a.mass[:, :, None] * b.mass[:, None]
    mass = products.reshape(products.shape[0], -1) * nonempty
    kept = mass.sum(axis=-1)
    ok = kept > CONFLICT_TOLERANCE
    if ok.all():
        mass /= kept[:, None]
    else:
        mass /= np.where(ok, kept, 1.0)[:, None]
        mass[~ok] = 0.0
    return Boxes(lo, hi, mass), 1.0 - kept, ok


def sizes(e: Boxes) -> np.ndarray:
    """Width (d = 1) or volume of each box, (R, N)."""
    w = e.hi - e.lo
    return w[..., 0] if w.shape[-1] == 1 else np.prod(w, axis=-1)


#: Added to both sides of a ratio so that 0/0 reads 0 (or 1 for a point): far below the
#: resolution of any non-zero width or energy, it leaves every other ratio bit-identical.
TINY = 1e-300


def specificity(w: np.ndarray, unit: np.ndarray) -> np.ndarray:
    """u / w per focal element (eqs. A1, A3), as :func:`dstoolkit.combination._specificity`:
    a point counts 1 when u = 0, an unbounded box 0. Every live w is ≥ u (u is the smallest
    live width); placeholders of mass 0 get a finite value."""
    return (unit + TINY) / (np.maximum(w, unit) + TINY)


def energy(e: Boxes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """En'(E) = Σ m_i w_min / w_i (eq. A1) per run; also w_min (R,) and the widths."""
    w = sizes(e)
    unit = np.where(e.mass > 0, w, np.inf).min(axis=-1)
    return (e.mass * specificity(w, unit[:, None])).sum(axis=-1), unit, w


def equal_boxes(a: Boxes, b: Boxes) -> np.ndarray:
    """[A_i = B_j], shape (R, N_a, N_b) (masses not looked at)."""
    same = (a.lo[:, :, None] == b.lo[:, None]) & (a.hi[:, :, None] == b.hi[:, None])
    return same[..., 0] if same.shape[-1] == 1 else same.all(axis=-1)


def dependence(a: Boxes, b: Boxes, mass_rule: MassRule = "min", *, check: bool = True
               ) -> BatchDependence:
    """Energies, energy of the intersection, D, R12, R21 of E1 = a, E2 = b per run
    (Def. 5, eqs. A1, A3–A6), equal to :func:`dstoolkit.dependence` on the merged evidence.

    E2's masses must be positive (E1 may hold mass-0 placeholders). With ``check``, raises
    EvidenceError when a coefficient leaves [0, 1] (``mass_rule="m2"`` can do that), as
    :func:`dstoolkit.decorrelate` does.
    """
    if mass_rule not in MASS_RULES:
        raise EvidenceError(f"mass_rule must be one of {MASS_RULES}, got {mass_rule!r}")
    en1, unit1, _ = energy(a)
    en2, unit2, w2 = energy(b)
    # m1(D) and m2(D) of the merged evidence, seen from each focal element B_j of E2
    on_b = (a.mass[:, None] @ equal_boxes(a, b))[:, 0]
    merged_b = (equal_boxes(b, b) @ b.mass[..., None])[..., 0]
    if mass_rule == "min":
        m_d = np.minimum(on_b, merged_b)
    else:  # "m1" is 0 off the common elements by itself, "m2" is not
        m_d = on_b if mass_rule == "m1" else merged_b * (on_b > 0)
    share = b.mass / merged_b  # spreads D's term over its copies in E2
    joint = (share * m_d * specificity(w2, np.minimum(unit1, unit2)[:, None])).sum(axis=-1)
    # as dstoolkit.dependence computes them; TINY turns 0/0 into 0 (no energy: D = 0, R = 1)
    degree = 2.0 * joint / (en1 + en2 + TINY)
    r12 = 1.0 - 0.5 * degree * en2 / (en1 + TINY)
    r21 = 1.0 - 0.5 * degree * en1 / (en2 + TINY)
    if check and (r12.min() < 0.0 or r21.min() < 0.0):  # D, En ≥ 0 keep R ≤ 1
        _coefficient_error(r12, r21, degree, mass_rule)
    return BatchDependence(en1, en2, joint, degree, r12, r21)


def _coefficient_error(r12: np.ndarray, r21: np.ndarray, degree: np.ndarray,
                       mass_rule: str) -> None:
    for name, r in (("R12", r12), ("R21", r21)):
        bad = ~((r >= 0.0) & (r <= 1.0))
        if bad.any():
            run = int(np.flatnonzero(bad)[0])
            raise EvidenceError(
                f"dependency coefficient {name} = {r[run]:.4g} lies outside [0, 1] with "
                f"mass_rule={mass_rule!r} (degree of dependence D = {degree[run]:.4g}, run "
                f"{run}); such a coefficient is not a discount factor; use mass_rule='min'"
            )


def hull(e: Boxes) -> tuple[np.ndarray, np.ndarray]:
    """Smallest box holding every positive-mass focal element, (R, d) each."""
    live = e.mass > 0
    if live.all():
        return e.lo.min(axis=1), e.hi.max(axis=1)
    return (np.where(live[..., None], e.lo, np.inf).min(axis=1),
            np.where(live[..., None], e.hi, -np.inf).max(axis=1))


def discount_onto_hull(e: Boxes, reliability: np.ndarray) -> Boxes:
    """m'(A) = R·m(A), m'(Θ) = 1 − R with Θ the hull of E (eqs. 9–10, A7–A8), per run."""
    h_lo, h_hi = hull(e)
    rel = reliability[:, None]
    return Boxes(np.concatenate([e.lo, h_lo[:, None]], axis=1),
                 np.concatenate([e.hi, h_hi[:, None]], axis=1),
                 np.concatenate([e.mass * rel, 1.0 - rel], axis=1))


def dempster_expectation(
    a: Boxes, b: Boxes, bounds: bool = False
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray] | None]:
    """Pignistic expectation (eq. 20) of Dempster's combination (eq. 1) of a and b, per run,
    without forming the N_a·N_b products' masses:

        E = Σ_ij m_a(i) m_b(j) [A_i ∩ B_j ≠ ∅] c(A_i ∩ B_j) / (1 − K),  c = the centre,

    two mass-weighted sums over the intersection matrix. Returns E (R, d), K (R,), the mask
    of runs with K < 1, and with ``bounds`` the hull of the combination (R, d) twice.
    """
    lo = np.maximum(a.lo[:, :, None], b.lo[:, None])  # (R, N_a, N_b, d)
    hi = np.minimum(a.hi[:, :, None], b.hi[:, None])
    nonempty = (lo[..., 0] <= hi[..., 0]) if lo.shape[-1] == 1 else (lo <= hi).all(axis=-1)
    left, right = a.mass[:, None, None], b.mass[:, None, :, None]  # (R, 1, 1, N_a), (R, 1, N_b, 1)
    centres = np.where(nonempty[..., None], lo + hi, 0.0).transpose(0, 3, 1, 2)  # (R,d,Na,Nb)
    kept = (left[:, 0] @ nonempty.astype(float) @ right[:, 0])[:, 0, 0]
    ok = kept > CONFLICT_TOLERANCE
    total = (left @ centres @ right)[..., 0, 0]  # (R, d)
    expectation = 0.5 * total / np.where(ok, kept, 1.0)[:, None]
    if not bounds:
        return expectation, 1.0 - kept, ok, None
    live = (nonempty & (a.mass[:, :, None] > 0) & (b.mass[:, None] > 0))[..., None]
    return expectation, 1.0 - kept, ok, (np.where(live, lo, np.inf).min(axis=(1, 2)),
                                         np.where(live, hi, -np.inf).max(axis=(1, 2)))


def pignistic_expectation(e: Boxes) -> np.ndarray:
    """Σ m(A_j)(a_j⁻ + a_j⁺)/2 per run (eq. 20), shape (R, d); masses must sum to 1."""
    return 0.5 * np.einsum("rn,rnd->rd", e.mass, e.lo + e.hi)

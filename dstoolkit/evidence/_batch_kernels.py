"""Interval-evidence algebra on raw arrays with a leading run axis (for batch filters).

The object path (:class:`~dstoolkit.IntervalEvidence` with :mod:`dstoolkit.evidence`)
merges equal focal elements; these kernels never merge, so every run of a batch keeps the
same number of focal elements and a whole batch is one numpy expression. Layout:
:class:`~dstoolkit.evidence.Boxes`, boxes ``lo``/``hi`` of shape (R, N, d) and masses
(R, N) (a mass row of shape (1, N) broadcasts); entries of mass 0 are placeholders (e.g.
conflicting products): they are ignored. The hull and the pignistic expectation are those
of :mod:`dstoolkit.evidence._boxes`.

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

from ._boxes import Boxes, hull, pignistic_expectation  # noqa: F401 (kernels of this layout)
from ._combination import CONFLICT_TOLERANCE, MASS_RULES, MassRule


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


def dependence_rows(lo: np.ndarray, hi: np.ndarray, masses: np.ndarray, e2: slice,
                    mass_rule: MassRule, out: np.ndarray) -> np.ndarray:
    """En'(E1), En'(E2), En'(E1, E2), D, R12, R21 (Def. 5, eqs. A1, A3–A6) per run into
    ``out`` (R, 6), for E1 and E2 held as the rows of one array.

    ``lo``, ``hi`` (R, N, d) hold E1's rows, then E2's from ``e2.start`` on; ``masses``
    (R, 2, N) holds E1's masses in row 0 (0 on E2's rows) and E2's in row 1 (0 on E1's).
    Rows of mass 0 are ignored, but E2's rows ``e2`` must have positive mass. One pass
    then gives both energies, and one matrix product m1(D) and m2(D) of every focal
    element D of E2 (the merged masses, recovered with equality matrices).

    With u the smallest live width of an evidence, every live width w is ≥ u, so the
    specificity u/w of eqs. A1 and A3 is (u + ε)/(w + ε), ε = :data:`TINY` (a point
    counts 1 when u = 0, an unbounded box 0); u + ε is taken out of each sum.
    """
    d = lo.shape[-1]
    split = e2.start
    # [A_i = B_j] for every row against E2's rows
    if d == 1:
        same = np.equal(lo[:, :, None, 0], lo[:, None, e2, 0])
        same &= hi[:, :, None, 0] == hi[:, None, e2, 0]
    else:
        same = ((lo[:, :, None] == lo[:, None, e2]) & (hi[:, :, None] == hi[:, None, e2])
                ).all(axis=-1)
    on_b, merged_b = np.matmul(masses, same, dtype=float).transpose(1, 0, 2)
    # energies (eq. A1) of E1 and E2 in one pass
    widths = hi - lo
    widths = widths[..., 0] if d == 1 else np.prod(widths, axis=-1)
    all_mass = np.add(masses[:, 0], masses[:, 1])
    segments = np.array([0, split])
    units = np.minimum.reduceat(np.where(all_mass > 0, widths, np.inf), segments, axis=1)
    units += TINY
    widths += TINY
    np.divide(all_mass, widths, out=all_mass)
    np.multiply(units, np.add.reduceat(all_mass, segments, axis=1), out=out[:, 0:2])
    # energy of the intersection (eq. A3): Σ_j m2_j/m2(D_j) · m(D_j) · u12/w_j
    if mass_rule == "min":
        m_d = np.minimum(on_b, merged_b)
    else:  # "m1" is 0 off the common elements by itself, "m2" is not
        m_d = on_b if mass_rule == "m1" else merged_b * (on_b > 0)
    m_d *= masses[:, 1, e2]
    m_d /= merged_b
    m_d /= widths[:, e2]
    np.multiply(units.min(axis=1), np.add.reduce(m_d, axis=1), out=out[:, 2])
    # D (eq. A4), R12 = 1 − D/2 · En'(E2)/En'(E1), R21 likewise (eqs. A5–A6); TINY turns
    # 0/0 into 0 (no energy: D = 0, R = 1)
    energies = out[:, 0:2]
    total = np.add.reduce(energies, axis=1)
    total += TINY
    np.divide(2.0 * out[:, 2], total, out=out[:, 3])
    ratio = np.multiply(0.5 * out[:, 3, None], energies[:, ::-1])
    ratio /= energies + TINY
    np.subtract(1.0, ratio, out=out[:, 4:6])
    return out


def dependence(a: Boxes, b: Boxes, mass_rule: MassRule = "min", *, check: bool = True
               ) -> BatchDependence:
    """Energies, energy of the intersection, D, R12, R21 of E1 = a, E2 = b per run
    (Def. 5, eqs. A1, A3–A6), equal to :func:`dstoolkit.dependence` on the merged evidence
    (:func:`dependence_rows` on the rows of a then b).

    E2's masses must be positive (E1 may hold mass-0 placeholders). With ``check``, raises
    EvidenceError when a coefficient leaves [0, 1] (``mass_rule="m2"`` can do that), as
    :func:`dstoolkit.decorrelate` does.
    """
    if mass_rule not in MASS_RULES:
        raise EvidenceError(f"mass_rule must be one of {MASS_RULES}, got {mass_rule!r}")
    runs = max(a.lo.shape[0], b.lo.shape[0])
    na, nb, d = a.lo.shape[1], b.lo.shape[1], a.lo.shape[2]
    lo = np.concatenate([np.broadcast_to(a.lo, (runs, na, d)),
                         np.broadcast_to(b.lo, (runs, nb, d))], axis=1)
    hi = np.concatenate([np.broadcast_to(a.hi, (runs, na, d)),
                         np.broadcast_to(b.hi, (runs, nb, d))], axis=1)
    masses = np.zeros((runs, 2, na + nb))
    masses[:, 0, :na], masses[:, 1, na:] = a.mass, b.mass
    out = dependence_rows(lo, hi, masses, slice(na, na + nb), mass_rule, np.empty((runs, 6)))
    if check and out[:, 4:6].min() < 0.0:  # D, En ≥ 0 keep R ≤ 1
        _coefficient_error(out[:, 4], out[:, 5], out[:, 3], mass_rule)
    return BatchDependence(*out.T)


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


def discount_onto_hull(e: Boxes, reliability: np.ndarray) -> Boxes:
    """m'(A) = R·m(A), m'(Θ) = 1 − R with Θ the hull of E (eqs. 9–10, A7–A8), per run."""
    h_lo, h_hi = hull(e)
    rel = reliability[:, None]
    return Boxes(np.concatenate([e.lo, h_lo[:, None]], axis=1),
                 np.concatenate([e.hi, h_hi[:, None]], axis=1),
                 np.concatenate([e.mass * rel, 1.0 - rel], axis=1))


class ProductWork(NamedTuple):
    """Buffers of :func:`dempster_expectation`: the products' ends ``lo``, ``hi``
    (R, d, N_a, N_b) and ``stack`` (R, 1 + d, N_a, N_b) = [nonempty, lo + hi]."""

    lo: np.ndarray
    hi: np.ndarray
    stack: np.ndarray

    @classmethod
    def allocate(cls, runs: int, d: int, na: int, nb: int) -> ProductWork:
        lo = np.empty((runs, d, na, nb))
        return cls(lo, np.empty_like(lo), np.empty((runs, 1 + d, na, nb)))


def dempster_expectation(
    a: Boxes, b: Boxes, bounds: bool = False, *, work: ProductWork | None = None,
    theta_last: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray] | None]:
    """Pignistic expectation (eq. 20) of Dempster's combination (eq. 1) of a and b, per run,
    without forming the N_a·N_b products' masses:

        E = Σ_ij m_a(i) m_b(j) [A_i ∩ B_j ≠ ∅] c(A_i ∩ B_j) / (1 − K),  c = the centre,

    two matrix products with the stack [nonempty, 2c] of the intersection matrix. Returns
    E (R, d), K (R,), the mask of runs with K < 1, and with ``bounds`` the hull of the
    combination (R, d) twice. ``work`` reuses buffers (:meth:`ProductWork.allocate`).
    ``theta_last`` tells that the last focal element of a and of b holds all the others (as
    after :func:`discount_onto_hull`): where both keep mass and meet, their intersection
    is then the hull.
    """
    runs = max(a.lo.shape[0], b.lo.shape[0])
    na, nb, d = a.lo.shape[1], b.lo.shape[1], a.lo.shape[2]
    lo, hi, stack = work if work is not None else ProductWork.allocate(runs, d, na, nb)
    a_lo, a_hi = a.lo.transpose(0, 2, 1)[..., None], a.hi.transpose(0, 2, 1)[..., None]
    b_lo, b_hi = b.lo.transpose(0, 2, 1)[:, :, None], b.hi.transpose(0, 2, 1)[:, :, None]
    np.maximum(a_lo, b_lo, out=lo)
    np.minimum(a_hi, b_hi, out=hi)
    nonempty, centres = stack[:, 0], stack[:, 1:]
    if d == 1:
        np.less_equal(lo[:, 0], hi[:, 0], out=nonempty)
    else:
        nonempty[...] = np.logical_and.reduce(lo <= hi, axis=1)
    np.add(lo, hi, out=centres)
    centres *= nonempty[:, None]
    sums = (a.mass[:, None, None] @ stack @ b.mass[:, None, :, None])[..., 0, 0]
    kept, total = sums[:, 0], sums[:, 1:]
    expectation = 0.5 * total
    if kept.min() > CONFLICT_TOLERANCE:
        ok = np.ones(runs, dtype=bool)
        expectation /= kept[:, None]
    else:
        ok = kept > CONFLICT_TOLERANCE
        expectation /= np.where(ok, kept, 1.0)[:, None]
    if not bounds:
        return expectation, 1.0 - kept, ok, None
    if (theta_last and a.mass[:, -1].min() > 0.0 and b.mass[:, -1].min() > 0.0
            and nonempty[:, -1, -1].min() > 0.0):
        return expectation, 1.0 - kept, ok, (lo[:, :, -1, -1].copy(), hi[:, :, -1, -1].copy())
    mass = a.mass[:, :, None] * b.mass[:, None] * nonempty
    products = Boxes(lo.reshape(runs, d, -1).transpose(0, 2, 1),
                     hi.reshape(runs, d, -1).transpose(0, 2, 1), mass.reshape(runs, -1))
    return expectation, 1.0 - kept, ok, hull(products)

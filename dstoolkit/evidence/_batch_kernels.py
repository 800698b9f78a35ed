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

Step 6 of the paper's filter runs on a second layout, the *columns* (:func:`columns`):
boxes (R, 2, d, N) with the focal elements last, so that each comparison and product of
focal elements is one call along a long axis. :class:`DependenceKernel` (eqs. A1–A6) and
:class:`ProductKernel` (eqs. 1, 20) bind their buffers and views once and then cost only
their numpy calls; :func:`dependence` and :func:`dempster_expectation` run them on Boxes.

``tests/test_dependent_filter.py`` checks all of this against the object path.
"""

from __future__ import annotations

from typing import Any, NamedTuple

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


def sizes(e: Boxes) -> np.ndarray:
    """Width (d = 1) or volume of each box.

    Parameters
    ----------
    e : Boxes
        Boxes (R, N, d) and masses (R, N); mass-0 entries are ignored.

    Returns
    -------
    ndarray, shape (R, N)
        The sizes (the variable's unit to the power d).

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.evidence.boxes import Boxes
    >>> b = Boxes(np.array([[[0.0], [1.0]]]), np.array([[[2.0], [3.0]]]),
    ...           np.array([[0.5, 0.5]]))
    >>> sizes(b)
    array([[2., 2.]])
    """
    w = e.hi - e.lo
    return w[..., 0] if w.shape[-1] == 1 else np.prod(w, axis=-1)


#: Added to both sides of a ratio so that 0/0 reads 0 (or 1 for a point): far below the
#: resolution of any non-zero width or energy, it leaves every other ratio bit-identical.
TINY = 1e-300


def least(values: np.ndarray) -> float:
    """Return the smallest of ``values`` (NaN if one is NaN), as a float.

    One element is read directly (cheaper than a reduction).
    """
    return values.item() if values.size == 1 else float(np.minimum.reduce(values, axis=None))


def per_run(values: np.ndarray) -> Any:
    """Return ``values`` (R,) as a column (R, 1) that broadcasts over each run's row.

    For one run, return a float (a numpy scalar operand costs as much as an array).
    """
    return values.item() if values.size == 1 else values[:, None]


def columns(e: Boxes) -> np.ndarray:
    """Lay out boxes (R, N, d) in the column layout (R, 2, d, N) of the Step 6 kernels.

    The ends (lo, hi) lie on axis 1, the focal elements last, so that every product and
    comparison of focal elements runs along a long, contiguous last axis.
    """
    return np.stack([e.lo, e.hi], axis=1).transpose(0, 1, 3, 2)


class DependenceKernel:
    """En'(E1), En'(E2), En'(E1, E2), D, R12, R21 (Def. 5, eqs. A1, A3–A6) per run.

    Computed on buffers and views bound once, for E1 and E2 held as the columns of one
    array.

    ``cols`` (R, 2, d, N) holds E1's focal elements in columns [0, n1) and E2's after;
    ``masses`` (R, 2, N) E1's masses in row 0 (0 on E2's columns) and E2's in row 1 (0 on
    E1's); ``live`` (R, n1) marks E1's columns of positive mass (None: all; E2's masses
    must be positive). :meth:`compute` writes the six figures into the rows of ``out``
    (6, R) and 1 − R12, 1 − R21 (the masses the discounting gives Θ1, Θ2, eqs. A7–A8)
    into ``theta_mass`` (R, 2); the arrays may change between calls, the buffers not.

    One pass gives both energies, and one matrix product with the equality matrix of
    every column against E2's gives m1(D) and m2(D) of each focal element D of E2 (the
    merged masses, recovered without merging). With u the smallest live width of an
    evidence, every live width w is ≥ u, so the specificity u/w of eqs. A1 and A3 is
    (u + ε)/(w + ε), ε = :data:`TINY` (a point counts 1 when u = 0, an unbounded box 0).
    """

    def __init__(
        self,
        cols: np.ndarray,
        masses: np.ndarray,
        n1: int,
        mass_rule: MassRule,
        out: np.ndarray,
        theta_mass: np.ndarray,
        live: np.ndarray | None = None,
    ) -> None:
        runs, _, d, n = cols.shape
        n2 = n - n1
        self.d, self.n1, self.rule, self.live = d, n1, mass_rule, live
        self.lo, self.hi, self.masses = cols[:, 0], cols[:, 1], masses
        self.width = np.empty((runs, d, n))
        """Widths per component, (R, d, N): an empty box has a negative one."""
        self.volume = self.width[:, 0] if d == 1 else np.empty((runs, n))
        self.wt = np.empty((runs, n))
        self.share = np.empty((runs, 2, n))
        self.units, self.sums = np.empty((runs, 2)), np.empty((runs, 3))
        self.e2 = cols[:, :, :, n1:, None]
        self.all = cols[:, :, :, None, :]
        self.equal = np.empty((2 * d, runs, n2, n), dtype=bool)  # one block an end
        self.equal_ends = self.equal.reshape(2, d, runs, n2, n).transpose(2, 0, 1, 3, 4)
        self.equal_lo, self.equal_hi = self.equal[0], self.equal[-1]  # d = 1
        self.same = np.empty((runs, n2, n))
        self.common = np.empty((runs, n2, 2))
        self.on, self.merged = self.common[..., 0], self.common[..., 1]
        self.m_d, self.weight = np.empty((runs, n2)), np.empty((runs, n2))
        # views made once: a step then costs only its numpy calls
        self.wt_rows, self.energy_sums = self.wt[:, None], self.sums[:, :2]
        self.widths = (self.volume[:, :n1], self.volume[:, n1:])
        self.unit_outs = (self.units[:, 0], self.units[:, 1])
        self.masses_t = masses.transpose(0, 2, 1)
        self.e2_share, self.joint_sum = self.share[:, 1, n1:], self.sums[:, 2]
        self.single = runs == 1
        # where the figures go: one run's as a row of floats, else as arrays (R,)
        self.figures = (out[:, 0], theta_mass[0]) if self.single else (out, theta_mass.T)
        self.coefficients = out[4:6]

    def compute(self) -> bool:
        """Fill ``out`` and ``theta_mass`` from the current columns and masses.

        Returns whether R12 and R21 lie in [0, 1] in every run (``mass_rule="m2"`` can
        break that: D, En ≥ 0 keep R ≤ 1). ``units[:, 0]`` is then the smallest width of
        E1's live focal elements, negative if one is empty.
        """
        # widths and energies (eq. A1): Σ m/(w + ε) per evidence, times its u + ε
        np.subtract(self.hi, self.lo, out=self.width)
        if self.d > 1:
            np.multiply.reduce(self.width, axis=1, out=self.volume)
        np.add(self.volume, TINY, out=self.wt)
        np.divide(self.masses, self.wt_rows, out=self.share)
        np.add.reduce(self.share, axis=2, out=self.energy_sums)
        (e1_widths, e2_widths), (u1_out, u2_out) = self.widths, self.unit_outs
        if self.live is None:
            np.minimum.reduce(e1_widths, axis=1, out=u1_out)
        else:
            np.minimum.reduce(e1_widths, axis=1, where=self.live, initial=np.inf, out=u1_out)
        np.minimum.reduce(e2_widths, axis=1, out=u2_out)
        # m1(D), m2(D) of every focal element D of E2: [A_i = B_j] per run (eq. A3)
        np.equal(self.e2, self.all, out=self.equal_ends)
        if self.d == 1:
            np.logical_and(self.equal_lo, self.equal_hi, out=self.same)
        else:
            np.logical_and.reduce(self.equal, axis=0, out=self.same)
        np.matmul(self.same, self.masses_t, out=self.common)
        # energy of the intersection (eq. A3): Σ_j m(D_j) · m2_j/m2(D_j) · u12/w_j
        if self.rule == "min":
            m_d = np.minimum(self.on, self.merged, out=self.m_d)
        elif self.rule == "m1":  # 0 off the common elements by itself
            m_d = self.on
        else:  # "m2" is not
            m_d = np.multiply(self.merged, self.on > 0, out=self.m_d)
        np.divide(self.e2_share, self.merged, out=self.weight)
        np.vecdot(m_d, self.weight, out=self.joint_sum)
        # the six figures per run: in plain floats for one run (a numpy call on one element
        # costs more than a float operation), else in arrays
        if self.single:
            w1, w2 = self.units.ravel().tolist()
            figures = dependence_figures(w1, w2, min(w1, w2), *self.sums.ravel().tolist())
            valid = not (figures[4] < 0.0 or figures[5] < 0.0)
        else:
            u1, u2 = self.units.T
            figures = dependence_figures(u1, u2, np.minimum(u1, u2), *self.sums.T)
            valid = not np.fmin.reduce(self.coefficients, axis=None) < 0.0
        rows, theta_rows = self.figures
        rows[...], theta_rows[...] = figures[:6], figures[6:]
        return valid


def dependence_figures(u1: Any, u2: Any, u12: Any, s1: Any, s2: Any, s12: Any) -> tuple[Any, ...]:
    """Compute En'(E1), En'(E2), En'(E1, E2), D, R12, R21, 1 − R12, 1 − R21 (eqs. A1, A3–A6).

    From the smallest live widths of E1, E2 and both (u1, u2, u12) and the sums
    Σ m/(w + ε) of eqs. A1 and A3 (s1, s2, s12); floats or arrays alike.

    D = 2 En'(E1, E2)/(En'(E1) + En'(E2)) (eq. A4); R12 = 1 − D/2 · En'(E2)/En'(E1), R21
    likewise (eqs. A5–A6); ε = :data:`TINY` turns 0/0 into 0 (no energy: D = 0, R = 1).
    """
    en1, en2, joint = (u1 + TINY) * s1, (u2 + TINY) * s2, (u12 + TINY) * s12
    half = joint / (en1 + en2 + TINY)
    t12, t21 = en2 / (en1 + TINY) * half, en1 / (en2 + TINY) * half
    return en1, en2, joint, half + half, 1.0 - t12, 1.0 - t21, t12, t21


def dependence(
    a: Boxes, b: Boxes, mass_rule: MassRule = "min", *, check: bool = True
) -> BatchDependence:
    """Compute the energies, energy of the intersection, D, R12, R21 of E1 = a, E2 = b per run.

    Def. 5, eqs. A1, A3–A6; equal to :func:`dstoolkit.dependence` on the merged evidence
    (``DependenceKernel`` on the columns of a then b).

    E2's masses must be positive (E1 may hold mass-0 placeholders). With ``check``, raises
    EvidenceError when a coefficient leaves [0, 1] (``mass_rule="m2"`` can do that), as
    :func:`dstoolkit.decorrelate` does.
    """
    if mass_rule not in MASS_RULES:
        raise EvidenceError(f"mass_rule must be one of {MASS_RULES}, got {mass_rule!r}")
    runs = max(a.lo.shape[0], b.lo.shape[0])
    na, nb = a.lo.shape[1], b.lo.shape[1]
    cols = np.concatenate(
        [np.broadcast_to(columns(e), (runs, 2, e.lo.shape[2], n)) for e, n in ((a, na), (b, nb))],
        axis=3,
    )
    masses = np.zeros((runs, 2, na + nb))
    masses[:, 0, :na], masses[:, 1, na:] = a.mass, b.mass
    out, theta_mass = np.empty((6, runs)), np.empty((runs, 2))
    live = np.ascontiguousarray(np.broadcast_to(a.mass > 0, (runs, na)))
    valid = DependenceKernel(cols, masses, na, mass_rule, out, theta_mass, live).compute()
    if check and not valid:
        coefficient_error(out[4], out[5], out[3], mass_rule)
    return BatchDependence(*out)


def coefficient_error(r12: np.ndarray, r21: np.ndarray, degree: np.ndarray, mass_rule: str) -> None:
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
    """m'(A) = R·m(A), m'(Θ) = 1 − R with Θ the hull of E (eqs. 9–10, A7–A8), per run.

    Parameters
    ----------
    e : Boxes
        Boxes (R, N, d) and masses (R, N); mass-0 entries are ignored.
    reliability : ndarray, shape (R,)
        R of each run, in [0, 1].

    Returns
    -------
    Boxes
        N + 1 focal elements per run: the boxes with masses R·m, then the hull with 1 − R.

    Raises
    ------
    EvidenceError
        Unless every rate lies in [0, 1]: any other number would give negative masses.

    References
    ----------
    The paper's eqs. (9)–(10) and (A7)–(A8).

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.evidence.boxes import Boxes
    >>> b = Boxes(np.array([[[0.0], [1.0]]]), np.array([[[2.0], [3.0]]]),
    ...           np.array([[0.5, 0.5]]))
    >>> discount_onto_hull(b, np.array([0.9])).mass
    array([[0.45, 0.45, 0.1 ]])
    """
    rel = np.asarray(reliability, dtype=float)
    if rel.ndim != 1 or not np.all((rel >= 0.0) & (rel <= 1.0)):
        raise EvidenceError(
            f"the discount rates must be one number in [0, 1] per run, got "
            f"{np.array2string(rel, threshold=6)}; a rate is a reliability (eq. 9): 1 keeps "
            "the evidence, 0 turns it into ignorance"
        )
    h_lo, h_hi = hull(e)
    rel = rel[:, None]
    return Boxes(
        np.concatenate([e.lo, h_lo[:, None]], axis=1),
        np.concatenate([e.hi, h_hi[:, None]], axis=1),
        np.concatenate([e.mass * rel, 1.0 - rel], axis=1),
    )


#: Products of Dempster's rule ``ProductKernel`` forms at once (about 14 MiB of buffers
#: for boxes in two dimensions): larger combinations run in blocks of rows of B, so that
#: their memory stays bounded whatever N_a·N_b.
PRODUCT_BLOCK = 2**18


def block_rows(runs: int, na: int, nb: int, block: int | None = None) -> int:
    """Return how many of B's focal elements one block of ``ProductKernel`` takes.

    All N_b when the R·N_a·N_b products fit in ``block`` (default ``PRODUCT_BLOCK``),
    else as many as fit (at least one).

    Examples
    --------
    >>> block_rows(runs=1, na=4097, nb=257)
    63
    >>> block_rows(runs=64, na=65, nb=17)
    17
    """
    block = PRODUCT_BLOCK if block is None else block
    return nb if runs * na * nb <= block else max(1, min(nb, block // (runs * na)))


class ProductWork(NamedTuple):
    """Buffers of ``ProductKernel`` (the column layout of ``columns``).

    ``ends`` (2, R, d, N_rows, N_a) = lo, hi of A_i ∩ B_j for one block of N_rows focal
    elements B_j; ``stack`` (1 + d, R, N_rows, N_a) = [nonempty, (lo + hi)·nonempty] of
    that block; ``partial`` (R, 1 + d, N_b, 1) the sums over A of every B_j, ``sums``
    (R, 1 + d, 1, 1). Each end and each row of the stack is one block: the passes over a
    batch run faster.

    Parameters
    ----------
    ends : ndarray, shape (2, R, d, N_rows, N_a)
        The ends of the intersections of one block.
    stack : ndarray, shape (1 + d, R, N_rows, N_a)
        Non-emptiness and twice the centres of one block.
    partial : ndarray, shape (R, 1 + d, N_b, 1)
        Sums over A.
    sums : ndarray, shape (R, 1 + d, 1, 1)
        Sums over A and B.

    Examples
    --------
    >>> work = ProductWork.allocate(runs=4, d=1, na=3, nb=5)
    >>> work.ends.shape
    (2, 4, 1, 5, 3)
    >>> ProductWork.allocate(runs=4, d=1, na=3, nb=5, rows=2).ends.shape
    (2, 4, 1, 2, 3)
    """

    ends: np.ndarray
    stack: np.ndarray
    partial: np.ndarray
    sums: np.ndarray

    @classmethod
    def allocate(cls, runs: int, d: int, na: int, nb: int, rows: int | None = None) -> ProductWork:
        """Empty buffers for ``runs`` runs of boxes in d dimensions, N_a and N_b of them.

        Parameters
        ----------
        runs, d, na, nb : int
            R, d, N_a and N_b.
        rows : int, optional
            B's focal elements per block (default: ``block_rows``).

        Returns
        -------
        ProductWork
            The buffers (uninitialised).
        """
        rows = block_rows(runs, na, nb) if rows is None else max(1, min(nb, rows))
        return cls(
            np.empty((2, runs, d, rows, na)),
            np.empty((1 + d, runs, rows, na)),
            np.empty((runs, 1 + d, nb, 1)),
            np.empty((runs, 1 + d, 1, 1)),
        )


class _ProductBlock(NamedTuple):
    """Views of one block of B's focal elements j0:j1 (``ProductKernel``)."""

    b_lo: np.ndarray
    b_hi: np.ndarray
    b_mass: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    ends_1d: tuple[np.ndarray, np.ndarray]
    nonempty: np.ndarray
    nonempty_rows: np.ndarray
    centres: np.ndarray
    stack: np.ndarray
    partial: np.ndarray


class ProductKernel:
    """Pignistic expectation (eq. 20) of Dempster's combination (eq. 1) of A and B per run.

    It does without forming the N_a·N_b products' masses, on buffers and views bound once:

        E = Σ_ij m_a(i) m_b(j) [A_i ∩ B_j ≠ ∅] c(A_i ∩ B_j) / (1 − K),  c = the centre,

    two matrix products with the stack [nonempty, 2c] of the intersection matrix. ``a``
    (R, 2, d, N_a) and ``b`` (R, 2, d, N_b) are columns (:func:`columns`), ``a_mass``
    (R, N_a) and ``b_mass`` (R, N_b) their masses (a row (1, N) broadcasts). The
    intersections are formed for a block of B's focal elements at a time (the rows of
    ``work``, by default ``block_rows``): the sum over A of each B_j is the same in any
    block, and the sum over B runs once over all of them. ``theta`` = (i, j) tells that A_i
    holds every other A and B_j every other B (Θ1, Θ2 after :func:`discount_onto_hull`):
    where both keep mass and meet, A_i ∩ B_j is a product of positive mass that holds every
    other, so it is the hull (``combine`` with ``bounds``).
    """

    def __init__(
        self,
        a: np.ndarray,
        b: np.ndarray,
        a_mass: np.ndarray,
        b_mass: np.ndarray,
        work: ProductWork | None = None,
        theta: tuple[int, int] | None = None,
    ) -> None:
        runs = max(a.shape[0], b.shape[0], a_mass.shape[0], b_mass.shape[0])
        d, na, nb = a.shape[2], a.shape[3], b.shape[3]
        self.work = work if work is not None else ProductWork.allocate(runs, d, na, nb)
        ends, stack, partial, sums = self.work
        rows = ends.shape[3]
        self.d, self.a_mass, self.b_mass = d, a_mass, b_mass
        self.a_lo, self.a_hi = a[:, 0, :, None, :], a[:, 1, :, None, :]
        stack_runs = stack.transpose(1, 0, 2, 3)  # (R, 1 + d, N_rows, N_a)
        self.blocks = [
            self._block(b, b_mass, ends, stack, stack_runs, partial, j, min(nb, j + rows))
            for j in range(0, nb, rows)
        ]
        self.a_col, self.b_row = a_mass[:, None, :, None], b_mass[:, None, None, :]
        self.theta = (
            None
            if theta is None
            else (
                a_mass[:, theta[0]],
                b_mass[:, theta[1]],
                a[:, :, :, theta[0]],
                b[:, :, :, theta[1]],
            )
        )  # Θ's masses and boxes (R, 2, d)
        self.kept, self.total = sums[:, 0, 0, 0], sums[:, 1:, 0, 0]
        self.fold = np.empty((runs, 2, d))

    @staticmethod
    def _block(
        b: np.ndarray,
        b_mass: np.ndarray,
        ends: np.ndarray,
        stack: np.ndarray,
        stack_runs: np.ndarray,
        partial: np.ndarray,
        j0: int,
        j1: int,
    ) -> _ProductBlock:
        """Bind the views of B's focal elements j0:j1 to the first j1 − j0 rows of ``work``."""
        rows = j1 - j0
        lo, hi = ends[0][:, :, :rows], ends[1][:, :, :rows]
        nonempty = stack[0][:, :rows]
        return _ProductBlock(
            b[:, 0, :, j0:j1, None],
            b[:, 1, :, j0:j1, None],
            b_mass[:, j0:j1, None],
            lo,
            hi,
            (lo[:, 0], hi[:, 0]),
            nonempty,
            nonempty[:, None],
            stack_runs[:, 1:, :rows],
            stack_runs[:, :, :rows],
            partial[:, :, j0:j1],
        )

    def combine(self, est: np.ndarray, bounds: np.ndarray | None = None) -> np.ndarray | None:
        """Write E into ``est`` (R, d), with ``bounds`` the hull of the combination (R, 2, d).

        Returns None when every run's combination exists (K < 1 above the tolerance), else
        the mask of those that do. ``self.kept`` = 1 − K. The hull is that of the products
        of positive mass (±inf in a run without one).
        """
        _, _, partial, sums = self.work
        fold = None if bounds is None or self._theta_hull(bounds) else bounds
        if fold is not None and len(self.blocks) > 1:
            fold[:, 0], fold[:, 1] = np.inf, -np.inf
        for block in self.blocks:
            np.maximum(self.a_lo, block.b_lo, out=block.lo)
            np.minimum(self.a_hi, block.b_hi, out=block.hi)
            if self.d == 1:
                np.less_equal(*block.ends_1d, out=block.nonempty)
            else:
                np.logical_and.reduce(block.lo <= block.hi, axis=1, out=block.nonempty)
            if fold is not None:
                self._fold_hull(block, fold)
            np.add(block.lo, block.hi, out=block.centres)
            np.multiply(block.centres, block.nonempty_rows, out=block.centres)
            np.matmul(block.stack, self.a_col, out=block.partial)
        np.matmul(self.b_row, partial, out=sums)
        kept = self.kept
        if least(kept) > CONFLICT_TOLERANCE:
            ok = None
            scale = 0.5 / per_run(kept)
        else:
            ok = kept > CONFLICT_TOLERANCE
            scale = 0.5 / np.where(ok, kept, 1.0)[:, None]
        np.multiply(self.total, scale, out=est)
        return ok

    def _theta_hull(self, out: np.ndarray) -> bool:
        """Write Θ1 ∩ Θ2 into ``out`` (R, 2, d) if it is the hull in every run; say whether."""
        if self.theta is None:
            return False
        theta1_mass, theta2_mass, theta1, theta2 = self.theta
        if not (least(theta1_mass) > 0.0 and least(theta2_mass) > 0.0):
            return False
        corner = np.array([np.maximum(theta1[:, 0], theta2[:, 0]),
                           np.minimum(theta1[:, 1], theta2[:, 1])])  # fmt: skip
        if not (corner[0] <= corner[1]).all():
            return False
        np.copyto(out, corner.transpose(1, 0, 2))
        return True

    def _fold_hull(self, block: _ProductBlock, out: np.ndarray) -> None:
        """Fold the ends of the block's products of positive mass into the hull ``out``."""
        mass = block.b_mass * self.a_mass[:, None, :]  # (R, N_rows, N_a)
        live = ((mass > 0.0) & (block.nonempty > 0.0))[:, None]
        if len(self.blocks) == 1:
            np.minimum.reduce(block.lo, axis=(-2, -1), where=live, initial=np.inf, out=out[:, 0])
            np.maximum.reduce(block.hi, axis=(-2, -1), where=live, initial=-np.inf, out=out[:, 1])
            return
        fold = self.fold
        np.minimum.reduce(block.lo, axis=(-2, -1), where=live, initial=np.inf, out=fold[:, 0])
        np.maximum.reduce(block.hi, axis=(-2, -1), where=live, initial=-np.inf, out=fold[:, 1])
        np.minimum(out[:, 0], fold[:, 0], out=out[:, 0])
        np.maximum(out[:, 1], fold[:, 1], out=out[:, 1])


def dempster_expectation(
    a: Boxes,
    b: Boxes,
    bounds: bool = False,
    *,
    work: ProductWork | None = None,
    theta_last: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray] | None]:
    """Compute the pignistic expectation (eq. 20) of Dempster's combination (eq. 1) of a and b.

    Per run (``ProductKernel``). Returns E (R, d), K (R,), the mask of runs with K < 1, and
    with ``bounds`` the hull of the combination (R, d) twice. ``work`` reuses buffers
    (``ProductWork.allocate``). ``theta_last`` tells that the last focal element of a
    and of b holds all the others (as after :func:`discount_onto_hull`).

    Parameters
    ----------
    a, b : Boxes
        Boxes (R, N_a, d), (R, N_b, d) and their masses.
    bounds : bool
        Also return the hull of the combination.
    work : ProductWork, optional
        Buffers to reuse.
    theta_last : bool
        The last focal element of each holds all the others.

    Returns
    -------
    expectation : ndarray, shape (R, d)
        E of the combination (eq. 20).
    conflict : ndarray, shape (R,)
        K (eq. 1).
    ok : ndarray of bool, shape (R,)
        Whether the combination exists (K < 1 beyond the tolerance).
    hull : tuple of ndarray, shape (R, d), or None
        The hull's ends, with ``bounds``.

    References
    ----------
    The paper's eqs. (1) and (20).

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.evidence.boxes import Boxes
    >>> b = Boxes(np.array([[[0.0], [1.0]]]), np.array([[[2.0], [3.0]]]),
    ...           np.array([[0.5, 0.5]]))
    >>> expectation, conflict, ok, _ = dempster_expectation(b, b)
    >>> expectation, conflict, ok
    (array([[1.5]]), array([0.]), array([ True]))
    """
    theta = (a.lo.shape[1] - 1, b.lo.shape[1] - 1) if theta_last else None
    kernel = ProductKernel(columns(a), columns(b), a.mass, b.mass, work, theta)
    runs, d = kernel.work.sums.shape[0], a.lo.shape[2]
    expectation = np.empty((runs, d))
    box = np.empty((runs, 2, d)) if bounds else None
    ok = kernel.combine(expectation, box)
    ok = np.ones(runs, dtype=bool) if ok is None else ok
    conflict = 1.0 - kernel.kept
    if box is None:
        return expectation, conflict, ok, None
    return expectation, conflict, ok, (box[:, 0], box[:, 1])

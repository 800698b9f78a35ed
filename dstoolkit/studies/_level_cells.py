"""The paper's filter with its Step 6 on a finite frame of cells: the cautious rule beside eq. 9–10.

Steps 2–5 of the paper's filter run as they are; Step 6 fuses E1 (the fused evidence mapped
back) and E2 (the prediction), which share the prediction and so are not distinct. The paper
discounts both by their dependency coefficients and applies Dempster's rule (eqs. 9–10,
A7–A8); here they can instead be put on a frame of cells and fused by the cautious rule
(Denœux 2008), which needs no energy: it counts what they share once by construction.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from dstoolkit.errors import EvidenceError
from dstoolkit.evidence import (
    IntervalEvidence,
    MassFunction,
    cautious,
    combine_dependent,
    dempster,
    discount_to_nondogmatic,
)
from dstoolkit.utils.checks import whole_number

from ._filter_runs import gauge_case

#: The Step-6 rules :func:`level_cell_filter` runs: the paper's on its intervals, and on
#: cells the paper's (eqs. 9–10 with the energy of eq. 2), the cautious rule and Dempster's
#: rule (no discounting).
CELL_RULES: tuple[str, ...] = ("paper", "paper_cells", "cautious", "dempster")

#: The discount rate that makes a cell mass function without m(Θ) non-dogmatic (the cautious
#: rule needs m(Θ) > 0); small beside the filter's ε = 0.05 on Θ.
NONDOGMATIC_RATE = 0.001


@dataclass(frozen=True)
class LevelCellRun:
    """The filter on one gauge sequence with each Step-6 rule.

    Parameters
    ----------
    truth : numpy.ndarray, shape (K,)
        The true resonance frequencies x_k, Hz.
    true_level_m : float
        L, m.
    estimates : dict of str to numpy.ndarray, shape (K,)
        x̂_k by each rule of :data:`CELL_RULES`, Hz.
    levels : dict of str to numpy.ndarray, shape (K,)
        L̂_k = n_k c/(2 x̂_k) by each rule, m (eq. 32).
    cells : int
        Cells of the frame in Step 6.
    """

    truth: np.ndarray
    true_level_m: float
    estimates: dict[str, np.ndarray]
    levels: dict[str, np.ndarray]
    cells: int

    @property
    def mean_abs_error_m(self) -> dict[str, float]:
        """Mean |L̂_k − L| over the steps, m, by rule."""
        return {
            rule: float(np.mean(np.abs(lv - self.true_level_m))) for rule, lv in self.levels.items()
        }

    @property
    def rms_error_hz(self) -> dict[str, float]:
        """Root mean square of x̂_k − x_k over the steps, Hz, by rule."""
        return {
            rule: float(np.sqrt(np.mean((x - self.truth) ** 2)))
            for rule, x in self.estimates.items()
        }


#: The most cells a frame of :func:`cell_frame` may have (its set functions: 2^16 numbers).
MAX_CELLS = 16


def cell_frame(
    a: IntervalEvidence, b: IntervalEvidence, cells: int | None = None
) -> tuple[np.ndarray, MassFunction, MassFunction]:
    """Put two bodies of 1-D interval evidence on one finite frame of cells.

    With ``cells=None`` the cells are the intervals between consecutive endpoints of all
    the focal elements: every focal interval, and every intersection of two, is then a
    union of cells, and nothing is lost. With a number, ``cells`` equal cells span the hull,
    and a focal interval becomes the set of cells it overlaps: an outer approximation (the
    frame cannot tell apart what lies within one cell).

    Parameters
    ----------
    a, b : IntervalEvidence
        One-dimensional evidence.
    cells : int, optional
        Number of equal cells, 2 to :data:`MAX_CELLS`; default the exact cells.

    Returns
    -------
    edges : numpy.ndarray
        The cells' edges (one more than the cells).
    ma, mb : MassFunction
        ``a`` and ``b`` on the frame of cells 0, 1, ..., equal focal elements merged.

    Raises
    ------
    EvidenceError
        For a number of cells outside 2..16, or more than 16 exact cells.

    Examples
    --------
    >>> from dstoolkit.evidence import IntervalEvidence
    >>> a = IntervalEvidence.from_pairs([(0.0, 1.0, 0.5), (0.0, 4.0, 0.5)])
    >>> b = IntervalEvidence.from_pairs([(2.5, 4.0, 1.0)])
    >>> edges, ma, mb = cell_frame(a, b, 4)
    >>> edges.tolist(), sorted(map(sorted, ma.focal_elements)), mb.focal_elements
    ([0.0, 1.0, 2.0, 3.0, 4.0], [[0], [0, 1, 2, 3]], [frozenset({2, 3})])
    >>> cell_frame(a, b)[0].tolist()
    [0.0, 1.0, 2.5, 4.0]
    """
    if cells is None:
        edges = np.unique(np.concatenate([a.lo_1d, a.hi_1d, b.lo_1d, b.hi_1d]))
        if not 3 <= len(edges) <= MAX_CELLS + 1:
            raise EvidenceError(
                f"the focal elements' endpoints make {len(edges) - 1} cells, outside 2 to "
                f"{MAX_CELLS}; pass cells= for that many equal cells"
            )
    else:
        cells = whole_number(cells, "cells", low=2, high=MAX_CELLS, error=EvidenceError)
        edges = np.linspace(
            min(a.lo_1d.min(), b.lo_1d.min()), max(a.hi_1d.max(), b.hi_1d.max()), cells + 1
        )
    n = len(edges) - 1
    frame = tuple(range(n))

    def on_cells(e: IntervalEvidence) -> MassFunction:
        first = np.clip(np.searchsorted(edges, e.lo_1d, side="right") - 1, 0, n - 1)
        last = np.clip(np.searchsorted(edges, e.hi_1d, side="left") - 1, first, n - 1)
        masses: dict[frozenset, float] = {}
        for i, j, m in zip(first, last, e.mass, strict=True):
            key = frozenset(range(int(i), int(j) + 1))
            masses[key] = masses.get(key, 0.0) + float(m)
        return MassFunction(masses, frame)

    return edges, on_cells(a), on_cells(b)


def cell_expectation(m: MassFunction, edges: Any) -> float:
    """Return the pignistic expectation of evidence on cells (eq. 20 on a frame of cells).

    Each focal element spreads its mass uniformly over the length of its cells, as eq. (20)
    spreads it over an interval: Σ_A m(A) Σ_{c ∈ A} w_c x_c / Σ_{c ∈ A} w_c, with w_c and
    x_c the width and the midpoint of cell c. On equal cells this is Σ_c BetP(c) x_c.

    Parameters
    ----------
    m : MassFunction
        Evidence on the frame of cells 0, 1, ... (as :func:`cell_frame` makes it).
    edges : array_like
        The cells' edges, increasing.

    Returns
    -------
    float
        The expectation.

    Raises
    ------
    EvidenceError
        When the edges do not match the frame or do not increase.

    Examples
    --------
    >>> from dstoolkit.evidence import MassFunction
    >>> cell_expectation(MassFunction({frozenset({0, 1}): 1.0}, (0, 1)), [0.0, 1.0, 3.0])
    1.5
    """
    edges = np.asarray(edges, dtype=float)
    if edges.ndim != 1 or len(edges) != len(m.frame) + 1 or np.any(np.diff(edges) <= 0):
        raise EvidenceError(
            f"edges must be {len(m.frame) + 1} increasing numbers for a frame of "
            f"{len(m.frame)} cells"
        )
    widths, mids = np.diff(edges), 0.5 * (edges[:-1] + edges[1:])
    total = 0.0
    for focal, mass in m.as_dict().items():
        idx = np.array(sorted(focal), dtype=int)
        total += mass * float(widths[idx] @ mids[idx]) / float(widths[idx].sum())
    return total


def level_cell_filter(
    level_m: float = 9.6,
    temperature_c: float = 23.9,
    *,
    cells: int = 12,
    seed: int = 0,
    first: int | None = None,
) -> LevelCellRun:
    """Run the paper's filter on the simulated gauge with three Step-6 rules side by side.

    ``"paper"``: the filter as the paper has it (discounting by the dependency coefficients,
    then Dempster's rule, on intervals). On ``cells`` equal cells over the hull of E1 and
    E2: ``"paper_cells"``, the paper's rule (eqs. 9–10, the energy of eq. 2);
    ``"cautious"``, the cautious rule (both made non-dogmatic if need be); ``"dempster"``,
    Dempster's rule as if they were distinct. Each rule runs
    its own filter (the next step starts from that rule's x̂, Step 2); Steps 2–5 are the
    paper's, with its noise figures and the true orders n_k.

    Parameters
    ----------
    level_m : float, optional
        L, m (default 9.6).
    temperature_c : float, optional
        Air temperature, °C (default 23.9).
    cells : int, optional
        Cells of Step 6's frame, 2 to 16 (default 12).
    seed : int, optional
        Seed of the readings.
    first : int, optional
        Filter only the first ``first`` readings (at least 2).

    Returns
    -------
    LevelCellRun
        Truth, estimates and levels by rule.

    Raises
    ------
    EvidenceError
        For cells outside 2..16 or fewer than 2 readings.

    See Also
    --------
    dstoolkit.evidence.cautious : the cautious rule.
    dstoolkit.evidence.combine_dependent : the paper's rule.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §3, eqs. (9)–(10), (32), (39)–(40);
    T. Denœux (2008), Artificial Intelligence 172, 234–264.

    Examples
    --------
    >>> run = level_cell_filter(9.6, 23.9, first=5)
    >>> sorted(run.levels), run.levels["cautious"].shape
    (['cautious', 'dempster', 'paper', 'paper_cells'], (5,))
    """
    from dstoolkit.filters import DependentEvidenceFilter
    from dstoolkit.gauge import gauge_state_space_model, level_from_resonance

    cells = whole_number(cells, "cells", low=2, high=MAX_CELLS, error=EvidenceError)
    seq = gauge_case(level_m, temperature_c, seed)
    z = seq.readings if first is None else seq.readings[:first]
    if len(z) < 2:
        raise EvidenceError(f"first must leave at least 2 readings to filter, got {len(z)}")
    n = seq.true_inputs.astype(float)
    model = gauge_state_space_model()
    flt = DependentEvidenceFilter(on_conflict="predict")
    estimates: dict[str, np.ndarray] = {}
    for rule in CELL_RULES:
        state = flt.initialize(model, z[0])
        xs = [float(state.estimate[0])]
        for k in range(1, len(z)):
            state, record = flt.step(state, z[k], n[k - 1 : k])
            if rule != "paper" and record.mapped_back is not None:
                state = dataclasses.replace(state, estimate=np.array([_fuse(record, rule, cells)]))
            xs.append(float(state.estimate[0]))
        estimates[rule] = np.array(xs)
    orders = seq.orders[: len(z)]
    levels = {
        r: np.asarray(level_from_resonance(x, orders, seq.speed_of_sound), dtype=float)
        for r, x in estimates.items()
    }
    return LevelCellRun(
        np.asarray(seq.truth[: len(z)], dtype=float).reshape(-1),
        float(seq.level_m),
        estimates,
        levels,
        cells,
    )


def _fuse(record: Any, rule: str, cells: int) -> float:
    """Step 6 on cells: E1 (mapped back) and E2 (the prediction) by ``rule``; x̂ on cells."""
    edges, m1, m2 = cell_frame(record.mapped_back, record.prediction, cells)
    if rule == "cautious":
        fused = cautious(
            discount_to_nondogmatic(m1, NONDOGMATIC_RATE),
            discount_to_nondogmatic(m2, NONDOGMATIC_RATE),
        )
    elif rule == "paper_cells":
        fused = combine_dependent(m1, m2)
    else:
        fused = dempster(m1, m2)
    return cell_expectation(fused, edges)

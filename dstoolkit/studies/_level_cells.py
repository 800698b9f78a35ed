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
    dempster,
    discount_to_nondogmatic,
)
from dstoolkit.utils.checks import whole_number

from ._filter_runs import gauge_case

#: The Step-6 rules :func:`level_cell_filter` runs: the paper's on its intervals, and the
#: cautious rule and Dempster's rule (no discounting) on cells.
CELL_RULES: tuple[str, ...] = ("paper", "cautious", "dempster")

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


def cell_frame(
    a: IntervalEvidence, b: IntervalEvidence, cells: int
) -> tuple[np.ndarray, MassFunction, MassFunction]:
    """Put two bodies of 1-D interval evidence on one frame of equal cells over their hull.

    A focal interval becomes the set of cells it overlaps (an outer approximation: the cell
    frame cannot tell apart what lies within one cell).

    Parameters
    ----------
    a, b : IntervalEvidence
        One-dimensional evidence.
    cells : int
        Number of cells, 2 to 16.

    Returns
    -------
    edges : numpy.ndarray, shape (cells + 1,)
        The cells' edges.
    ma, mb : MassFunction
        ``a`` and ``b`` on the frame of cells 0..cells−1, equal focal elements merged.

    Raises
    ------
    EvidenceError
        For a number of cells outside 2..16.

    Examples
    --------
    >>> from dstoolkit.evidence import IntervalEvidence
    >>> a = IntervalEvidence.from_pairs([(0.0, 1.0, 0.5), (0.0, 4.0, 0.5)])
    >>> b = IntervalEvidence.from_pairs([(2.5, 4.0, 1.0)])
    >>> edges, ma, mb = cell_frame(a, b, 4)
    >>> edges.tolist(), sorted(map(sorted, ma.focal_elements)), mb.focal_elements
    ([0.0, 1.0, 2.0, 3.0, 4.0], [[0], [0, 1, 2, 3]], [frozenset({2, 3})])
    """
    cells = whole_number(cells, "cells", low=2, high=16, error=EvidenceError)
    lo = min(a.lo_1d.min(), b.lo_1d.min())
    hi = max(a.hi_1d.max(), b.hi_1d.max())
    edges = np.linspace(lo, hi, cells + 1)
    frame = tuple(range(cells))

    def on_cells(e: IntervalEvidence) -> MassFunction:
        first = np.clip(np.searchsorted(edges, e.lo_1d, side="right") - 1, 0, cells - 1)
        last = np.clip(np.searchsorted(edges, e.hi_1d, side="left") - 1, first, cells - 1)
        masses: dict[frozenset, float] = {}
        for i, j, m in zip(first, last, e.mass, strict=True):
            key = frozenset(range(int(i), int(j) + 1))
            masses[key] = masses.get(key, 0.0) + float(m)
        return MassFunction(masses, frame)

    return edges, on_cells(a), on_cells(b)


def _cell_estimate(m: MassFunction, edges: np.ndarray) -> float:
    """Return Σ BetP(cell) · the cell's midpoint: the pignistic expectation on cells (eq. 20)."""
    mids = 0.5 * (edges[:-1] + edges[1:])
    betp = m.pignistic()
    return float(sum(p * mids[c] for c, p in betp.items()))


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
    then Dempster's rule, on intervals). ``"cautious"``: E1 and E2 on ``cells`` equal cells
    over their hull, made non-dogmatic if need be, fused by the cautious rule.
    ``"dempster"``: the same cells fused by Dempster's rule as if distinct. Each rule runs
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
    (['cautious', 'dempster', 'paper'], (5,))
    """
    from dstoolkit.filters import DependentEvidenceFilter
    from dstoolkit.gauge import gauge_state_space_model, level_from_resonance

    cells = whole_number(cells, "cells", low=2, high=16, error=EvidenceError)
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
    else:
        fused = dempster(m1, m2)
    return _cell_estimate(fused, edges)

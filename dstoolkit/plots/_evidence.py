"""Pictures of evidence: focal elements, p-boxes, possibility distributions, Bel/Pl bars.

Every function draws on a given matplotlib ``Axes`` (or a new figure) and returns the
:class:`~matplotlib.figure.Figure`; none calls ``plt.show()``. In a notebook a figure made
by pyplot is shown when the cell ends; in a widget callback, ``display(fig)`` it.

The small table helpers at the end turn evidence into Markdown tables (rendered as tables
by Jupyter and by the book), optionally beside the values a paper prints.
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Sequence
from itertools import combinations
from typing import Any, NamedTuple

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from dstoolkit.errors import EvidenceError
from dstoolkit.evidence._finite_frame import MassFunction
from dstoolkit.evidence._intervals import IntervalEvidence
from dstoolkit.evidence._possibility import alpha_cuts, possibility

from ._style import (
    BEL_COLOUR,
    BETP_COLOUR,
    FOCAL_CMAP,
    PL_COLOUR,
    SMALL_PT,
    column_size,
    legend_above,
    styled,
)


def _axes(ax: Axes | None, figsize: tuple[float, float]) -> tuple[Figure, Axes]:
    if ax is not None:
        return ax.figure, ax
    fig, new_ax = plt.subplots(figsize=column_size(*figsize), layout="constrained")
    return fig, new_ax


#: The outline of every focal element's bar.
FOCAL_BAR_EDGE: dict[str, Any] = {"edgecolor": "black", "linewidth": 0.6}
#: How a focal element's mass is written on its bar.
MASS_LABEL: dict[str, Any] = {
    "ha": "center", "va": "center", "fontsize": SMALL_PT,
    "bbox": {"boxstyle": "round,pad=0.15", "fc": "white", "alpha": 0.7, "lw": 0}}


class FocalBars(NamedTuple):
    """Where :func:`plot_focal_intervals` draws scalar evidence: each focal element's bar
    from ``left`` to ``right`` (clipped to the x range), from ``bottoms`` up by its mass,
    in ``colours``; ``labels``: (x, y, text) of the masses written on the bars."""

    left: np.ndarray
    right: np.ndarray
    bottoms: np.ndarray
    colours: Any
    labels: list[tuple[float, float, str]]


def focal_bars(ev: IntervalEvidence, xlim: tuple[float, float], *, colour: str | None = None,
               label_masses: bool = True) -> FocalBars:
    """The bars of scalar evidence stacked in its order inside ``xlim`` (see
    :func:`plot_focal_intervals`): a mass over 0.05 is written on its bar, with the ends of
    an element that the x range clips."""
    lo, hi, m = ev.lo, ev.hi, ev.mass
    bottoms = np.concatenate([[0.0], np.cumsum(m)[:-1]])
    colours = (
        [colour] * len(ev) if colour is not None
        else plt.get_cmap(FOCAL_CMAP)(np.linspace(0.15, 0.85, max(len(ev), 1)))
    )
    left, right = np.maximum(lo, xlim[0]), np.minimum(hi, xlim[1])
    labels = []
    if label_masses:
        for i in range(len(ev)):
            clipped = lo[i] < xlim[0] or hi[i] > xlim[1]
            text = f"{m[i]:.4g}" + (f"  [{lo[i]:.4g}, {hi[i]:.4g}]" if clipped else "")
            if m[i] > 0.05:
                labels.append((0.5 * (left[i] + right[i]), bottoms[i] + 0.5 * m[i], text))
    return FocalBars(left, right, bottoms, colours, labels)


def _scalar(ev: IntervalEvidence, what: str) -> None:
    if not isinstance(ev, IntervalEvidence) or ev.dim != 1:
        raise EvidenceError(f"{what} draws scalar interval evidence (IntervalEvidence, d = 1)")


# -- interval evidence -------------------------------------------------------------------


@styled
def plot_focal_intervals(
    ev: IntervalEvidence,
    ax: Axes | None = None,
    *,
    xlim: tuple[float, float] | None = None,
    title: str | None = None,
    label_masses: bool = True,
    colour: str | None = None,
    xlabel: str = "x",
) -> Figure:
    """Focal elements as stacked bars: bar i spans [lo_i, hi_i] and is m_i high.

    The bars are stacked in the order of the evidence, so the total height is 1 and the
    area of the picture that lies above a point x is the plausibility of {x}. Focal
    elements wider than ``xlim`` (a wide Θ, say) are clipped, with their ends written.

    Parameters
    ----------
    ev
        Scalar interval evidence.
    xlim
        Range of the x axis; default: the hull of the focal elements, 5 % margin.
    title
        Axes title.
    label_masses
        Write each mass (and a clipped element's ends) on its bar.
    colour
        One colour for every bar; default: a colour map over the focal elements.
    xlabel
        Label of the x axis: the quantity and its unit, e.g. ``"frequency (Hz)"``.
    """
    _scalar(ev, "plot_focal_intervals")
    fig, ax = _axes(ax, (6.0, 2.8))
    if xlim is None:
        a, b = float(np.min(ev.lo)), float(np.max(ev.hi))
        pad = 0.05 * (b - a if b > a else 1.0)
        xlim = (a - pad, b + pad)
    bars = focal_bars(ev, xlim, colour=colour, label_masses=label_masses)
    ax.barh(bars.bottoms, bars.right - bars.left, left=bars.left, height=ev.mass,
            align="edge", color=bars.colours, **FOCAL_BAR_EDGE)
    for x, y, text in bars.labels:
        ax.text(x, y, text, **MASS_LABEL)
    ax.set_xlim(*xlim)
    ax.set_ylim(0, 1)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("cumulated mass")
    if title:
        ax.set_title(title)
    return fig


@styled
def plot_pbox(
    ev: IntervalEvidence,
    ax: Axes | None = None,
    *,
    x: Any = None,
    xlim: tuple[float, float] | None = None,
    title: str | None = None,
    label: str = "",
    xlabel: str = "x",
) -> Figure:
    """The p-box of scalar evidence: F_*(x) = Bel((−∞, x]) below, F^*(x) = Pl((−∞, x]) above.

    Every probability distribution compatible with the evidence has its cdf between the
    two step functions (see :meth:`~dstoolkit.evidence.IntervalEvidence.cdf_bounds`).
    """
    _scalar(ev, "plot_pbox")
    fig, ax = _axes(ax, (6.0, 2.8))
    if x is None:
        finite = np.concatenate([ev.lo, ev.hi])
        finite = finite[np.isfinite(finite)]
        a, b = (xlim if xlim is not None else (finite.min(), finite.max()))
        pad = 0.05 * (b - a if b > a else 1.0)
        x = np.linspace(a - pad, b + pad, 801)
    x = np.asarray(x, dtype=float)
    lower, upper = ev.cdf_bounds(x)
    prefix = f"{label} " if label else ""
    ax.fill_between(x, lower, upper, step="post", color=PL_COLOUR, alpha=0.5)
    ax.step(x, upper, where="post", color=BEL_COLOUR, ls="--", label=prefix + "upper cdf  Pl")
    ax.step(x, lower, where="post", color=BEL_COLOUR, label=prefix + "lower cdf  Bel")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlim(x[0], x[-1])
    ax.set_xlabel(xlabel)
    ax.set_ylabel("probability")
    if title:
        ax.set_title(title)
    legend_above(ax)
    return fig


def contour(ev: IntervalEvidence, x: Any) -> np.ndarray:
    """Pl({x}) = Σ of the masses of focal elements containing x (the contour function).

    For consonant (nested) evidence it is the possibility distribution the evidence
    stands for (the staircase under π in the paper's Fig. 4).
    """
    _scalar(ev, "contour")
    x = np.asarray(x, dtype=float)
    inside = (ev.lo[None, :] <= x.reshape(-1, 1)) & (ev.hi[None, :] >= x.reshape(-1, 1))
    return (inside @ ev.mass).reshape(x.shape)


@styled
def plot_possibility(
    lower: float,
    mode: float,
    upper: float,
    p: int = 3,
    ax: Axes | None = None,
    *,
    evidence: IntervalEvidence | None = None,
    xlim: tuple[float, float] | None = None,
    title: str | None = None,
    xlabel: str = "x",
) -> Figure:
    """The triangular possibility π (paper eq. 22) with its p α-cuts (eq. 24) drawn as lines.

    With ``evidence`` given, its contour function Pl({x}) is drawn too: the staircase that
    the evidence puts in place of π.
    """
    fig, ax = _axes(ax, (6.0, 2.8))
    if xlim is None:
        half = 0.15 * (upper - lower if upper > lower else 1.0)
        xlim = (lower - half, upper + half)
    x = np.linspace(xlim[0], xlim[1], 801)
    ax.plot(x, possibility(x, lower, mode, upper), color="black", lw=1.5, label="π(x)")
    lo, hi = alpha_cuts(lower, mode, upper, p)
    alphas = np.arange(p)[::-1] / p
    colours = plt.get_cmap(FOCAL_CMAP)(np.linspace(0.15, 0.85, p))
    for a, b, alpha, c in zip(lo, hi, alphas, colours, strict=True):
        ax.hlines(alpha, a, b, color=c, lw=3)
        ax.vlines([a, b], 0, alpha, color=c, lw=0.8, ls=":")
        if p <= 6:
            ax.text(b, alpha, f"  α = {alpha:.3g}", va="center", fontsize=SMALL_PT)
    if evidence is not None:
        ax.step(x, contour(evidence, x), where="mid", color=BETP_COLOUR, lw=1.2,
                label="Pl({x}) of the evidence")
    ax.set_xlim(*xlim)
    ax.set_ylim(-0.02, 1.08)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("possibility")
    if title:
        ax.set_title(title)
    legend_above(ax)
    return fig


# -- finite frames -----------------------------------------------------------------------


def _name(subset: Iterable[Hashable], frame: Sequence[Hashable]) -> str:
    members = set(subset)
    if len(members) == len(frame):
        return "Θ"
    return "{" + ",".join(str(h) for h in frame if h in members) + "}"


def all_subsets(frame: Sequence[Hashable]) -> list[frozenset]:
    """Every non-empty subset of a frame, by size then in frame order."""
    return [frozenset(c) for r in range(1, len(frame) + 1) for c in combinations(frame, r)]


@styled
def plot_bel_pl(
    mf: MassFunction,
    subsets: Sequence[Any] | None = None,
    ax: Axes | None = None,
    *,
    title: str | None = None,
) -> Figure:
    """Belief and plausibility of subsets as bars: Bel solid, the gap up to Pl light.

    The gap Pl(A) − Bel(A) is the mass that neither supports nor contradicts A. Singletons
    also get a red tick at their pignistic probability BetP, which always lies between.
    Default subsets: all non-empty subsets for frames of up to 4 hypotheses, else
    the singletons.
    """
    if not isinstance(mf, MassFunction):
        raise EvidenceError("plot_bel_pl draws a MassFunction on a finite frame")
    frame = mf.frame
    if subsets is None:
        subsets = all_subsets(frame) if len(frame) <= 4 else [frozenset([h]) for h in frame]
    sets = [frozenset(MassFunction._elements(s, frame)) for s in subsets]
    bel = np.array([mf.belief(s) for s in sets])
    pl = np.array([mf.plausibility(s) for s in sets])
    betp = mf.pignistic()
    fig, ax = _axes(ax, (max(4.0, 0.7 * len(sets) + 1.5), 2.8))
    xs = np.arange(len(sets))
    ax.bar(xs, bel, color=BEL_COLOUR, label="Bel", edgecolor="black", linewidth=0.5)
    ax.bar(xs, pl - bel, bottom=bel, color=PL_COLOUR, label="Pl − Bel", edgecolor="black",
           linewidth=0.5)
    single = [i for i, s in enumerate(sets) if len(s) == 1]
    if single:
        ax.scatter(xs[single], [betp[next(iter(sets[i]))] for i in single], marker="_",
                   s=400, color=BETP_COLOUR, linewidths=2.5, label="BetP", zorder=3)
    ax.set_xticks(xs, [_name(s, frame) for s in sets], rotation=30 if len(sets) > 6 else 0)
    ax.set_ylim(0, 1.05)
    ax.set_xlabel("subset A of the frame")
    ax.set_ylabel("Bel(A), Pl(A)")
    if title:
        ax.set_title(title)
    legend_above(ax)
    return fig


@styled
def plot_masses(
    mf: MassFunction, ax: Axes | None = None, *, title: str | None = None
) -> Figure:
    """The masses of a finite mass function, one bar per focal element."""
    if not isinstance(mf, MassFunction):
        raise EvidenceError("plot_masses draws a MassFunction on a finite frame")
    items = mf.as_dict()
    fig, ax = _axes(ax, (max(4.0, 0.7 * len(items) + 1.5), 2.5))
    xs = np.arange(len(items))
    ax.bar(xs, list(items.values()), color=BEL_COLOUR, edgecolor="black", linewidth=0.5)
    for x, v in zip(xs, items.values(), strict=True):
        ax.text(x, v, f"{v:.3g}", ha="center", va="bottom", fontsize=SMALL_PT)
    ax.set_xticks(xs, [_name(s, mf.frame) for s in items])
    ax.set_xlabel("focal element")
    ax.set_ylim(0, 1.1)
    ax.set_ylabel("mass")
    if title:
        ax.set_title(title)
    return fig


@styled
def plot_products(
    a: MassFunction, b: MassFunction, ax: Axes | None = None, *, title: str | None = None
) -> Figure:
    """Dempster's product table (paper eq. 1): cell (i, j) holds m1(A_i)·m2(B_j) on A_i ∩ B_j.

    Empty intersections — the conflict K — are hatched grey.
    """
    a._check_compatible(b)
    fa, fb = a.focal_elements, b.focal_elements
    prod = np.multiply.outer(a.mass, b.mass)
    fig, ax = _axes(ax, (1.4 * len(fb) + 2.0, 0.8 * len(fa) + 1.2))
    ax.imshow(prod, cmap="Blues", vmin=0, vmax=max(float(prod.max()), 1e-12), aspect="auto")
    for i, s in enumerate(fa):
        for j, t in enumerate(fb):
            inter = s & t
            if not inter:
                ax.add_patch(plt.Rectangle((j - 0.5, i - 0.5), 1, 1, facecolor="0.85",
                                           hatch="//", edgecolor="0.5"))
            label = _name(inter, a.frame) if inter else "∅"
            ax.text(j, i, f"{label}\n{prod[i, j]:.4g}", ha="center", va="center",
                    fontsize=SMALL_PT)
    ax.set_xticks(range(len(fb)), [f"{_name(t, a.frame)}\n{m:.3g}" for t, m in
                                   zip(fb, b.mass, strict=True)])
    ax.set_yticks(range(len(fa)), [f"{_name(s, a.frame)}  {m:.3g}" for s, m in
                                   zip(fa, a.mass, strict=True)])
    ax.set_xlabel("second source m2")
    ax.set_ylabel("first source m1")
    ax.tick_params(length=0)
    if title:
        ax.set_title(title)
    return fig


# -- random relations (book/random_sets.md) ------------------------------------------------


@styled
def plot_boxes(
    ev: IntervalEvidence,
    ax: Axes | None = None,
    *,
    xlim: tuple[float, float] | None = None,
    ylim: tuple[float, float] | None = None,
    title: str | None = None,
    labels: Sequence[str] | None = None,
) -> Figure:
    """The focal elements of 2-D interval evidence (a random relation, paper eq. 16) as
    rectangles shaded by mass, each with its mass (or its ``labels`` entry) at its centre."""
    if not isinstance(ev, IntervalEvidence) or ev.dim != 2:
        raise EvidenceError("plot_boxes draws 2-D interval evidence (IntervalEvidence, d = 2)")
    fig, ax = _axes(ax, (4.5, 4.0))
    lo, hi, m = ev.boxes_lo, ev.boxes_hi, ev.mass
    shade = plt.get_cmap("Blues")(0.25 + 0.65 * m / m.max())
    for i in np.argsort(-(hi - lo).prod(axis=1)):  # widest first, so small boxes stay on top
        ax.add_patch(plt.Rectangle(lo[i], *(hi[i] - lo[i]), facecolor=shade[i], alpha=0.55,
                                   edgecolor="black", linewidth=1.0))
        text = f"{m[i]:.3g}" if labels is None else labels[i]
        ax.text(*(0.5 * (lo[i] + hi[i])), text, ha="center", va="center", fontsize=9,
                bbox={"boxstyle": "round,pad=0.15", "fc": "white", "alpha": 0.8, "lw": 0})
    pad = 0.05 * (hi.max(axis=0) - lo.min(axis=0))
    ax.set_xlim(*(xlim or (lo[:, 0].min() - pad[0], hi[:, 0].max() + pad[0])))
    ax.set_ylim(*(ylim or (lo[:, 1].min() - pad[1], hi[:, 1].max() + pad[1])))
    ax.set_xlabel("ξ₁")
    ax.set_ylabel("ξ₂")
    if title:
        ax.set_title(title)
    return fig


# -- tables ------------------------------------------------------------------------------


def markdown_table(headers: Sequence[str], rows: Iterable[Sequence[Any]],
                   fmt: str = ".4f") -> Any:
    """A Markdown table (an IPython ``Markdown`` object); floats formatted with ``fmt``."""
    from IPython.display import Markdown

    def cell(v: Any) -> str:
        if isinstance(v, float | np.floating):
            return format(float(v), fmt)
        return str(v)

    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in rows]
    return Markdown("\n".join(lines))


def interval_table(ev: IntervalEvidence, paper: Sequence[Sequence[float]] | None = None,
                   fmt: str = ".4f") -> Any:
    """Focal elements and masses of scalar evidence as a Markdown table.

    With ``paper`` (rows lo, hi, mass as printed in a paper) a second group of columns
    shows the printed values and the difference of the masses.
    """
    _scalar(ev, "interval_table")
    ours = ev.to_rows()

    def iv(lo: float, hi: float) -> str:
        return f"[{lo:.4g}, {hi:.4g}]"

    if paper is None:
        return markdown_table(["focal element", "mass"],
                              [(iv(lo, hi), m) for lo, hi, m in ours], fmt)
    paper = np.asarray(paper, dtype=float)
    if paper.shape != ours.shape:
        raise EvidenceError(f"paper rows have shape {paper.shape}, evidence {ours.shape}")
    def diff(d: float) -> str:
        return "0" if d == 0 else f"{d:+.1e}"

    rows = [(iv(a, b), m, iv(pa, pb), pm, diff(m - pm))
            for (a, b, m), (pa, pb, pm) in zip(ours, paper, strict=True)]
    return markdown_table(["computed", "mass", "paper", "mass", "difference"], rows, fmt)

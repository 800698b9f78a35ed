"""Pictures of evidence: focal elements, p-boxes, possibility distributions, Bel/Pl bars.

Every function draws on a given matplotlib ``Axes`` (or a new figure) and returns the
:class:`~matplotlib.figure.Figure`; none calls ``plt.show()``. In a notebook a figure made
by pyplot is shown when the cell ends; in a widget callback, ``display(fig)`` it.

The figures an explorer redraws on every change of a control are drawn in two steps, so
that it can keep its figure: ``draw_x(ax, ...)`` draws what no data changes (axis labels,
ranges, legend) and returns the artists (an ``XArtists``), ``update_x(artists, data)``
draws the data in them; ``plot_x`` does both. With ``animated=True`` the artists that
follow the data, and the axes' spines, are marked animated (``animate``): an explorer
then draws only them on the unchanged rest of the picture.

The small table helpers at the end turn evidence into Markdown tables (rendered as tables
by Jupyter and by the book), optionally beside the values a paper prints.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Hashable, Iterable, Sequence
from dataclasses import dataclass, field
from itertools import combinations
from typing import Any, TypeVar, cast

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.collections import (
    FillBetweenPolyCollection,
    LineCollection,
    PathCollection,
    PolyCollection,
)
from matplotlib.container import BarContainer
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Rectangle
from matplotlib.text import Text

from dstoolkit.errors import EvidenceError, InvalidInputError
from dstoolkit.evidence import IntervalEvidence, MassFunction, alpha_cuts, possibility

from ._kept import animate, set_limits
from ._style import (
    BEL_COLOUR,
    BETP_COLOUR,
    FOCAL_CMAP,
    PL_COLOUR,
    SMALL_PT,
    column_size,
    legend_above,
    root_figure,
    styled,
)


def _axes(ax: Axes | None, figsize: tuple[float, float]) -> tuple[Figure, Axes]:
    if ax is not None:
        return root_figure(ax), ax
    fig, new_ax = plt.subplots(figsize=column_size(*figsize), layout="constrained")
    return fig, new_ax


def _scalar(ev: IntervalEvidence, what: str) -> None:
    if not isinstance(ev, IntervalEvidence) or ev.dim != 1:
        raise EvidenceError(f"{what} draws scalar interval evidence (IntervalEvidence, d = 1)")


A = TypeVar("A", bound=Artist)


#: Artists an animated pool makes beyond those it needs (hidden until needed): making an
#: artist redraws a kept figure whole, showing a hidden one does not.
SPARE_ARTISTS = 4


def _resize(artists: list[A], count: int, make: Callable[[], A], animated: bool) -> list[A]:
    """Return the first ``count`` of ``artists`` (drawn on an Axes), shown.

    Missing ones are made by ``make()`` (in order, as a fresh drawing makes them; if
    ``animated``, so marked and :data:`SPARE_ARTISTS` more), the others hidden, not removed
    (adding or removing an artist redraws a kept figure whole; hiding an animated one does
    not). The caller then sets every shown one's data.
    """
    if len(artists) < count:
        for _ in range(count - len(artists) + (SPARE_ARTISTS if animated else 0)):
            artists.append(make())
            artists[-1].set_animated(animated)
    for i, artist in enumerate(artists):
        artist.set_visible(i < count)
    return artists[:count]


# -- interval evidence -------------------------------------------------------------------


@functools.lru_cache(maxsize=64)
def focal_colours(n: int) -> np.ndarray:
    """Return the colours of ``n`` focal elements (or α-cuts): RGBA rows over the colour map.

    Kept per ``n`` (read-only): an explorer colours the same number of bars again and again.
    """
    colours = plt.get_cmap(FOCAL_CMAP)(np.linspace(0.15, 0.85, n))
    colours.flags.writeable = False
    return colours


@dataclass
class FocalIntervalArtists:
    """What :func:`plot_focal_intervals` draws on ``ax``.

    The bars of the focal elements, one polygon each in one collection (drawn in one
    call, however many focal elements there are), and the masses written on them. Made by
    ``draw_focal_intervals``, set by ``update_focal_intervals``.
    """

    ax: Axes
    bars: PolyCollection
    animated: bool = False
    labels: list[Text] = field(default_factory=list)


@styled
def draw_focal_intervals(
    ax: Axes, *, title: str | None = None, xlabel: str = "x", animated: bool = False
) -> FocalIntervalArtists:
    """Draw the parts of :func:`plot_focal_intervals` that no evidence changes on ``ax``.

    Axis labels, y range, title, and the (empty) collection of bars; the bars' shapes and
    colours come with ``update_focal_intervals``.
    """
    _fixed_parts(ax, xlabel, "cumulated mass", 1.0, title, animated)
    bars = PolyCollection([], edgecolors="black", linewidths=0.6)
    ax.add_collection(bars, autolim=False)
    bars.set_animated(animated)
    return FocalIntervalArtists(ax, bars, animated)


def _fixed_parts(
    ax: Axes, xlabel: str, ylabel: str, top: float, title: str | None, animated: bool
) -> None:
    """Set the labels, y range [0, ``top``] and title of a bar panel.

    Its spines are animated with its bars.
    """
    ax.set_ylim(0, top)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title)
    if animated:
        animate(spines_of=ax)


@styled
def update_focal_intervals(
    artists: FocalIntervalArtists,
    ev: IntervalEvidence,
    *,
    xlim: tuple[float, float] | None = None,
    label_masses: bool = True,
    colour: str | None = None,
) -> None:
    """Draw ``ev`` in the bars of ``draw_focal_intervals``.

    The parameters are as in :func:`plot_focal_intervals`: an explorer's kept figure follows
    the evidence.
    """
    _scalar(ev, "plot_focal_intervals")
    ax = artists.ax
    lo, hi, m = ev.lo_1d, ev.hi_1d, ev.mass
    if xlim is None:
        a, b = float(np.min(lo)), float(np.max(hi))
        pad = 0.05 * (b - a if b > a else 1.0)
        xlim = (a - pad, b + pad)
    bottoms = np.concatenate([[0.0], np.cumsum(m)[:-1]])
    colours = [colour] * len(ev) if colour is not None else focal_colours(max(len(ev), 1))
    left, right = np.maximum(lo, xlim[0]), np.minimum(hi, xlim[1])
    tops = bottoms + m
    # bar i: the rectangle [left_i, right_i] × [bottom_i, top_i], corners counter-clockwise
    corners = np.empty((len(ev), 4, 2))
    corners[:, (0, 3), 0], corners[:, (1, 2), 0] = left[:, None], right[:, None]
    corners[:, :2, 1], corners[:, 2:, 1] = bottoms[:, None], tops[:, None]
    artists.bars.set_verts(cast(Any, corners))  # an (n, 4, 2) array: matplotlib's fast path
    artists.bars.set_facecolor(cast(Any, colours))
    shown = [i for i in range(len(ev)) if label_masses and m[i] > 0.05]

    def label() -> Text:
        return ax.text(
            0.0,
            0.0,
            "",
            ha="center",
            va="center",
            fontsize=SMALL_PT,
            bbox={"boxstyle": "round,pad=0.15", "fc": "white", "alpha": 0.7, "lw": 0},
        )

    for text, i in zip(
        _resize(artists.labels, len(shown), label, artists.animated), shown, strict=True
    ):
        clipped = lo[i] < xlim[0] or hi[i] > xlim[1]
        text.set_position((0.5 * (left[i] + right[i]), bottoms[i] + 0.5 * m[i]))
        text.set_text(f"{m[i]:.4g}" + (f"  [{lo[i]:.4g}, {hi[i]:.4g}]" if clipped else ""))
    set_limits(ax, x=xlim)


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
    (``draw_focal_intervals`` then ``update_focal_intervals``.)

    Parameters
    ----------
    ev
        Scalar interval evidence.
    ax
        Axes to draw on; by default a new figure of its own.
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

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    Raises
    ------
    dstoolkit.errors.EvidenceError
        If ``ev`` is not scalar interval evidence.

    Examples
    --------
    >>> from dstoolkit.evidence import triangular_evidence
    >>> ev = triangular_evidence(-10.59, -6.9, -3.21, p=3, epsilon=0.05, theta=(-20.0, 10.0))
    >>> fig = plot_focal_intervals(ev, xlim=(-12, -2), xlabel="noise w (Hz)")
    >>> fig.axes[0].get_xlabel()
    'noise w (Hz)'
    """
    _scalar(ev, "plot_focal_intervals")
    fig, ax = _axes(ax, (6.0, 2.8))
    artists = draw_focal_intervals(ax, title=title, xlabel=xlabel)
    update_focal_intervals(artists, ev, xlim=xlim, label_masses=label_masses, colour=colour)
    return fig


def pbox_grid(a: float, b: float) -> np.ndarray:
    """Return the points at which :func:`plot_pbox` evaluates a p-box over [a, b].

    801 points, with a 5 % margin on both sides.
    """
    pad = 0.05 * (b - a if b > a else 1.0)
    return np.linspace(a - pad, b + pad, 801)


@dataclass
class PboxArtists:
    """What :func:`plot_pbox` draws on ``ax`` at the points ``x``.

    The band between the two cdfs and their step lines. Made by ``draw_pbox``, set by
    ``update_pbox``.
    """

    ax: Axes
    x: np.ndarray
    band: FillBetweenPolyCollection
    upper: Line2D
    lower: Line2D


@styled
def draw_pbox(
    ax: Axes,
    x: Any,
    *,
    title: str | None = None,
    label: str = "",
    xlabel: str = "x",
    animated: bool = False,
) -> PboxArtists:
    """Draw the parts of :func:`plot_pbox` at the points ``x`` that no evidence changes.

    Lines, legend, ranges, labels on ``ax``; the cdfs come with ``update_pbox``.
    """
    x = np.asarray(x, dtype=float)
    zero = np.zeros_like(x)
    prefix = f"{label} " if label else ""
    band = ax.fill_between(x, zero, zero, step="post", color=PL_COLOUR, alpha=0.5)
    (upper,) = ax.step(
        x, zero, where="post", color=BEL_COLOUR, ls="--", label=prefix + "upper cdf  Pl"
    )
    (lower,) = ax.step(x, zero, where="post", color=BEL_COLOUR, label=prefix + "lower cdf  Bel")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlim(x[0], x[-1])
    ax.set_xlabel(xlabel)
    ax.set_ylabel("probability")
    if title:
        ax.set_title(title)
    legend_above(ax)
    if animated:
        animate(band, upper, lower, spines_of=ax)
    return PboxArtists(ax, x, band, upper, lower)


def update_pbox(artists: PboxArtists, ev: IntervalEvidence) -> None:
    """Draw the p-box of ``ev`` in the artists of ``draw_pbox``."""
    _scalar(ev, "plot_pbox")
    lower, upper = ev.cdf_bounds(artists.x)
    artists.band.set_data(artists.x, lower, upper)
    artists.upper.set_ydata(upper)
    artists.lower.set_ydata(lower)


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
    """Plot the p-box of scalar evidence: F_*(x) = Bel((−∞, x]) below, F^*(x) = Pl((−∞, x]) above.

    Every probability distribution compatible with the evidence has its cdf between the
    two step functions (see :meth:`~dstoolkit.evidence.IntervalEvidence.cdf_bounds`).
    Default ``x``: ``pbox_grid`` over ``xlim``, else over the finite ends of the focal
    elements. (``draw_pbox`` then ``update_pbox``.)

    Parameters
    ----------
    ev : dstoolkit.evidence.IntervalEvidence
        Scalar interval evidence (d = 1).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    x : array_like, optional
        Shape (n,): points at which both bounds are drawn (unit of the quantity).
    xlim : tuple of float, optional
        Range of the x axis (unit of the quantity).
    title : str, optional
        Title of the axes.
    label : str, optional
        Written after "Bel" and "Pl" in the legend.
    xlabel : str, optional
        Label of the x axis: the quantity and its unit.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    Raises
    ------
    dstoolkit.errors.EvidenceError
        If ``ev`` is not scalar interval evidence.

    Examples
    --------
    >>> from dstoolkit.evidence import triangular_evidence
    >>> ev = triangular_evidence(-10.59, -6.9, -3.21, p=3, epsilon=0.05, theta=(-20.0, 10.0))
    >>> fig = plot_pbox(ev, xlabel="noise w (Hz)")
    >>> fig.axes[0].get_xlabel()
    'noise w (Hz)'
    """
    _scalar(ev, "plot_pbox")
    fig, ax = _axes(ax, (6.0, 2.8))
    if x is None:
        finite = np.concatenate([ev.lo_1d, ev.hi_1d])
        finite = finite[np.isfinite(finite)]
        x = pbox_grid(*(xlim if xlim is not None else (finite.min(), finite.max())))
    update_pbox(draw_pbox(ax, x, title=title, label=label, xlabel=xlabel), ev)
    return fig


def contour(ev: IntervalEvidence, x: Any) -> np.ndarray:
    """Pl({x}) = Σ of the masses of focal elements containing x (the contour function).

    For consonant (nested) evidence it is the possibility distribution the evidence
    stands for (the staircase under π in the paper's Fig. 4).

    Parameters
    ----------
    ev : dstoolkit.evidence.IntervalEvidence
        Scalar interval evidence (d = 1).
    x : array_like
        Points (unit of the quantity), any shape.

    Returns
    -------
    numpy.ndarray
        Pl({x}) at each point, the shape of ``x``; values in [0, 1].

    Raises
    ------
    dstoolkit.errors.EvidenceError
        If ``ev`` is not scalar interval evidence.

    Examples
    --------
    >>> from dstoolkit.evidence import triangular_evidence
    >>> ev = triangular_evidence(-10.59, -6.9, -3.21, p=3, epsilon=0.05, theta=(-20.0, 10.0))
    >>> float(contour(ev, -6.9))
    1.0
    >>> float(contour(ev, 5.0)) < 0.1
    True
    """
    _scalar(ev, "contour")
    x = np.asarray(x, dtype=float)
    inside = (ev.lo_1d[None, :] <= x.reshape(-1, 1)) & (ev.hi_1d[None, :] >= x.reshape(-1, 1))
    return (inside @ ev.mass).reshape(x.shape)


@dataclass
class PossibilityArtists:
    """What :func:`plot_possibility` draws on ``ax`` at the points ``x``.

    π, the α-cuts (their levels and, dotted, their ends), the α of each cut and the
    evidence's contour. Made by ``draw_possibility``, set by ``update_possibility``.
    """

    ax: Axes
    x: np.ndarray
    pi: Line2D
    ends: LineCollection
    cuts: LineCollection
    contour: Line2D | None
    animated: bool = False
    labels: list[Text] = field(default_factory=list)


@styled
def draw_possibility(
    ax: Axes,
    xlim: tuple[float, float],
    *,
    evidence: bool = False,
    title: str | None = None,
    xlabel: str = "x",
    animated: bool = False,
) -> PossibilityArtists:
    """Draw the parts of :func:`plot_possibility` over ``xlim`` that no distribution changes.

    Lines, legend, ranges, labels on ``ax``, with the contour line if ``evidence``; the data
    come with ``update_possibility``.
    """
    x = np.linspace(xlim[0], xlim[1], 801)
    zero = np.zeros_like(x)
    (pi,) = ax.plot(x, zero, color="black", lw=1.5, label="π(x)")
    # every cut's ends first, then every level: each level crosses only the ends of the
    # cuts above it, and covers them, as when each cut is drawn in turn
    ends = ax.vlines([], [], [], lw=0.8, ls=":")
    cuts = ax.hlines([], [], [], lw=3)
    line = None
    if evidence:
        (line,) = ax.step(
            x, zero, where="mid", color=BETP_COLOUR, lw=1.2, label="Pl({x}) of the evidence"
        )
    ax.set_xlim(*xlim)
    ax.set_ylim(-0.02, 1.08)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("possibility")
    if title:
        ax.set_title(title)
    legend_above(ax)
    if animated:
        animate(pi, ends, cuts, line, spines_of=ax)
    return PossibilityArtists(ax, x, pi, ends, cuts, line, animated)


@styled
def update_possibility(
    artists: PossibilityArtists,
    lower: float,
    mode: float,
    upper: float,
    p: int = 3,
    evidence: IntervalEvidence | None = None,
) -> None:
    """Draw π(lower, mode, upper) (eq. 22) in the artists of ``draw_possibility``.

    Also its ``p`` α-cuts (eq. 24) and the contour of ``evidence`` (if the artists have its
    line).
    """
    x, ax = artists.x, artists.ax
    artists.pi.set_ydata(possibility(x, lower, mode, upper))
    lo, hi = alpha_cuts(lower, mode, upper, p)
    alphas = np.arange(p)[::-1] / p
    colours = focal_colours(p)
    artists.cuts.set_segments([[(a, y), (b, y)] for a, b, y in zip(lo, hi, alphas, strict=True)])
    artists.cuts.set_color(list(colours))
    artists.ends.set_segments(
        [[(e, 0.0), (e, y)] for a, b, y in zip(lo, hi, alphas, strict=True) for e in (a, b)]
    )
    artists.ends.set_color(list(np.repeat(colours, 2, axis=0)))

    def label() -> Text:
        return ax.text(0.0, 0.0, "", va="center", fontsize=SMALL_PT)

    labels = _resize(artists.labels, p if p <= 6 else 0, label, artists.animated)
    for text, b, y in zip(labels, hi, alphas, strict=False):
        text.set_position((b, y))
        text.set_text(f"  α = {y:.3g}")
    if artists.contour is not None and evidence is not None:
        artists.contour.set_ydata(contour(evidence, x))


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
    """Plot the triangular possibility π (paper eq. 22) with its p α-cuts (eq. 24) as lines.

    With ``evidence`` given, its contour function Pl({x}) is drawn too: the staircase that
    the evidence puts in place of π. (``draw_possibility`` then
    ``update_possibility``.)

    Parameters
    ----------
    lower, mode, upper : float
        Support and mode of π (unit of the quantity), ``lower <= mode <= upper``.
    p : int, optional
        Number of α-cuts.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    evidence : dstoolkit.evidence.IntervalEvidence, optional
        Scalar evidence whose contour function is drawn as well.
    xlim : tuple of float, optional
        Range of the x axis; by default the support with a 15 % margin.
    title : str, optional
        Title of the axes.
    xlabel : str, optional
        Label of the x axis: the quantity and its unit.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    References
    ----------
    The paper's eqs. (22) and (24).

    Examples
    --------
    >>> fig = plot_possibility(-10.59, -6.9, -3.21, 3, xlabel="noise w (Hz)")
    >>> fig.axes[0].get_ylabel()
    'possibility'
    """
    fig, ax = _axes(ax, (6.0, 2.8))
    if xlim is None:
        half = 0.15 * (upper - lower if upper > lower else 1.0)
        xlim = (lower - half, upper + half)
    artists = draw_possibility(ax, xlim, evidence=evidence is not None, title=title, xlabel=xlabel)
    update_possibility(artists, lower, mode, upper, p, evidence)
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


def _bel_pl_sets(frame: Sequence[Hashable], subsets: Sequence[Any] | None) -> list[frozenset]:
    if subsets is None:
        subsets = all_subsets(frame) if len(frame) <= 4 else [frozenset([h]) for h in frame]
    return [frozenset(MassFunction._elements(s, tuple(frame))) for s in subsets]


@dataclass
class BelPlArtists:
    """What :func:`plot_bel_pl` draws on ``ax`` for the subsets ``sets`` of ``frame``.

    The Bel bars, the Pl − Bel bars on them and the BetP ticks of the ``single`` ones (their
    indices). Made by ``draw_bel_pl``, set by ``update_bel_pl``.
    """

    ax: Axes
    frame: tuple[Hashable, ...]
    sets: list[frozenset]
    bel: BarContainer
    gap: BarContainer
    single: list[int]
    betp: PathCollection | None


@styled
def draw_bel_pl(
    ax: Axes,
    frame: Sequence[Hashable],
    subsets: Sequence[Any] | None = None,
    *,
    title: str | None = None,
    animated: bool = False,
) -> BelPlArtists:
    """Draw the parts of :func:`plot_bel_pl` that no masses on ``frame`` change.

    Bars, ticks, legend, labels on ``ax``; the heights come with ``update_bel_pl``.
    """
    sets = _bel_pl_sets(frame, subsets)
    xs = np.arange(len(sets))
    zero = np.zeros(len(sets))
    bel = ax.bar(xs, zero, color=BEL_COLOUR, label="Bel", edgecolor="black", linewidth=0.5)
    gap = ax.bar(
        xs, zero, bottom=zero, color=PL_COLOUR, label="Pl − Bel", edgecolor="black", linewidth=0.5
    )
    single = [i for i, s in enumerate(sets) if len(s) == 1]
    betp = None
    if single:
        betp = ax.scatter(
            xs[single],
            np.zeros(len(single)),
            marker="_",
            s=400,
            color=BETP_COLOUR,
            linewidths=2.5,
            label="BetP",
            zorder=3,
        )
    ax.set_xticks(xs, [_name(s, frame) for s in sets], rotation=30 if len(sets) > 6 else 0)
    ax.set_ylim(0, 1.05)
    ax.set_xlabel("subset A of the frame")
    ax.set_ylabel("Bel(A), Pl(A)")
    if title:
        ax.set_title(title)
    legend_above(ax)
    if animated:
        animate(*bel.patches, *gap.patches, betp, spines_of=ax)
    return BelPlArtists(ax, tuple(frame), sets, bel, gap, single, betp)


def update_bel_pl(artists: BelPlArtists, mf: MassFunction) -> None:
    """Draw Bel, Pl and BetP of ``mf`` (Def. 2) in the artists of ``draw_bel_pl``."""
    if not isinstance(mf, MassFunction) or tuple(mf.frame) != artists.frame:
        raise EvidenceError(f"plot_bel_pl draws a MassFunction on the frame {artists.frame}")
    bel = [mf.belief(s) for s in artists.sets]
    pl = [mf.plausibility(s) for s in artists.sets]
    for rect, b in zip(artists.bel.patches, bel, strict=True):
        rect.set_height(b)
    for rect, b, p in zip(artists.gap.patches, bel, pl, strict=True):
        rect.set_y(b)
        rect.set_height(p - b)
    if artists.betp is not None:
        betp = mf.pignistic()
        ys = [betp[next(iter(artists.sets[i]))] for i in artists.single]
        artists.betp.set_offsets(np.column_stack([artists.single, ys]))


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
    the singletons. (``draw_bel_pl`` then ``update_bel_pl``.)

    Parameters
    ----------
    mf : dstoolkit.evidence.MassFunction
        A mass function on a finite frame.
    subsets : collections.abc.Sequence, optional
        The subsets to draw (each a tuple of hypotheses).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    title : str, optional
        Title of the axes.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    Raises
    ------
    dstoolkit.errors.EvidenceError
        If ``mf`` is not a :class:`~dstoolkit.evidence.MassFunction`.

    Examples
    --------
    >>> from dstoolkit.evidence import MassFunction
    >>> frame = ("low", "mid", "high")
    >>> mf = MassFunction({("low",): 0.5, ("low", "mid"): 0.3, frame: 0.2}, frame)
    >>> fig = plot_bel_pl(mf)
    >>> len(fig.axes)
    1
    """
    if not isinstance(mf, MassFunction):
        raise EvidenceError("plot_bel_pl draws a MassFunction on a finite frame")
    count = len(_bel_pl_sets(mf.frame, subsets))
    fig, ax = _axes(ax, (max(4.0, 0.7 * count + 1.5), 2.8))
    update_bel_pl(draw_bel_pl(ax, mf.frame, subsets, title=title), mf)
    return fig


@dataclass
class MassArtists:
    """What :func:`plot_masses` draws on ``ax``.

    One bar per focal element, its mass written on it. Made by ``draw_masses``, set by
    ``update_masses``.
    """

    ax: Axes
    animated: bool = False
    bars: list[Rectangle] = field(default_factory=list)
    labels: list[Text] = field(default_factory=list)
    names: list[str] = field(default_factory=list)


@styled
def _fit_category_labels(ax: Axes, names: Sequence[str]) -> None:
    """Tilt the category labels of ``ax`` when, set level, they would run into each other.

    Each gets the axes' width over the number of categories, and a label is about 0.6 em
    wide per character.
    """
    labels = ax.get_xticklabels()
    if not labels:
        return
    size_in = float(labels[0].get_fontsize()) / 72.0
    width_in = ax.get_position().width * root_figure(ax).get_figwidth()
    slot_in = width_in / max(len(names), np.ptp(ax.get_xlim()), 1.0)
    crowded = max(len(n) for n in names) * 0.6 * size_in > 0.9 * slot_in
    for label in labels:
        label.set_rotation(30 if crowded else 0)
        label.set_horizontalalignment("right" if crowded else "center")
        label.set_rotation_mode("anchor" if crowded else "default")


def draw_masses(ax: Axes, *, title: str | None = None, animated: bool = False) -> MassArtists:
    """Draw the parts of :func:`plot_masses` that no masses change on ``ax``.

    Labels, y range, title; the bars come with ``update_masses``.
    """
    _fixed_parts(ax, "focal element", "mass", 1.1, title, animated)
    return MassArtists(ax, animated)


@styled
def update_masses(artists: MassArtists, mf: MassFunction, *, title: str | None = None) -> None:
    """Draw the masses of ``mf`` in the artists of ``draw_masses`` and ``title`` if given.

    One bar per focal element, the x range following their number.
    """
    if not isinstance(mf, MassFunction):
        raise EvidenceError("plot_masses draws a MassFunction on a finite frame")
    ax = artists.ax
    items = mf.as_dict()

    def bar() -> Rectangle:
        patch = Rectangle(
            (0.0, 0.0), 0.8, 0.0, facecolor=BEL_COLOUR, edgecolor="black", linewidth=0.5
        )
        ax.add_patch(patch)
        return patch

    def label() -> Text:
        return ax.text(0.0, 0.0, "", ha="center", va="bottom", fontsize=SMALL_PT)

    bars = _resize(artists.bars, len(items), bar, artists.animated)
    labels = _resize(artists.labels, len(items), label, artists.animated)
    for x, (rect, text, v) in enumerate(zip(bars, labels, items.values(), strict=True)):
        rect.set_xy((x - 0.4, 0.0))
        rect.set_height(v)
        text.set_position((x, v))
        text.set_text(f"{v:.3g}")
    names = [_name(s, mf.frame) for s in items]
    if names != artists.names:  # (setting ticks or limits, even unchanged, redraws all)
        artists.names = names
        ax.set_xticks(range(len(names)), names)
        ax.relim(visible_only=True)  # the x range follows the bars, as when drawn anew
        ax.autoscale_view(scaley=False)
        _fit_category_labels(ax, names)
    if title:
        ax.title.set_text(title)


@styled
def plot_masses(mf: MassFunction, ax: Axes | None = None, *, title: str | None = None) -> Figure:
    """Plot the masses of a finite mass function, one bar per focal element.

    (``draw_masses`` then ``update_masses``.)

    Parameters
    ----------
    mf : dstoolkit.evidence.MassFunction
        A mass function on a finite frame.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    title : str, optional
        Title of the axes.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    Raises
    ------
    dstoolkit.errors.EvidenceError
        If ``mf`` is not a :class:`~dstoolkit.evidence.MassFunction`.

    Examples
    --------
    >>> from dstoolkit.evidence import MassFunction
    >>> frame = ("low", "mid", "high")
    >>> mf = MassFunction({("low",): 0.5, ("low", "mid"): 0.3, frame: 0.2}, frame)
    >>> fig = plot_masses(mf)
    >>> len(fig.axes[0].patches)
    3
    """
    if not isinstance(mf, MassFunction):
        raise EvidenceError("plot_masses draws a MassFunction on a finite frame")
    fig, ax = _axes(ax, (max(4.0, 0.7 * len(mf.as_dict()) + 1.5), 2.5))
    update_masses(draw_masses(ax, title=title), mf)
    return fig


@styled
def plot_products(
    a: MassFunction, b: MassFunction, ax: Axes | None = None, *, title: str | None = None
) -> Figure:
    """Dempster's product table (paper eq. 1): cell (i, j) holds m1(A_i)·m2(B_j) on A_i ∩ B_j.

    Empty intersections — the conflict K — are hatched grey.

    Parameters
    ----------
    a, b : dstoolkit.evidence.MassFunction
        Two mass functions on one frame.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    title : str, optional
        Title of the axes.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    Raises
    ------
    dstoolkit.errors.EvidenceError
        If the two are not on the same frame.

    References
    ----------
    The paper's eq. (1).

    Examples
    --------
    >>> from dstoolkit.evidence import MassFunction
    >>> frame = ("low", "mid", "high")
    >>> mf = MassFunction({("low",): 0.5, ("low", "mid"): 0.3, frame: 0.2}, frame)
    >>> other = MassFunction({("mid",): 0.6, frame: 0.4}, frame)
    >>> fig = plot_products(mf, other)
    >>> len(fig.axes[0].texts)
    6
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
                ax.add_patch(
                    plt.Rectangle(
                        (j - 0.5, i - 0.5), 1, 1, facecolor="0.85", hatch="//", edgecolor="0.5"
                    )
                )
            label = _name(inter, a.frame) if inter else "∅"
            ax.text(j, i, f"{label}\n{prod[i, j]:.4g}", ha="center", va="center", fontsize=SMALL_PT)
    ax.set_xticks(
        range(len(fb)), [f"{_name(t, a.frame)}\n{m:.3g}" for t, m in zip(fb, b.mass, strict=True)]
    )
    ax.set_yticks(
        range(len(fa)), [f"{_name(s, a.frame)}  {m:.3g}" for s, m in zip(fa, a.mass, strict=True)]
    )
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
    """Plot the focal elements of 2-D interval evidence as rectangles shaded by mass.

    The evidence is a random relation (paper eq. 16); each rectangle has its mass (or its
    ``labels`` entry) at its centre.

    Parameters
    ----------
    ev : dstoolkit.evidence.IntervalEvidence
        Interval evidence in two dimensions (d = 2).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    xlim, ylim : tuple of float, optional
        Ranges of the axes; by default the hull of the boxes with a 5 % margin.
    title : str, optional
        Title of the axes.
    labels : collections.abc.Sequence, optional
        One text per focal element, written in place of its mass.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    Raises
    ------
    dstoolkit.errors.EvidenceError
        If ``ev`` is not two-dimensional interval evidence.

    References
    ----------
    The paper's eq. (16).

    Examples
    --------
    >>> from dstoolkit.evidence import IntervalEvidence
    >>> ev = IntervalEvidence([[0.0, 0.0], [0.5, 0.2]], [[2.0, 1.0], [1.5, 0.8]], [0.4, 0.6])
    >>> fig = plot_boxes(ev)
    >>> sorted(t.get_text() for t in fig.axes[0].texts)
    ['0.4', '0.6']
    """
    if not isinstance(ev, IntervalEvidence) or ev.dim != 2:
        raise EvidenceError("plot_boxes draws 2-D interval evidence (IntervalEvidence, d = 2)")
    fig, ax = _axes(ax, (4.5, 4.0))
    lo, hi, m = ev.boxes_lo, ev.boxes_hi, ev.mass
    shade = plt.get_cmap("Blues")(0.25 + 0.65 * m / m.max())
    for i in np.argsort(-(hi - lo).prod(axis=1)):  # widest first, so small boxes stay on top
        ax.add_patch(
            plt.Rectangle(
                lo[i],
                *(hi[i] - lo[i]),
                facecolor=shade[i],
                alpha=0.55,
                edgecolor="black",
                linewidth=1.0,
            )
        )
        text = f"{m[i]:.3g}" if labels is None else labels[i]
        centre_x, centre_y = 0.5 * (lo[i] + hi[i])
        ax.text(
            centre_x,
            centre_y,
            text,
            ha="center",
            va="center",
            fontsize=9,
            bbox={"boxstyle": "round,pad=0.15", "fc": "white", "alpha": 0.8, "lw": 0},
        )
    pad = 0.05 * (hi.max(axis=0) - lo.min(axis=0))
    ax.set_xlim(*(xlim or (lo[:, 0].min() - pad[0], hi[:, 0].max() + pad[0])))
    ax.set_ylim(*(ylim or (lo[:, 1].min() - pad[1], hi[:, 1].max() + pad[1])))
    ax.set_xlabel("ξ₁")
    ax.set_ylabel("ξ₂")
    if title:
        ax.set_title(title)
    return fig


# -- tables ------------------------------------------------------------------------------


def markdown_table(headers: Sequence[str], rows: Iterable[Sequence[Any]], fmt: str = ".4f") -> Any:
    """Return a Markdown table (an IPython ``Markdown`` object); floats formatted with ``fmt``.

    Parameters
    ----------
    headers : collections.abc.Sequence
        The column headers, each one named (a blank header cell leaves a screen reader
        nothing to say for its column).
    rows : collections.abc.Iterable
        The rows, one value per column.
    fmt : str, optional
        Format of the floats (``format`` specification).

    Returns
    -------
    IPython.display.Markdown
        The table, shown as a table in a notebook.

    Raises
    ------
    InvalidInputError
        A header is blank.

    Examples
    --------
    >>> print(markdown_table(["x", "y"], [(1.0, "a")], fmt=".1f").data)
    | x | y |
    |---|---|
    | 1.0 | a |
    """
    from IPython.display import Markdown

    blank = [i for i, header in enumerate(headers) if not str(header).strip()]
    if blank:
        raise InvalidInputError(
            f"markdown_table: the header of column {blank[0] + 1} is blank; name every "
            "column (what its cells are), so that a screen reader can say it"
        )

    def cell(v: Any) -> str:
        if isinstance(v, float | np.floating):
            return format(float(v), fmt)
        return str(v)

    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in rows]
    return Markdown("\n".join(lines))


def interval_table(
    ev: IntervalEvidence, paper: Sequence[Sequence[float]] | None = None, fmt: str = ".4f"
) -> Any:
    """Focal elements and masses of scalar evidence as a Markdown table.

    With ``paper`` (rows lo, hi, mass as printed in a paper) a second group of columns
    shows the printed values and the difference of the masses.

    Parameters
    ----------
    ev : dstoolkit.evidence.IntervalEvidence
        Scalar interval evidence (d = 1).
    paper : collections.abc.Sequence, optional
        Rows (lo, hi, mass): the focal elements and masses as printed, one row per
        focal element of ``ev``.
    fmt : str, optional
        Format of the masses.

    Returns
    -------
    IPython.display.Markdown
        The table.

    Raises
    ------
    dstoolkit.errors.EvidenceError
        If ``ev`` is not scalar, or ``paper`` has another shape than its rows.

    Examples
    --------
    >>> from dstoolkit.evidence import triangular_evidence
    >>> ev = triangular_evidence(-10.59, -6.9, -3.21, p=3, epsilon=0.05, theta=(-20.0, 10.0))
    >>> interval_table(ev).data.splitlines()[0]
    '| focal element | mass |'
    """
    _scalar(ev, "interval_table")
    ours = ev.to_rows()

    def iv(lo: float, hi: float) -> str:
        return f"[{lo:.4g}, {hi:.4g}]"

    if paper is None:
        return markdown_table(
            ["focal element", "mass"], [(iv(lo, hi), m) for lo, hi, m in ours], fmt
        )
    printed = np.asarray(paper, dtype=float)
    if printed.shape != ours.shape:
        raise EvidenceError(f"paper rows have shape {printed.shape}, evidence {ours.shape}")

    def diff(d: float) -> str:
        return "0" if d == 0 else f"{d:+.1e}"

    rows = [
        (iv(a, b), m, iv(pa, pb), pm, diff(m - pm))
        for (a, b, m), (pa, pb, pm) in zip(ours, printed, strict=True)
    ]
    return markdown_table(["computed", "mass", "paper", "mass", "difference"], rows, fmt)

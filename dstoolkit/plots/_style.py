"""One figure style for the package and the book: sizes, fonts, colours, legends.

Every figure function of :mod:`dstoolkit.plots` draws inside :func:`styled` (the style is
applied while the figure is made, and the caller's matplotlib settings are left alone);
a chapter or notebook that draws its own figures calls :func:`use_style` once.

The rules, checked for every figure function by ``tests/test_figures.py``:

- a figure is at most :data:`COLUMN_WIDTH_IN` wide, the width of the book's text column,
  so it is shown at (nearly) its own size and its text stays legible;
- no text is smaller than :data:`SMALL_PT` points (ticks, legends, annotations);
- every axis has a label with its unit in parentheses, or a dimensionless quantity;
- a legend sits outside the data area (:func:`legend_above`) or where nothing is drawn.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any, TypeVar

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.axis import Axis
from matplotlib.figure import Figure
from matplotlib.legend import Legend
from matplotlib.lines import Line2D
from matplotlib.text import Text
from matplotlib.ticker import LogLocator, NullLocator, StrMethodFormatter

#: Width of the book's text column in inches (about 615 px at 96 px per inch, at 1280 px).
COLUMN_WIDTH_IN = 6.4
#: Body text of a figure: axis labels and titles, points.
FONT_PT = 10.0
#: The smallest text in a figure (tick labels, legends, annotations), points.
SMALL_PT = 9.0

#: Colours of the book: lower/belief, upper/plausibility, pignistic/estimate, truth, grey.
BEL_COLOUR = "#1f77b4"
PL_COLOUR = "#aec7e8"
BETP_COLOUR = "#d62728"
TRUTH_COLOUR = "#2ca02c"
GREY = "#7f7f7f"
#: Colour map of focal elements.
FOCAL_CMAP = "viridis"
#: The Okabe–Ito palette (Okabe and Ito, "Color Universal Design", 2008): eight colours
#: that people with any of the common colour-vision deficiencies can tell apart. The
#: methods of the book are drawn in them, each also with its own line style and marker.
OKABE_ITO = {
    "black": "#000000",
    "orange": "#E69F00",
    "sky blue": "#56B4E9",
    "bluish green": "#009E73",
    "yellow": "#F0E442",
    "blue": "#0072B2",
    "vermillion": "#D55E00",
    "reddish purple": "#CC79A7",
}

#: The matplotlib settings of the style.
RC: dict[str, Any] = {
    "figure.dpi": 96,
    "savefig.dpi": 150,
    "figure.figsize": (COLUMN_WIDTH_IN, 3.0),
    "figure.constrained_layout.use": True,
    "font.size": FONT_PT,
    "axes.titlesize": FONT_PT,
    "axes.labelsize": FONT_PT,
    "xtick.labelsize": SMALL_PT,
    "ytick.labelsize": SMALL_PT,
    "legend.fontsize": SMALL_PT,
    "legend.title_fontsize": SMALL_PT,
    "legend.framealpha": 0.9,
    "figure.titlesize": FONT_PT + 1,
    "axes.grid": False,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.linewidth": 1.4,
    "lines.markersize": 4.0,
    "mathtext.fontset": "dejavusans",
}

F = TypeVar("F", bound=Callable[..., Any])


@contextmanager
def figure_style() -> Iterator[None]:
    """Draw with the book's style inside the ``with`` block; restore the settings after.

    Only the keys of ``RC`` are restored (not ``mpl.rc_context``, which restores every
    setting: when the first figure of an IPython session is made inside it, the interactive
    mode that IPython's inline backend switches on would be undone, and the notebook's
    later figures would no longer show).

    Yields
    ------
    None
        Inside the block, figures are drawn in the book's style.

    See Also
    --------
    use_style : the same style for the rest of the session.

    Examples
    --------
    >>> import matplotlib as mpl
    >>> before = mpl.rcParams["font.size"]
    >>> with figure_style():
    ...     mpl.rcParams["font.size"] == FONT_PT
    True
    >>> mpl.rcParams["font.size"] == before
    True
    """
    params: Any = mpl.rcParams  # its keys are typed as literals; RC's are checked by the tests
    saved = {key: params[key] for key in RC}
    params.update(RC)
    try:
        yield
    finally:
        params.update(saved)


def styled(function: F) -> F:
    """Make the decorated figure function run inside :func:`figure_style`."""

    @functools.wraps(function)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with figure_style():
            return function(*args, **kwargs)

    return wrapper  # type: ignore[return-value]


def use_style() -> None:
    """Make the book's style matplotlib's default (for a chapter that draws its own figures).

    See Also
    --------
    figure_style : the style for one block only.

    Examples
    --------
    >>> import matplotlib as mpl
    >>> saved = dict(mpl.rcParams)
    >>> use_style()
    >>> mpl.rcParams["axes.labelsize"] == FONT_PT
    True
    >>> mpl.rcParams.update(saved)
    """
    params: Any = mpl.rcParams  # its keys are typed as literals
    params.update(RC)


def column_size(width: float, height: float) -> tuple[float, float]:
    """Return a figure size no wider than the text column (the height is scaled along)."""
    if width <= COLUMN_WIDTH_IN:
        return (width, height)
    return (COLUMN_WIDTH_IN, height * COLUMN_WIDTH_IN / width)


def root_figure(ax: Axes) -> Figure:
    """Return the :class:`~matplotlib.figure.Figure` that holds ``ax``, through any subfigures."""
    fig = ax.figure
    while not isinstance(fig, Figure):  # a SubFigure: its parent's figure
        fig = fig.figure
    return fig


def new_figure(width: float = COLUMN_WIDTH_IN, height: float = 3.0) -> Figure:
    """Make a constrained-layout :class:`Figure` of at most the column's width (no pyplot state)."""
    return Figure(figsize=column_size(width, height), layout="constrained", dpi=RC["figure.dpi"])


def legend_above(ax: Axes, ncols: int | None = None, **kwargs: Any) -> Legend | None:
    """Put the legend of ``ax`` in rows above its data area, where it cannot hide data.

    The axes' titles move up above it. Returns None when nothing is labelled.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes whose labelled artists the legend names.
    ncols : int, optional
        Entries per row; by default as many as there are, up to 3.
    **kwargs
        Further keyword arguments of ``matplotlib.axes.Axes.legend``.

    Returns
    -------
    matplotlib.legend.Legend or None
        The legend, or None if nothing is labelled.

    See Also
    --------
    label_line_ends : names written at the ends of the lines.

    Examples
    --------
    >>> fig = new_figure(4.0, 2.5)
    >>> ax = fig.subplots()
    >>> _ = ax.plot([0, 1], [0, 1], label="rising")
    >>> legend_above(ax).get_texts()[0].get_text()
    'rising'
    """
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return None
    ncols = ncols if ncols is not None else min(len(handles), 3)
    legend = ax.legend(
        handles,
        labels,
        loc="lower left",
        bbox_to_anchor=(0.0, 1.01),
        ncols=ncols,
        frameon=False,
        borderaxespad=0.0,
        handlelength=1.8,
        **kwargs,
    )
    rows = -(-len(handles) // ncols)
    for loc in ("left", "center", "right"):
        if ax.get_title(loc):
            ax.set_title(ax.get_title(loc), loc=loc, pad=8.0 + rows * 1.75 * SMALL_PT)
    return legend


def spread_positions(
    positions: list[float], gap: float, low: float = 0.0, high: float = 1.0
) -> list[float]:
    """Move positions apart until neighbours are at least ``gap`` apart.

    Each is pushed up past the one below it, then, if the highest passes ``high``, the stack
    is pushed down.

    Parameters
    ----------
    positions : list of float
        Wanted positions (any order), e.g. in axes fractions.
    gap : float
        The smallest distance between two returned positions, same unit.
    low, high : float, optional
        The range the positions should stay in.

    Returns
    -------
    list of float
        The positions, in the order given.

    Examples
    --------
    >>> [round(p, 2) for p in spread_positions([0.5, 0.52, 0.9], 0.1)]
    [0.5, 0.6, 0.9]
    """
    order = sorted(range(len(positions)), key=lambda i: positions[i])
    placed = [float(positions[i]) for i in order]
    for i in range(1, len(placed)):  # up from the lowest
        placed[i] = max(placed[i], placed[i - 1] + gap)
    if placed and placed[-1] > high:  # down from the highest, when the top overflows
        placed[-1] = max(high, low + gap * (len(placed) - 1))
        for i in range(len(placed) - 2, -1, -1):
            placed[i] = min(placed[i], placed[i + 1] - gap)
    # a pair pushed together by both passes: centre it on its wanted positions
    for i in range(1, len(placed)):
        if placed[i] - placed[i - 1] < gap - 1e-12:
            middle = 0.5 * (placed[i] + placed[i - 1])
            placed[i - 1], placed[i] = middle - gap / 2, middle + gap / 2
    result = [0.0] * len(positions)
    for rank, index in enumerate(order):
        result[index] = placed[rank]
    return result


def label_line_ends(
    ax: Axes,
    lines: list[Line2D] | None = None,
    *,
    labels: list[str] | None = None,
    short: bool = False,
) -> list[Text]:
    """Write direct labels: each line's label just right of the data area.

    Level with the line's last point, moved apart where two would overlap.

    A reader matches a series to its name where it ends, without the legend and without
    telling colours apart. Call it once the axes' limits are final.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes whose lines are labelled.
    lines : list of matplotlib.lines.Line2D, optional
        The lines to label; by default every line of ``ax`` with a label (not ``_...``).
    labels : list of str, optional
        Their texts (one per line); by default each line's label.
    short : bool, optional
        Whether parenthesised notes, such as "(eq. 32)", are left out of the texts (a
        legend can keep the full names).

    Returns
    -------
    list of matplotlib.text.Text
        The labels, in the order of ``lines``.

    Examples
    --------
    >>> fig = new_figure(4.0, 2.5)
    >>> ax = fig.subplots()
    >>> a, = ax.plot([0, 1], [0, 1], "-o", label="rising")
    >>> b, = ax.plot([0, 1], [1, 0.95], "--s", label="flat")
    >>> [t.get_text() for t in label_line_ends(ax)]
    ['rising', 'flat']
    """
    if lines is None:
        lines = [line for line in ax.get_lines() if not str(line.get_label()).startswith("_")]
    texts = labels if labels is not None else [str(line.get_label()) for line in lines]
    if short:
        texts = [re.sub(r"\s+\([^)]*\)", "", text) for text in texts]
    if len(texts) != len(lines):
        raise ValueError(
            f"label_line_ends got {len(lines)} lines and {len(texts)} labels; "
            "give one label per line"
        )
    engine = root_figure(ax).get_layout_engine()
    if engine is not None:  # the axes' height after the layout sets the labels' spacing
        engine.execute(root_figure(ax))
    made = [
        ax.text(
            1.02,
            0.5,
            text,
            transform=ax.transAxes,
            ha="left",
            va="center",
            fontsize=SMALL_PT,
            color="#222222",
            gid=END_LABEL_GID,
        )
        for text in texts
    ]
    place_line_end_labels(ax, lines, made)
    return made


#: The gid of the texts :func:`label_line_ends` writes, which tests and updates look for.
END_LABEL_GID = "line-end-label"


def place_line_end_labels(ax: Axes, lines: Sequence[Line2D], texts: Sequence[Text]) -> None:
    """Move the labels of :func:`label_line_ends` level with their lines' last points again.

    Call it when the lines got new data, once the axes' limits are final; a line with no
    finite point hides its label.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes of the lines.
    lines : sequence of matplotlib.lines.Line2D
        The labelled lines.
    texts : sequence of matplotlib.text.Text
        Their labels, in the same order.

    Examples
    --------
    >>> fig = new_figure(4.0, 2.5)
    >>> ax = fig.subplots()
    >>> line, = ax.plot([0, 1], [0, 1], label="rising")
    >>> texts = label_line_ends(ax)
    >>> line.set_data([], [])
    >>> place_line_end_labels(ax, [line], texts)
    >>> texts[0].get_visible()
    False
    """
    ax.get_xlim(), ax.get_ylim()  # the limits, autoscaled now if they are still pending
    to_axes = ax.transScale + ax.transLimits  # data -> axes fraction, whatever the layout
    ends, shown = [], []
    for line, text in zip(lines, texts, strict=True):
        x, y = (np.asarray(v, dtype=float).reshape(-1) for v in line.get_data())
        finite = np.flatnonzero(np.isfinite(x) & np.isfinite(y))
        if text.get_visible() != bool(finite.size):
            text.set_visible(bool(finite.size))
        if finite.size:
            ends.append(
                float(np.clip(to_axes.transform((x[finite[-1]], y[finite[-1]]))[1], 0.0, 1.0))
            )
            shown.append(text)
    # original=True: the position the layout gave, without apply_aspect (which would mark a
    # kept figure stale)
    height_pt = ax.get_position(original=True).height * root_figure(ax).get_figheight() * 72.0
    positions = spread_positions(ends, 1.25 * SMALL_PT / max(height_pt, 1.0))
    for level, text in zip(positions, shown, strict=True):
        # rounded: a kept figure's labels stand where a fresh figure's do, whatever the order
        # of the floating-point steps to its limits
        level = round(float(level), 6)
        if text.get_position()[1] != level:  # an unmoved label leaves a kept figure unchanged
            text.set_y(level)


def log_ticks(axis: Axis) -> None:
    """Readable ticks on a log axis: 1, 2, 5 per decade, written as plain numbers (0.2, 5).

    Matplotlib's default labels only the decades, so a range within one decade shows a
    single label, or none.

    Parameters
    ----------
    axis : matplotlib.axis.Axis
        A log-scaled axis, e.g. ``ax.yaxis``.

    Examples
    --------
    >>> fig = new_figure(4.0, 2.5)
    >>> ax = fig.subplots()
    >>> _ = ax.semilogy([1, 2], [0.3, 0.9])
    >>> log_ticks(ax.yaxis)
    >>> type(ax.yaxis.get_major_formatter()).__name__
    'StrMethodFormatter'
    """
    axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(StrMethodFormatter("{x:g}"))
    axis.set_minor_locator(NullLocator())

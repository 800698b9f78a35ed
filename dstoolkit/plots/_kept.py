"""A figure built once and then updated in place, for explorers that redraw on every change.

Building a figure (axes, ticks, legend) costs more than drawing new data on it, so an
explorer keeps one: the first call builds it, later calls update its artists
(``line.set_data``, ``text.set_text``, limits). The building function draws through the
updating one, so a kept figure and a freshly built one show the same for equal inputs.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Any, Generic, TypeVar

import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.ticker import AutoLocator

#: What a KeptFigure keeps: a Figure, or an object that holds one and its artists (such
#: as :class:`~dstoolkit.plots.FilterStepFigure`).
K = TypeVar("K")


class KeptFigure(Generic[K]):
    """``build(*args)`` on the first call, then ``update(figure, *args)`` on the same figure.

    Parameters
    ----------
    build
        Makes the figure (without pyplot) and draws the arguments on it; it may return an
        object that holds the figure and its artists instead of the ``Figure`` itself.
    update
        Draws other arguments on a figure (or such an object) that ``build`` made.

    Calling with ``key=...`` keeps one figure per key (figures of different layouts, e.g.
    one per choice of a dropdown).
    """

    def __init__(self, build: Callable[..., K], update: Callable[..., Any]) -> None:
        self.build, self.update = build, update
        self.figures: dict[Hashable, K] = {}

    def __call__(self, *args: Any, key: Hashable = None, **kwargs: Any) -> K:
        fig = self.figures.get(key)
        if fig is None:
            fig = self.figures[key] = self.build(*args, **kwargs)
        else:
            self.update(fig, *args, **kwargs)
        return fig


#: The steps of a linear axis's snapped limits (times a power of ten), as MaxNLocator's.
_LINEAR_STEPS = (1.0, 2.0, 2.5, 5.0, 10.0)
#: The values of a log axis's snapped limits within a decade: the ticks of ``log_ticks``.
_LOG_STEPS = (1.0, 2.0, 5.0, 10.0)


def snapped_limits(
    lo: float, hi: float, *, log: bool = False, margin: float = 0.05, bins: int = 5
) -> tuple[float, float]:
    """Return axis limits around data from ``lo`` to ``hi``, out to round numbers.

    Then widened by ``margin`` of that span (of its logarithm on a ``log`` axis), as
    matplotlib's margins.

    Round numbers are multiples of a step of 1, 2, 2.5 or 5 × 10ⁿ that cuts the span into
    at most ``bins`` (linear), or 1, 2, 5 × 10ⁿ (log, the ticks of ``log_ticks``). The limits
    of a kept figure then change only when the data cross a round number, so that most
    changes redraw only the data (``Explorer.png`` blits).
    """
    if log:
        a, b = np.log10(lo), np.log10(hi)
        a, b = np.log10(_round_log(a, np.floor)), np.log10(_round_log(b, np.ceil))
        pad = margin * (b - a)
        return float(10.0 ** (a - pad)), float(10.0 ** (b + pad))
    if not hi > lo:
        lo, hi = lo - 0.5 * (abs(lo) or 1.0), hi + 0.5 * (abs(hi) or 1.0)
    scale = 10.0 ** np.floor(np.log10((hi - lo) / bins))
    step = scale * next(s for s in _LINEAR_STEPS if s * scale * bins >= hi - lo)
    # rounded, so that 0.30000000000000004 reads 0.3
    lo = float(np.round(np.floor(lo / step) * step, 12))
    hi = float(np.round(np.ceil(hi / step) * step, 12))
    pad = margin * (hi - lo)
    return lo - pad, hi + pad


def zero_based_limits(lo: float, hi: float, *, margin: float = 0.05) -> tuple[float, float]:
    """Return axis limits from 0 (or −1, 2, 5 × 10ⁿ below it) to 1, 2, 5 × 10ⁿ (or 0).

    Around data from ``lo`` to ``hi``, widened by ``margin`` of that span: for a quantity
    read from zero (an error), limits that change only when the data cross a factor 2 or
    2.5.
    """
    lo = -_round_log(np.log10(-lo), np.ceil) if lo < 0 else 0.0
    hi = _round_log(np.log10(hi), np.ceil) if hi > 0 else 0.0
    if lo == hi:
        hi = 1.0
    pad = margin * (hi - lo)
    return lo - pad, hi + pad


def _round_log(exponent: float, outward: Callable[[float], float]) -> float:
    """10**exponent moved ``outward`` (np.floor or np.ceil) to 1, 2 or 5 × 10ⁿ."""
    decade = np.floor(exponent)
    within = 10.0 ** (exponent - decade)
    if outward is np.floor:
        value = max(s for s in _LOG_STEPS if s <= within * (1 + 1e-12))
    else:
        value = min(s for s in _LOG_STEPS if s >= within * (1 - 1e-12))
    return float(np.round(value * 10.0**decade, 12 - int(decade)))


def set_limits(
    ax: Axes, *, x: tuple[float, float] | None = None, y: tuple[float, float] | None = None
) -> None:
    """Set the axes' limits that differ from ``x`` and ``y``.

    Matplotlib marks a figure stale on any ``set_xlim``, even of the same values, and then
    it is drawn whole.
    """
    if x is not None and tuple(ax.get_xlim()) != tuple(map(float, x)):
        ax.set_xlim(*x)
    if y is not None and tuple(ax.get_ylim()) != tuple(map(float, y)):
        ax.set_ylim(*y)


class InnerTicks(AutoLocator):
    """Return matplotlib's default ticks, less those within ``margin`` of either end.

    ``margin`` is a fraction of the view. Their labels then never reach past the axes' ends,
    so that a kept figure whose limits move keeps its layout (a label sticking out of the
    figure makes :meth:`dstoolkit.teaching.Explorer.png` lay it out afresh, a second whole
    draw).
    """

    def __init__(self, margin: float = 0.04) -> None:
        super().__init__()
        self.margin = margin

    def tick_values(self, vmin: float, vmax: float) -> Any:
        ticks = np.asarray(super().tick_values(vmin, vmax), dtype=float)
        lo, hi = min(vmin, vmax), max(vmin, vmax)
        inset = self.margin * (hi - lo)
        return ticks[(ticks >= lo + inset) & (ticks <= hi - inset)]


def animate(*artists: Artist | None, spines_of: Axes | None = None) -> None:
    """Mark ``artists`` (None is skipped) as following the controls.

    A kept figure whose other artists did not change redraws only them (blitting, see
    :meth:`dstoolkit.teaching.Explorer.png`), on the picture of the rest as it was last
    drawn, above it, in order of zorder. ``spines_of``: the spines of that axes come along,
    because a fresh drawing puts them (zorder 2.5) over bars that reach the axes' edge.
    """
    spines = spines_of.spines.values() if spines_of is not None else ()
    for artist in (*artists, *spines):
        if artist is not None:
            artist.set_animated(True)

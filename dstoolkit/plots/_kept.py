"""A figure built once and then updated in place, for explorers that redraw on every change.

Building a figure (axes, ticks, legend) costs more than drawing new data on it, so an
explorer keeps one: the first call builds it, later calls update its artists
(``line.set_data``, ``text.set_text``, limits). The building function draws through the
updating one, so a kept figure and a freshly built one show the same for equal inputs.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Any, Generic, TypeVar

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

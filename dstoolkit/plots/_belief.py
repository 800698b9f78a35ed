"""Figures of the chapter on belief functions beyond Dempster: one curve per combination rule."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure

from ._style import GREY, OKABE_ITO, legend_above, new_figure, styled

#: Each combination rule's colour, line style, marker and label: the rules differ in line
#: style and marker as well as in colour.
RULE_STYLE: dict[str, dict[str, str]] = {
    "paper": {
        "color": OKABE_ITO["vermillion"],
        "ls": "-",
        "marker": "o",
        "label": "paper's rule (eqs. 9–10)",
    },
    "paper_cells": {
        "color": OKABE_ITO["orange"],
        "ls": "-.",
        "marker": "D",
        "label": "paper's rule on cells",
    },
    "cautious": {
        "color": OKABE_ITO["blue"],
        "ls": "--",
        "marker": "s",
        "label": "cautious rule",
    },
    "dempster": {
        "color": OKABE_ITO["bluish green"],
        "ls": ":",
        "marker": "^",
        "label": "Dempster's rule",
    },
}


@styled
def plot_rule_curves(
    x: Sequence[float],
    curves: Mapping[str, Sequence[float]],
    *,
    xlabel: str,
    ylabel: str,
    current: float | None = None,
    title: str | None = None,
    height: float = 3.0,
) -> Figure:
    """Plot one curve per combination rule of :data:`RULE_STYLE` against a common x.

    Parameters
    ----------
    x : sequence of float
        The common abscissae.
    curves : dict
        The values of each rule (keys of :data:`RULE_STYLE`), a sequence of float per
        rule, one per x.
    xlabel, ylabel : str
        The axes' labels, with units.
    current : float, optional
        An x to mark with a grey vertical line (the explorer's setting).
    title : str, optional
        The title.
    height : float, optional
        The figure's height, inches.

    Returns
    -------
    matplotlib.figure.Figure
        One panel, the legend above it.

    Examples
    --------
    >>> fig = plot_rule_curves([1, 2], {"cautious": [0.4, 0.4], "dempster": [0.4, 0.64]},
    ...                        xlabel="copies n", ylabel="Bel({ok})")
    >>> [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    ['cautious rule', "Dempster's rule"]
    """
    fig = new_figure(height=height)
    ax = fig.subplots()
    xs = np.asarray(x, dtype=float)
    every = max(1, xs.size // 12)
    for i, (rule, ys) in enumerate(curves.items()):
        st = RULE_STYLE[rule]
        ax.plot(
            xs,
            np.asarray(ys, dtype=float),
            color=st["color"],
            ls=st["ls"],
            marker=st["marker"],
            markevery=(i % every, every),
            ms=5,
            label=st["label"],
        )
    if current is not None:
        ax.axvline(current, color=GREY, lw=1.0, ls="-.", label="your setting")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title)
    legend_above(ax, ncols=2)
    return fig

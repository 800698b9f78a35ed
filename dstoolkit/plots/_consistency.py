"""The consistency figure: average NEES and NIS per step against their χ² bands."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from dstoolkit.studies import ConsistencyStudy

from ._experiments import STYLE
from ._style import GREY, legend_above, new_figure, styled

#: What each side of a band means, written on the figure (not told by colour alone).
_BAND_LABEL = "95 % band of a consistent filter"


@styled
def plot_consistency(study: ConsistencyStudy, *, title: str | None = None) -> Figure:
    """Plot the average NEES (top) and NIS (bottom) per step of a study's Gaussian filters.

    Each panel shades the 95 % χ² band of an average of N runs
    (:func:`dstoolkit.filters.chi2_band`); the y axes are logarithmic, so that a filter
    over- or under-confident by a factor shows as a shift by the same distance either way.

    Parameters
    ----------
    study : dstoolkit.studies.ConsistencyStudy
        What :func:`dstoolkit.studies.gauge_consistency` returned.
    title : str, optional
        Title above the top panel.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels sharing the step axis.

    Examples
    --------
    >>> from dstoolkit.studies import gauge_consistency
    >>> fig = plot_consistency(gauge_consistency(runs=5))
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['average NEES', 'average NIS']
    """
    fig = new_figure(height=4.6)
    top, bottom = fig.subplots(2, 1, sharex=True)
    panels = (
        (top, study.nees, study.nees_band, "average NEES"),
        (bottom, study.nis, study.nis_band, "average NIS"),
    )
    for ax, values, band, label in panels:
        ax.axhspan(*band, color=GREY, alpha=0.25, hatch="//", label=_BAND_LABEL)
        for index, (name, series) in enumerate(values.items()):
            steps = np.arange(1, series.size + 1)
            style = STYLE[name]
            ax.plot(
                steps,
                series,
                color=style["color"],
                ls=style["ls"],
                marker=style["marker"],
                # the filters' markers alternate steps, so that none hides another's
                markevery=(2 * index % 4, 4),
                ms=4,
                label=style["label"],
            )
        ax.set_yscale("log")
        ax.set_ylabel(label)
        finite = np.concatenate([v[np.isfinite(v)] for v in values.values()] + [np.array(band)])
        ax.set_ylim(min(0.1, finite.min() / 1.5), max(10.0, finite.max() * 1.5))
    bottom.set_xlabel("step k")
    if title:
        top.set_title(title)
    legend_above(top, ncols=2)
    return fig

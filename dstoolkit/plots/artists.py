"""Figures kept and redrawn in place: the drawing layer the explorers build on.

A ``draw_…`` function makes a figure's artists once and returns them in a small artists
object; the matching ``update_…`` moves those artists to new data without making a new
figure, which is what keeps an explorer's answer to a slider under its latency budget.
:class:`KeptFigure` and :func:`animate` hold such a figure for its whole life.

Users who only want a picture call the ``plot_…`` functions of :mod:`dstoolkit.plots`.
"""

from __future__ import annotations

from ._evidence import (
    BelPlArtists,
    FocalIntervalArtists,
    MassArtists,
    PboxArtists,
    PossibilityArtists,
    draw_bel_pl,
    draw_focal_intervals,
    draw_masses,
    draw_pbox,
    draw_possibility,
    pbox_grid,
    update_bel_pl,
    update_focal_intervals,
    update_masses,
    update_pbox,
    update_possibility,
)
from ._experiments import update_estimates
from ._gauge import gauge_detection_figure, update_gauge_detection
from ._kept import KeptFigure, animate
from ._studies import noise_bounds_figure, update_noise_bounds_figure

__all__ = [
    "BelPlArtists",
    "FocalIntervalArtists",
    "KeptFigure",
    "MassArtists",
    "PboxArtists",
    "PossibilityArtists",
    "animate",
    "draw_bel_pl",
    "draw_focal_intervals",
    "draw_masses",
    "draw_pbox",
    "draw_possibility",
    "gauge_detection_figure",
    "noise_bounds_figure",
    "pbox_grid",
    "update_bel_pl",
    "update_estimates",
    "update_focal_intervals",
    "update_gauge_detection",
    "update_masses",
    "update_noise_bounds_figure",
    "update_pbox",
    "update_possibility",
]

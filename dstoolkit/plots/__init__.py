"""Figures for the book and for users (needs the ``plots`` extra: matplotlib).
"""

from __future__ import annotations

from dstoolkit.errors import require_extra

require_extra("matplotlib", "plots", "dstoolkit.plots")

from ._evidence import (  # noqa: E402
    contour,
    interval_table,
    markdown_table,
    plot_bel_pl,
    plot_boxes,
    plot_enclosure,
    plot_filter_errors,
    plot_filter_step,
    plot_focal_intervals,
    plot_masses,
    plot_pbox,
    plot_possibility,
    plot_products,
)
from ._experiments import (  # noqa: E402
    STYLE,
    plot_estimates,
    plot_table3,
)
from ._gauge import (  # noqa: E402
    GREY,
    TRUTH_COLOUR,
    plot_recording,
    plot_resonances,
)
from ._studies import (  # noqa: E402
    plot_example,
    plot_noise_assumption,
    plot_order_rule_study,
    plot_scale_study,
    plot_step_errors,
)

__all__ = [
    "GREY",
    "STYLE",
    "TRUTH_COLOUR",
    "contour",
    "interval_table",
    "markdown_table",
    "plot_bel_pl",
    "plot_boxes",
    "plot_enclosure",
    "plot_estimates",
    "plot_example",
    "plot_filter_errors",
    "plot_filter_step",
    "plot_focal_intervals",
    "plot_masses",
    "plot_noise_assumption",
    "plot_order_rule_study",
    "plot_pbox",
    "plot_possibility",
    "plot_products",
    "plot_recording",
    "plot_resonances",
    "plot_scale_study",
    "plot_step_errors",
    "plot_table3",
]

"""Figures for the book and for users (needs the ``plots`` extra: matplotlib).

Every figure is drawn in one style (``_style``): at most the book's column wide, text of
9 pt or more, labelled axes with units, legends off the data. ``use_style()`` makes it
matplotlib's default for figures drawn by hand. The pictures of filter runs are also
classes (``EnclosureFigure``, ``FilterErrorsFigure``, ``FilterStepFigure``) whose
``update`` redraws a kept figure for another run, as the explorers do on every change.
"""

from __future__ import annotations

from dstoolkit.errors import require_extra

require_extra("matplotlib", "plots", "dstoolkit.plots")

from ._belief import RULE_STYLE, plot_rule_curves  # noqa: E402
from ._chapter_figures import (  # noqa: E402
    plot_image_methods,
    plot_nassreddine_step,
    plot_sweep_peaks,
)
from ._consistency import plot_consistency  # noqa: E402
from ._evidence import (  # noqa: E402
    contour,
    interval_table,
    markdown_table,
    plot_bel_pl,
    plot_boxes,
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
from ._filter_figures import (  # noqa: E402
    EnclosureFigure,
    FilterErrorsFigure,
    FilterStepFigure,
    plot_enclosure,
    plot_filter_errors,
    plot_filter_step,
)
from ._gauge import (  # noqa: E402
    add_trace,
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
from ._style import (  # noqa: E402
    BEL_COLOUR,
    BETP_COLOUR,
    GREY,
    OKABE_ITO,
    TRUTH_COLOUR,
    figure_style,
    label_line_ends,
    legend_above,
    log_ticks,
    spread_positions,
    use_style,
)

__all__ = [
    "add_trace",
    "plot_consistency",
    "plot_rule_curves",
    "RULE_STYLE",
    "BEL_COLOUR",
    "BETP_COLOUR",
    "EnclosureFigure",
    "FilterErrorsFigure",
    "FilterStepFigure",
    "GREY",
    "OKABE_ITO",
    "STYLE",
    "TRUTH_COLOUR",
    "contour",
    "figure_style",
    "interval_table",
    "label_line_ends",
    "legend_above",
    "log_ticks",
    "markdown_table",
    "plot_bel_pl",
    "plot_boxes",
    "plot_enclosure",
    "plot_estimates",
    "plot_example",
    "plot_filter_errors",
    "plot_filter_step",
    "plot_focal_intervals",
    "plot_image_methods",
    "plot_masses",
    "plot_nassreddine_step",
    "plot_noise_assumption",
    "plot_order_rule_study",
    "plot_pbox",
    "plot_possibility",
    "plot_products",
    "plot_recording",
    "plot_resonances",
    "plot_scale_study",
    "plot_step_errors",
    "plot_sweep_peaks",
    "plot_table3",
    "spread_positions",
    "use_style",
]

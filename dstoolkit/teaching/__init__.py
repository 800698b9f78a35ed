"""The teaching layer (needs the ``teaching`` extra).

The explorers (widgets), the exercise check cells and the lab helpers.

The explorers' framework (:class:`Explorer`, its controls, its static-site form) is
``_explorer``; each chapter's explorers are in ``_explorers_<chapter>`` (the lab's
measuring station, :class:`LabWidget`, is an ``Explorer`` too), and the numbers they print
in ``_readouts``.
"""

from __future__ import annotations

from dstoolkit.errors import require_extra

require_extra("ipywidgets", "teaching", "dstoolkit.teaching")
require_extra("matplotlib", "teaching", "dstoolkit.teaching")

from ._exercises import (  # noqa: E402
    FAILURE_RUNS,
    FAILURE_SCALE,
    FRAME,
    GAUGE_LATENCY,
    LAB_BAND,
    LAB_CUTOFF_DIAMETER,
    LAB_LAG_SAMPLES,
    LAB_SAMPLERATE,
    LAB_TOLERANCE_CASE,
    LAB_UNCERTAINTIES_MM,
    MONOTONE_BOX,
    NASSREDDINE_PREDICTION,
    NASSREDDINE_READING,
    PAPER_Z1,
    REGISTRY,
    SWEEP_RATE,
    Case,
    CodingExercise,
    Exercise,
    Feedback,
    check,
    coding_exercise,
    eq43_readings,
    exercise,
    exercises,
    mistake,
    once,
    zadeh,
)
from ._explorer import (  # noqa: E402
    STATIC_SITE_ENV,
    Explorer,
    positions,
    slider,
    static_site,
)
from ._explorers_belief import copies_explorer  # noqa: E402
from ._explorers_beyond import noise_bounds_explorer  # noqa: E402
from ._explorers_bounded import bounded_error_explorer  # noqa: E402
from ._explorers_combining import conflict_explorer  # noqa: E402
from ._explorers_dependent import dependent_combination_explorer  # noqa: E402
from ._explorers_estimation import level_estimation_explorer  # noqa: E402
from ._explorers_filter import filter_step_explorer, filter_widget, render_filter  # noqa: E402
from ._explorers_gauge import GAUGE_CONDITIONS, gauge_explorer  # noqa: E402
from ._explorers_lab import LabWidget, lab_widget  # noqa: E402
from ._explorers_mass import mass_function_explorer  # noqa: E402
from ._explorers_noise import noise_evidence_explorer  # noqa: E402
from ._explorers_random_sets import compare_image_methods, extension_explorer  # noqa: E402
from ._explorers_recursion import consistency_explorer  # noqa: E402
from ._handin import hand_in  # noqa: E402
from ._lab import (  # noqa: E402
    VIRTUAL,
    VIRTUAL_LABEL,
    LabSettings,
    calibration_correlation,
    draw_gauge,
    imitate_audio_failure,
    lab_measurement,
    lab_numbers,
    level_error_from_temperature,
    plot_calibration,
    plot_method_levels,
)
from ._limits import set_time_limit  # noqa: E402
from ._print_edition import register_print_figures  # noqa: E402
from ._variants import set_variant  # noqa: E402

# the PDF edition shows an explorer's first figure where the web page shows the widget
register_print_figures(Explorer, LabWidget)

__all__ = [
    "consistency_explorer",
    "copies_explorer",
    "Case",
    "CodingExercise",
    "Exercise",
    "Explorer",
    "FAILURE_RUNS",
    "FAILURE_SCALE",
    "FRAME",
    "Feedback",
    "GAUGE_CONDITIONS",
    "GAUGE_LATENCY",
    "LAB_BAND",
    "LAB_CUTOFF_DIAMETER",
    "LAB_LAG_SAMPLES",
    "LAB_SAMPLERATE",
    "LAB_TOLERANCE_CASE",
    "LAB_UNCERTAINTIES_MM",
    "LabSettings",
    "LabWidget",
    "MONOTONE_BOX",
    "NASSREDDINE_PREDICTION",
    "NASSREDDINE_READING",
    "PAPER_Z1",
    "REGISTRY",
    "STATIC_SITE_ENV",
    "SWEEP_RATE",
    "VIRTUAL",
    "VIRTUAL_LABEL",
    "bounded_error_explorer",
    "calibration_correlation",
    "check",
    "coding_exercise",
    "compare_image_methods",
    "conflict_explorer",
    "dependent_combination_explorer",
    "draw_gauge",
    "eq43_readings",
    "exercise",
    "exercises",
    "extension_explorer",
    "filter_step_explorer",
    "filter_widget",
    "gauge_explorer",
    "hand_in",
    "imitate_audio_failure",
    "lab_measurement",
    "lab_numbers",
    "lab_widget",
    "level_error_from_temperature",
    "level_estimation_explorer",
    "mistake",
    "mass_function_explorer",
    "noise_bounds_explorer",
    "noise_evidence_explorer",
    "once",
    "plot_calibration",
    "plot_method_levels",
    "positions",
    "render_filter",
    "set_time_limit",
    "set_variant",
    "slider",
    "static_site",
    "zadeh",
]

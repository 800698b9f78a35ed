"""Every exercise of the book and its sheets, registered on import.

The checked answers (:mod:`._ex_evidence`, :mod:`._ex_filter`, :mod:`._ex_gauge`) and the coding
exercises (:mod:`._ex_coding`; the teacher's plain solutions are in the repository's
``answer_key``, not in this package). The checker
itself is :mod:`._checking` (answers) and :mod:`._coding` (functions).
"""

from __future__ import annotations

from . import (
    _ex_belief,  # noqa: F401  (registers the belief functions' exercises)
    _ex_coding,  # noqa: F401  (registers the coding exercises)
    _ex_recursion,  # noqa: F401  (registers the one recursion's exercises)
)
from ._checking import REGISTRY, Exercise, Feedback, check, exercise, exercises, mistake
from ._coding import Case, CodingExercise, coding_exercise
from ._ex_evidence import FRAME, MONOTONE_BOX, once, zadeh
from ._ex_filter import PAPER_Z1
from ._ex_gauge import (
    FAILURE_RUNS,
    FAILURE_SCALE,
    GAUGE_LATENCY,
    LAB_BAND,
    LAB_CUTOFF_DIAMETER,
    LAB_LAG_SAMPLES,
    LAB_SAMPLERATE,
    LAB_TOLERANCE_CASE,
    LAB_UNCERTAINTIES_MM,
    NASSREDDINE_PREDICTION,
    NASSREDDINE_READING,
    SWEEP_RATE,
    eq43_readings,
)

__all__ = [
    "Case",
    "CodingExercise",
    "Exercise",
    "FAILURE_RUNS",
    "FAILURE_SCALE",
    "FRAME",
    "Feedback",
    "GAUGE_LATENCY",
    "LAB_BAND",
    "LAB_CUTOFF_DIAMETER",
    "LAB_LAG_SAMPLES",
    "LAB_SAMPLERATE",
    "LAB_TOLERANCE_CASE",
    "LAB_UNCERTAINTIES_MM",
    "MONOTONE_BOX",
    "NASSREDDINE_PREDICTION",
    "NASSREDDINE_READING",
    "PAPER_Z1",
    "REGISTRY",
    "SWEEP_RATE",
    "check",
    "coding_exercise",
    "eq43_readings",
    "exercise",
    "exercises",
    "mistake",
    "once",
    "zadeh",
]

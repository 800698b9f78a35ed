"""State-space models and the filters: the paper's dependent-evidence filter
(Steps 1-6, eqs. 30-31), Nassreddine's filter, a bounded-error (set-membership) filter,
the extended Kalman filter and a bootstrap particle filter, and example systems.
"""

from __future__ import annotations

from dstoolkit.errors import (
    InconsistentDataError,
)

from ._analysis import (
    converged_at,
    enclosure_summary,
)
from ._base import (
    FilterBase,
)
from ._bounded_error import (
    BoundedErrorFilter,
)
from ._dependent import (
    COUNTS,
    DIAGNOSTICS,
    DependentEvidenceFilter,
    NoiseEvidence,
    observe,
    predict,
)
from ._example_systems import (
    LOTKA_VOLTERRA_X0,
    lotka_volterra,
    random_walk,
    simulate_lotka_volterra,
)
from ._kalman import (
    KalmanFilter,
    finite_difference_jacobian,
)
from ._model import (
    BoundedNoise,
    Filter,
    FilterResult,
    ScalarMaps,
    StateSpaceModel,
    with_input,
)
from ._nassreddine import (
    NassreddineFilter,
    cluster_boxes,
    merge_equal_boxes,
)
from ._particle import (
    ParticleFilter,
    systematic_resample,
)

__all__ = [
    "BoundedErrorFilter",
    "BoundedNoise",
    "COUNTS",
    "DIAGNOSTICS",
    "DependentEvidenceFilter",
    "Filter",
    "FilterBase",
    "FilterResult",
    "InconsistentDataError",
    "KalmanFilter",
    "LOTKA_VOLTERRA_X0",
    "NassreddineFilter",
    "NoiseEvidence",
    "ParticleFilter",
    "ScalarMaps",
    "StateSpaceModel",
    "cluster_boxes",
    "converged_at",
    "enclosure_summary",
    "finite_difference_jacobian",
    "lotka_volterra",
    "merge_equal_boxes",
    "observe",
    "predict",
    "random_walk",
    "simulate_lotka_volterra",
    "systematic_resample",
    "with_input",
]

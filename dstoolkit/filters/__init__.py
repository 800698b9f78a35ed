"""State-space models, the filters and example systems.

The paper's dependent-evidence filter (§3.2, Steps 1–6, on eq. 21's model: eqs. 22–26,
eqs. 13–16, eq. 20, eqs. A1–A8), Nassreddine's filter, a
bounded-error (set-membership) filter, the extended Kalman filter, the unscented Kalman filter and a
bootstrap particle filter; NEES/NIS consistency checks with their χ² bands, the
Rauch–Tung–Striebel smoother; and example systems.
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
    KERNELS,
    Filter,
    FilterState,
)
from ._bounded_error import (
    BoundedErrorFilter,
    BoundedErrorRecord,
    BoundedErrorState,
)
from ._consistency import (
    SmootherResult,
    chi2_band,
    nees,
    nis,
    rts_smoother,
    smooth_kalman,
)
from ._dependent import (
    COUNTS,
    DIAGNOSTICS,
    DependentEvidenceFilter,
    DependentRecord,
    DependentState,
    NoiseEvidence,
)
from ._example_systems import (
    LOTKA_VOLTERRA_X0,
    lotka_volterra,
    random_walk,
    simulate_lotka_volterra,
)
from ._kalman import (
    KalmanFilter,
    KalmanRecord,
    KalmanState,
    finite_difference_jacobian,
)
from ._model import (
    BatchResult,
    BoundedNoise,
    FilterResult,
    StateSpaceModel,
    with_input,
)
from ._nassreddine import (
    NassreddineFilter,
    NassreddineRecord,
    NassreddineState,
)
from ._particle import (
    ParticleFilter,
    ParticleRecord,
    ParticleState,
    systematic_resample,
)
from ._registry import (
    ComparisonSettings,
    FilterEntry,
    filter_named,
    gaussian_filters,
    register_filter,
    registered_filters,
    set_comparison_kernel,
    table3_filters,
    unregister_filter,
)
from ._unscented import (
    UnscentedKalmanFilter,
    UnscentedRecord,
    UnscentedState,
    sigma_points,
    sigma_weights,
)

__all__ = [
    "BatchResult",
    "BoundedErrorFilter",
    "BoundedErrorRecord",
    "BoundedErrorState",
    "BoundedNoise",
    "ComparisonSettings",
    "set_comparison_kernel",
    "COUNTS",
    "DIAGNOSTICS",
    "DependentEvidenceFilter",
    "DependentRecord",
    "DependentState",
    "Filter",
    "FilterEntry",
    "FilterState",
    "KERNELS",
    "FilterResult",
    "InconsistentDataError",
    "KalmanFilter",
    "KalmanRecord",
    "KalmanState",
    "LOTKA_VOLTERRA_X0",
    "NassreddineFilter",
    "NassreddineRecord",
    "NassreddineState",
    "NoiseEvidence",
    "ParticleFilter",
    "ParticleRecord",
    "ParticleState",
    "SmootherResult",
    "StateSpaceModel",
    "UnscentedKalmanFilter",
    "UnscentedRecord",
    "UnscentedState",
    "chi2_band",
    "converged_at",
    "enclosure_summary",
    "filter_named",
    "finite_difference_jacobian",
    "lotka_volterra",
    "nees",
    "nis",
    "random_walk",
    "register_filter",
    "gaussian_filters",
    "registered_filters",
    "rts_smoother",
    "sigma_points",
    "sigma_weights",
    "smooth_kalman",
    "simulate_lotka_volterra",
    "systematic_resample",
    "table3_filters",
    "unregister_filter",
    "with_input",
]

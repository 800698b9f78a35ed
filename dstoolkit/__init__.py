"""dstoolkit: evidence-theory state estimation under bounded noise.

Implements Xu, Li, Li, Zhou, "State Estimation Using Dependent Evidence Fusion: Application
to Acoustic Resonance-Based Liquid Level Measurement", Sensors 17(4):924, 2017.

The package is built in layers, each importing only those below it: :mod:`dstoolkit.errors`,
:mod:`dstoolkit.evidence` (the evidence algebra), :mod:`dstoolkit.filters` (models and
filters), :mod:`dstoolkit.gauge` (the acoustic level gauge) and :mod:`dstoolkit.studies`
(the paper's Table 3 and the studies beyond it) form the core, which needs numpy and scipy
only; :mod:`dstoolkit.plots`, :mod:`dstoolkit.audio` and :mod:`dstoolkit.teaching` need
extras. The most used names of the core are importable from ``dstoolkit`` itself.

Examples
--------
The paper's filter on a simulated gauge at 9.6 m (eqs. 39–40 of the paper):

>>> import dstoolkit
>>> from dstoolkit.gauge import gauge_state_space_model, simulate_gauge
>>> sequence = simulate_gauge(9.6, 23.9, seed=0)
>>> flt = dstoolkit.DependentEvidenceFilter()
>>> result = flt.run(gauge_state_space_model(), sequence.readings, sequence.inputs)
>>> result.estimates.shape
(83, 1)
"""

from importlib.metadata import PackageNotFoundError as _PackageNotFoundError
from importlib.metadata import version as _version

from . import _startup  # noqa: F401 - first: the command stops quietly while importing
from .errors import (
    AudioUnavailableError,
    DetectionError,
    DstoolkitError,
    DstoolkitWarning,
    EvidenceError,
    InconsistentDataError,
    InvalidInputError,
    MemoryBudgetError,
    MissingExtraError,
    NotMonotoneError,
    TotalConflictError,
    VertexMethodWarning,
)
from .evidence import (
    Dependence,
    Evidence,
    IntervalEvidence,
    MassFunction,
    TriangularBounds,
    alpha_cuts,
    cartesian_product,
    combine_dependent,
    conflict,
    decorrelate,
    dempster,
    dependence,
    discount,
    energy,
    image,
    joint_energy,
    memory_budget,
    possibility,
    projection,
    set_memory_budget,
    triangular_evidence,
    triangular_from_samples,
)
from .filters import (
    BatchResult,
    BoundedErrorFilter,
    BoundedNoise,
    DependentEvidenceFilter,
    Filter,
    FilterResult,
    KalmanFilter,
    NassreddineFilter,
    ParticleFilter,
    StateSpaceModel,
)

__all__ = [
    "BatchResult",
    "Filter",
    "AudioUnavailableError",
    "BoundedErrorFilter",
    "BoundedNoise",
    "Dependence",
    "DependentEvidenceFilter",
    "DetectionError",
    "DstoolkitError",
    "DstoolkitWarning",
    "Evidence",
    "EvidenceError",
    "FilterResult",
    "InconsistentDataError",
    "IntervalEvidence",
    "InvalidInputError",
    "KalmanFilter",
    "MassFunction",
    "MemoryBudgetError",
    "MissingExtraError",
    "NassreddineFilter",
    "NotMonotoneError",
    "ParticleFilter",
    "StateSpaceModel",
    "TotalConflictError",
    "TriangularBounds",
    "VertexMethodWarning",
    "alpha_cuts",
    "cartesian_product",
    "combine_dependent",
    "conflict",
    "decorrelate",
    "dempster",
    "dependence",
    "discount",
    "energy",
    "image",
    "joint_energy",
    "memory_budget",
    "possibility",
    "projection",
    "set_memory_budget",
    "triangular_evidence",
    "triangular_from_samples",
]


try:
    __version__ = _version("dstoolkit")
except _PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"

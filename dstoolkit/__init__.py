"""dstoolkit: evidence-theory state estimation under bounded noise.

Implements Xu, Li, Li, Zhou, "State Estimation Using Dependent Evidence Fusion: Application
to Acoustic Resonance-Based Liquid Level Measurement", Sensors 17(4):924, 2017.
"""

from importlib.metadata import PackageNotFoundError as _PackageNotFoundError
from importlib.metadata import version as _version

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

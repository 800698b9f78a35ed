"""dstoolkit: evidence-theory state estimation under bounded noise.

Implements Xu, Li, Li, Zhou, "State Estimation Using Dependent Evidence Fusion: Application
to Acoustic Resonance-Based Liquid Level Measurement", Sensors 17(4):924, 2017.
"""

from .bounded_error_filter import BoundedErrorFilter
from .combination import (
    Dependence,
    combine_dependent,
    conflict,
    decorrelate,
    dempster,
    dependence,
    discount,
    energy,
    joint_energy,
)
from .dependent_filter import DependentEvidenceFilter
from .errors import (
    AudioUnavailableError,
    DetectionError,
    EvidenceError,
    InconsistentDataError,
    NotMonotoneError,
    TotalConflictError,
)
from .evidence import Evidence
from .extension import VertexMethodWarning, cartesian_product, image, projection
from .finite_frame import MassFunction
from .intervals import IntervalEvidence
from .kalman_filter import KalmanFilter
from .model import BoundedNoise, FilterResult, StateSpaceModel
from .nassreddine_filter import NassreddineFilter
from .particle_filter import ParticleFilter
from .possibility import (
    TriangularBounds,
    alpha_cuts,
    possibility,
    triangular_evidence,
    triangular_from_samples,
)

__all__ = [
    "AudioUnavailableError",
    "BoundedErrorFilter",
    "BoundedNoise",
    "DependentEvidenceFilter",
    "FilterResult",
    "KalmanFilter",
    "NassreddineFilter",
    "ParticleFilter",
    "StateSpaceModel",
    "VertexMethodWarning",
    "cartesian_product",
    "image",
    "projection",
    "Dependence",
    "DetectionError",
    "Evidence",
    "EvidenceError",
    "InconsistentDataError",
    "IntervalEvidence",
    "MassFunction",
    "NotMonotoneError",
    "TotalConflictError",
    "TriangularBounds",
    "alpha_cuts",
    "combine_dependent",
    "conflict",
    "decorrelate",
    "dempster",
    "dependence",
    "discount",
    "energy",
    "joint_energy",
    "possibility",
    "triangular_evidence",
    "triangular_from_samples",
]

__version__ = "0.1.0"

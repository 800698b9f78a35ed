"""The evidence algebra: mass functions, their combination rules and the batched kernels.

Mass functions on finite frames and on intervals, the combination rules (Dempster's eq. 1,
the dependent combination of eqs. 8-20, rivals such as Yager's), possibility distributions
turned into evidence (eqs. 21-24), the extension principle (eqs. 25-29), the batched
kernels the filters use, and belief functions beyond Dempster's rule on finite frames
(set functions, conditioning, the cautious rule, least commitment, decisions).
"""

from __future__ import annotations

from dstoolkit.errors import (
    EvidenceError,
    NotMonotoneError,
    TotalConflictError,
    VertexMethodWarning,
)
from dstoolkit.utils.budget import (
    DEFAULT_MEMORY_BUDGET,
    memory_budget,
    set_memory_budget,
)

from ._base import (
    Evidence,
    validate_masses,
)
from ._batch_kernels import (
    ProductWork,
    dempster_expectation,
    discount_onto_hull,
    sizes,
)
from ._belief_functions import (
    COMPARE_TOLERANCE,
    CONDITIONING_RULES,
    CRITERIA,
    MAX_SET_FUNCTION_FRAME,
    MOBIUS_TOLERANCE,
    SET_FUNCTIONS,
    SetFunction,
    canonical_weights,
    cautious,
    conditional,
    decide,
    discount_to_nondogmatic,
    expected_utilities,
    from_set_function,
    more_committed,
    set_function,
)
from ._boxes import (
    Boxes,
    hull,
    pignistic_expectation,
)
from ._clustering import (
    cluster_boxes,
    merge_equal_boxes,
)
from ._combination import (
    CONFLICT_TOLERANCE,
    MASS_RULES,
    THETA_RULES,
    Dependence,
    MassRule,
    ThetaRule,
    combine_dependent,
    conflict,
    decorrelate,
    dempster,
    dependence,
    discount,
    energy,
    joint_energy,
    product_sources,
    yager,
)
from ._examples import (
    APPENDIX_A2,
    APPENDIX_E1,
    APPENDIX_E2,
    PAPER_A6,
    PAPER_EN1,
    ZADEH_FRAME,
    appendix_evidence,
    appendix_pair,
    zadeh_sources,
)
from ._extension import (
    IMAGE_METHODS,
    ImageMethod,
    box_image,
    cartesian_product,
    image,
    image_subdivision,
    projection,
    vertices,
)
from ._finite_frame import (
    MassFunction,
)
from ._intervals import (
    IntervalEvidence,
)
from ._possibility import (
    TriangularBounds,
    alpha_cuts,
    default_theta,
    possibility,
    triangular_evidence,
    triangular_from_samples,
)

__all__ = [
    "COMPARE_TOLERANCE",
    "CONDITIONING_RULES",
    "CRITERIA",
    "MAX_SET_FUNCTION_FRAME",
    "MOBIUS_TOLERANCE",
    "SET_FUNCTIONS",
    "SetFunction",
    "canonical_weights",
    "cautious",
    "conditional",
    "decide",
    "discount_to_nondogmatic",
    "expected_utilities",
    "from_set_function",
    "more_committed",
    "set_function",
    "APPENDIX_A2",
    "APPENDIX_E1",
    "APPENDIX_E2",
    "Boxes",
    "CONFLICT_TOLERANCE",
    "DEFAULT_MEMORY_BUDGET",
    "Dependence",
    "Evidence",
    "EvidenceError",
    "IMAGE_METHODS",
    "ImageMethod",
    "IntervalEvidence",
    "MASS_RULES",
    "MassFunction",
    "MassRule",
    "NotMonotoneError",
    "PAPER_A6",
    "PAPER_EN1",
    "ProductWork",
    "THETA_RULES",
    "ThetaRule",
    "TotalConflictError",
    "TriangularBounds",
    "VertexMethodWarning",
    "ZADEH_FRAME",
    "alpha_cuts",
    "appendix_evidence",
    "appendix_pair",
    "box_image",
    "cartesian_product",
    "cluster_boxes",
    "combine_dependent",
    "conflict",
    "decorrelate",
    "default_theta",
    "dempster",
    "dempster_expectation",
    "dependence",
    "discount",
    "discount_onto_hull",
    "energy",
    "hull",
    "image",
    "image_subdivision",
    "joint_energy",
    "product_sources",
    "memory_budget",
    "merge_equal_boxes",
    "pignistic_expectation",
    "possibility",
    "projection",
    "set_memory_budget",
    "sizes",
    "triangular_evidence",
    "triangular_from_samples",
    "validate_masses",
    "vertices",
    "yager",
    "zadeh_sources",
]

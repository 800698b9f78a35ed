"""The low-level layer of the evidence: interval evidence as raw box arrays.

Everything here works on :class:`Boxes` — boxes ``lo``/``hi`` of shape (R, N, d) and
masses (R, N), one row per run — so that a batch of runs is one numpy expression; entries
of mass 0 are placeholders and ignored. The filters are built on it; a user who writes a
vectorised filter of their own can be too. The evidence objects
(:class:`~dstoolkit.evidence.IntervalEvidence` and the combination rules of
:mod:`dstoolkit.evidence`) are the reference these kernels are tested against.

- Reading a batch: :func:`hull`, :func:`pignistic_expectation` (eq. 20), :func:`sizes`,
  :func:`row_sum`.
- Combining without merging (the paper's eqs. 1, 9–10, A1–A8): :func:`dependence`,
  :func:`discount_onto_hull`, :func:`dempster_expectation`, and the kernels they run,
  :class:`DependenceKernel` and :class:`ProductKernel` on the column layout of
  :func:`columns`, bound once to their buffers (:class:`ProductWork`), the products formed
  in blocks of at most :data:`PRODUCT_BLOCK` (:func:`block_rows`).
- Merging and capping: :func:`merge_equal_boxes` (eq. 14) and :func:`cluster_boxes`
  (Denœux's outer approximation), with compiled twins (extra ``speed``) that give the
  same numbers, :func:`merge_equal_boxes_compiled` and :func:`cluster_boxes_compiled`.
  Their choices between computed values follow one tie rule, so that they do not hang on
  the last bits of a float: values within :data:`TIE_RTOL` of each other tie and keep
  their order (:func:`tie_classes`, :func:`tie_order`), and bounds that tie are snapped
  outwards to one value before equal boxes merge (:func:`snap_bounds`).
- Images of boxes (extension principle, eqs. 13–19, Props. 1–2): :func:`image_boxes`,
  :func:`parse_signs`, :func:`state_signs`, :func:`resolve_method`, and the relative
  tolerance :data:`CHECK_RTOL` of the monotonicity checks.
"""

from __future__ import annotations

from ._batch_kernels import (
    PRODUCT_BLOCK,
    TINY,
    BatchDependence,
    DependenceKernel,
    ProductKernel,
    ProductWork,
    block_rows,
    coefficient_error,
    columns,
    dempster_expectation,
    dependence,
    discount_onto_hull,
    least,
    per_run,
    sizes,
)
from ._boxes import Boxes, hull, pignistic_expectation, row_sum
from ._clustering import (
    MAX_CLUSTER_ROUNDS,
    bounded_count,
    cluster_boxes,
    merge_equal_boxes,
    merged_mass,
    no_pair,
    too_many_rounds,
    unit_widths,
)
from ._compiled import cluster_boxes_compiled, merge_equal_boxes_compiled
from ._extension import CHECK_RTOL, image_boxes, parse_signs, resolve_method, state_signs
from ._ties import TIE_RTOL, snap_bounds, tie_classes, tie_order

__all__ = [
    "CHECK_RTOL",
    "MAX_CLUSTER_ROUNDS",
    "PRODUCT_BLOCK",
    "TIE_RTOL",
    "TINY",
    "BatchDependence",
    "Boxes",
    "DependenceKernel",
    "ProductKernel",
    "ProductWork",
    "block_rows",
    "bounded_count",
    "cluster_boxes",
    "cluster_boxes_compiled",
    "coefficient_error",
    "columns",
    "dempster_expectation",
    "dependence",
    "discount_onto_hull",
    "hull",
    "image_boxes",
    "least",
    "merge_equal_boxes",
    "merge_equal_boxes_compiled",
    "merged_mass",
    "no_pair",
    "parse_signs",
    "per_run",
    "pignistic_expectation",
    "resolve_method",
    "row_sum",
    "sizes",
    "snap_bounds",
    "state_signs",
    "tie_classes",
    "tie_order",
    "too_many_rounds",
    "unit_widths",
]

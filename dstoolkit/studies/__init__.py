"""The paper's studies: Table 3 reproduced, and the estimation experiments beyond it.

The figures the paper prints are kept as data (:data:`TABLE3_MEAN_ABS_ERROR_M`) to compare
with; every study runs seeded, so its numbers can be reproduced.

Examples
--------
>>> from dstoolkit.studies import TABLE3_CASES, TABLE3_MEAN_ABS_ERROR_M
>>> TABLE3_CASES[-1], TABLE3_MEAN_ABS_ERROR_M[9.6]["dependent_evidence"]
((9.6, 23.9), 0.0435)
"""

from __future__ import annotations

from ._consistency import (
    CONSISTENCY_ORDERS,
    ConsistencyStudy,
    gauge_consistency,
)
from ._estimation import (
    ALL_FILTERS,
    ExampleComparison,
    GaugeRun,
    MismatchResult,
    OrderRuleStudy,
    TrackingData,
    all_filters,
    bound_scale_study,
    bounded_error_failures,
    example_comparison,
    filter_level_errors,
    gauge_run,
    noise_mismatch,
    order_rule_study,
    scaled_noise,
    start_study,
    table3_readings,
    table3_rows,
    tracking_data,
)
from ._experiments import (
    CSV_COLUMNS,
    METHODS,
    CaseReadings,
    OrderRule,
    Simulation,
    Table3,
    Table3Row,
    estimate_levels,
    estimate_orders,
    paper_filters,
    run_table3,
)
from ._filter_runs import (
    ORDER_SOURCES,
    filter_case,
    gauge_case,
)
from ._level_cells import (
    CELL_RULES,
    MAX_CELLS,
    NONDOGMATIC_RATE,
    LevelCellRun,
    cell_expectation,
    cell_frame,
    level_cell_filter,
)
from ._paper_results import (
    OBSERVATION_NOISE_HZ,
    PAPER_RUNTIME_RANGE_S,
    STATE_NOISE_HZ,
    TABLE3_CASES,
    TABLE3_MEAN_ABS_ERROR_M,
)

__all__ = [
    "CELL_RULES",
    "MAX_CELLS",
    "cell_expectation",
    "NONDOGMATIC_RATE",
    "LevelCellRun",
    "cell_frame",
    "level_cell_filter",
    "ConsistencyStudy",
    "CONSISTENCY_ORDERS",
    "gauge_consistency",
    "ALL_FILTERS",
    "CSV_COLUMNS",
    "CaseReadings",
    "ExampleComparison",
    "GaugeRun",
    "METHODS",
    "MismatchResult",
    "OBSERVATION_NOISE_HZ",
    "ORDER_SOURCES",
    "OrderRule",
    "OrderRuleStudy",
    "PAPER_RUNTIME_RANGE_S",
    "STATE_NOISE_HZ",
    "Simulation",
    "TABLE3_CASES",
    "TABLE3_MEAN_ABS_ERROR_M",
    "Table3",
    "Table3Row",
    "TrackingData",
    "all_filters",
    "bound_scale_study",
    "bounded_error_failures",
    "estimate_levels",
    "estimate_orders",
    "example_comparison",
    "filter_case",
    "filter_level_errors",
    "gauge_case",
    "gauge_run",
    "noise_mismatch",
    "order_rule_study",
    "paper_filters",
    "run_table3",
    "scaled_noise",
    "start_study",
    "table3_readings",
    "table3_rows",
    "tracking_data",
]
